// Targetless rig calibration, in memory: from every view's features to every camera's cam_from_rig.
// No file is read and no truth is seen; pipeline/ reads a dataset, scores the result against the
// truth (evaluation/) and writes it.
//
// Stages: the pairwise stage (pairwise.h: matches per frame, one two-view estimate per pair over
// pooled frames, and each camera matched with itself between consecutive frames) -> view graph
// (view_graph.h) -> robust rotation averaging (rotation_averaging.h) -> rig rotation per frame
// from the temporal pairs -> tracks over all views (camera, frame) -> camera and rig positions by
// linear translation averaging over the tracks -> multi-frame bundle adjustment
// (multi_frame_rig.h). The rig's motion links the scales of the camera pairs, so a ring where
// only neighbours overlap (a chain, not parallel rigid) is determined once it moves. Without
// temporal pairs (one frame, or none given) every frame is an independent capture of a static rig
// and only same-frame tracks constrain the positions.
//
// Where the same-instant pairs leave a camera without a full pose and the rig moved, the stages run
// with links from the rig's motion (motion_links.h: hand-eye starts, views matched across time,
// every rotation averaged jointly), kept when they place more cameras.
// Gauge: camera 0 is the rig frame (its cam_from_rig is the identity); frame 0's rig frame is the
// world. Only the cameras those links reach from camera 0 get rotations; every other camera is
// reported "not connected: <reason>" and gets no pose, never a guessed one. A camera with a
// rotation whose position the data do not determine (e.g. a chain of cameras and one frame) is
// reported "rotation only: <reason>": result.cam_from_rig_rotation has its rotation, the rig
// (and rig.json) has no cam_from_rig for it: there is no made-up translation.
// Scale: images fix none. Without a known distance the centre of the first calibrated camera
// after camera 0 is at distance 1 ("unit scale"); with one, the two named cameras' centres are
// that many metres apart ("metric").
#pragma once

#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "calibrator/capture_time.h"
#include "calibrator/correspondences.h"
#include "calibrator/cross_time_candidates.h"
#include "calibrator/hand_eye.h"
#include "calibrator/intrinsics_refinement.h"
#include "calibrator/multi_frame_rig.h"
#include "calibrator/pairwise.h"
#include "calibrator/rig_positions.h"
#include "calibrator/rig_rotation_averaging.h"
#include "calibrator/rig_turns.h"
#include "calibrator/rotation_averaging.h"
#include "calibrator/view_graph.h"
#include "geometry/rig.h"

namespace rigsim {

// The distance between two cameras' centres, the only source of metric scale.
struct KnownDistance {
  std::string cam_a;
  std::string cam_b;
  double metres = 0.0;
};

// The indices in `names` of the known distance's two cameras. Throws std::invalid_argument starting
// with `where` when it names a camera that is not there, listing the cameras that are.
std::pair<int, int> KnownDistanceCameras(const KnownDistance& known, const std::vector<std::string>& names,
                                         const std::string& where);

// The motion stage (motion_links.h): links between cameras that share little or nothing of their
// views at the same instant, from the rig's motion.
struct MotionLinkOptions {
  // Run it when the same-instant pairs leave a camera without a full pose and the rig moved over
  // at least min_frames frames (temporal pairs).
  bool enabled = true;
  int min_frames = 3;
  HandEyeOptions hand_eye;
  RigTurnOptions rig_turns;
  CrossTimeCandidateOptions candidates;
  // The joint averaging of every rotation (same-instant, temporal and cross-time pairs).
  RigRotationAveragingOptions rotation_averaging;
  // A view pair matched because the rotations predicted that the views meet, whose two-view
  // rotation is farther than this (deg) from the predicted one, is not used: a wrong match of
  // repeated structure (the joint averaging drops the rest).
  double max_prediction_disagreement_deg = 10.0;
  // A camera the same-instant pairs do not reach keeps the rotation the motion links give it only
  // when two things agree on it: its hand-eye rotation within this (deg), or two cross-time pairs
  // with cameras that are kept. One pair alone could be a wrong match nothing would contradict.
  double max_hand_eye_disagreement_deg = 2.0;
  // The rig the motion links made is checked on view pairs it predicts to meet that were not matched
  // to make it: one whose rotation is within this (deg) of the rig's agrees, a farther one
  // contradicts; the rig is not kept when, for one of its cameras, at least
  // min_prediction_contradictions contradict and more than twice as many as agree
  // (PredictionCheck; the figures behind the rule are in BENCHMARKS.md).
  double max_prediction_check_deg = 3.0;
  int min_prediction_contradictions = 2;
  // The bundle adjustment weighs the observations of points that two or more cameras see up, by a
  // quarter of the ratio of all observations to theirs, at most this much
  // (RigBundleAdjustmentOptions::inter_camera_weight).
  double max_inter_camera_weight = 10.0;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct RigCalibrationOptions {
  // Matching and two-view estimation of every pair (pairwise.h).
  PairwiseOptions pairwise;
  // Which pairs become edges.
  ViewGraphOptions view_graph;
  // Robust rotation averaging and its outlier threshold.
  RotationAveragingOptions rotation_averaging;
  // Positions from the tracks (one of the bundle adjustment's starts, rig_positions.h).
  RigPositionOptions positions;
  // Triangulation, bundle adjustment and its outlier filter.
  RigBundleAdjustmentOptions bundle_adjustment;
  // Metric scale; without it the result has unit scale.
  std::optional<KnownDistance> known_distance;
  // A camera whose direction from camera 0 the bundle adjustment's covariance leaves more
  // uncertain than this (standard deviation, deg) is reported "rotation only", not placed. The
  // covariance is optimistic (correlated feature errors): on the rendered target rigs of
  // bench/calibrator_targets.sh the direction errors are up to 9 times it (a 10 cm ring: 6.1 deg at
  // 0.69) and 12 times where it is small (1.7 deg at 0.14), so 0.5 deg keeps placed cameras within
  // the 5 deg direction tolerance. Well-fixed cameras are at 0.01-0.4 deg; cameras that sit (next
  // to) together far above: a co-located ring 7-32 deg, a 3 cm ring 1.6-41 deg.
  double max_direction_std_deg = 0.5;
  // The bundle adjustment runs from every initial position estimate (rig_positions.h) and keeps
  // the result the images agree with best. A camera that another start puts more than
  // max_start_disagreement_deg (direction from camera 0) away is reported ambiguous, not placed,
  // unless the other start's cost is more than min_start_cost_ratio times the best: then that
  // start ended in a minimum the images do not support. Measured on the target rigs of
  // bench/calibrator_targets.sh where the starts ended apart: the other start cost 2.1-10.8 times
  // the best, and every camera of the best that the covariance kept (max_direction_std_deg) was
  // within tolerance. A wrong pair that makes a wrong rig fit best is left to the pair checks
  // (cheirality, the pair-vs-rig check).
  double max_start_disagreement_deg = 2.0;
  double min_start_cost_ratio = 1.5;
  // A used pair whose two-view rotation is more than max_pair_rotation_disagreement_deg from the
  // rig's, or whose baseline direction is more than max_pair_direction_disagreement_deg from the
  // rig's, is left out and the rig made again without it (at most max_rejected_pairs times, the
  // worst first): a wrong pair agrees with the rest only by chance. The rotation bound is loose:
  // a fisheye pair's two-view rotation can be 1.6-1.9 deg off a rig that the tracks make right
  // within 0.1 deg (the surround rig of tests/end_to_end_test.cc), and a wrong pair shows in its
  // direction (measured 12-20 deg on the surround rig at 960x540, 160 deg on a mirror pose).
  double max_pair_rotation_disagreement_deg = 3.0;
  double max_pair_direction_disagreement_deg = 10.0;
  int max_rejected_pairs = 3;
  // A pair whose rotation agrees with the rig's within half max_pair_rotation_disagreement_deg and
  // whose baseline direction is off by no more than this keeps its rotation and its matches in the
  // rig, only its direction is left out: a few percent of wrong inliers bias a direction by 10-20
  // deg (the parking surround rig without masks) while its rotation and matches still serve;
  // leaving the whole pair out there cut the reference camera off. Farther off (a mirror pose of
  // repeated structure, 160-175 deg) the whole pair goes.
  double max_direction_only_disagreement_deg = 30.0;
  // Keep what a report shows of every stage in RigCalibrationResult::details (matches with their
  // flags, rotations after rotation averaging, points, reprojection errors). Costs memory only.
  bool keep_details = false;
  // Capture times: offsets and rolling-shutter readouts estimated, or checked (capture_time.h).
  // Uses RigObservations::frame_times_s.
  CaptureTimeOptions capture_time;
  // Links between cameras from the rig's motion (motion_links.h; EstimateRigFromPairs only).
  MotionLinkOptions motion;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

// What the rig stages consume, independent of images: the pairwise outcome and its inliers.
struct RigObservations {
  std::vector<std::string> camera_names;
  std::vector<Camera> cameras;
  FrameKeypoints keypoints;          // [frame][camera][keypoint]
  std::vector<PairEstimate> pairs;   // one per camera pair
  std::vector<PairMatches> inliers;  // the same pairs' two-view inliers per frame (empty when failed)
  // The same pairs' matches per frame, the inliers' superset; may be empty (then a pair cannot be
  // estimated again, e.g. with refined intrinsics).
  std::vector<PairMatches> matches;
  // Each camera between consecutive frames (pairwise.h PairwiseMatchData::temporal). Empty: the
  // frames are independent captures of a static rig (no rig motion is estimated).
  std::vector<TemporalPairEstimate> temporal;
  // Each frame's timestamp (s); empty when unknown (then capture times are not modelled).
  std::vector<double> frame_times_s;
  // Per camera: its rolling shutter reads the bottom row first; empty: every one top to bottom.
  std::vector<char> readout_bottom_to_top;
  // From the rig's motion (motion_links.h); empty unless that stage ran. View pairs of cameras at
  // different frames; per camera the start of its rotation in the rig (nullopt: none), the rotation
  // hand-eye calibration determined (hand_eye.h kSolved; nullopt otherwise), and the turn axis of a
  // planar motion (in the rig) along which its motion does not fix its centre.
  std::vector<CrossTimePairEstimate> cross_time;
  std::vector<std::optional<Eigen::Quaterniond>> rotation_start;
  std::vector<std::optional<Eigen::Quaterniond>> hand_eye_rotation;
  std::vector<std::optional<Eigen::Vector3d>> open_axis;

  bool HasMotionLinks() const { return !rotation_start.empty(); }
};

struct RigCameraStats {
  int observations = 0;  // bundle-adjustment observations kept
  // Standard deviation of the direction of the camera's centre from camera 0's (deg), from the
  // bundle adjustment's covariance: how well the images fix where the camera is, without truth.
  std::optional<double> direction_std_deg;
  // With RigBundleAdjustmentOptions::refine_intrinsics, for a camera in the bundle adjustment: its
  // given and refined intrinsics and their standard deviations.
  std::optional<RefinedIntrinsics> intrinsics;
  // Relative to camera 0's (s), with their standard deviations: estimated with
  // CaptureTimeOptions::estimate_offsets / estimate_readout, or, for the offset, measured by the
  // synchronisation check; nullopt otherwise.
  std::optional<double> time_offset_s, time_offset_stddev_s;
  std::optional<double> readout_s, readout_stddev_s;
  // With the synchronisation check or offsets estimated: how much an offset of one frame interval
  // would change the camera's view on the rig's path (px, capture_time.h IntervalVisibilityPx);
  // below CaptureTimeOptions::min_interval_visibility_px the images cannot show its capture time.
  std::optional<double> interval_visibility_px;
};

struct RigEdgeStats {
  std::string cam_a, cam_b;
  int inliers = 0;
  bool used = false;           // active after rotation averaging
  bool rotation_only = false;  // no translation direction
  bool rotation_outlier = false;
  std::optional<double> rotation_residual_deg;  // R_b R_a^T vs the pair's rotation at the solution
  // The pair's two-view estimate against the final rig: rotation (deg) and, when both cameras
  // have a position, baseline direction (deg).
  std::optional<double> rotation_disagreement_deg;
  std::optional<double> direction_disagreement_deg;
  bool rejected = false;  // left out for disagreeing with the rig (status says by how much)
  bool direction_left_out = false;  // used for its rotation only: its direction disagreed with the rig
  std::string status;     // "used" or why not
};

// One start of the bundle adjustment (RigCalibrationOptions::max_start_disagreement_deg).
struct RigStartSummary {
  std::string source;  // "two-view directions", "tracks"
  double cost = 0.0;   // TruncatedReprojectionCost after the adjustment (px^2)
  int observations = 0;
  bool chosen = false;
  // Per camera c > 0: the angle between this start's and the chosen one's direction of c from
  // camera 0 after the adjustment; nullopt where either has no position.
  std::vector<std::optional<double>> direction_difference_deg;
};

// The stages of one calibration as a report shows them (RigCalibrationOptions::keep_details).
struct RigCalibrationDetails {
  // The pairwise stage's keypoints, every match with its inlier flag (pairwise.h, kept with
  // PairwiseOptions::keep_match_details); empty for EstimateRig on given observations.
  PairwiseMatchData matches;
  // Per camera: cam_from_rig's rotation after rotation averaging, before the bundle adjustment.
  std::vector<std::optional<Eigen::Quaterniond>> rotation_averaging;
  // The bundle adjustment's points in the result's world (frame 0's rig frame, the result's
  // scale), how many views see each, and the reprojection errors (px) of every observation at
  // the initial poses and at the end (multi_frame_rig.h).
  std::vector<Eigen::Vector3d> points;
  std::vector<int> point_observations;
  std::vector<double> initial_residuals_px, final_residuals_px;
};

// What the calibration made of a camera.
enum class CameraOutcome {
  kCalibrated,    // a full pose (camera 0: the rig frame)
  // A full pose that holds only if the camera captured with camera 0: the synchronisation check
  // ran, and the rig's path moves alike at every frame, so it cannot show a time offset.
  kCalibratedIfSynchronised,
  kRotationOnly,  // a rotation, no position (CameraStatus::position says why)
  kNotConnected,  // no pair links it to camera 0's part of the view graph: no pose at all
  kUnsynchronised,  // it did not capture with camera 0 and offsets were not estimated: no pose
  kTimeNotDetermined,  // its offset was to be estimated and the rig's path cannot show it: no pose
  // A rotation and a position but for one component: a planar motion placed it and no point joins
  // it with another camera, so its offset along the turn axis is open (PositionOutcome::kOpenAlongTurnAxis;
  // RigCalibrationResult::partial_centre). No cam_from_rig in the rig: no made-up component.
  kOpenAlongAxis,
};

// The position of a camera with a rotation: placed, or why not.
enum class PositionOutcome {
  kPlaced,
  kNotObservable,  // nothing links its position to the placed cameras' (no start for it)
  kNotDetermined,  // the images fix its direction from camera 0 too loosely (max_direction_std_deg)
  kAmbiguous,      // bundle adjustments from different starts put it in different places
  kOpenAlongTurnAxis,  // placed across the turn axis of a planar motion, open along it
};

struct CameraStatus {
  CameraOutcome outcome = CameraOutcome::kNotConnected;
  PositionOutcome position = PositionOutcome::kNotObservable;  // kPlaced when calibrated
  // Why, in words: for a rotation-only camera why it has no position and what would place it; for a
  // camera not connected its pairs with the connected cameras; "reference: rig frame" for camera 0.
  std::string reason;

  // The status as evaluation.json and the tables give it: "calibrated", "calibrated (reference:
  // rig frame)", "calibrated if synchronised: <reason>", "rotation only: position <reason>",
  // "placed but for one axis: <reason>" or "not connected: <reason>".
  std::string Text() const;
};
inline std::ostream& operator<<(std::ostream& os, const CameraStatus& s) { return os << s.Text(); }
// Whether the outcome gives the camera a full pose, unconditionally or if synchronised.
bool HasFullPose(CameraOutcome outcome);

// Images fix no scale: the result's unit of length is none (no camera placed besides camera 0),
// the distance of one camera from camera 0 (unit), or metres from a known distance (metric).
enum class ScaleKind { kNone, kUnit, kMetric };

struct RigCalibrationResult {
  std::string semantic_mode;
  // Intrinsics as given (refined with RigBundleAdjustmentOptions::refine_intrinsics); cam_from_rig
  // estimated for calibrated cameras, nullopt otherwise.
  Rig rig;
  // Per camera: the estimated cam_from_rig rotation of calibrated and "rotation only" cameras;
  // nullopt for cameras not connected.
  std::vector<std::optional<Eigen::Quaterniond>> cam_from_rig_rotation;
  // Per camera with CameraOutcome::kOpenAlongAxis: the axis (unit, in the rig) along which its
  // centre is not determined, and its centre in the rig without that component (the part the
  // images determine, in the result's unit); nullopt otherwise.
  std::vector<std::optional<Eigen::Vector3d>> open_axis;
  std::vector<std::optional<Eigen::Vector3d>> partial_centre;
  // Per camera: what the calibration made of it, and why.
  std::vector<CameraStatus> camera_status;
  std::vector<RigCameraStats> camera_stats;
  std::vector<RigEdgeStats> edges;  // per camera pair
  // With refine_intrinsics (rig_intrinsics.h): each pair's two-view estimate made again with the
  // refined intrinsics, which the rig used (RigObservations::pairs order); empty otherwise.
  std::vector<TwoViewEstimate> reestimated_pairs;
  // How the unit of length was fixed, and in words, e.g. "unit scale: |centre of cam1| = 1".
  ScaleKind scale_kind = ScaleKind::kNone;
  std::string scale;
  std::vector<std::string> warnings;
  double initial_reprojection_rms_px = 0.0;
  double reprojection_rms_px = 0.0;
  int num_tracks = 0;
  int num_conflicting_tracks = 0;  // dropped: two keypoints of one camera
  int num_points = 0;
  int num_observations = 0;
  int num_filtered_observations = 0;
  int num_rotation_outliers = 0;
  // Rig motion: frames with a rig pose (all frames when static), and whether the rig was tracked
  // between frames (temporal pairs used) or taken as static.
  int num_frames = 0;
  int num_frames_posed = 0;
  // Per frame: the rig's pose, rig_from_world, with the rig frame at frame 0 as the world and in
  // the scale of cam_from_rig (the identity for every frame of a static rig); nullopt for a frame
  // without one. Empty when the camera positions are not observable.
  std::vector<std::optional<Rigid3d>> rig_from_world;
  bool rig_motion_estimated = false;
  int num_temporal_pairs_used = 0;  // successful temporal pairs between cameras with a rotation
  int num_cross_time_pairs_used = 0;  // cross-time pairs (motion_links.h) rotation averaging kept
  // How clearly the tracks single out one set of positions (RigPositions::eigenvalue_ratio).
  double position_eigenvalue_ratio = 0.0;
  // The bundle adjustment's starts and how each ended.
  std::vector<RigStartSummary> position_starts;
  // The motion stage (motion_links.h) when it ran: whether its result was kept (it placed more
  // cameras), the motion's kind, the view pairs matched across time, the successful ones, those
  // rotation averaging kept, the temporal pairs that took their planar alternative or failed
  // against the rig's turns (rig_turns.h), the view pairs its rig predicts that agree with it and
  // contradict it, and its time.
  struct MotionLinkSummary {
    bool kept = false;
    MotionKind motion = MotionKind::kStraight;
    int candidates = 0;
    int pairs = 0;
    int pairs_used = 0;
    int temporal_alternatives_taken = 0;
    int temporal_pairs_disagreeing = 0;
    int predicted_views_agreeing = 0;
    int predicted_views_contradicting = 0;
    double time_s = 0.0;
  };
  std::optional<MotionLinkSummary> motion_links;
  CalibrationReport pairwise;
  // Full runs of the rig stages (EstimateRig, its pair-rejection rounds included) that made this
  // result: 2 where a pass with the motion links and one without both ran, or intrinsics were refined.
  int rig_passes = 0;
  // Wall time of the rig stages (the pairwise ones are in `pairwise`), summed over the rig_passes
  // and the rounds of a pass stopped before its bundle adjustment (EstimateRigUnlessUnplaced).
  double rotation_averaging_time_s = 0.0;
  double positions_time_s = 0.0;
  double tracks_time_s = 0.0;
  double bundle_adjustment_time_s = 0.0;
  double synchronisation_check_time_s = 0.0;  // CaptureTimeOptions::check_synchronisation
  // With RigCalibrationOptions::keep_details only; shared, so copies of a result stay cheap.
  std::shared_ptr<RigCalibrationDetails> details;
};

// The rig stages on given observations (no truth, no pairwise report). Throws
// std::invalid_argument on inconsistent observations or a known distance naming an unknown camera.
RigCalibrationResult EstimateRig(const RigObservations& observations, const RigCalibrationOptions& options);

// Where EstimateRigUnlessUnplaced stopped. Exists so that the motion stage can run before a full
// pass whose result it would replace.
struct RigPreCheck {
  // The pair-rejection round (0: the first; r: after r pairs left out, max_rejected_pairs) whose
  // early stages (rotation averaging, the rig's motion, tracks, initial positions) it checked.
  int round = 0;
  // Per camera: rotation averaging gives it a rotation and some start of the bundle adjustment a
  // position. A camera without is left without a full pose, unless a pair a later round rejects made
  // rotation averaging leave it out; one with may still lose its position in the bundle adjustment
  // (RigCalibrationOptions::max_direction_std_deg, ambiguous starts).
  std::vector<char> may_be_placed;
  // Per camera: cam_from_rig's rotation from that round's rotation averaging; nullopt where none.
  std::vector<std::optional<Eigen::Quaterniond>> cam_from_rig_rotation;
  // The stage times of what ran until the stop (every earlier round whole, rig_passes 0).
  RigCalibrationResult work;

  bool SomeCameraWithoutFullPose() const;
};

// EstimateRig, stopped before the bundle adjustment of the first round whose early stages leave a
// camera without a rotation or a start position: then nullopt, and `stop` says where and why.
// Throws like EstimateRig.
std::optional<RigCalibrationResult> EstimateRigUnlessUnplaced(const RigObservations& observations,
                                                              const RigCalibrationOptions& options, RigPreCheck* stop);

// Adds `from`'s rig_passes and stage times into `into`, which then counts the work of both.
void AddRigWork(const RigCalibrationResult& from, RigCalibrationResult* into);

// The rig stages on the pairwise stage's outcome (pairwise.h MatchRigPairs) of `views`, with the
// motion stage (motion_links.h EstimateRigWithMotionLinks) where it applies. The
// result has the pairwise report, its pairs as the rig used them (re-estimated with the refined
// intrinsics under RigBundleAdjustmentOptions::refine_intrinsics; marked where the rig left them
// out) and, with keep_details, the match data. Throws like EstimateRig.
RigCalibrationResult EstimateRigFromPairs(const RigViews& views, const PairwiseResult& pairwise,
                                          const RigCalibrationOptions& options);

// The whole calibration of `views`: MatchRigPairs, then EstimateRigFromPairs. Throws
// std::invalid_argument on bad options or views.
RigCalibrationResult CalibrateRig(const RigViews& views, const RigCalibrationOptions& options);

// With reestimated_pairs: result->pairwise's two-view estimates replaced by them (the report then
// shows the pairs the rig used).
void UseReestimatedPairs(RigCalibrationResult* result);

// Sets PairResult::left_out_by_rig on result->pairwise's pairs whose edge the rig stage rejected or
// found a rotation outlier: the pair's own pose is then no longer what the calibrator stands by.
void MarkPairsTheRigLeftOut(RigCalibrationResult* result);

}  // namespace rigsim
