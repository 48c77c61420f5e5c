#include "apps/rigsim/render_support.h"

#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "apps/rigsim/interrupt.h"
#include "apps/rigsim/parse_errors.h"
#include "apps/rigsim/progress.h"
#include "common/format.h"
#include "dataset/dataset.h"
#include "dataset/render_shards.h"
#include "gltf/gltf_loader.h"
#include "gltf/label_rules.h"
#include "pipeline/report_table.h"

namespace rigsim::cli {

RenderOptions RenderSettings::ToRenderOptions() const {
  RenderOptions o;
  o.samples_per_pixel = samples_per_pixel;
  o.seed = seed;
  o.num_threads = threads;
  o.Check();
  return o;
}

void AddRenderSettingsOptions(CLI::App& cmd, RenderSettings& s) {
  cmd.add_option("--spp", s.samples_per_pixel, "RGB samples per pixel (anti-aliasing); labels and depth use the pixel centre")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  cmd.add_option("--seed", s.seed, "seed of the sample jitter; the same seed gives the same bytes")
      ->capture_default_str();
  cmd.add_option("--threads", s.threads, "worker threads, 0 = all cores (output does not depend on it)")
      ->capture_default_str()
      ->check(NonNegative());
}

PhotometricOptions PhotometricSettings::ToOptions(uint64_t seed, const PhotometricOptions& base) const {
  PhotometricOptions o = defaults ? PhotometricOptions::Defaults() : base;
  if (exposure_sigma) o.exposure_stops_sigma = *exposure_sigma;
  if (white_balance_sigma) o.white_balance_stops_sigma = *white_balance_sigma;
  if (vignetting) o.vignetting_strength = *vignetting;
  if (shot_noise) o.shot_noise = *shot_noise;
  if (read_noise) o.read_noise_stddev = *read_noise;
  o.seed = seed;
  o.Check();
  return o;
}

void AddPhotometricOptions(CLI::App& cmd, PhotometricSettings& s) {
  const PhotometricOptions d = PhotometricOptions::Defaults();
  auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%g", v);
    return std::string(buf);
  };
  const std::string group = "Photometric differences between cameras (RGB only; off unless asked for)";
  cmd.add_flag("--photometric", s.defaults,
               "give every camera its own exposure, white balance, vignetting and sensor noise, drawn from --seed, "
               "with the default magnitudes below (each option below overrides its one; alone, an option turns on "
               "only itself). Labels, instances and depth stay exact; the draws go to photometric.json")
      ->group(group);
  cmd.add_option("--exposure-sigma", s.exposure_sigma,
                 "spread of the per-camera exposure, stops (gain 2^N(0, sigma)); --photometric: " + num(d.exposure_stops_sigma))
      ->check(CLI::Range(0.0, 3.0))
      ->group(group);
  cmd.add_option("--white-balance-sigma", s.white_balance_sigma,
                 "spread of the per-camera red and blue gains relative to green, stops; --photometric: " +
                     num(d.white_balance_stops_sigma))
      ->check(CLI::Range(0.0, 1.0))
      ->group(group);
  cmd.add_option("--vignetting", s.vignetting,
                 "fraction of light lost at the image corner farthest from the principal point, cos^4-shaped falloff, "
                 "in [0, 1); --photometric: " + num(d.vignetting_strength))
      ->check(CLI::Range(0.0, 0.999))
      ->group(group);
  cmd.add_option("--shot-noise", s.shot_noise,
                 "signal-dependent noise: variance per unit linear intensity (1 = white; ~1/full-well electrons); "
                 "--photometric: " + num(d.shot_noise))
      ->check(CLI::Range(0.0, 0.1))
      ->group(group);
  cmd.add_option("--read-noise", s.read_noise,
                 "signal-independent noise: standard deviation in linear intensity (1 = white); --photometric: " +
                     num(d.read_noise_stddev))
      ->check(CLI::Range(0.0, 0.5))
      ->group(group);
}

namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}

std::string FullNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

}  // namespace

void AddSensorOptions(CLI::App& cmd, SensorSettings& s) {
  const std::string group = "Sensor model (RGB only; docs/scenes-and-rigs.md lists each preset's values and sources)";
  std::string presets;
  for (const SensorPreset& p : SensorPresets()) {
    presets += "\n  " + p.name + ": " + p.summary;
    if (p.name == "ideal") continue;
    presets += "\n    full well " + Num(p.full_well_electrons) + " e-, read noise " + Num(p.read_noise_electrons) +
               " e-, gain " + Num(p.analog_gain) + "; f/" + Num(p.defocus.f_number) + " focused at " +
               Num(p.defocus.focus_distance_m) + " m, " + Num(p.defocus.pixel_pitch_um) + " um pixels; " +
               (p.jpeg_quality > 0 ? "JPEG " + std::to_string(p.jpeg_quality) : std::string("no JPEG"));
  }
  cmd.add_option("--sensor", s.preset,
                 "the camera's sensor and lens, a named preset: exposure and white balance per camera, vignetting, "
                 "defocus (thin lens), shot and read noise, JPEG, drawn from --seed. Labels, instances and depth stay "
                 "exact; sensor.json and photometric.json record what ran. The photometric options below override "
                 "the preset's magnitudes; --photometric is its own set, not combined with a preset:" + presets)
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--f-number", s.f_number, "defocus: the lens's f-number N (0 = a pinhole, no defocus); overrides the preset's")
      ->check(CLI::Range(0.0, 64.0))
      ->group(group);
  cmd.add_option("--focus-distance", s.focus_distance, "defocus: the distance in sharp focus (m); overrides the preset's")
      ->check(CLI::PositiveNumber)
      ->group(group);
  cmd.add_option("--pixel-pitch", s.pixel_pitch,
                 "defocus: the sensor's pixel size (um), which with fx gives the focal length; overrides the preset's "
                 "(ideal: 3)")
      ->check(CLI::Range(0.01, 100.0))
      ->group(group);
  cmd.add_option("--jpeg-quality", s.jpeg_quality,
                 "a JPEG round trip at this quality (1..100; 0 = none): the images stay PNG with the JPEG's artefacts; "
                 "overrides the preset's")
      ->check(CLI::Range(0, 100))
      ->group(group);
}

void ApplySensorSettings(const SensorSettings& sensor, const PhotometricSettings& photometric, uint64_t seed,
                         RenderJob& job) {
  const SensorPreset& preset = FindSensorPreset(sensor.preset);
  if (photometric.defaults && preset.name != "ideal") {
    throw std::invalid_argument("--photometric and --sensor " + preset.name +
                                " both set the photometric magnitudes: give one of them (the options --exposure-sigma, "
                                "--vignetting, --shot-noise, ... change one value of either)");
  }
  job.photometric = photometric.ToOptions(seed, preset.photometric);
  job.defocus = preset.defocus;
  if (sensor.f_number) job.defocus.f_number = *sensor.f_number;
  if (sensor.focus_distance) job.defocus.focus_distance_m = *sensor.focus_distance;
  if (sensor.pixel_pitch) job.defocus.pixel_pitch_um = *sensor.pixel_pitch;
  if (job.defocus.enabled() && job.defocus.focus_distance_m <= 0) {
    throw std::invalid_argument("--f-number " + Num(job.defocus.f_number) +
                                ": defocus needs the distance in focus too (--focus-distance M)");
  }
  job.defocus.Check();
  job.jpeg_quality = sensor.jpeg_quality ? *sensor.jpeg_quality : preset.jpeg_quality;
  job.sensor_preset = preset.name;
}

std::vector<std::string> SensorArgs(const SensorSettings& sensor, const PhotometricSettings& p) {
  std::vector<std::string> args;
  if (sensor.preset != "ideal") args.insert(args.end(), {"--sensor", sensor.preset});
  for (const auto& [option, value] : {std::pair{"--f-number", sensor.f_number}, {"--focus-distance", sensor.focus_distance},
                                      {"--pixel-pitch", sensor.pixel_pitch}}) {
    if (value) args.insert(args.end(), {option, FullNumber(*value)});
  }
  if (sensor.jpeg_quality) args.insert(args.end(), {"--jpeg-quality", std::to_string(*sensor.jpeg_quality)});
  if (p.defaults) args.push_back("--photometric");
  for (const auto& [option, value] : {std::pair{"--exposure-sigma", p.exposure_sigma}, {"--white-balance-sigma", p.white_balance_sigma},
                                      {"--vignetting", p.vignetting}, {"--shot-noise", p.shot_noise}, {"--read-noise", p.read_noise}}) {
    if (value) args.insert(args.end(), {option, FullNumber(*value)});
  }
  return args;
}

void AddLabelRulesOption(CLI::App& cmd, std::string& rules_path) {
  cmd.add_option("--rules", rules_path,
                 "label rules JSON: classes from node, mesh or material names (a glTF without extras.class)")
      ->check(CLI::ExistingFile);
}

Scene LoadSceneVerbose(const std::filesystem::path& path, const std::string& rules_path) {
  std::optional<LabelRules> rules;
  GltfLoadOptions options;
  if (!rules_path.empty()) {
    rules = LabelRules::Read(rules_path);
    options.label_rules = &*rules;
  }
  Scene scene = LoadGltf(path, options);
  std::fprintf(stderr, "scene %s: %s, %s, %s\n", path.string().c_str(), Count(scene.meshes.size(), "mesh", "meshes").c_str(),
               Count(scene.NumTriangles(), "triangle").c_str(), Count(scene.textures.size(), "texture").c_str());
  if (rules) std::fprintf(stderr, "  label rules %s (%s)\n", rules_path.c_str(), Count(rules->rules().size(), "rule").c_str());
  for (const std::string& w : scene.warnings) std::fprintf(stderr, "  warning: %s\n", w.c_str());
  return scene;
}

void RequirePoses(const Rig& rig, const std::filesystem::path& rig_path, const FramesFile& frames,
                  const std::filesystem::path& frames_path, const std::string& command) {
  for (const RigCamera& c : rig.cameras) {
    if (!c.cam_from_rig) {
      throw std::runtime_error(rig_path.string() + ": camera '" + c.name + "' has no cam_from_rig; " + command +
                               " needs every camera's pose in the rig (rigsim make-rig writes it, calibrate estimates it)");
    }
  }
  for (size_t i = 0; i < frames.frames.size(); ++i) {
    if (!frames.frames[i].rig_from_world) {
      throw std::runtime_error(frames_path.string() + ": frames[" + std::to_string(i) + "] ('" + frames.frames[i].name +
                               "') has no rig_from_world; " + command +
                               " needs the rig's pose at every frame (rigsim make-rig writes them)");
    }
  }
}

void RenderAndReport(const RenderJob& job, const std::filesystem::path& out, bool force) {
  const auto start = std::chrono::steady_clock::now();
  Progress progress("rendering views");
  {
    // Ctrl-C stops after the view being rendered; the staging folder is removed on the way out.
    const InterruptScope interrupt;
    RenderDataset(job, out, force, [&](int done, int total) {
      progress(done, total);
      InterruptScope::ThrowIfRequested();
    });
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const FrameRange range = ShardFrames(int(job.frames.frames.size()), job.shard.index, job.shard.count);
  const size_t frames = size_t(range.end - range.begin);
  std::printf("rendered %s (%s x %s, %d spp) into %s in %.1f s\n", Count(job.rig.cameras.size() * frames, "view").c_str(),
              Count(job.rig.cameras.size(), "camera").c_str(), Count(frames, "frame").c_str(), job.options.samples_per_pixel,
              out.string().c_str(), seconds);
  if (job.shard.count > 1) {
    std::printf("shard %d/%d: frames %s to %s of %zu; combine the shards with: rigsim render-merge OUT SHARD_DIR...\n",
                job.shard.index, job.shard.count, job.frames.frames[range.begin].name.c_str(),
                job.frames.frames[range.end - 1].name.c_str(), job.frames.frames.size());
  }
  if (!job.sensor_preset.empty() && job.sensor_preset != "ideal") {
    std::printf("sensor %s: %s (%s)\n", job.sensor_preset.c_str(), FindSensorPreset(job.sensor_preset).summary.c_str(),
                DatasetLayout(out).SensorJson().string().c_str());
  }
  if (job.defocus.enabled()) {
    std::printf("  defocus: f/%g focused at %g m, %g um pixels: blur circle %.2f px across at infinity (%s)\n",
                job.defocus.f_number, job.defocus.focus_distance_m, job.defocus.pixel_pitch_um,
                BlurCircleDiameterPx(job.defocus, job.rig.cameras.front().camera.fx(), 0.0),
                job.rig.cameras.front().name.c_str());
  }
  if (job.jpeg_quality > 0) std::printf("  JPEG quality %d (round trip; the images stay PNG)\n", job.jpeg_quality);
  if (job.photometric.enabled()) {
    std::printf("photometric differences (seed %llu; %s):\n", static_cast<unsigned long long>(job.photometric.seed),
                DatasetLayout(out).PhotometricJson().string().c_str());
    for (size_t c = 0; c < job.rig.cameras.size(); ++c) {
      const CameraPhotometry p = DrawCameraPhotometry(job.photometric, int(c));
      std::printf("  %-10s exposure %+.2f stops (gain %.3f)  white balance R %.3f B %.3f\n", job.rig.cameras[c].name.c_str(),
                  p.exposure_stops, p.gain(), p.white_balance.x(), p.white_balance.z());
    }
    std::printf("  every camera: vignetting %.0f%% at the farthest corner, noise variance %g * I + %g^2\n",
                100 * job.photometric.vignetting_strength, job.photometric.shot_noise, job.photometric.read_noise_stddev);
  }
  if (job.rig.cameras.size() < 2) return;  // no pair to share a view
  const OverlapTable overlap = ReadOverlap(DatasetLayout(out).OverlapJson());
  std::printf("ground-truth overlap (fraction of the view both cameras share):\n");
  for (size_t a = 0; a < job.rig.cameras.size(); ++a) {
    for (size_t b = a + 1; b < job.rig.cameras.size(); ++b) {
      const auto it = overlap.find({job.rig.cameras[a].name, job.rig.cameras[b].name});
      if (it != overlap.end()) {
        std::printf("  %s-%s %5.1f%%\n", job.rig.cameras[a].name.c_str(), job.rig.cameras[b].name.c_str(),
                    100 * it->second);
      }
    }
  }
}

}  // namespace rigsim::cli
