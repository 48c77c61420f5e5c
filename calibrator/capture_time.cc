#include "calibrator/capture_time.h"

#include <cmath>
#include <set>
#include <stdexcept>

#include <Eigen/Geometry>

namespace rigsim {

void CaptureTimeOptions::Check() const {
  if (!(min_offset_s >= 0) || !std::isfinite(min_offset_s)) throw std::invalid_argument("min_offset_s must be >= 0");
  if (!(min_sigmas > 0)) throw std::invalid_argument("min_sigmas must be > 0");
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

std::vector<double> StartTimeOffsets(int num_cameras, const std::vector<double>& frame_times_s,
                                     const std::vector<TemporalPairEstimate>& temporal,
                                     const TimeOffsetSearchOptions& options) {
  std::vector<double> out(num_cameras, 0.0);
  const int frames = static_cast<int>(frame_times_s.size());
  if (frames < 2 || num_cameras < 2) return out;
  std::vector<std::vector<std::optional<double>>> turn(num_cameras, std::vector<std::optional<double>>(frames - 1));
  for (const TemporalPairEstimate& t : temporal) {
    if (!t.two_view.success || t.camera < 0 || t.camera >= num_cameras || t.frame < 0 || t.frame + 1 >= frames) continue;
    turn[t.camera][t.frame] = Eigen::AngleAxisd(t.two_view.cam_b_from_cam_a.rotation).angle();
  }
  const std::vector<SearchedOffset> found = SearchTimeOffsets(frame_times_s, turn, options);
  for (int c = 1; c < num_cameras; ++c) {
    if (found[c].determined) out[c] = found[c].offset_s;
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
  CaptureTiming timing;
  timing.frame_times_s = frame_times_s;
  timing.time_offset_s = start_offsets_s;
  timing.readout_s.assign(n, 0.0);
  timing.readout_bottom_to_top = readout_bottom_to_top;
  timing.estimate_offsets = true;
  ba_options.refine_intrinsics = false;  // held: the question is time, asked of the rig as adjusted
  ba_options.keep_points = false;
  const MultiFrameBundleAdjustmentResult freed =
      MultiFrameRigBundleAdjust(adjusted.cameras, keypoints, tracks, adjusted.cam_from_rig, adjusted.rig_from_world,
                                scale_camera, ba_options, false, &timing);
  for (int c = 1; c < n && c < static_cast<int>(freed.timing.size()); ++c) {
    if (!adjusted.cam_from_rig[c] || !freed.time_offset_stddev_s[c]) continue;
    CameraSynchronisation& s = out[c];
    s.offset_s = freed.timing[c][0];
    s.offset_stddev_s = *freed.time_offset_stddev_s[c];
    const double magnitude = std::abs(*s.offset_s);
    s.unsynchronised = magnitude > options.min_offset_s && magnitude > options.min_sigmas * *s.offset_stddev_s;
  }
  return out;
}

}  // namespace rigsim
