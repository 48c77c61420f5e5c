#include "calibrator/estimators/capture_time.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <utility>

#include <Eigen/Geometry>
#include <tbb/parallel_invoke.h>

#include "calibrator/model/rig_state.h"
#include "geometry/pose_interpolation.h"

namespace rigsim {

void CaptureTimeOptions::Check() const {
  if (!(min_offset_s >= 0) || !std::isfinite(min_offset_s)) throw std::invalid_argument("min_offset_s must be >= 0");
  if (!(min_sigmas > 0)) throw std::invalid_argument("min_sigmas must be > 0");
  if (!(min_visible_px >= 0) || !std::isfinite(min_visible_px)) throw std::invalid_argument("min_visible_px must be >= 0");
  if (!(min_interval_visibility_px >= 0) || !std::isfinite(min_interval_visibility_px)) {
    throw std::invalid_argument("min_interval_visibility_px must be >= 0");
  }
  if (check_max_tracks < 0) throw std::invalid_argument("check_max_tracks must be >= 0");
  if (!(min_readout_s >= 0) || !std::isfinite(min_readout_s)) throw std::invalid_argument("min_readout_s must be >= 0");
  if (readout_max_tracks < 0) throw std::invalid_argument("readout_max_tracks must be >= 0");
  search.Check();
}

std::optional<std::string> WhyNoTimingModel(const std::vector<double>& frame_times_s) {
  if (frame_times_s.size() < 3) return "capture times need at least three frames of a moving rig";
  std::set<double> distinct;
  for (double t : frame_times_s) {
    if (!std::isfinite(t)) return "a frame's timestamp is not finite";
    distinct.insert(t);
  }
  if (distinct.size() != frame_times_s.size()) return "two frames share a timestamp (frames.json timestamp_s)";
  return std::nullopt;
}

double MedianFrameInterval(std::vector<double> frame_times_s) {
  std::sort(frame_times_s.begin(), frame_times_s.end());
  std::vector<double> steps;
  for (size_t k = 1; k < frame_times_s.size(); ++k) steps.push_back(frame_times_s[k] - frame_times_s[k - 1]);
  if (steps.empty()) return 0.0;
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  return steps[steps.size() / 2];
}

std::vector<double> StartTimeOffsets(int num_cameras, const std::vector<double>& frame_times_s,
                                     const std::vector<TemporalPairEstimate>& temporal,
                                     const TimeOffsetSearchOptions& options) {
  std::vector<double> out(num_cameras, 0.0);
  const int frames = static_cast<int>(frame_times_s.size());
  if (frames < 2 || num_cameras < 2) return out;
  std::vector<PerFrame<double>> turn(num_cameras, PerFrame<double>(frames - 1));
  for (const TemporalPairEstimate& t : temporal) {
    if (!t.PoseUsable() || t.camera < 0 || t.camera >= num_cameras || t.frame < 0 || t.frame + 1 >= frames) continue;
    turn[t.camera][t.frame] = Eigen::AngleAxisd(t.two_view.cam_b_from_cam_a.rotation).angle();
  }
  const std::vector<SearchedOffset> found = SearchTimeOffsets(frame_times_s, turn, options);
  for (int c = 1; c < num_cameras; ++c) {
    if (found[c].determined) out[c] = found[c].offset_s;
  }
  return out;
}

namespace {

// Per frame whose capture at `offset_s` falls within the path's frames, D = rig(t + o)_from_rig(t),
// and their mean; empty with fewer than two such frames or
// three posed ones.
struct RigChanges {
  std::vector<Rigid3d> per_frame;
  Rigid3d mean;
};
RigChanges ChangesOverOffset(const PerFrame<Rigid3d>& rig_from_world,
                             const std::vector<double>& frame_times_s, double offset_s) {
  std::vector<TimedPose> path;
  for (size_t k = 0; k < rig_from_world.size() && k < frame_times_s.size(); ++k) {
    if (rig_from_world[k]) path.push_back({frame_times_s[k], *rig_from_world[k]});
  }
  RigChanges out;
  if (path.size() < 3) return out;
  path = SortedByTime(std::move(path));
  for (const TimedPose& p : path) {
    // Beyond the first and last frames the path goes on straight, which a rig that turns does not:
    // the images of those captures say more about that model than about time.
    const double t = p.time_s + offset_s;
    if (t < path.front().time_s || t > path.back().time_s) continue;
    out.per_frame.push_back(RigFromWorldOnPath(path, t) * p.rig_from_world.Inverse());
  }
  if (out.per_frame.size() < 2) {
    out.per_frame.clear();
    return out;
  }
  out.mean = MeanOfNearbyPoses(out.per_frame);
  return out;
}

// A change of the rig as the image motion it causes in a camera of `pixels_per_radian` looking at
// the scene at `scene_depth`.
double ImageMotionPx(const Rigid3d& change, double pixels_per_radian, double scene_depth) {
  return pixels_per_radian * (Eigen::AngleAxisd(change.rotation).angle() + change.translation.norm() / scene_depth);
}

// An even subsample of at most `max_tracks` tracks (0: all of them).
std::vector<ViewTrack> EvenSubsample(const std::vector<ViewTrack>& tracks, int max_tracks) {
  const size_t stride = max_tracks > 0 ? std::max<size_t>((tracks.size() + max_tracks - 1) / max_tracks, 1) : 1;
  std::vector<ViewTrack> out;
  for (size_t i = 0; i < tracks.size(); i += stride) out.push_back(tracks[i]);
  return out;
}

}  // namespace

double OffsetVisibilityPx(const PerFrame<Rigid3d>& rig_from_world,
                          const std::vector<double>& frame_times_s, double offset_s, double pixels_per_radian,
                          double scene_depth) {
  if (!(scene_depth > 0)) return 0.0;
  const RigChanges changes = ChangesOverOffset(rig_from_world, frame_times_s, offset_s);
  double worst = 0.0;
  for (const Rigid3d& d : changes.per_frame) {
    worst = std::max(worst, ImageMotionPx(d * changes.mean.Inverse(), pixels_per_radian, scene_depth));
  }
  return worst;
}

std::optional<Rigid3d> MeanRigChange(const PerFrame<Rigid3d>& rig_from_world,
                                     const std::vector<double>& frame_times_s, double offset_s) {
  const RigChanges changes = ChangesOverOffset(rig_from_world, frame_times_s, offset_s);
  if (changes.per_frame.empty()) return std::nullopt;
  return changes.mean;
}

double ReadoutVisibilityPx(const PerFrame<Rigid3d>& rig_from_world,
                           const std::vector<double>& frame_times_s, double readout_s, double pixels_per_radian,
                           double scene_depth) {
  if (!(scene_depth > 0)) return 0.0;
  const std::optional<Rigid3d> during = MeanRigChange(rig_from_world, frame_times_s, std::abs(readout_s));
  return during ? ImageMotionPx(*during, pixels_per_radian, scene_depth) : 0.0;
}

double IntervalVisibilityPx(const PerFrame<Rigid3d>& rig_from_world,
                            const std::vector<double>& frame_times_s, double pixels_per_radian, double scene_depth) {
  return OffsetVisibilityPx(rig_from_world, frame_times_s, MedianFrameInterval(frame_times_s), pixels_per_radian,
                            scene_depth);
}

double PixelsPerRadian(const Camera& camera) {
  const Eigen::Vector2d centre(0.5 * (camera.width() - 1), 0.5 * (camera.height() - 1));
  const auto left = camera.CamFromImg(centre - Eigen::Vector2d(0.5, 0.0));
  const auto right = camera.CamFromImg(centre + Eigen::Vector2d(0.5, 0.0));
  if (!left || !right) return 0.0;
  const double angle = std::atan2(left->cross(*right).norm(), left->dot(*right));
  return angle > 0 ? 1.0 / angle : 0.0;
}

namespace {

// A solve's cost with each filtered observation counted at the filter's threshold: two solves of
// the same tracks compare by it, whatever each filtered.
double TruncatedCost(const MultiFrameBundleAdjustmentResult& r, double max_error_px) {
  return r.num_observations * r.reprojection_rms_px * r.reprojection_rms_px +
         r.num_filtered_observations * max_error_px * max_error_px;
}

// A freed offset or readout the images show: beyond `min_value_s`, beyond options.min_sigmas of its
// standard deviation, and moving the view by options.min_visible_px or more on the rig's path.
bool FoundInTheImages(double value_s, double stddev_s, double visibility_px, double min_value_s,
                      const CaptureTimeOptions& options) {
  const double magnitude = std::abs(value_s);
  return magnitude > min_value_s && magnitude > options.min_sigmas * stddev_s && visibility_px >= options.min_visible_px;
}

// `best`'s solve started again with the offsets of `moved` cameras moved by `step_s`, every
// offset free. Each moved camera's mounting starts turned by the rig's mean motion over the step,
// so that on a path moving alike at every frame the start lies in the valley the step moves along.
template <typename Solve>
MultiFrameBundleAdjustmentResult SolveFromMovedOffsets(const MultiFrameBundleAdjustmentResult& best,
                                                       const std::vector<int>& moved, double step_s,
                                                       const std::vector<double>& frame_times_s, CaptureTiming timing,
                                                       const Solve& solve) {
  for (size_t k = 0; k < timing.time_offset_s.size() && k < best.timing.size(); ++k) timing.time_offset_s[k] = best.timing[k][0];
  RigPoses start = best.poses;
  const std::optional<Rigid3d> d = MeanRigChange(best.poses.rig_from_world, frame_times_s, step_s);
  for (int c : moved) {
    timing.time_offset_s[c] += step_s;
    if (d && start.cam_from_rig[c]) start.cam_from_rig[c] = *start.cam_from_rig[c] * d->Inverse();
  }
  return solve(start, timing);
}

// A frame whose pose camera 0's own observations fix: it sees at least this many of the tracks
// there.
constexpr int kMinOwnObservationsPerFrame = 20;

}  // namespace

std::optional<ReferencePath> ReferenceCameraPath(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                                 const std::vector<ViewTrack>& tracks, const RigPoses& adjusted,
                                                 RigBundleAdjustmentOptions ba_options, int max_tracks) {
  if (adjusted.cam_from_rig.empty() || !adjusted.cam_from_rig[0] || adjusted.rig_from_world.empty()) return std::nullopt;
  std::vector<ViewTrack> own;
  for (const ViewTrack& track : tracks) {
    ViewTrack seen;
    for (const ViewObservation& o : track.observations) {
      if (o.camera == 0) seen.observations.push_back(o);
    }
    if (seen.observations.size() >= 2) own.push_back(std::move(seen));
  }
  own = EvenSubsample(own, max_tracks);
  std::vector<int> seen_per_frame(adjusted.rig_from_world.size(), 0);
  for (const ViewTrack& track : own) {
    for (const ViewObservation& o : track.observations) {
      if (o.frame >= 0 && o.frame < static_cast<int>(seen_per_frame.size())) ++seen_per_frame[o.frame];
    }
  }
  RigPoses start = adjusted;
  for (size_t c = 1; c < start.cam_from_rig.size(); ++c) start.cam_from_rig[c].reset();
  ba_options.refine_intrinsics = false;
  ba_options.given_intrinsics_sd.reset();
  ba_options.keep_points = false;
  ba_options.covariance = false;  // only the path's shape is read
  ba_options.held_centre_axis.clear();
  const MultiFrameBundleAdjustmentResult solved =
      MultiFrameRigBundleAdjust(cameras, keypoints, own, start, /*scale_camera=*/-1, ba_options);
  if (solved.num_points == 0 || !(solved.median_depth > 0)) return std::nullopt;
  // A frame camera 0 barely sees keeps the pose it started from, which the other cameras gave it.
  ReferencePath out{solved.poses.rig_from_world, solved.median_depth};
  int posed = 0;
  for (size_t k = 0; k < out.rig_from_world.size(); ++k) {
    if (seen_per_frame[k] < kMinOwnObservationsPerFrame) out.rig_from_world[k].reset();
    posed += out.rig_from_world[k].has_value();
  }
  if (posed < 3) return std::nullopt;
  return out;
}

std::vector<std::optional<OffsetRestart>> RestartFromMovedOffsets(
    const std::vector<Camera>& cameras, const FrameKeypoints& keypoints, const std::vector<ViewTrack>& tracks,
    const MultiFrameBundleAdjustmentResult& solved, int scale_camera, RigBundleAdjustmentOptions ba_options,
    const CaptureTiming& timing, const std::vector<int>& restarted, const CaptureTimeOptions& options) {
  std::vector<std::optional<OffsetRestart>> out(cameras.size());
  if (restarted.empty() || options.restart_max_tracks < 0 || solved.timing.size() != cameras.size()) return out;
  const std::vector<ViewTrack> few = EvenSubsample(tracks, options.restart_max_tracks);
  ba_options.refine_intrinsics = false;
  ba_options.given_intrinsics_sd.reset();
  ba_options.keep_points = false;
  ba_options.covariance = false;  // the restarts compare costs only
  auto solve = [&](const RigPoses& poses, const CaptureTiming& start) {
    return MultiFrameRigBundleAdjust(solved.cameras, keypoints, few, poses, scale_camera, ba_options, false, &start);
  };
  const double max_error_px = ba_options.max_reprojection_error_px;
  const MultiFrameBundleAdjustmentResult reference = SolveFromMovedOffsets(solved, {}, 0.0, timing.frame_times_s, timing, solve);
  const double variance = 0.5 * reference.reprojection_rms_px * reference.reprojection_rms_px;  // per coordinate
  if (!(variance > 0) || reference.timing.size() != cameras.size()) return out;
  const double quarter = 0.25 * MedianFrameInterval(timing.frame_times_s);
  for (double step : {quarter, -quarter, 2 * quarter, -2 * quarter}) {
    std::vector<int> open;  // cameras not yet found to fit elsewhere as well
    for (int c : restarted) {
      if (!out[c] || out[c]->sigmas >= options.min_sigmas) open.push_back(c);
    }
    if (open.empty()) break;
    const MultiFrameBundleAdjustmentResult moved = SolveFromMovedOffsets(reference, open, step, timing.frame_times_s, timing, solve);
    if (moved.num_observations == 0 || moved.timing.size() != reference.timing.size()) continue;
    const double change = (TruncatedCost(moved, max_error_px) - TruncatedCost(reference, max_error_px)) / variance;
    const double sigmas = std::copysign(std::sqrt(std::abs(change)), change);
    for (int c : open) {
      if (std::abs(moved.timing[c][0] - reference.timing[c][0]) < 0.5 * quarter) continue;  // back where it was
      if (!out[c] || sigmas < out[c]->sigmas) out[c] = OffsetRestart{moved.timing[c][0], sigmas};
    }
  }
  return out;
}

std::vector<CameraSynchronisation> CheckSynchronisation(
    const std::vector<Camera>& cameras, const FrameKeypoints& keypoints, const std::vector<ViewTrack>& tracks,
    const MultiFrameBundleAdjustmentResult& adjusted, int scale_camera, RigBundleAdjustmentOptions ba_options,
    const std::vector<double>& frame_times_s, const std::vector<double>& start_offsets_s,
    const std::vector<char>& readout_bottom_to_top, const CaptureTimeOptions& options) {
  const int n = static_cast<int>(cameras.size());
  std::vector<CameraSynchronisation> out(n);
  const auto shows_time = [&](const CameraSynchronisation& s) {
    return s.checked && s.interval_visibility_px >= options.min_interval_visibility_px;
  };
  for (int c = 1; c < n && c < static_cast<int>(adjusted.poses.cam_from_rig.size()); ++c) {
    if (!adjusted.poses.cam_from_rig[c]) continue;
    out[c].checked = true;
    out[c].interval_visibility_px = IntervalVisibilityPx(adjusted.poses.rig_from_world, frame_times_s,
                                                         PixelsPerRadian(adjusted.cameras[c]), adjusted.median_depth);
  }
  if (std::none_of(out.begin(), out.end(), shows_time)) return out;
  // Taken as synchronised, the adjustment can bend the path to fit cameras that captured at other
  // times, and a bent path seems to show time: it shows only where camera 0's own motion shows it too.
  if (const std::optional<ReferencePath> own =
          ReferenceCameraPath(cameras, keypoints, tracks, adjusted.poses, ba_options, options.check_max_tracks)) {
    for (int c = 1; c < n; ++c) {
      if (!shows_time(out[c])) continue;
      out[c].interval_visibility_px =
          std::min(out[c].interval_visibility_px, IntervalVisibilityPx(own->rig_from_world, frame_times_s,
                                                                       PixelsPerRadian(adjusted.cameras[c]),
                                                                       own->median_depth));
    }
  }
  if (std::none_of(out.begin(), out.end(), shows_time)) return out;
  CaptureTiming timing;
  timing.frame_times_s = frame_times_s;
  timing.time_offset_s = start_offsets_s;
  timing.readout_s.assign(n, 0.0);
  timing.readout_bottom_to_top = readout_bottom_to_top;
  timing.estimate_offsets = true;
  ba_options.refine_intrinsics = false;  // held: the question is time, asked of the rig as adjusted
  ba_options.given_intrinsics_sd.reset();  // and the time offsets' deviations are the images' alone
  ba_options.keep_points = false;
  auto solve = [&](const std::vector<ViewTrack>& solved_tracks, CaptureTiming start, const RigPoses& poses) {
    return MultiFrameRigBundleAdjust(adjusted.cameras, keypoints, solved_tracks, poses, scale_camera, ba_options,
                                     false, &start);
  };
  // Rolling shutters are asked with the offsets held at zero and every readout free. Freed together
  // with the offsets, readouts and offsets trade against each other over few frames and condemned a
  // synchronised global-shutter rig (BENCHMARKS.md), so they are solved apart.
  CaptureTiming rows;
  rows.frame_times_s = frame_times_s;
  rows.time_offset_s.assign(n, 0.0);
  rows.readout_s.assign(n, 0.0);
  rows.readout_bottom_to_top = readout_bottom_to_top;
  rows.estimate_readout = true;
  // The turn angles' start can be wrong (camera 0 tracked over few frames): the synchronised start is
  // solved too, and the one the images fit better kept, so that a wrong start cannot condemn a camera.
  const bool from_zero_too =
      std::any_of(start_offsets_s.begin(), start_offsets_s.end(), [](double o) { return o != 0.0; });
  CaptureTiming zero = timing;
  zero.time_offset_s.assign(n, 0.0);
  const std::vector<ViewTrack> subsample = EvenSubsample(tracks, options.check_max_tracks);
  MultiFrameBundleAdjustmentResult freed, from_zero, read_out;
  // Each solve is single-threaded and stands alone: side by side they give the same bits as one
  // after the other.
  tbb::parallel_invoke([&] { freed = solve(subsample, timing, adjusted.poses); },
                       [&] {
                         if (from_zero_too) from_zero = solve(subsample, zero, adjusted.poses);
                       },
                       [&] {
                         if (options.check_readout) {
                           read_out = solve(EvenSubsample(tracks, options.readout_max_tracks), rows, adjusted.poses);
                         }
                       });
  if (from_zero_too && TruncatedCost(from_zero, ba_options.max_reprojection_error_px) <
                           TruncatedCost(freed, ba_options.max_reprojection_error_px)) {
    freed = std::move(from_zero);
  }
  std::vector<int> restarted;
  for (int c = 1; c < n && c < static_cast<int>(freed.timing.size()); ++c) {
    CameraSynchronisation& s = out[c];
    if (!s.checked || !freed.time_offset_stddev_s[c] || s.interval_visibility_px < options.min_interval_visibility_px) {
      continue;
    }
    s.offset_s = freed.timing[c][0];
    s.offset_stddev_s = *freed.time_offset_stddev_s[c];
    s.offset_visibility_px = OffsetVisibilityPx(adjusted.poses.rig_from_world, frame_times_s, *s.offset_s,
                                                PixelsPerRadian(adjusted.cameras[c]), adjusted.median_depth);
    // An offset so long that fewer than two frames' captures fall within the path: nothing shows the
    // rig's motion over it, so it cannot pass for another mounting, and where the images put it
    // beyond min_offset_s and min_sigmas the camera did not capture with camera 0.
    const bool longer_than_the_path = !MeanRigChange(adjusted.poses.rig_from_world, frame_times_s, *s.offset_s);
    s.unsynchronised = longer_than_the_path ? FoundInTheImages(*s.offset_s, *s.offset_stddev_s, options.min_visible_px,
                                                               options.min_offset_s, options)
                                            : FoundInTheImages(*s.offset_s, *s.offset_stddev_s, s.offset_visibility_px,
                                                               options.min_offset_s, options);
    if (!s.unsynchronised) restarted.push_back(c);
  }
  // The freed offset can sit at a kink of the cost rather than at its minimum (at zero each
  // capture meets a frame, where the path between frames bends), with a standard deviation that
  // claims it: the cameras that seem to capture with camera 0 are solved again from moved offsets.
  const std::vector<std::optional<OffsetRestart>> restarts =
      RestartFromMovedOffsets(cameras, keypoints, tracks, freed, scale_camera, ba_options, timing, restarted, options);
  for (int c : restarted) {
    if (!restarts[c]) continue;
    CameraSynchronisation& s = out[c];
    s.offset_alternative_s = restarts[c]->offset_s;
    s.offset_restart_sigmas = restarts[c]->sigmas;
    s.offset_undetermined = restarts[c]->sigmas < options.min_sigmas;
    // Clearly better: the camera captures there (the restart solved no covariance).
    if (restarts[c]->sigmas <= -options.min_sigmas && std::abs(restarts[c]->offset_s) > options.min_offset_s) {
      s.offset_undetermined = false;
      s.unsynchronised = true;
      s.offset_s = restarts[c]->offset_s;
      s.offset_stddev_s.reset();
    }
  }
  // Not found capturing apart is not found capturing together: where an offset the images do not
  // exclude (min_sigmas deviations beyond the freed one) would move the camera's view by
  // min_visible_px, or runs beyond the path, the check cannot show that it captured with camera 0.
  for (int c : restarted) {
    CameraSynchronisation& s = out[c];
    if (s.unsynchronised || s.offset_undetermined || !s.offset_s || !s.offset_stddev_s) continue;
    const double not_excluded = *s.offset_s + std::copysign(options.min_sigmas * *s.offset_stddev_s, *s.offset_s);
    const bool beyond_the_path = !MeanRigChange(adjusted.poses.rig_from_world, frame_times_s, not_excluded);
    if (beyond_the_path || OffsetVisibilityPx(adjusted.poses.rig_from_world, frame_times_s, not_excluded,
                                              PixelsPerRadian(adjusted.cameras[c]),
                                              adjusted.median_depth) >= options.min_visible_px) {
      s.offset_undetermined = true;
      s.offset_not_excluded_s = not_excluded;
    }
  }
  // A rolling shutter also shows as an offset of the cameras without one (their rows are captured,
  // on average, half a readout from the others'): either verdict takes a camera's pose, and the
  // remedy of both is to estimate capture times.
  if (!options.check_readout) return out;
  for (int c = 0; c < n && c < static_cast<int>(read_out.timing.size()); ++c) {
    CameraSynchronisation& s = out[c];
    if ((c > 0 && !s.checked) || !read_out.readout_stddev_s[c]) continue;
    s.readout_s = read_out.timing[c][1];
    s.readout_stddev_s = *read_out.readout_stddev_s[c];
    s.readout_visibility_px = ReadoutVisibilityPx(adjusted.poses.rig_from_world, frame_times_s, *s.readout_s,
                                                  PixelsPerRadian(adjusted.cameras[c]), adjusted.median_depth);
    s.rolling_shutter =
        FoundInTheImages(*s.readout_s, *s.readout_stddev_s, s.readout_visibility_px, options.min_readout_s, options);
  }
  return out;
}

}  // namespace rigsim
