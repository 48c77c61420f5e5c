#include "calibrator/stages/registered_rig_adjustment.h"

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "calibrator/estimators/bundle_covariance.h"
#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/estimators/capture_time.h"
#include "calibrator/stages/rig_calibration.h"
#include "calibrator/stages/rig_capture_times.h"
#include "calibrator/stages/stage_clock.h"
#include "calibrator/stages/stated_deviations.h"
#include "common/format.h"

namespace rigsim {
namespace {

// The start: the placed rig's poses with the registered cameras' (registration.placed_poses is in
// `placed`'s unit).
RigPoses StartPoses(const TrackRegistration& registration) {
  RigPoses start = registration.placed_poses;
  for (const CameraRegistration& r : registration.cameras) {
    if (r.registered) start.cam_from_rig[r.camera] = r.cam_from_rig;
  }
  return start;
}

// The camera whose distance from camera 0 is held in the adjustment and is then the unit of
// length: `placed`'s unit camera where it has one, else a registered camera; -1 when no camera but
// camera 0 has a centre apart from it.
int UnitCamera(const RigCalibrationResult& placed, const RigPoses& start) {
  if (placed.unit_camera >= 0) return placed.unit_camera;
  for (int c = 1; c < static_cast<int>(start.cam_from_rig.size()); ++c) {
    if (start.cam_from_rig[c] && start.cam_from_rig[c]->translation.norm() > 1e-9) return c;
  }
  return -1;
}

// The capture times of the adjustment. Estimated where the rig stage estimated them (started from
// the placed rig's and, for a registered camera, from its own turns, as the rig stage starts them);
// otherwise the placed rig's, held (nullopt when every camera captures at its frame's timestamp, or
// the frames have none).
std::optional<CaptureTiming> TimingOf(const RigObservations& obs, const RigCalibrationResult& placed,
                                      const CaptureTimeOptions& options) {
  const int n = static_cast<int>(obs.cameras.size());
  if (obs.frame_times_s.size() != obs.keypoints.size() || WhyNoTimingModel(obs.frame_times_s)) return std::nullopt;
  const bool estimate = options.estimate_offsets || options.estimate_readout;
  const std::vector<double> own_start =
      options.estimate_offsets ? StartTimeOffsets(n, obs.frame_times_s, obs.temporal, options.search)
                               : std::vector<double>(n, 0.0);
  CaptureTiming timing;
  timing.frame_times_s = obs.frame_times_s;
  timing.readout_bottom_to_top = obs.readout_bottom_to_top;
  timing.estimate_offsets = options.estimate_offsets;
  timing.estimate_readout = options.estimate_readout;
  bool any = false;
  for (int c = 0; c < n; ++c) {
    const RigCamera& rc = placed.rig.cameras[c];
    const bool placed_camera = HasFullPose(placed.camera_status[c].outcome);
    timing.time_offset_s.push_back(placed_camera ? rc.time_offset_s : own_start[c]);
    timing.readout_s.push_back(placed_camera ? rc.readout_s : 0.0);
    any = any || timing.time_offset_s.back() != 0.0 || timing.readout_s.back() != 0.0;
  }
  if (!estimate && !any) return std::nullopt;
  return timing;
}

// What the adjustment makes of registered camera `c`: its status, and whether its pose is kept.
struct RegisteredOutcome {
  CameraStatus status;
  bool placed = false;
  bool rotated = false;
};

RegisteredOutcome JudgeRegistered(const RigObservations& obs, const CameraRegistration& r,
                                  const MultiFrameBundleAdjustmentResult& ba, const RigCalibrationOptions& options) {
  const int c = r.camera;
  RegisteredOutcome out;
  out.status = {CameraOutcome::kNotConnected, PositionOutcome::kNotObservable, ""};
  const auto& pose = ba.poses.cam_from_rig[c];
  const int kept = ba.observations_per_camera[c];
  if (!pose || kept < options.registration.resection.min_inliers) {
    out.status.reason = "the adjustment keeps only " + std::to_string(kept) + " of its observations";
    return out;
  }
  // The resection takes the camera as capturing at its frame's time: with offsets estimated, the
  // adjustment may turn it from there, by the rig's turn over its offset.
  const double turn = RotationDifferenceDeg(pose->rotation, r.cam_from_rig.rotation);
  if (turn > kMaxRegisteredRotationChangeDeg && !options.capture_time.estimate_offsets) {
    out.status.reason = "the adjustment turns it " + Fixed(turn, 2) + " deg from where its matches put it";
    return out;
  }
  out.rotated = true;
  const auto& cov = c < static_cast<int>(ba.centre_covariance.size()) ? ba.centre_covariance[c] : std::nullopt;
  const double std_deg = cov ? DirectionStdDeg(pose->SourceOriginInTarget(), *cov) : 180.0;
  // The bound is held against deviations that count every residual as independent, as the rig
  // stage holds it (rig_calibration.cc).
  const double bound_deg =
      cov ? *PlacementDirectionStdDeg(ba, c, pose->SourceOriginInTarget()) : std_deg / std::sqrt(ba.residual_correlation);
  if (bound_deg > options.max_direction_std_deg) {
    out.status = {CameraOutcome::kRotationOnly, PositionOutcome::kNotDetermined,
                  "the adjusted rig fixes its direction from " + obs.camera_names[0] + " to +-" + Fixed(std_deg, 1) +
                      " deg only" + (HasIntrinsicsShare(ba, c) ? " with the given intrinsics' uncertainty" : "")};
    return out;
  }
  out.placed = true;
  out.status = {CameraOutcome::kCalibrated, PositionOutcome::kPlaced, ""};
  return out;
}

// Per camera of the adjustment: the observations kept and the deviations (`spread` its jackknives'
// larger).
void SetStats(const MultiFrameBundleAdjustmentResult& ba, const JackknifeSpread& spread, int c, RigCameraStats* stats) {
  stats->observations = ba.observations_per_camera[c];
  const auto& pose = ba.poses.cam_from_rig[c];
  const auto jackknife = [c](const PerCamera<double>& std_deg) {
    return c < static_cast<int>(std_deg.size()) ? std_deg[c] : std::nullopt;
  };
  stats->direction_jackknife_std_deg.reset();
  if (c > 0 && pose && c < static_cast<int>(ba.centre_covariance.size()) && ba.centre_covariance[c]) {
    stats->direction_std_deg = DirectionStdDeg(pose->SourceOriginInTarget(), *ba.centre_covariance[c]);
    stats->direction_jackknife_std_deg = jackknife(spread.direction_std_deg);
  }
  if (c < static_cast<int>(ba.rotation_stddev_deg.size())) {
    stats->rotation_std_deg = ba.rotation_stddev_deg[c];
    stats->rotation_jackknife_std_deg = jackknife(spread.rotation_std_deg);
  }
  SetIntrinsicsShare(ba, c, stats);
}

// Sets the unit of length, as the rig stage does: |centre of `unit_camera`| = 1, then metres from
// the known distance when both its cameras are placed; returns the factor the lengths were scaled
// by.
double SetScale(const RigObservations& obs, const RigCalibrationOptions& options, int unit_camera,
                RigCalibrationResult* result) {
  PerCamera<Rigid3d> poses;
  for (const RigCamera& rc : result->rig.cameras) poses.push_back(rc.cam_from_rig);
  double factor = 1.0 / poses[unit_camera]->translation.norm();
  ScaleTranslations(factor, &poses, &result->rig_from_world);
  result->unit_camera = unit_camera;
  result->scale_kind = ScaleKind::kUnit;
  result->scale = "unit scale: |centre of " + obs.camera_names[unit_camera] + "| = 1";
  DropKnownDistanceWarning(result);  // the placed rig's; this one says its own
  if (options.known_distance) {
    const MetricScale metric = ScaleToKnownDistance(obs, *options.known_distance, &poses, &result->rig_from_world);
    if (metric.why_not.empty()) {
      factor *= metric.factor;
      result->scale_kind = ScaleKind::kMetric;
      result->scale = metric.scale;
    } else {
      result->warnings.push_back(metric.Warning());
    }
  }
  for (size_t c = 0; c < poses.size(); ++c) result->rig.cameras[c].cam_from_rig = poses[c];
  return factor;
}

}  // namespace

RegisteredRig AdjustRegisteredRig(const RigObservations& obs, const RigCalibrationResult& placed,
                                  const TrackRegistration& registration, const RigCalibrationOptions& options) {
  const int n = static_cast<int>(obs.cameras.size());
  const auto start_time = StageClock::now();
  const RigPoses start = StartPoses(registration);
  std::vector<char> in_rig(n, 0);
  for (int c = 0; c < n; ++c) in_rig[c] = start.cam_from_rig[c].has_value();
  const std::vector<ViewTrack> tracks = TracksOfCameras(obs, placed, in_rig);
  std::vector<Camera> cameras;
  for (int c = 0; c < n; ++c) cameras.push_back(placed.rig.cameras[c].camera);  // refined where they were

  RigBundleAdjustmentOptions ba_options = options.bundle_adjustment;
  if (ba_options.refine_intrinsics && ba_options.intrinsics_priors.centres.empty()) {
    ba_options.intrinsics_priors.centres = obs.cameras;
  }
  ba_options.keep_points = ba_options.keep_points || options.keep_details;
  const std::optional<CaptureTiming> timing =
      ba_options.refine_intrinsics || ba_options.given_intrinsics_sd ? std::nullopt
                                                                     : TimingOf(obs, placed, options.capture_time);
  const int unit_camera = UnitCamera(placed, start);
  const MultiFrameBundleAdjustmentResult ba =
      MultiFrameRigBundleAdjust(cameras, obs.keypoints, tracks, start, unit_camera, ba_options,
                                !placed.rig_motion_estimated, timing ? &*timing : nullptr);
  const double adjustment_s = SecondsSince(start_time);

  RegisteredRig out;
  RigCalibrationResult& result = out.result;
  result = placed;
  SetRefinedIntrinsics(obs, options, ba, &result);
  result.num_tracks = static_cast<int>(tracks.size());
  SetAdjustmentSummary(ba, &result);
  result.rig_from_world = ba.poses.rig_from_world;
  const JackknifeSpread spread = LargerSpread(ba.frame_jackknife, ba.point_jackknife);
  for (int c = 0; c < n; ++c) {
    if (!HasFullPose(placed.camera_status[c].outcome) || !ba.poses.cam_from_rig[c]) continue;
    result.rig.cameras[c].cam_from_rig = ba.poses.cam_from_rig[c];
    result.cam_from_rig_rotation[c] = ba.poses.cam_from_rig[c]->rotation;
    SetStats(ba, spread, c, &result.camera_stats[c]);
  }
  const std::string remedy = "to place it: more overlap with a placed camera, or more frames while the rig moves";
  for (const CameraRegistration& r : registration.cameras) {
    if (!r.registered) continue;
    const RegisteredOutcome judged = JudgeRegistered(obs, r, ba, options);
    CameraStatus& s = result.camera_status[r.camera];
    if (!judged.placed) out.not_placed.push_back(result.rig.cameras[r.camera].name + ": " + judged.status.reason);
    if (!judged.rotated || (!judged.placed && s.outcome == CameraOutcome::kRotationOnly)) continue;
    s = judged.status;
    if (!judged.placed) {
      s.reason = "registered through tracks (" + std::to_string(r.inliers) + " of its " +
                 std::to_string(r.correspondences) + " matches with placed points), but " + s.reason + "; " + remedy;
    }
    result.cam_from_rig_rotation[r.camera] = ba.poses.cam_from_rig[r.camera]->rotation;
    SetStats(ba, spread, r.camera, &result.camera_stats[r.camera]);
    if (judged.placed) {
      result.rig.cameras[r.camera].cam_from_rig = ba.poses.cam_from_rig[r.camera];
    } else {
      result.camera_stats[r.camera].direction_std_deg.reset();
      result.camera_stats[r.camera].direction_jackknife_std_deg.reset();
      result.camera_stats[r.camera].direction_intrinsics_std_deg.reset();
    }
  }
  // The capture times judged as the rig stage judges them: a registered camera that did not capture
  // with the reference, or whose capture time the path cannot show, is not placed as if it had.
  const auto check_start = StageClock::now();
  const std::vector<CameraSynchronisation> synchronisation = CheckCaptureTimes(
      obs, options.capture_time, ba_options, placed.rig_motion_estimated, tracks, unit_camera, ba);
  result.work.synchronisation_check_time_s += SecondsSince(check_start);
  DropHiddenTimeWarning(&result);
  SetCaptureTimes(obs, options.capture_time, ba, synchronisation, &result);
  for (const CameraRegistration& r : registration.cameras) {
    const CameraStatus& s = result.camera_status[r.camera];
    if (r.registered && (s.outcome == CameraOutcome::kUnsynchronised || s.outcome == CameraOutcome::kTimeNotDetermined)) {
      out.not_placed.push_back(result.rig.cameras[r.camera].name + ": " + s.reason);
    }
  }
  // The unit (and the metres of a known distance) as the rig stage sets them; where camera 0 was
  // the only one placed, the unit had been the reference camera's first step.
  int unit = unit_camera >= 0 && result.rig.cameras[unit_camera].cam_from_rig ? unit_camera : -1;
  for (int c = 1; c < n && unit < 0; ++c) {
    const auto& pose = result.rig.cameras[c].cam_from_rig;
    if (pose && pose->translation.norm() > 1e-12) unit = c;
  }
  const double length_scale = unit >= 0 ? SetScale(obs, options, unit, &result) : 1.0;
  if (options.keep_details) {
    result.details = std::make_shared<RigCalibrationDetails>(placed.details ? *placed.details : RigCalibrationDetails{});
    result.details->points.clear();
    for (const Eigen::Vector3d& x : ba.points) result.details->points.push_back(length_scale * x);
    result.details->point_observations = ba.point_observations;
    result.details->initial_residuals_px = ba.initial_residuals_px;
    result.details->final_residuals_px = ba.final_residuals_px;
  }
  result.work.bundle_adjustment_time_s += adjustment_s;
  return out;
}

}  // namespace rigsim
