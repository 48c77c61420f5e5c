// The sensor stages (renderer/sensor_model.h) on the same street view, each timed alone: the
// cost a sensor preset adds to a render (BM_StreetSensorStage).
//
// Renderer speed against its lower bounds: a labelled frame (RGB + label + instance + range) of
// the built-in street at 1280x720 through the demo rig's first camera, the minimal labelled frame
// (MinimalFrameForBenchmark: the same rays, flat grey Lambert, no texture or material), and Embree
// alone tracing exactly the same primary and shadow rays (TraceOnlyForBenchmark,
// renderer/trace_only_benchmark.h).
//
// Counters: ms_per_frame, Mrays_per_s (primary + shadow rays of the frame / wall time),
// peak_rss_MB (getrusage ru_maxrss of the whole process so far: benchmarks run in the order they
// are registered, so the street's figure is not inflated by the 1M-triangle scene).
// Reproduce: see BENCHMARKS.md.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "common/data_dir.h"
#include "gltf/gltf_loader.h"
#include "renderer/renderer.h"
#include "renderer/sensor_model.h"
#include "renderer/trace_only_benchmark.h"
#include "rigs/rig_presets.h"
#include "rigs/trajectories.h"

namespace rigsim {
namespace {

double PeakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // kilobytes on Linux
}

struct StreetView {
  Scene scene;
  std::unique_ptr<Renderer> renderer;
  Camera camera;
  Rigid3d cam_from_world;
};

// The demo's scene and camera: MakeRingRig's cam0 at the first pose of the demo trajectory.
StreetView& Street() {
  static StreetView* view = [] {
    auto* v = new StreetView;
    v->scene = LoadGltf(DataPath("assets/scenes/street.glb").string());
    v->renderer = std::make_unique<Renderer>(v->scene);
    const Rig rig = MakeRingRig(RingRigOptions{});
    const FramesFile frames = MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 4), 0, 1, 2);
    v->camera = rig.cameras[0].camera;
    v->cam_from_world = *rig.cameras[0].cam_from_rig * *frames.frames[0].rig_from_world;
    return v;
  }();
  return *view;
}

// The street with every material glossy (a dielectric of roughness 0.1): every hit traces a
// reflected ray and shades its hit, the most the specular bounce can add to the street's frame.
StreetView& GlossyStreet() {
  static StreetView* view = [] {
    auto* v = new StreetView;
    v->scene = LoadGltf(DataPath("assets/scenes/street.glb").string());
    for (Material& m : v->scene.materials) {
      m.metallic = 0.0f;
      m.roughness = 0.1f;
    }
    v->renderer = std::make_unique<Renderer>(v->scene);
    v->camera = Street().camera;
    v->cam_from_world = Street().cam_from_world;
    return v;
  }();
  return *view;
}

// A 1M-triangle heightfield (708 x 708 quads, gently rolling), seen from 2 m above at an angle.
struct GridView {
  Scene scene;
  std::unique_ptr<Renderer> renderer;
  Camera camera;
  Rigid3d cam_from_world;
};

GridView& Grid() {
  static GridView* view = [] {
    auto* v = new GridView;
    const int n = 708;  // 2 * 708^2 = 1,002,528 triangles
    const float size = 40.0f;
    SceneMesh mesh;
    mesh.name = "grid";
    mesh.class_id = 7;  // road
    mesh.instance_id = 1;
    mesh.positions.reserve(size_t(n + 1) * (n + 1));
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        const float x = size * (float(i) / n - 0.5f), z = -size * float(j) / n;
        mesh.positions.emplace_back(x, 0.3f * std::sin(0.7f * x) * std::cos(0.5f * z), z);
      }
    }
    mesh.indices.reserve(size_t(n) * n * 6);
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
        for (uint32_t k : {a, c, b, b, c, d}) mesh.indices.push_back(k);
      }
    }
    v->scene.source = "1M-triangle grid";
    v->scene.meshes.push_back(std::move(mesh));
    v->renderer = std::make_unique<Renderer>(v->scene);
    v->camera = MakeRingRig(RingRigOptions{}).cameras[0].camera;
    v->cam_from_world = RigFromWorldAt(Eigen::Vector3d(0, 2, 1), 0);
    return v;
  }();
  return *view;
}

RenderOptions Options(int spp, int threads) {
  RenderOptions options;
  options.samples_per_pixel = spp;
  options.num_threads = threads;  // 0 = all cores
  options.seed = 1;
  return options;
}

void RenderFrames(benchmark::State& state, const Renderer& renderer, const Camera& camera, const Rigid3d& pose,
                  const std::string& key) {
  const RenderOptions options = Options(int(state.range(0)), int(state.range(1)));
  const TraceOnlyStats rays = TraceOnlyForBenchmark(renderer, camera, pose, options);  // ray counts only
  double seconds = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    RenderedView view = renderer.Render(camera, pose, options);
    benchmark::DoNotOptimize(view.rgb.data.data());
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const double per_frame = seconds / double(std::max<benchmark::IterationCount>(1, state.iterations()));
  state.counters["ms_per_frame"] = 1e3 * per_frame;
  state.counters["Mrays_per_s"] = double(rays.primary_rays + rays.shadow_rays) * 1e-6 / per_frame;
  state.counters["peak_rss_MB"] = PeakRssMb();
  state.counters["primary_rays"] = double(rays.primary_rays);
  state.counters["shadow_rays"] = double(rays.shadow_rays);
  state.SetLabel(key);
}

// The floor under a labelled frame (MinimalFrameForBenchmark): timed like RenderFrames.
void MinimalFrames(benchmark::State& state, const Renderer& renderer, const Camera& camera, const Rigid3d& pose,
                   const std::string& key) {
  const RenderOptions options = Options(int(state.range(0)), int(state.range(1)));
  double seconds = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    RenderedView view = MinimalFrameForBenchmark(renderer, camera, pose, options);
    benchmark::DoNotOptimize(view.rgb.data.data());
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  state.counters["ms_per_frame"] = 1e3 * seconds / double(std::max<benchmark::IterationCount>(1, state.iterations()));
  state.SetLabel(key);
}

void TraceOnly(benchmark::State& state, const Renderer& renderer, const Camera& camera, const Rigid3d& pose,
               const std::string& key) {
  const RenderOptions options = Options(int(state.range(0)), int(state.range(1)));
  TraceOnlyStats rays;
  double seconds = 0;
  for (auto _ : state) {
    rays = TraceOnlyForBenchmark(renderer, camera, pose, options);
    state.SetIterationTime(rays.seconds);
    seconds += rays.seconds;
  }
  const double per_frame = seconds / double(std::max<benchmark::IterationCount>(1, state.iterations()));
  state.counters["ms_per_frame"] = 1e3 * per_frame;
  state.counters["Mrays_per_s"] = double(rays.primary_rays + rays.shadow_rays) * 1e-6 / per_frame;
  state.counters["peak_rss_MB"] = PeakRssMb();
  state.SetLabel(key);
}

std::string Key(const char* what, const benchmark::State& state) {
  return std::string(what) + " spp=" + std::to_string(state.range(0)) + " threads=" +
         (state.range(1) == 0 ? std::string("all") : std::to_string(state.range(1)));
}

void BM_StreetLabelledFrame(benchmark::State& state) {
  StreetView& v = Street();
  RenderFrames(state, *v.renderer, v.camera, v.cam_from_world, Key("street frame", state));
}

void BM_GlossyStreetLabelledFrame(benchmark::State& state) {
  StreetView& v = GlossyStreet();
  RenderFrames(state, *v.renderer, v.camera, v.cam_from_world, Key("glossy street frame", state));
}

void BM_StreetEmbreeAlone(benchmark::State& state) {
  StreetView& v = Street();
  TraceOnly(state, *v.renderer, v.camera, v.cam_from_world, Key("street embree", state));
}

void BM_StreetMinimalFrame(benchmark::State& state) {
  StreetView& v = Street();
  MinimalFrames(state, *v.renderer, v.camera, v.cam_from_world, Key("street minimal", state));
}

void BM_Grid1MLabelledFrame(benchmark::State& state) {
  GridView& v = Grid();
  RenderFrames(state, *v.renderer, v.camera, v.cam_from_world, Key("grid1M frame", state));
  state.counters["triangles"] = double(v.scene.NumTriangles());
}

void BM_Grid1MEmbreeAlone(benchmark::State& state) {
  GridView& v = Grid();
  TraceOnly(state, *v.renderer, v.camera, v.cam_from_world, Key("grid1M embree", state));
}

// The sensor stages of the automotive preset on the street frame (1 spp), each alone, on a copy of
// the rendered view: 0 photometry (exposure, white balance, vignetting, noise, 8-bit: ApplyPhotometry),
// 1 the same in two steps around a defocus (LinearBeforeNoise + AddNoiseAndEncode), 2 defocus at
// the preset's lens, 3 defocus focused at 0.3 m (the street beyond blurred by several pixels),
// 4 the JPEG round trip at quality 75, 5 every stage as a render runs them (ApplySensorStages).
void BM_StreetSensorStage(benchmark::State& state) {
  StreetView& v = Street();
  static const RenderedView view = v.renderer->Render(v.camera, v.cam_from_world, Options(1, 0));
  const int stage = int(state.range(0)), threads = int(state.range(1));
  const SensorPreset& preset = FindSensorPreset("automotive");
  PhotometricOptions photometric = preset.photometric;
  photometric.seed = 1;
  SensorStages stages;
  stages.photometric = true;
  stages.photometry = DrawCameraPhotometry(photometric, 0);
  stages.noise_key = {1, 0, 0};
  stages.defocus = preset.defocus;
  if (stage == 3) stages.defocus.focus_distance_m = 0.3;
  stages.jpeg_quality = preset.jpeg_quality;
  const double fx = v.camera.fx(), cx = v.camera.cx(), cy = v.camera.cy();
  const ImageF linear = LinearBeforeNoise(stages.photometry, cx, cy, view.rgb);
  double seconds = 0;
  for (auto _ : state) {
    ImageU8 rgb = view.rgb;
    ImageF blurred = linear;
    const auto start = std::chrono::steady_clock::now();
    switch (stage) {
      case 0: ApplyPhotometry(stages.photometry, stages.noise_key, cx, cy, rgb, nullptr, threads); break;
      case 1: {
        const ImageF l = LinearBeforeNoise(stages.photometry, cx, cy, rgb, nullptr, threads);
        AddNoiseAndEncode(stages.photometry, stages.noise_key, l, rgb, nullptr, threads);
        break;
      }
      case 2:
      case 3: ApplyDefocus(stages.defocus, fx, view.range, blurred, nullptr, threads); break;
      case 4: JpegRoundTrip(rgb, stages.jpeg_quality); break;
      default: ApplySensorStages(stages, fx, cx, cy, view.range, rgb, nullptr, threads); break;
    }
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    benchmark::DoNotOptimize(rgb.data.data());
    benchmark::DoNotOptimize(blurred.data.data());
  }
  state.counters["ms_per_frame"] = 1e3 * seconds / double(std::max<benchmark::IterationCount>(1, state.iterations()));
  state.counters["blur_px_at_infinity"] = BlurCircleDiameterPx(stages.defocus, fx, 0.0);
  static const char* kNames[] = {"photometry", "photometry in two steps", "defocus (preset lens)",
                                 "defocus (focused at 0.3 m)", "JPEG 75 round trip", "all stages"};
  state.SetLabel(std::string("street sensor ") + kNames[std::min(stage, 5)] + " threads=" +
                 (threads == 0 ? std::string("all") : std::to_string(threads)));
}

// Args: {samples per pixel, threads (0 = all cores)}.
BENCHMARK(BM_StreetLabelledFrame)->Args({1, 0})->Args({4, 0})->Args({1, 1})->Args({1, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_GlossyStreetLabelledFrame)->Args({1, 0})->Args({4, 0})->Args({1, 1})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_StreetEmbreeAlone)->Args({1, 0})->Args({4, 0})->Args({1, 1})->Args({1, 2})
    ->Unit(benchmark::kMillisecond)->UseManualTime()->MinTime(2.0);
BENCHMARK(BM_StreetMinimalFrame)->Args({1, 0})->Args({1, 1})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_Grid1MLabelledFrame)->Args({1, 0})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_Grid1MEmbreeAlone)->Args({1, 0})->Unit(benchmark::kMillisecond)->UseManualTime()->MinTime(2.0);
// Args: {stage (above), threads (0 = all cores)}.
BENCHMARK(BM_StreetSensorStage)->ArgsProduct({{0, 1, 2, 3, 4, 5}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);

}  // namespace
}  // namespace rigsim

BENCHMARK_MAIN();
