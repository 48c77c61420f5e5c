// An estimate of a rig's extrinsics as any tool gives it, read into one form so that every tool
// is scored by the same code (evaluation/rig_scores.h):
//   - a rig.json (rigsim's format: cameras with cam_from_rig, cameras without one unplaced);
//   - a calibration folder written by `rigsim calibrate` (evaluation.json and <mode>/rig.json):
//     one estimate per semantic mode, "rotation only" cameras with their rotation, cameras "placed
//     but for one axis" with their rotation, open axis and centre across it;
//   - a COLMAP text model (a folder with images.txt, or the mapper's sparse/ with sub-models, of
//     which the one with the most images is read) of the dataset's photos, named <cam>/<frame>.*
//     as `rigsim export --format colmap` and COLMAP on DATASET/images name them: each camera's
//     cam_from_rig is cam_from_world of its image times cam0's inverse, averaged over the frames
//     where both are registered;
//   - a Kalibr camchain.yaml (cameras by rostopic /<name>/image_raw, else in order).
// Cameras are matched to the truth by name.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "geometry/rigid3.h"

namespace rigsim {

// The part of a camera's centre that a motion about one axis fixes (rigsim's "placed but for one
// axis"), in the estimate's rig frame and unit of length: the axis along which the centre is open
// (unit), and the centre without its component along that axis.
struct OpenAxisCentre {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();
  Eigen::Vector3d centre_across_axis = Eigen::Vector3d::Zero();
};

// What a tool estimated: per camera of the truth (same order), a full pose, a rotation only (with,
// for a camera placed but for one axis, its centre across the axis), or nothing.
struct RigEstimate {
  std::string method;  // "none", "mask", ... (a calibration's modes), "colmap", "kalibr", "rig.json"
  std::vector<std::optional<Rigid3d>> cam_from_rig;
  std::vector<std::optional<Eigen::Quaterniond>> rotation_only;  // cameras with a rotation and no full pose
  // Of a camera with rotation_only: the part of its centre the estimate fixes, when it fixes all but
  // one axis.
  std::vector<std::optional<OpenAxisCentre>> open_axis;
  // Of a camera with a full pose: 1 when the pose holds only if the camera captured with camera 0
  // (rigsim's "calibrated if synchronised": the rig's path cannot show a time offset).
  std::vector<char> if_synchronised;
  // The standard deviations the tool states for a camera's rotation and for the direction of its
  // centre from camera 0's (deg); nullopt where it states none (every peer).
  std::vector<std::optional<double>> rotation_std_deg, direction_std_deg;
  bool metric = false;  // translations in metres (position errors without a scale fit)
  std::vector<std::string> notes;  // what the reader could not use, e.g. images not registered
  // What the tool reported besides the poses (a calibration's timing and match statistics), as it
  // reported it; null when nothing.
  nlohmann::json details;
};

// How to treat the estimate's scale: as the estimate says (a calibration folder knows, and so do
// the rig.json and camchain.yaml of rigsim's estimates; COLMAP never is metric; any other Kalibr
// camchain is; any other rig.json is taken as unit scale), or forced.
enum class EstimateScale { kAuto, kMetric, kFit };

// Reads ESTIMATE for the cameras of `truth` (names) and the frames of the dataset (COLMAP).
// Throws std::runtime_error naming the file and what is wrong (an unknown camera name with a
// suggestion, an unrecognised file); with `skip_unknown_cameras`, a camera the truth does not have
// is left out instead (a truth of only the cameras both sides have: ReadEstimateCameras).
std::vector<RigEstimate> ReadRigEstimates(const std::filesystem::path& estimate, const Rig& truth,
                                          const FramesFile& frames, EstimateScale scale = EstimateScale::kAuto,
                                          bool skip_unknown_cameras = false);

// The cameras an estimate names, for matching it with a truth that is not a dataset's (`rigsim
// evaluate ESTIMATE --truth RIG`): a calibration folder's (its first mode's rig.json), a rig.json's,
// a Kalibr camchain's rostopic names (none when a camera has none: matched in order), a COLMAP
// model's image prefixes (<camera>/<frame>.*, in the order first seen), with the model's frames.
struct EstimateCameras {
  std::vector<std::string> names;  // in the estimate's order
  bool named = true;               // false: a camchain without rostopics
  bool ordered = true;             // false: a COLMAP model (no reference camera; its order is the images')
  FramesFile colmap_frames;        // a COLMAP model's frames (the images' stems), sorted by name
};
// Throws std::runtime_error as ReadRigEstimates.
EstimateCameras ReadEstimateCameras(const std::filesystem::path& estimate);

// COLMAP images (name -> cam_from_world) as a rig: see the header comment. Images whose name is
// not <camera>/<frame>.<ext> of the truth's cameras and the frames are named in the notes.
RigEstimate RigEstimateFromColmap(const std::vector<std::pair<std::string, Rigid3d>>& images, const Rig& truth,
                                  const FramesFile& frames);

}  // namespace rigsim
