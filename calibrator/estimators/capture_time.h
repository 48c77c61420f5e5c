// Time in the rig stage: each camera's capture time is its frame's timestamp plus its
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

#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/estimators/time_offset_search.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/model/view_graph.h"

namespace rigsim {

struct CaptureTimeOptions {
  // Estimate each camera's time offset from camera 0 (--estimate-time-offsets) and each camera's
  // rolling-shutter readout time (--rolling-shutter) in the bundle adjustment.
  bool estimate_offsets = false;
  bool estimate_readout = false;
  // Not estimating offsets, a moving rig with frames at distinct times is checked: a camera whose
  // freed offset is farther from zero than both min_offset_s and min_sigmas standard deviations,
  // and that the rig's path would show by at least min_visible_px (OffsetVisibilityPx), did not
  // capture with camera 0 and is not calibrated. The standard deviation alone does not decide: where
  // the path hides offsets (a straight line or a circle at constant speed) the freed offset follows
  // the noise in the rig's poses, with a standard deviation that claims it is determined.
  bool check_synchronisation = true;
  // The check solves once more with the offsets held at zero and each camera's rolling-shutter
  // readout free, on an even subsample of at most
  // readout_max_tracks tracks, judged by min_readout_s, min_sigmas and min_visible_px
  // (ReadoutVisibilityPx): min_readout_s lies above what the freed readouts of global-shutter
  // renders read and below common rolling shutters' readouts (BENCHMARKS.md).
  bool check_readout = true;
  double min_readout_s = 0.010;
  int readout_max_tracks = 500;
  double min_offset_s = 0.005;
  double min_sigmas = 5.0;
  double min_visible_px = 1.0;
  // The path shows capture times at all when an offset of one frame interval shows by this much
  // (IntervalVisibilityPx) for the camera; below it the check does not condemn the camera and an
  // estimated offset is not determined. Noise in the estimated path alone reads 1.5-2.2 px on a
  // rendered circle (4 frames, 640x360), and a turn driven at a changing speed 23-30 px.
  double min_interval_visibility_px = 5.0;
  // The check solves on an even subsample of at most this many tracks (0: all): an offset that
  // matters moves thousands of observations alike, and the standard deviation it is judged by is
  // that of the subsample. Its solve costs several times a solve of the rig (the timed costs).
  int check_max_tracks = 2000;
  // The cameras the check finds capturing with camera 0, and estimated offsets, are solved again
  // from moved offsets (RestartFromMovedOffsets) on an even subsample of at most this many tracks
  // (0: all; negative: not at all): up to five solves of the rig, whatever its size.
  int restart_max_tracks = 300;
  TimeOffsetSearchOptions search;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

// The start of the offsets: SearchTimeOffsets over each camera's turn angles between frames (its
// successful temporal pairs); 0 for a camera the search does not determine. One per camera.
std::vector<double> StartTimeOffsets(int num_cameras, const std::vector<double>& frame_times_s,
                                     const std::vector<TemporalPairEstimate>& temporal,
                                     const TimeOffsetSearchOptions& options);

// The median time between consecutive frames (s); 0 with fewer than two frames.
double MedianFrameInterval(std::vector<double> frame_times_s);

// Whether capture times can be modelled at all: at least three frames at distinct, finite times.
// Otherwise the reason, in words.
std::optional<std::string> WhyNoTimingModel(const std::vector<double>& frame_times_s);

// How much the rig's path would show a camera that captures `offset_s` after camera 0 (px). Taken as
// synchronised, that camera sees from rig(t + o) where the rig model puts it at rig(t); one constant
// change of its mounting, D = rig(t + o)_from_rig(t), explains this wherever the path moves alike
// at every frame (a straight line or a circle at constant speed), so the images cannot tell the
// offset from the mounting there. What they can see is how D varies over the frames: the largest
// departure of a frame's D from the mean, as the image motion it causes in a camera of
// `pixels_per_radian` looking at the scene at `scene_depth` (the path's unit):
// pixels_per_radian * (angle + shift / scene_depth), over the frames whose capture falls within the
// path's frames (beyond them the path is extrapolated straight, a model, not a motion the images
// show). 0 with fewer than two such frames of three or more posed ones.
double OffsetVisibilityPx(const PerFrame<Rigid3d>& rig_from_world,
                          const std::vector<double>& frame_times_s, double offset_s, double pixels_per_radian,
                          double scene_depth);

// The mean over those frames of D = rig(t + offset)_from_rig(t): the rig's motion between two
// captures `offset_s` apart, as a pair of cameras pooled over the frames sees it on average; nullopt
// where OffsetVisibilityPx has nothing to compare.
std::optional<Rigid3d> MeanRigChange(const PerFrame<Rigid3d>& rig_from_world,
                                     const std::vector<double>& frame_times_s, double offset_s);

// How much the rig's motion over a readout of `readout_s` shows (px): MeanRigChange over that time
// as image motion, as OffsetVisibilityPx measures it; 0 with nothing to compare.
double ReadoutVisibilityPx(const PerFrame<Rigid3d>& rig_from_world,
                           const std::vector<double>& frame_times_s, double readout_s, double pixels_per_radian,
                           double scene_depth);

// OffsetVisibilityPx of an offset of one frame interval (the median time between frames): the most
// any offset within a frame can show.
double IntervalVisibilityPx(const PerFrame<Rigid3d>& rig_from_world,
                            const std::vector<double>& frame_times_s, double pixels_per_radian, double scene_depth);

// The camera's image scale at its centre: pixels per radian of view.
double PixelsPerRadian(const Camera& camera);

// The rig's path as camera 0 alone sees it: `adjusted`'s frames adjusted from camera 0's
// observations only (an even subsample of at most `max_tracks` of the tracks it sees; 0: all), posed
// only where camera 0 sees enough of them, and the median depth of its points, in that solve's own
// unit. Camera 0's capture times are the reference, so no assumption about the other cameras'
// shapes it. nullopt where camera 0 has no pose or poses fewer than three frames on its own.
struct ReferencePath {
  PerFrame<Rigid3d> rig_from_world;
  double median_depth = 0.0;
};
std::optional<ReferencePath> ReferenceCameraPath(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                                 const std::vector<ViewTrack>& tracks, const RigPoses& adjusted,
                                                 RigBundleAdjustmentOptions ba_options, int max_tracks);

// What the images say of one camera's capture time relative to camera 0's.
struct CameraSynchronisation {
  bool checked = false;  // the camera has a pose to check
  // How much the path shows a frame interval's worth of offset (IntervalVisibilityPx): below
  // min_interval_visibility_px it cannot show whether the camera captured with camera 0.
  double interval_visibility_px = 0.0;
  // The freed offset, and how much the path shows it (OffsetVisibilityPx); nullopt where the path
  // hides time: there the freed offset follows the noise in the path, whatever its deviation says.
  std::optional<double> offset_s, offset_stddev_s;
  double offset_visibility_px = 0.0;
  bool unsynchronised = false;
  // For a camera found capturing with camera 0, or with an estimated offset: where its offset goes
  // when the solve starts from moved offsets (RestartFromMovedOffsets). Below min_sigmas the
  // images do not fix the offset, whatever the covariance at the freed one says: the camera is then
  // not known to capture with camera 0, nor known not to. At -min_sigmas or less (and beyond
  // min_offset_s) it captures there: unsynchronised, with that offset and no standard deviation.
  std::optional<double> offset_alternative_s, offset_restart_sigmas;
  // For a camera not found capturing apart: the offset min_sigmas deviations beyond the freed one,
  // where the images do not exclude it and the path would show it by min_visible_px or more (or it
  // runs beyond the path). The check then cannot show that the camera captured with camera 0.
  std::optional<double> offset_not_excluded_s;
  bool offset_undetermined = false;
  // The freed readout (first row to last, s), and how much the rig's motion over it shows
  // (ReadoutVisibilityPx): rows read out over a moving rig's path see
  // from different places, which no mounting explains, so it is judged on any path that shows time.
  // Camera 0's too (its offset is the gauge, its readout is not).
  std::optional<double> readout_s, readout_stddev_s;
  double readout_visibility_px = 0.0;
  bool rolling_shutter = false;
};

// Where a camera's offset goes when the solve starts elsewhere: the offset it ends at and how many
// standard deviations of the reprojection noise that fits worse than the solve it started from
// (sqrt of the rise in chi-square; negative where it fits better).
struct OffsetRestart {
  double offset_s = 0.0;
  double sigmas = 0.0;
};

// `solved` (a bundle adjustment with `timing`'s offsets free; its offsets and poses are the start)
// solved again on an even subsample of at most options.restart_max_tracks tracks, first as it is
// (the reference), then from the offsets of the `restarted` cameras moved a quarter, then half a
// frame interval either way, each moved camera's mounting turned by the rig's mean motion over the
// step (on a path moving alike at every frame the start then lies in the valley the step moves
// along). Per camera: the restart whose offset stayed away from the reference's (by an eighth of
// an interval or more) with the least rise, nullopt where none stayed away. The restarts stop for
// a camera once one fits within options.min_sigmas.
std::vector<std::optional<OffsetRestart>> RestartFromMovedOffsets(
    const std::vector<Camera>& cameras, const FrameKeypoints& keypoints, const std::vector<ViewTrack>& tracks,
    const MultiFrameBundleAdjustmentResult& solved, int scale_camera, RigBundleAdjustmentOptions ba_options,
    const CaptureTiming& timing, const std::vector<int>& restarted, const CaptureTimeOptions& options);

// The bundle adjustment solved again from `adjusted` (a result taken as synchronised) with every
// camera's offset free (camera 0's the gauge), started at StartTimeOffsets and, when those are not
// all zero, at zero too (the start the images fit better is kept); then, with check_readout, with
// the offsets at zero and every readout free. One verdict per camera: an offset beyond min_offset_s,
// min_sigmas and min_visible_px is unsynchronised; one within them is restarted
// (RestartFromMovedOffsets): undetermined where another start fits about as well, unsynchronised
// where one fits clearly better; a readout beyond min_readout_s, min_sigmas and min_visible_px is
// a rolling shutter.
// A camera's interval visibility is the adjusted path's, or where that shows time the lesser of it
// and camera 0's own (ReferenceCameraPath). Where the path hides time for every camera, nothing is
// solved: the check could not condemn one.
std::vector<CameraSynchronisation> CheckSynchronisation(
    const std::vector<Camera>& cameras, const FrameKeypoints& keypoints, const std::vector<ViewTrack>& tracks,
    const MultiFrameBundleAdjustmentResult& adjusted, int scale_camera, RigBundleAdjustmentOptions ba_options,
    const std::vector<double>& frame_times_s, const std::vector<double>& start_offsets_s,
    const std::vector<char>& readout_bottom_to_top, const CaptureTimeOptions& options);

}  // namespace rigsim
