#include "renderer/render_dataset.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <utility>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include "common/stable_hash.h"
#include "dataset/capture_poses.h"
#include "dataset/coco.h"
#include "dataset/ground_truth.h"
#include "dataset/image_io.h"
#include "dataset/label_image.h"
#include "dataset/previews.h"
#include "dataset/render_shards.h"
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
  job.defocus.Check();
  if (job.jpeg_quality < 0 || job.jpeg_quality > 100) {
    throw std::invalid_argument("render: JPEG quality " + std::to_string(job.jpeg_quality) + " must be 0 (none) or in 1..100");
  }
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

void WriteView(const DatasetLayout& layout, const ExtraOutputs& extras, const std::string& cam, const std::string& frame,
               const RenderedView& view) {
  std::vector<fs::path> paths = {layout.Image(cam, frame), layout.Label(cam, frame), layout.LabelColor(cam, frame),
                                 layout.Instance(cam, frame), layout.Depth(cam, frame)};
  if (extras.previews) paths.insert(paths.end(), {layout.DepthColor(cam, frame), layout.InstanceColor(cam, frame)});
  if (extras.normals) paths.push_back(layout.Normal(cam, frame));
  for (const fs::path& p : paths) fs::create_directories(p.parent_path());
  // In parallel: compressing the five files takes longer than rendering a 1-spp view.
  tbb::parallel_invoke([&] { WriteImage(layout.Image(cam, frame), view.rgb); },
                       [&] { WriteImage(layout.Label(cam, frame), view.label); },
                       [&] { WriteImage(layout.LabelColor(cam, frame), ColorizeLabels(view.label)); },
                       [&] { WriteImage(layout.Instance(cam, frame), view.instance); },
                       [&] { WriteImage(layout.Depth(cam, frame), view.range); },
                       [&] {
                         if (extras.previews) WriteImage(layout.DepthColor(cam, frame), ColorizeDepth(view.range));
                       },
                       [&] {
                         if (extras.previews) WriteImage(layout.InstanceColor(cam, frame), ColorizeInstances(view.instance));
                       },
                       [&] {
                         if (extras.normals) WriteImage(layout.Normal(cam, frame), view.normal);
                       });
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

// Whether the job asks for more than the photometric stage: then sensor.json says what ran.
bool SensorStagesOn(const RenderJob& job) {
  return job.defocus.enabled() || job.jpeg_quality > 0 || (!job.sensor_preset.empty() && job.sensor_preset != "ideal");
}

nlohmann::json SensorStagesJson(const RenderJob& job) {
  nlohmann::json stages = nlohmann::json::array();
  if (job.photometric.exposure_stops_sigma > 0 || job.photometric.white_balance_stops_sigma > 0) {
    stages.push_back("exposure and white balance");
  }
  if (job.photometric.vignetting_strength > 0) stages.push_back("vignetting");
  if (job.defocus.enabled()) stages.push_back("defocus");
  if (job.photometric.shot_noise > 0 || job.photometric.read_noise_stddev > 0) stages.push_back("shot and read noise");
  stages.push_back("8-bit sRGB");
  if (job.jpeg_quality > 0) stages.push_back("JPEG");
  const DefocusOptions& d = job.defocus;
  return {{"preset", job.sensor_preset.empty() ? "ideal" : job.sensor_preset},
          {"stages", stages},
          {"defocus",
           d.enabled() ? nlohmann::json{{"f_number", d.f_number},
                                        {"focus_distance_m", d.focus_distance_m},
                                        {"pixel_pitch_um", d.pixel_pitch_um},
                                        {"max_radius_px", d.max_radius_px},
                                        {"model", "thin lens: blur circle diameter (px) = fx (f / N) / (s - f) |d - s| / d, "
                                                  "f = fx * pixel pitch, d = the pixel's distance along the optical axis; a disc blur in linear light "
                                                  "with a depth test (renderer/defocus.h)"}}
                       : nlohmann::json()},
          {"jpeg_quality", job.jpeg_quality},
          {"photometric", "photometric.json"}};
}

// The scene posed at evenly spaced times over a camera's capture span (at most 5 ms apart, at most
// 9 steps): what the renderer moves the animated meshes between.
struct PosedSpan {
  std::vector<std::vector<SceneMesh>> steps;
  double begin = 0, end = 0;
};
PosedSpan PoseOverSpan(const Scene& scene, const RigCamera& cam, const Frame& frame, int spp) {
  const double exposure = spp > 1 ? cam.exposure_s : 0.0;
  const double first = std::min(cam.RowTime(0), cam.RowTime(cam.camera.height() - 1));
  const double last = std::max(cam.RowTime(0), cam.RowTime(cam.camera.height() - 1));
  PosedSpan span;
  span.begin = frame.timestamp_s + first - exposure / 2;
  span.end = frame.timestamp_s + last + exposure / 2;
  const int steps = std::clamp(int(std::ceil((span.end - span.begin) / 0.005)) + 1, 2, 9);
  for (int k = 0; k < steps; ++k) {
    span.steps.push_back(PoseMeshesAt(scene, span.begin + (span.end - span.begin) * k / (steps - 1)));
  }
  return span;
}

nlohmann::json PoseJson(const Rigid3d& pose) { return json_io::PoseToJson(pose); }

// One camera's entry of a frame in poses.json.
nlohmann::json PosesEntry(const RigCamera& cam, const Frame& frame, const ViewPose& pose) {
  const int first_row = cam.readout_bottom_to_top ? cam.camera.height() - 1 : 0;
  nlohmann::json entry{{"frame", frame.name},
                       {"capture_time_s", frame.timestamp_s + cam.time_offset_s},
                       {"cam_from_world", PoseJson(pose.Row(first_row))}};
  if (pose.Rolling()) {
    nlohmann::json rows = nlohmann::json::array();
    for (int y = 0; y < cam.camera.height(); ++y) {
      const Rigid3d& p = pose.Row(y);
      rows.push_back({frame.timestamp_s + cam.RowTime(y), p.rotation.w(), p.rotation.x(), p.rotation.y(), p.rotation.z(),
                      p.translation.x(), p.translation.y(), p.translation.z()});
    }
    entry["rows"] = std::move(rows);
  }
  return entry;
}

nlohmann::json PosesJsonOf(const RenderJob& job, const std::vector<nlohmann::json>& per_camera) {
  nlohmann::json cameras = nlohmann::json::array();
  for (size_t c = 0; c < per_camera.size(); ++c) {
    const RigCamera& cam = job.rig.cameras[c];
    cameras.push_back({{"name", cam.name},
                       {"time_offset_s", cam.time_offset_s},
                       {"readout_s", cam.readout_s},
                       {"readout_direction", cam.readout_bottom_to_top ? "bottom-to-top" : "top-to-bottom"},
                       {"exposure_s", cam.exposure_s},
                       {"frames", per_camera[c]}});
  }
  return {{"description",
           "true cam_from_world of every camera at its capture time per frame (capture_time_s = timestamp_s + "
           "time_offset_s, the first row read out, mid exposure); with a rolling shutter 'rows' holds, for image rows "
           "0..height-1, [time_s, qw, qx, qy, qz, tx, ty, tz]: row r is captured at capture_time_s + k * readout_s / "
           "height, k = r (top-to-bottom) or height - 1 - r (bottom-to-top)"},
          {"cameras", cameras}};
}

// What a rendered view leaves for the ground truth across views.
struct ViewResult {
  ImageF range;
  ViewPose pose;
};

// Every camera's surface pixels and those visible in every other camera, over one frame. Without rolling shutters and correspondence maps, band by band (CountCoVisible);
// else from the correspondence maps, which give the same counts and are written when asked for.
FrameOverlapCounts FrameOverlap(const RenderJob& job, const std::vector<ViewResult>& views,
                                const std::vector<std::shared_ptr<const std::vector<Eigen::Vector3f>>>& bearings,
                                const DatasetLayout& layout, const std::string& frame) {
  const std::vector<RigCamera>& cams = job.rig.cameras;
  const int num_cams = int(cams.size());
  bool rolling = false;
  for (const ViewResult& v : views) rolling = rolling || v.pose.Rolling();
  std::vector<size_t> surface(num_cams, 0), visible(size_t(num_cams) * num_cams, 0);
  tbb::task_arena arena(job.options.num_threads > 0 ? job.options.num_threads : tbb::task_arena::automatic);
  if (rolling || job.extras.correspondence) {
    std::vector<std::pair<int, int>> pairs;
    for (int a = 0; a < num_cams; ++a) {
      for (int b = 0; b < num_cams; ++b) {
        if (a != b) pairs.push_back({a, b});
      }
    }
    std::vector<size_t> pair_surface(pairs.size());
    arena.execute([&] {
      tbb::parallel_for(size_t(0), pairs.size(), [&](size_t i) {
        const auto [a, b] = pairs[i];
        const CorrespondenceMap m = ComputeCorrespondence(cams[a].camera, views[a].range, views[a].pose, *bearings[a],
                                                          cams[b].camera, views[b].range, views[b].pose);
        pair_surface[i] = m.surface;  // the same for every b
        visible[size_t(a) * num_cams + b] = m.visible;
        if (job.extras.correspondence && m.visible > 0) {
          const fs::path path = layout.Correspondence(cams[a].name, cams[b].name, frame);
          fs::create_directories(path.parent_path());
          WriteImage(path, m.map);
        }
      });
    });
    for (size_t i = 0; i < pairs.size(); ++i) surface[pairs[i].first] = pair_surface[i];
  } else {
    // Each camera's surface pixels against every other camera, in bands of rows in parallel,
    // each into its own slot: a pixel's ray is undistorted once for all the other cameras.
    constexpr int kBandRows = 32;
    struct Band {
      int a, y_begin;
    };
    std::vector<Band> bands;
    for (int a = 0; a < num_cams; ++a) {
      for (int y = 0; y < views[a].range.height; y += kBandRows) bands.push_back({a, y});
    }
    std::vector<CoVisibleCounts> counts(bands.size());
    arena.execute([&] {
      tbb::parallel_for(size_t(0), bands.size(), [&](size_t i) {
        const int a = bands[i].a;
        std::vector<TransferTarget> targets;
        for (int b = 0; b < num_cams; ++b) {
          if (b != a) {
            targets.push_back({&cams[b].camera, &views[b].range, views[b].pose.Row(0) * views[a].pose.Row(0).Inverse()});
          }
        }
        counts[i] = CountCoVisible(cams[a].camera, views[a].range, targets, bands[i].y_begin, bands[i].y_begin + kBandRows,
                                   {}, bearings[a].get());
      });
    });
    for (size_t i = 0; i < bands.size(); ++i) {
      const int a = bands[i].a;
      surface[a] += counts[i].surface;
      for (int b = 0, t = 0; b < num_cams; ++b) {
        if (b != a) visible[size_t(a) * num_cams + b] += counts[i].visible[t++];
      }
    }
  }
  return {std::move(surface), std::move(visible)};
}

// flow/<cam>/<frame>.exr: each camera's pixels at the previous frame in its image of this one.
void WriteFlow(const RenderJob& job, const std::vector<ViewResult>& previous, const std::vector<ViewResult>& current,
               const std::vector<std::shared_ptr<const std::vector<Eigen::Vector3f>>>& bearings,
               const DatasetLayout& layout, const std::string& previous_frame) {
  const std::vector<RigCamera>& cams = job.rig.cameras;
  tbb::task_arena arena(job.options.num_threads > 0 ? job.options.num_threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(size_t(0), cams.size(), [&](size_t c) {
      const CorrespondenceMap m = ComputeCorrespondence(cams[c].camera, previous[c].range, previous[c].pose, *bearings[c],
                                                        cams[c].camera, current[c].range, current[c].pose);
      const fs::path path = layout.Flow(cams[c].name, previous_frame);
      fs::create_directories(path.parent_path());
      WriteImage(path, m.map);
    });
  });
}

// What the shards of one render share: the rig, the whole frames file and what changes the pixels.
std::string RenderIdentity(const RenderJob& job, const FramesFile& frames) {
  const RenderOptions& o = job.options;
  const nlohmann::json options{{"spp", o.samples_per_pixel},
                               {"seed", o.seed},
                               {"sun", {o.sun_direction_world.x(), o.sun_direction_world.y(), o.sun_direction_world.z()}},
                               {"sun_intensity", o.sun_intensity},
                               {"sky_intensity", o.sky_intensity},
                               {"exposure", o.exposure},
                               {"shadows", o.shadows},
                               {"photometric", job.photometric.enabled() ? PhotometryJson(job, {}) : nlohmann::json()},
                               {"extras", {job.extras.correspondence, job.extras.normals, job.extras.coco, job.extras.previews}}};
  // The sensor stages join only when on, so that the hash of a render without them stays the same.
  const std::string sensor = SensorStagesOn(job) ? SensorStagesJson(job).dump() : "";
  return StableHash(RigToJsonText(job.rig) + FramesToJsonText(frames) + options.dump() + sensor);
}

// rig.json and frames.json; a shard's frames.json lists its frames, and its shard.json what the
// merge needs of them.
void WriteRigAndFrames(const RenderJob& job, FrameRange range, std::vector<FrameOverlapCounts> overlap,
                       const DatasetLayout& layout) {
  WriteRig(job.rig, layout.RigJson());
  FramesFile frames = job.frames;
  frames.seed = job.options.seed;
  if (frames.scene.empty()) frames.scene = job.scene_name;
  if (job.shard.count > 1) {
    RenderShardInfo shard{job.shard.index, job.shard.count, RenderIdentity(job, frames), int(frames.frames.size()),
                          range.begin, std::move(overlap)};
    json_io::WriteTextAtomic(RenderShardJsonPath(layout.root()), RenderShardJson(shard).dump(1) + "\n");
    frames.frames = std::vector<Frame>(frames.frames.begin() + range.begin, frames.frames.begin() + range.end);
  }
  WriteFrames(frames, layout.FramesJson());
}

}  // namespace

void RenderDataset(const RenderJob& given, const fs::path& out_dir, bool force,
                   const std::function<void(int done, int total)>& progress) {
  CheckJob(given);
  // Everything is rendered, and its ground truth made, through each camera's render lens; rig.json
  // keeps the model beside it (WriteRigAndFrames below writes `given`).
  RenderJob job = given;
  job.rig = given.rig.AsRendered();
  const std::vector<RigCamera>& cams = job.rig.cameras;
  const int num_cams = int(cams.size());
  const FrameRange range = ShardFrames(int(job.frames.frames.size()), job.shard.index, job.shard.count);
  const int total = num_cams * (range.end - range.begin);
  const CapturePoses clock(job.rig.cameras, job.frames);  // before anything is built: repeated timestamps are refused

  // Built before the staging folder exists so that a bad scene leaves nothing behind.
  Renderer renderer(*job.scene);
  if (job.ego_vehicle != nullptr) renderer.SetAttached(*job.ego_vehicle);
  const bool animated = job.scene->IsAnimated();
  const bool photometric = job.photometric.enabled();
  const bool sensor_stages = SensorStagesOn(job);
  // A focus distance inside a camera's focal length is refused before anything is written.
  for (const RigCamera& cam : cams) BlurCircleDiameterPx(job.defocus, cam.camera.fx(), 0.0);
  // The thin lens focuses on a plane: each view's range goes along the optical axis by its pixels' rays.
  std::vector<std::shared_ptr<const PixelCentreRays>> defocus_rays;
  if (job.defocus.enabled()) {
    const PixelCentreRayCache rays;
    for (const RigCamera& cam : cams) defocus_rays.push_back(rays.For(cam.camera));
  }
  std::vector<CameraPhotometry> photometry;
  if (photometric) {
    for (int c = 0; c < num_cams; ++c) photometry.push_back(DrawCameraPhotometry(job.photometric, c));
  }
  RenderOptions options = job.options;
  options.normals = job.extras.normals;

  StagedOutput staged(OutputFolderRequest{out_dir, "", "rigsim render", {}, force});
  const DatasetLayout layout(staged.staging_dir());

  std::vector<FrameOverlapCounts> overlap;  // per frame rendered
  int done = 0;
  std::vector<SceneMesh> posed;  // the renderer's meshes while an animated scene is posed
  PosedSpan posed_span;          // or while it is posed over a camera's capture span
  // Each camera's pixel-centre rays, for the overlap: computed by the renderer, once per run.
  std::vector<std::shared_ptr<const std::vector<Eigen::Vector3f>>> bearings(num_cams);
  for (int c = 0; c < num_cams; ++c) bearings[c] = renderer.PixelCentreBearings(cams[c].camera);
  std::vector<nlohmann::json> poses_json(num_cams, nlohmann::json::array());
  CocoInstances coco;
  std::vector<ViewResult> previous;
  // A shard's flow from the frame before its first needs that frame's views, rendered unwritten.
  const int first = job.extras.correspondence && range.begin > 0 ? range.begin - 1 : range.begin;
  for (int frame_index = first; frame_index < range.end; ++frame_index) {
    const Frame& frame = job.frames.frames[frame_index];
    const bool written = frame_index >= range.begin;
    std::vector<ViewResult> views(num_cams);
    std::vector<CocoInstances> view_coco(job.extras.coco ? num_cams : 0);
    auto finish = [&](int c, RenderedView view) {
      if (written) {
        if (photometric || sensor_stages) {
          const ImageU8 invalid = InvalidPixels(view);
          SensorStages stages;
          stages.photometric = photometric;
          if (photometric) stages.photometry = photometry[c];
          stages.noise_key = PhotometricNoiseKey{job.photometric.seed, c, frame_index};
          stages.defocus = job.defocus;
          stages.jpeg_quality = job.jpeg_quality;
          ApplySensorStages(stages, cams[c].camera.fx(), cams[c].camera.cx(), cams[c].camera.cy(),
                            job.defocus.enabled() ? AxialDistance(*defocus_rays[c], view.range) : view.range, view.rgb,
                            &invalid, job.options.num_threads);
        }
        WriteView(layout, job.extras, cams[c].name, frame.name, view);
        if (job.extras.coco) view_coco[c].AddImage(cams[c].name + "/" + frame.name + ".png", view.label, view.instance);
        if (clock.timed()) poses_json[c].push_back(PosesEntry(cams[c], frame, views[c].pose));
      }
      views[c].range = std::move(view.range);
      if (!written) return;
      ++done;
      if (progress) progress(done, total);
    };
    // Cameras that capture at one instant grouped by their time: an animated scene is posed once
    // per distinct time; a static one is never re-posed. Cameras whose capture spans time each
    // get the scene posed over their span.
    std::map<double, std::vector<int>> cams_by_time;
    std::vector<int> spanning;
    for (int c = 0; c < num_cams; ++c) {
      if (cams[c].CaptureSpansTime()) {
        spanning.push_back(c);
      } else {
        cams_by_time[animated ? frame.timestamp_s + cams[c].time_offset_s : 0.0].push_back(c);
      }
    }
    for (const auto& [time, group] : cams_by_time) {
      if (animated) {
        posed = PoseMeshesAt(*job.scene, time);
        renderer.SetMeshes(posed);
      }
      for (int c : group) {
        views[c].pose = clock.Of(cams[c], frame);
        finish(c, renderer.Render(cams[c].camera, views[c].pose.Row(0), options, *cams[c].cam_from_rig));
      }
    }
    for (int c : spanning) {
      if (animated) {
        posed_span = PoseOverSpan(*job.scene, cams[c], frame, options.samples_per_pixel);
        renderer.SetMeshesOverTime(posed_span.steps, posed_span.begin, posed_span.end);
      }
      MovingCameraView moving{&cams[c], frame.timestamp_s,
                              [&, c](double t) { return clock.CamFromWorld(cams[c], frame, t); }};
      views[c].pose = clock.Of(cams[c], frame);
      finish(c, renderer.Render(moving, options));
    }
    if (!written) {
      previous = std::move(views);
      continue;
    }
    overlap.push_back(FrameOverlap(job, views, bearings, layout, frame.name));
    if (job.extras.correspondence && frame_index > 0) {
      WriteFlow(job, previous, views, bearings, layout, job.frames.frames[frame_index - 1].name);
    }
    if (job.extras.correspondence) previous = std::move(views);
    // COCO's images in frame and rig order, whatever order the cameras were rendered in.
    for (const CocoInstances& c : view_coco) coco.AddAll(c.ToJson());
  }

  std::vector<std::string> names;
  for (const RigCamera& cam : cams) names.push_back(cam.name);
  json_io::WriteTextAtomic(layout.OverlapJson(), OverlapJson(names, overlap).dump(2) + "\n");
  if (photometric) json_io::WriteTextAtomic(layout.PhotometricJson(), PhotometryJson(job, photometry).dump(2) + "\n");
  if (sensor_stages) json_io::WriteTextAtomic(layout.SensorJson(), SensorStagesJson(job).dump(2) + "\n");
  if (clock.timed()) json_io::WriteTextAtomic(layout.PosesJson(), PosesJsonOf(job, poses_json).dump() + "\n");
  if (job.extras.coco) json_io::WriteTextAtomic(layout.CocoJson(), coco.ToJson().dump() + "\n");

  WriteRigAndFrames(given, range, std::move(overlap), layout);

  staged.Commit();
}

}  // namespace rigsim
