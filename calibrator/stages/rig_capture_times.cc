#include "calibrator/stages/rig_capture_times.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/format.h"

namespace rigsim {
namespace {

// With offsets estimated: a camera whose offset the rig's path cannot show (a frame interval's worth
// moves its view by less than min_interval_visibility_px) has an offset, and so a mounting, the images do not
// fix: it is not calibrated.
void TakePoseWhenThePathHidesTime(const RigObservations& obs, const CaptureTimeOptions& options,
                                  const MultiFrameBundleAdjustmentResult& ba, int c, RigCalibrationResult* result) {
  if (result->camera_status[c].outcome != CameraOutcome::kCalibrated &&
      result->camera_status[c].outcome != CameraOutcome::kRotationOnly) {
    return;
  }
  const double shown =
      IntervalVisibilityPx(ba.poses.rig_from_world, obs.frame_times_s, PixelsPerRadian(ba.cameras[c]), ba.median_depth);
  result->camera_stats[c].interval_visibility_px = shown;
  if (shown >= options.min_interval_visibility_px) return;
  result->camera_status[c] = {
      CameraOutcome::kTimeNotDetermined, PositionOutcome::kNotObservable,
      "its time offset is not determined: the rig's path moves alike at every frame (constant speed and turn "
      "rate), so a time offset looks like a different mounting (an offset of one frame interval changes its view "
      "by " + Fixed(shown, 2) + " px); to calibrate it: drive a path that changes speed or turn rate, or "
      "synchronise the cameras"};
  result->rig.cameras[c].cam_from_rig.reset();
  result->cam_from_rig_rotation[c].reset();
}

// Estimated offsets can stop at a kink of the cost (at zero each capture meets a frame), with a
// standard deviation that claims them: each is solved again from moved offsets
// (RestartFromMovedOffsets), and a camera whose offset goes elsewhere at a cost within min_sigmas,
// or fits clearly better there, is marked undetermined.
std::vector<CameraSynchronisation> RestartEstimatedOffsets(const RigObservations& obs, const CaptureTimeOptions& o,
                                                           const RigBundleAdjustmentOptions& bundle_adjustment,
                                                           const std::vector<ViewTrack>& tracks, int scale_camera,
                                                           const MultiFrameBundleAdjustmentResult& ba) {
  const int n = static_cast<int>(obs.cameras.size());
  std::vector<CameraSynchronisation> out(n);
  std::vector<int> estimated;
  CaptureTiming timing;
  timing.frame_times_s = obs.frame_times_s;
  timing.readout_bottom_to_top = obs.readout_bottom_to_top;
  timing.estimate_offsets = true;
  timing.estimate_readout = o.estimate_readout;
  for (int c = 0; c < n; ++c) {
    timing.time_offset_s.push_back(ba.timing[c][0]);
    timing.readout_s.push_back(ba.timing[c][1]);
    if (c > 0 && ba.poses.cam_from_rig[c] && ba.time_offset_stddev_s[c]) estimated.push_back(c);
  }
  const std::vector<std::optional<OffsetRestart>> restarts =
      RestartFromMovedOffsets(ba.cameras, obs.keypoints, tracks, ba, scale_camera, bundle_adjustment, timing, estimated, o);
  for (int c : estimated) {
    out[c].checked = true;
    if (!restarts[c]) continue;
    out[c].offset_alternative_s = restarts[c]->offset_s;
    out[c].offset_restart_sigmas = restarts[c]->sigmas;
    out[c].offset_undetermined = restarts[c]->sigmas < o.min_sigmas;
  }
  return out;
}

// An estimated offset that another start moves elsewhere, fitting as well or better: the images do
// not fix it, nor the mounting it trades with.
void TakePoseWhenAnotherStartMovesTheOffset(const RigObservations& obs, const std::vector<CameraSynchronisation>& checked,
                                            int c, RigCalibrationResult* result) {
  if (c >= static_cast<int>(checked.size()) || !checked[c].offset_undetermined) return;
  if (result->camera_status[c].outcome != CameraOutcome::kCalibrated &&
      result->camera_status[c].outcome != CameraOutcome::kRotationOnly) {
    return;
  }
  const double sigmas = *checked[c].offset_restart_sigmas;
  result->camera_stats[c].time_offset_undetermined = true;
  result->camera_stats[c].time_offset_also_fits_s = checked[c].offset_alternative_s;
  result->camera_stats[c].time_offset_stddev_s.reset();
  result->camera_status[c] = {
      CameraOutcome::kTimeNotDetermined, PositionOutcome::kNotObservable,
      "its time offset is not determined: solved from another start it ends at " +
          Fixed(1000.0 * *checked[c].offset_alternative_s, 0) + " ms, where the images fit " +
          (sigmas < 0 ? Fixed(-sigmas, 1) + " standard deviations better (the estimate stopped short of its best)"
                      : "about as well") +
          ", so neither its offset nor its mounting is known; to calibrate it: drive a path that changes speed or "
          "turn rate more, or synchronise the cameras"};
  result->rig.cameras[c].cam_from_rig.reset();
  result->cam_from_rig_rotation[c].reset();
}

}  // namespace

// Step 8: capture times. Estimated, each camera's offset and readout go into its stats and the
// rig; not estimated, the synchronisation check (run on the adjustment before it is scaled) takes
// the pose of every camera that did not capture with camera 0.
// The start of the warning that names the cameras whose capture time the path hides.
constexpr const char* kHiddenTimeWarning = "the rig's path cannot show whether ";

void DropHiddenTimeWarning(RigCalibrationResult* result) { DropWarnings(result, kHiddenTimeWarning); }

void PutHiddenTimeWarningLast(RigCalibrationResult* result) {
  std::stable_partition(result->warnings.begin(), result->warnings.end(),
                        [](const std::string& w) { return w.rfind(kHiddenTimeWarning, 0) != 0; });
}

void SetCaptureTimes(const RigObservations& obs, const CaptureTimeOptions& o,
                     const MultiFrameBundleAdjustmentResult& ba, const std::vector<CameraSynchronisation>& checked,
                     RigCalibrationResult* result) {
  const int n = static_cast<int>(obs.cameras.size());
  if (o.estimate_offsets || o.estimate_readout) {
    if (static_cast<int>(ba.timing.size()) != n) return;  // no bundle adjustment ran
    for (int c = 0; c < n; ++c) {
      if (!ba.poses.cam_from_rig[c]) continue;
      RigCameraStats& stats = result->camera_stats[c];
      RigCamera& camera = result->rig.cameras[c];
      camera.time_offset_s = ba.timing[c][0];
      camera.readout_s = ba.timing[c][1];
      camera.readout_bottom_to_top = !obs.readout_bottom_to_top.empty() && obs.readout_bottom_to_top[c];
      if (o.estimate_offsets) {
        stats.time_offset_s = ba.timing[c][0];
        stats.time_offset_stddev_s = c == 0 ? std::optional<double>(0.0) : ba.time_offset_stddev_s[c];
      }
      if (o.estimate_readout) {
        stats.readout_s = ba.timing[c][1];
        stats.readout_stddev_s = ba.readout_stddev_s[c];
      }
      if (c > 0 && o.estimate_offsets) {
        TakePoseWhenThePathHidesTime(obs, o, ba, c, result);
        TakePoseWhenAnotherStartMovesTheOffset(obs, checked, c, result);
      }
    }
    return;
  }
  std::vector<std::string> hidden;  // cameras whose offset the path cannot show
  for (int c = 1; c < n && c < static_cast<int>(checked.size()); ++c) {
    if (!checked[c].checked) continue;
    result->camera_stats[c].interval_visibility_px = checked[c].interval_visibility_px;
    if (checked[c].interval_visibility_px >= o.min_interval_visibility_px) {
      if (checked[c].offset_not_excluded_s && result->camera_status[c].outcome == CameraOutcome::kCalibrated) {
        result->camera_status[c] = {
            CameraOutcome::kCalibratedIfSynchronised, PositionOutcome::kPlaced,
            "the images put its capture " + Fixed(1000.0 * *checked[c].offset_s, 1) +
                PlusMinus(1000.0 * *checked[c].offset_stddev_s, 1) + " ms after " + obs.camera_names[0] +
                "'s, and do not exclude " + Fixed(1000.0 * *checked[c].offset_not_excluded_s, 0) +
                " ms, which the rig's path would show; so they cannot show whether it captured with it; a path "
                "that changes speed or turn rate more, or more frames, would show it"};
      } else if (checked[c].offset_undetermined && result->camera_status[c].outcome == CameraOutcome::kCalibrated) {
        result->camera_status[c] = {
            CameraOutcome::kCalibratedIfSynchronised, PositionOutcome::kPlaced,
            "the images fit it capturing " + Fixed(1000.0 * *checked[c].offset_alternative_s, 0) + " ms after " +
                obs.camera_names[0] + " about as well (" + Fixed(std::max(*checked[c].offset_restart_sigmas, 0.0), 1) +
                " standard deviations worse), so they cannot show whether it captured with it; a path that "
                "changes speed or turn rate more would show it"};
      }
      continue;
    }
    hidden.push_back(obs.camera_names[c]);
    if (result->camera_status[c].outcome != CameraOutcome::kCalibrated) continue;
    result->camera_status[c] = {
        CameraOutcome::kCalibratedIfSynchronised, PositionOutcome::kPlaced,
        "the rig's path cannot show whether it captured with " + obs.camera_names[0] +
            " (it moves alike at every frame: an offset of one frame interval changes its view by " +
            Fixed(checked[c].interval_visibility_px, 2) + " px); a path that changes speed or turn rate would show it"};
  }
  if (!hidden.empty()) {
    std::string names;
    for (const std::string& name : hidden) names += (names.empty() ? "" : ", ") + name;
    result->warnings.push_back(
        kHiddenTimeWarning + names + " captured together with " + obs.camera_names[0] +
        ": it moves alike at every frame (constant speed and turn rate), so a time offset would look like a "
        "different mounting; these poses hold only if the cameras are synchronised. A path that changes speed or "
        "turn rate would show it");
  }
  for (int c = 0; c < n && c < static_cast<int>(checked.size()); ++c) {
    const CameraSynchronisation& v = checked[c];
    if (!v.readout_s) continue;
    result->camera_stats[c].readout_s = v.readout_s;
    result->camera_stats[c].readout_stddev_s = v.readout_stddev_s;
    if (!v.rolling_shutter) continue;
    const std::string rows = "read out over " + Fixed(1000.0 * *v.readout_s, 1) +
                             PlusMinus(1000.0 * *v.readout_stddev_s, 1) + " ms (a rolling shutter) while the rig moves";
    const std::string fix = "--estimate-time-offsets --rolling-shutter, a global shutter, or moving slower";
    if (c == 0) {
      result->warnings.push_back(obs.camera_names[0] + "'s rows are " + rows +
                                 ": every pose here is taken as captured at one instant and may hold the rig's "
                                 "motion; to calibrate the rig: " + fix);
      continue;
    }
    if (result->camera_status[c].outcome == CameraOutcome::kNotConnected) continue;
    result->camera_status[c] = {CameraOutcome::kUnsynchronised, PositionOutcome::kNotObservable,
                                "its rows are " + rows + ", so a pose taken as captured at one instant would hold the "
                                "rig's motion; to calibrate it: " + fix};
    result->rig.cameras[c].cam_from_rig.reset();
    result->cam_from_rig_rotation[c].reset();
  }
  for (int c = 1; c < n && c < static_cast<int>(checked.size()); ++c) {
    const CameraSynchronisation& v = checked[c];
    if (!v.offset_s) continue;
    result->camera_stats[c].time_offset_s = v.offset_s;
    result->camera_stats[c].time_offset_undetermined = v.offset_undetermined;
    if (v.offset_undetermined) result->camera_stats[c].time_offset_also_fits_s = v.offset_alternative_s;
    if (!v.offset_undetermined) result->camera_stats[c].time_offset_stddev_s = v.offset_stddev_s;
    // A camera whose rolling shutter was found keeps that reason: its offset is then the readout's.
    const CameraOutcome outcome = result->camera_status[c].outcome;
    if (!v.unsynchronised || outcome == CameraOutcome::kNotConnected || outcome == CameraOutcome::kUnsynchronised) continue;
    const double ms = 1000.0 * *v.offset_s;
    result->camera_status[c] = {
        CameraOutcome::kUnsynchronised, PositionOutcome::kNotObservable,
        "it captures " + Fixed(std::abs(ms), 1) + (v.offset_stddev_s ? PlusMinus(1000.0 * *v.offset_stddev_s, 1) : "") +
            " ms " +
            (ms > 0 ? "after " : "before ") + obs.camera_names[0] +
            " while the rig moves, so a pose taken as synchronised would hold the rig's motion; to calibrate it: "
            "estimate the time offsets (--estimate-time-offsets; with --rolling-shutter where rows are read out "
            "over time), synchronise the cameras, or move slower"};
    result->rig.cameras[c].cam_from_rig.reset();
    result->cam_from_rig_rotation[c].reset();
  }
}

// The synchronisation check of a result taken as synchronised (CaptureTimeOptions); empty when it
// does not apply (offsets estimated, the check off, a static rig, frames without distinct times,
// no bundle adjustment).
std::vector<CameraSynchronisation> CheckCaptureTimes(const RigObservations& obs, const CaptureTimeOptions& o,
                                                     const RigBundleAdjustmentOptions& bundle_adjustment,
                                                     bool rig_moving, const std::vector<ViewTrack>& tracks,
                                                     int scale_camera, const MultiFrameBundleAdjustmentResult& ba) {
  const int n = static_cast<int>(obs.cameras.size());
  if (o.estimate_offsets && rig_moving && static_cast<int>(ba.timing.size()) == n && ba.num_points > 0) {
    return RestartEstimatedOffsets(obs, o, bundle_adjustment, tracks, scale_camera, ba);
  }
  if (o.estimate_offsets || o.estimate_readout || !o.check_synchronisation || !rig_moving) return {};
  if (WhyNoTimingModel(obs.frame_times_s) || ba.poses.cam_from_rig.empty() || ba.num_points == 0) return {};
  return CheckSynchronisation(ba.cameras, obs.keypoints, tracks, ba, scale_camera, bundle_adjustment,
                              obs.frame_times_s, StartTimeOffsets(n, obs.frame_times_s, obs.temporal, o.search),
                              obs.readout_bottom_to_top, o);
}

}  // namespace rigsim
