#include "calibrator/stages/rig_options.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rigsim {

std::pair<int, int> KnownDistanceCameras(const KnownDistance& known, const std::vector<std::string>& names,
                                         const std::string& where) {
  auto index = [&](const std::string& name) {
    for (size_t c = 0; c < names.size(); ++c) {
      if (names[c] == name) return int(c);
    }
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    throw std::invalid_argument(where + ": the known distance names camera '" + name + "', which is not in the rig (" +
                                list + ")");
  };
  return {index(known.cam_a), index(known.cam_b)};
}

void MotionLinkOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("MotionLinkOptions: " + why); };
  if (min_frames < 3) fail("min_frames must be >= 3");
  hand_eye.Check();
  rig_turns.Check();
  candidates.Check();
  rotation_averaging.Check();
  if (!(max_prediction_disagreement_deg > 0)) fail("max_prediction_disagreement_deg must be > 0");
  if (!(max_hand_eye_disagreement_deg > 0)) fail("max_hand_eye_disagreement_deg must be > 0");
  if (!(max_prediction_check_deg > 0)) fail("max_prediction_check_deg must be > 0");
  if (min_prediction_contradictions < 1) fail("min_prediction_contradictions must be >= 1");
  if (!(max_inter_camera_weight >= 1)) fail("max_inter_camera_weight must be >= 1");
}

void TrackRegistrationOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("TrackRegistrationOptions: " + why); };
  if (frame_reach < 0) fail("frame_reach must be >= 0");
  if (max_view_pairs_per_camera < 1) fail("max_view_pairs_per_camera must be >= 1");
  if (!(min_triangulation_angle_deg >= 0)) fail("min_triangulation_angle_deg must be >= 0");
  if (!(max_track_error_px > 0)) fail("max_track_error_px must be > 0");
  if (!(max_rotation_disagreement_deg > 0)) fail("max_rotation_disagreement_deg must be > 0");
  if (min_view_pair_inliers < 1) fail("min_view_pair_inliers must be >= 1");
  resection.Check();
}

void RigCalibrationOptions::Check() const {
  pairwise.Check();
  capture_time.Check();
  motion.Check();
  registration.Check();
  if ((capture_time.estimate_offsets || capture_time.estimate_readout) && bundle_adjustment.refine_intrinsics) {
    throw std::invalid_argument("RigCalibrationOptions: capture times are not estimated together with refined intrinsics");
  }
  if ((capture_time.estimate_offsets || capture_time.estimate_readout) && bundle_adjustment.given_intrinsics_sd) {
    throw std::invalid_argument(
        "RigCalibrationOptions: capture times are not estimated together with the given intrinsics' deviations");
  }
  view_graph.Check();
  rotation_averaging.Check();
  bundle_adjustment.Check();
  if (known_distance) {
    if (known_distance->cam_a == known_distance->cam_b) {
      throw std::invalid_argument("RigCalibrationOptions: known_distance needs two different cameras");
    }
    if (!(known_distance->metres > 0) || !std::isfinite(known_distance->metres)) {
      throw std::invalid_argument("RigCalibrationOptions: known_distance.metres must be > 0");
    }
  }
  auto fail = [](const std::string& why) { throw std::invalid_argument("RigCalibrationOptions: " + why); };
  if (!(max_direction_std_deg > 0)) fail("max_direction_std_deg must be > 0");
  if (!(max_start_disagreement_deg > 0)) fail("max_start_disagreement_deg must be > 0");
  if (!(max_rival_rotation_deg > 0)) fail("max_rival_rotation_deg must be > 0");
  if (!(min_start_cost_ratio >= 1)) fail("min_start_cost_ratio must be >= 1");
  if (!(max_pair_rotation_disagreement_deg > 0)) fail("max_pair_rotation_disagreement_deg must be > 0");
  if (!(max_pair_direction_disagreement_deg > 0)) fail("max_pair_direction_disagreement_deg must be > 0");
  if (max_rejected_pairs < 0) fail("max_rejected_pairs must be >= 0");
  if (!(max_direction_only_disagreement_deg >= 0)) fail("max_direction_only_disagreement_deg must be >= 0");
}

}  // namespace rigsim
