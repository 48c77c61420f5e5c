#include "renderer/render_dataset.h"

#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include "dataset/ground_truth.h"
#include "dataset/image_io.h"
#include "dataset/label_image.h"
#include "geometry/json_io.h"
#include "scene/scene_pose.h"

namespace rigsim {
namespace fs = std::filesystem;
namespace {

// Names become folder and file names: refuse anything that would escape or collide.
void CheckName(const std::string& name, const std::string& what) {
  if (name.empty() || name == "." || name == ".." || name.find_first_of("/\\") != std::string::npos) {
    throw std::invalid_argument("render: " + what + " name '" + name + "' cannot be used as a file name");
  }
}

void CheckJob(const RenderJob& job) {
  if (job.scene == nullptr) throw std::invalid_argument("render: no scene");
  if (job.rig.cameras.empty()) throw std::invalid_argument("render: the rig has no cameras");
  if (job.frames.frames.empty()) throw std::invalid_argument("render: no frames to render");
  job.options.Check();
  job.photometric.Check();
  std::set<std::string> names;
  for (const RigCamera& cam : job.rig.cameras) {
    CheckName(cam.name, "camera");
    if (!names.insert(cam.name).second) throw std::invalid_argument("render: camera name '" + cam.name + "' repeats");
    if (!cam.cam_from_rig) {
      throw std::invalid_argument("render: camera '" + cam.name + "' has no cam_from_rig; a rig to render needs every pose");
    }
  }
  names.clear();
  for (const Frame& frame : job.frames.frames) {
    CheckName(frame.name, "frame");
    if (!names.insert(frame.name).second) throw std::invalid_argument("render: frame name '" + frame.name + "' repeats");
    if (!frame.rig_from_world) throw std::invalid_argument("render: frame '" + frame.name + "' has no rig_from_world");
  }
}

void WriteView(const DatasetLayout& layout, const std::string& cam, const std::string& frame, const RenderedView& view) {
  const fs::path paths[] = {layout.Image(cam, frame), layout.Label(cam, frame), layout.LabelColor(cam, frame),
                            layout.Instance(cam, frame), layout.Depth(cam, frame)};
  for (const fs::path& p : paths) fs::create_directories(p.parent_path());
  // In parallel: compressing the five files took longer than rendering a 1-spp view.
  tbb::parallel_invoke([&] { WriteImage(layout.Image(cam, frame), view.rgb); },
                       [&] { WriteImage(layout.Label(cam, frame), view.label); },
                       [&] { WriteImage(layout.LabelColor(cam, frame), ColorizeLabels(view.label)); },
                       [&] { WriteImage(layout.Instance(cam, frame), view.instance); },
                       [&] { WriteImage(layout.Depth(cam, frame), view.range); });
}

// Pixels outside the lens's valid region: the renderer marks them label 0 with range 0 (a surface
// without a class has a range; sky has label kSkyId). They stay black under photometric changes.
ImageU8 InvalidPixels(const RenderedView& view) {
  ImageU8 invalid(view.label.width, view.label.height, 1, 0);
  for (size_t i = 0; i < invalid.data.size(); ++i) invalid.data[i] = view.label.data[i] == 0 && view.range.data[i] == 0.0f;
  return invalid;
}

nlohmann::json PhotometryJson(const RenderJob& job, const std::vector<CameraPhotometry>& drawn) {
  const PhotometricOptions& o = job.photometric;
  nlohmann::json cameras = nlohmann::json::array();
  for (size_t c = 0; c < drawn.size(); ++c) {
    const CameraPhotometry& p = drawn[c];
    cameras.push_back({{"name", job.rig.cameras[c].name},
                       {"exposure_stops", p.exposure_stops},
                       {"gain", p.gain()},
                       {"white_balance_rgb", {p.white_balance.x(), p.white_balance.y(), p.white_balance.z()}},
                       {"vignetting_strength", p.vignetting_strength},
                       {"shot_noise", p.shot_noise},
                       {"read_noise_stddev", p.read_noise_stddev}});
  }
  return {{"seed", o.seed},
          {"model",
           "linear light: out_c = gain * white_balance_rgb[c] * V(r) * in_c + Normal(0, shot_noise * I + read_noise_stddev^2), "
           "clipped to [0, 1] and sRGB-encoded; gain = 2^exposure_stops; V(r) = 1 / (1 + k r^2)^2 with V(1) = "
           "1 - vignetting_strength, r = distance from the principal point / distance to the farthest image corner; "
           "I = the noise-free value"},
          {"options",
           {{"exposure_stops_sigma", o.exposure_stops_sigma},
            {"white_balance_stops_sigma", o.white_balance_stops_sigma},
            {"vignetting_strength", o.vignetting_strength},
            {"shot_noise", o.shot_noise},
            {"read_noise_stddev", o.read_noise_stddev}}},
          {"cameras", cameras}};
}

}  // namespace

void RenderDataset(const RenderJob& job, const fs::path& out_dir, bool force,
                   const std::function<void(int done, int total)>& progress) {
  CheckJob(job);
  const std::vector<RigCamera>& cams = job.rig.cameras;
  const int num_cams = int(cams.size());
  const int num_frames = int(job.frames.frames.size());
  const int total = num_cams * num_frames;

  // Built before the staging folder exists so that a bad scene leaves nothing behind.
  Renderer renderer(*job.scene);
  const bool animated = job.scene->IsAnimated();
  const bool photometric = job.photometric.enabled();
  std::vector<CameraPhotometry> photometry;
  if (photometric) {
    for (int c = 0; c < num_cams; ++c) photometry.push_back(DrawCameraPhotometry(job.photometric, c));
  }

  StagedOutput staged(OutputFolderRequest{out_dir, "", "rigsim render", {}, force});
  const DatasetLayout layout(staged.staging_dir());

  // overlap[a * num_cams + b] sums, over frames, the fraction of a's surface seen by b.
  std::vector<double> overlap(size_t(num_cams) * num_cams, 0.0);
  int done = 0;
  std::vector<SceneMesh> posed;  // the renderer's meshes while an animated scene is posed
  // Each camera's pixel-centre rays, for the overlap: computed by the renderer, once per run.
  std::vector<std::shared_ptr<const std::vector<Eigen::Vector3f>>> bearings(num_cams);
  for (int c = 0; c < num_cams; ++c) bearings[c] = renderer.PixelCentreBearings(cams[c].camera);
  for (int frame_index = 0; frame_index < num_frames; ++frame_index) {
    const Frame& frame = job.frames.frames[frame_index];
    std::vector<Rigid3d> cam_from_world(num_cams);
    std::vector<ImageF> ranges(num_cams);
    // Cameras grouped by capture time (timestamp + time_offset_s): an animated scene is posed once
    // per distinct time; a static one is never re-posed.
    std::map<double, std::vector<int>> cams_by_time;
    for (int c = 0; c < num_cams; ++c) {
      const double time = animated ? frame.timestamp_s + cams[c].time_offset_s : 0.0;
      cams_by_time[time].push_back(c);
    }
    for (const auto& [time, group] : cams_by_time) {
      if (animated) {
        posed = PoseMeshesAt(*job.scene, time);
        renderer.SetMeshes(posed);
      }
      for (int c : group) {
        cam_from_world[c] = *cams[c].cam_from_rig * *frame.rig_from_world;
        RenderedView view = renderer.Render(cams[c].camera, cam_from_world[c], job.options);
        if (photometric) {
          const ImageU8 invalid = InvalidPixels(view);
          ApplyPhotometry(photometry[c], PhotometricNoiseKey{job.photometric.seed, c, frame_index}, cams[c].camera.cx(),
                          cams[c].camera.cy(), view.rgb, &invalid, job.options.num_threads);
        }
        WriteView(layout, cams[c].name, frame.name, view);
        ranges[c] = std::move(view.range);
        ++done;
        if (progress) progress(done, total);
      }
    }
    // Each camera's surface pixels against every other camera, in bands of rows in parallel,
    // each into its own slot: a pixel's ray is undistorted once for all the other cameras.
    constexpr int kBandRows = 32;
    struct Band {
      int a, y_begin;
    };
    std::vector<Band> bands;
    for (int a = 0; a < num_cams; ++a) {
      for (int y = 0; y < ranges[a].height; y += kBandRows) bands.push_back({a, y});
    }
    std::vector<CoVisibleCounts> counts(bands.size());
    tbb::task_arena arena(job.options.num_threads > 0 ? job.options.num_threads : tbb::task_arena::automatic);
    arena.execute([&] {
      tbb::parallel_for(size_t(0), bands.size(), [&](size_t i) {
        const int a = bands[i].a;
        std::vector<TransferTarget> targets;
        for (int b = 0; b < num_cams; ++b) {
          if (b != a) targets.push_back({&cams[b].camera, &ranges[b], cam_from_world[b] * cam_from_world[a].Inverse()});
        }
        counts[i] = CountCoVisible(cams[a].camera, ranges[a], targets, bands[i].y_begin, bands[i].y_begin + kBandRows, {},
                                   bearings[a].get());
      });
    });
    std::vector<size_t> surface(num_cams, 0), visible(size_t(num_cams) * num_cams, 0);
    for (size_t i = 0; i < bands.size(); ++i) {
      const int a = bands[i].a;
      surface[a] += counts[i].surface;
      for (int b = 0, t = 0; b < num_cams; ++b) {
        if (b != a) visible[size_t(a) * num_cams + b] += counts[i].visible[t++];
      }
    }
    for (int a = 0; a < num_cams; ++a) {
      for (int b = 0; b < num_cams; ++b) {
        const size_t ab = size_t(a) * num_cams + b;
        if (b != a && surface[a] > 0) overlap[ab] += double(visible[ab]) / double(surface[a]);
      }
    }
  }

  nlohmann::json pairs = nlohmann::json::array();
  for (int a = 0; a < num_cams; ++a) {
    for (int b = a + 1; b < num_cams; ++b) {
      pairs.push_back({{"a", cams[a].name},
                       {"b", cams[b].name},
                       {"overlap_a_in_b", overlap[size_t(a) * num_cams + b] / num_frames},
                       {"overlap_b_in_a", overlap[size_t(b) * num_cams + a] / num_frames}});
    }
  }
  const nlohmann::json overlap_json{{"frames", num_frames}, {"pairs", pairs}};
  json_io::WriteTextAtomic(layout.OverlapJson(), overlap_json.dump(2) + "\n");
  if (photometric) json_io::WriteTextAtomic(layout.PhotometricJson(), PhotometryJson(job, photometry).dump(2) + "\n");

  WriteRig(job.rig, layout.RigJson());
  FramesFile frames = job.frames;
  frames.seed = job.options.seed;
  if (frames.scene.empty()) frames.scene = job.scene_name;
  WriteFrames(frames, layout.FramesJson());

  staged.Commit();
}

}  // namespace rigsim
