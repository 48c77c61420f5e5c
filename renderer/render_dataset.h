// Renders a whole dataset: every camera of a rig at every frame, written in the layout of
// dataset/dataset.h together with the ground-truth overlap between cameras.
//
// cam_from_world = cam_from_rig * rig_from_world (geometry/rigid3.h). The output folder appears
// only when everything has been written (StagedOutput): an error or an interruption leaves the
// previous folder, or nothing.
//
// Time: each camera sees the scene at its own capture time, frame.timestamp_s + time_offset_s
// (rig.json). An animated scene (Scene::IsAnimated) is posed at every distinct capture time
// (scene/scene_pose.h), so unsynchronised cameras see moving objects in different places; a
// static scene builds its acceleration structure once. overlap.json compares the ranges each
// camera saw at its own time (moving objects count where each camera saw them).
//
// Photometric variation (RenderJob::photometric, off by default): each camera's RGB images get
// that camera's exposure, white balance, vignetting and sensor noise (renderer/photometric.h),
// drawn from the job's photometric seed and recorded in photometric.json. Labels, instances and
// depth are untouched; with the options off the output is byte-identical to a render without them
// and no photometric.json is written.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "renderer/photometric.h"
#include "renderer/renderer.h"
#include "scene/scene.h"

namespace rigsim {

struct RenderJob {
  const Scene* scene = nullptr;  // must outlive the call
  std::string scene_name;        // recorded in frames.json ("scene") when frames.scene is empty
  Rig rig;                       // every camera needs cam_from_rig
  FramesFile frames;             // every frame needs rig_from_world
  RenderOptions options;         // the seed is recorded in frames.json
  // Per-camera RGB differences; all zero (the default) = none. Its seed is its own (the CLI passes
  // --seed) and is recorded in photometric.json.
  PhotometricOptions photometric;
};

// Writes into out_dir:
//   rig.json, frames.json, images/ labels/ labels_color/ instances/ depth/ per camera and frame,
//   overlap.json: {"frames": F, "pairs": [{"a": "cam0", "b": "cam1", "overlap_a_in_b": 0.31,
//                  "overlap_b_in_a": 0.29}, ...]} for every unordered camera pair a < b (rig order);
//                  overlap_a_in_b is the fraction of a's surface pixels (range > 0) that are visible
//                  in b (dataset/ground_truth.h CountCoVisible), averaged over the frames.
//   photometric.json (only when job.photometric is enabled):
//                 {"seed": S, "options": {...PhotometricOptions fields}, "model": "...",
//                  "cameras": [{"name": "cam0", "exposure_stops": 0.1, "gain": 1.07,
//                               "white_balance_rgb": [1.02, 1, 0.97], "vignetting_strength": 0.3,
//                               "shot_noise": 1e-4, "read_noise_stddev": 0.002}, ...]} in rig order.
// Throws std::invalid_argument (before writing anything) when the job is incomplete, and
// std::runtime_error when out_dir exists and `force` is false or when writing fails; any
// exception, including one thrown by `progress`, leaves out_dir untouched.
// `progress(done, total)` is called after each rendered view (total = cameras x frames).
void RenderDataset(const RenderJob& job, const std::filesystem::path& out_dir, bool force,
                   const std::function<void(int done, int total)>& progress = {});

}  // namespace rigsim
