// Time in the rig stage (issue 31): each camera's capture time is its frame's timestamp plus its
// offset from camera 0 (plus its row's share of a rolling shutter's readout). The rig bundle
// adjustment estimates these with a CaptureTiming (multi_frame_rig.h); this module makes its start
// and decides, when they are not estimated, whether the images show cameras that did not capture
// together.
//
// A camera that captures o seconds after camera 0 while the rig moves sees from where the rig is
// o seconds later; taken as synchronised, the bundle adjustment bends that motion into the
// camera's mounting and reports a wrong pose as calibrated. Freeing the offsets shows it: a
// synchronised rig's come out at zero within their standard deviations.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "calibrator/multi_frame_rig.h"
#include "calibrator/time_offset_search.h"
#include "calibrator/view_graph.h"

namespace rigsim {

struct CaptureTimeOptions {
  // Estimate each camera's time offset from camera 0 (--estimate-time-offsets) and each camera's
  // rolling-shutter readout time (--rolling-shutter) in the bundle adjustment.
  bool estimate_offsets = false;
  bool estimate_readout = false;
  // Not estimating offsets, a moving rig with frames at distinct times is checked: a camera whose
  // freed offset is farther from zero than both min_offset_s and min_sigmas standard deviations
  // did not capture with camera 0, and is not calibrated. Off by default: on a synchronised rig
  // with weak motion (tests/degenerate_calibration_test.cc) the freed offset came out 91.5 +- 10.4
  // ms, so the standard deviation is too optimistic to decide on its own.
  bool check_synchronisation = false;
  double min_offset_s = 0.005;
  double min_sigmas = 5.0;
  TimeOffsetSearchOptions search;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

// The start of the offsets: SearchTimeOffsets over each camera's turn angles between frames (its
// successful temporal pairs); 0 for a camera the search does not determine. One per camera.
std::vector<double> StartTimeOffsets(int num_cameras, const std::vector<double>& frame_times_s,
                                     const std::vector<TemporalPairEstimate>& temporal,
                                     const TimeOffsetSearchOptions& options);

// Whether capture times can be modelled at all: at least three frames at distinct, finite times.
// Otherwise the reason, in words.
std::optional<std::string> WhyNoTimingModel(const std::vector<double>& frame_times_s);

// What the images say of one camera's capture time relative to camera 0's.
struct CameraSynchronisation {
  std::optional<double> offset_s, offset_stddev_s;  // the freed offset; nullopt: not estimated
  bool unsynchronised = false;
};

// The bundle adjustment solved again from `adjusted` (a result taken as synchronised) with every
// camera's offset free (camera 0's the gauge), started at StartTimeOffsets; one verdict per camera.
std::vector<CameraSynchronisation> CheckSynchronisation(
    const std::vector<Camera>& cameras, const FrameKeypoints& keypoints, const std::vector<ViewTrack>& tracks,
    const MultiFrameBundleAdjustmentResult& adjusted, int scale_camera, RigBundleAdjustmentOptions ba_options,
    const std::vector<double>& frame_times_s, const std::vector<double>& start_offsets_s,
    const std::vector<char>& readout_bottom_to_top, const CaptureTimeOptions& options);

}  // namespace rigsim
