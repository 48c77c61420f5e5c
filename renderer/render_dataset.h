// Renders a whole dataset: every camera of a rig at every frame, written in the layout of
// dataset/dataset.h together with the ground-truth overlap between cameras.
//
// cam_from_world = cam_from_rig * rig_from_world (geometry/rigid3.h). The output folder appears
// only when everything has been written (StagedOutput): an error or an interruption leaves the
// previous folder, or nothing.
//
// Time: each camera captures at its own time, frame.timestamp_s + time_offset_s (rig.json), row
// by row with a rolling shutter (readout_s), each row over its exposure (exposure_s). The rig is
// where the trajectory puts it at that time (dataset/capture_poses.h RigTrajectory: the frames'
// poses interpolated by their timestamps), and an animated scene (Scene::IsAnimated) is posed at
// that time (scene/scene_pose.h): at every distinct capture time of cameras that capture at one
// instant, and for a camera whose capture spans time at evenly spaced steps over the span, at most
// 5 ms apart and at most 9, between which Embree moves the vertices linearly. A static scene builds
// its acceleration structure once. overlap.json and the correspondence maps compare the ranges
// each camera saw at its own time (moving objects count where each camera saw them). With every
// time_offset_s, readout_s and exposure_s zero, nothing of this changes the output.
//
// Photometric variation (RenderJob::photometric, off by default): each camera's RGB images get
// that camera's exposure, white balance, vignetting and sensor noise (renderer/photometric.h),
// drawn from the job's photometric seed and recorded in photometric.json. Labels, instances and
// depth are untouched; with the options off the output is byte-identical to a render without them
// and no photometric.json is written. Defocus and JPEG (RenderJob::defocus, jpeg_quality) and the
// named sensor presets that set them with the photometric options: renderer/sensor_model.h.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "renderer/photometric.h"
#include "renderer/sensor_model.h"
#include "renderer/renderer.h"
#include "scene/scene.h"

namespace rigsim {

// Ground truth beyond labels, instances and depth, each off unless asked for (dataset layout in
// docs/datasets.md).
struct ExtraOutputs {
  // correspondence/<a>/<b>/<frame>.exr for every ordered camera pair of a frame where some pixel
  // of a is visible in b, and flow/<cam>/<frame>.exr from each frame to the next (same camera):
  // dataset/ground_truth.h ComputeCorrespondence, 3-channel float EXR (R, G, B = x, y, visible).
  bool correspondence = false;
  bool normals = false;   // normals/<cam>/<frame>.exr: camera-frame unit normals (R, G, B = x, y, z)
  bool coco = false;      // instances_coco.json (dataset/coco.h)
  bool previews = false;  // depth_color/ and instances_color/ PNGs
};

struct RenderJob {
  const Scene* scene = nullptr;  // must outlive the call
  // The rig's own vehicle, its meshes in the rig frame (procedural/ego_vehicle.h), attached to the
  // rig (Renderer::SetAttached): every view shows it where its camera sees it; nullptr = none.
  const Scene* ego_vehicle = nullptr;
  std::string scene_name;        // recorded in frames.json ("scene") when frames.scene is empty
  Rig rig;                       // every camera needs cam_from_rig
  FramesFile frames;             // every frame needs rig_from_world
  RenderOptions options;         // the seed is recorded in frames.json
  // Per-camera RGB differences; all zero (the default) = none. Its seed is its own (the CLI passes
  // --seed) and is recorded in photometric.json.
  PhotometricOptions photometric;
  // The lens's defocus and the camera's JPEG, after the photometric stage (renderer/sensor_model.h);
  // off by default. `sensor_preset` names the preset they and `photometric` came from (recorded in
  // sensor.json; "" or "ideal": none).
  DefocusOptions defocus;
  int jpeg_quality = 0;  // 0: no JPEG; 1..100: a JPEG round trip at that quality
  std::string sensor_preset;
  ExtraOutputs extras;
  // Shard `index` of `count` renders only its block of the frames (dataset/render_shards.h): its
  // folder holds those frames' files, frames.json and overlap.json over them, and shard.json,
  // from which MergeRenderShards writes the one-machine render's bytes. count 1: every frame.
  struct {
    int index = 0, count = 1;
  } shard;
};

// Writes into out_dir:
//   rig.json, frames.json, images/ labels/ labels_color/ instances/ depth/ per camera and frame,
//   overlap.json: {"frames": F, "pairs": [{"a": "cam0", "b": "cam1", "overlap_a_in_b": 0.31,
//                  "overlap_b_in_a": 0.29}, ...]} for every unordered camera pair a < b (rig order);
//                  overlap_a_in_b is the fraction of a's surface pixels (range > 0) that are visible
//                  in b (dataset/ground_truth.h CountCoVisible), averaged over the frames.
//   poses.json (only when some camera has a time offset, rolling shutter or exposure): per camera
//                 and frame the true pose at its capture time, and per image row with a rolling
//                 shutter (format in docs/datasets.md).
//   the ExtraOutputs asked for.
//   photometric.json (only when job.photometric is enabled):
//                 {"seed": S, "options": {...PhotometricOptions fields}, "model": "...",
//                  "cameras": [{"name": "cam0", "exposure_stops": 0.1, "gain": 1.07,
//                               "white_balance_rgb": [1.02, 1, 0.97], "vignetting_strength": 0.3,
//                               "shot_noise": 1e-4, "read_noise_stddev": 0.002}, ...]} in rig order.
//   sensor.json (only with a sensor preset other than ideal, defocus or JPEG):
//                 {"preset": "automotive", "stages": [...in order...], "defocus": {...DefocusOptions
//                  fields}, "jpeg_quality": 75}
// Throws std::invalid_argument (before writing anything) when the job is incomplete, and
// std::runtime_error when out_dir exists and `force` is false or when writing fails; any
// exception, including one thrown by `progress`, leaves out_dir untouched.
// `progress(done, total)` is called after each rendered view (total = cameras x frames).
void RenderDataset(const RenderJob& job, const std::filesystem::path& out_dir, bool force,
                   const std::function<void(int done, int total)>& progress = {});

}  // namespace rigsim
