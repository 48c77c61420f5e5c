#include "calibrator/stages/rig_calibration.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <utility>

#include <tbb/parallel_for.h>

#include "calibrator/estimators/bundle_covariance.h"
#include "calibrator/estimators/camera_centres.h"
#include "calibrator/estimators/rig_positions.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/stages/rig_adjustment_cache.h"
#include "calibrator/stages/rig_capture_times.h"
#include "calibrator/stages/rig_edges.h"
#include "calibrator/stages/rig_motion_links.h"
#include "calibrator/stages/stage_clock.h"
#include "calibrator/stages/stated_deviations.h"
#include "common/format.h"

namespace rigsim {
namespace {

// A calibrated camera whose place rests on one pair only, a pair whose fit explains under a
// quarter of its matches, may be a wrong view that agreed with some pose by chance (a mirrored
// photo of a symmetric facade does: 17% inliers, 121 deg off); genuine pairs of the demo and of
// Herz-Jesus explain 60-90%. The pose is kept, with a warning that says what to look at.
constexpr double kWeakPairInlierRatio = 0.25;

// The edges (= input pairs) that place camera c: active, with a translation, between two cameras
// with a rotation.
std::vector<int> PlacingEdges(const ViewGraph& graph, const std::vector<char>& rotated, int c) {
  std::vector<int> held_by;
  for (int e = 0; e < static_cast<int>(graph.edges.size()); ++e) {
    const ViewGraphEdge& g = graph.edges[e];
    if (g.active && !g.rotation_only && (g.cam_a == c || g.cam_b == c) && rotated[g.cam_a] && rotated[g.cam_b]) {
      held_by.push_back(e);
    }
  }
  return held_by;
}

void WarnAboutCamerasHeldByOneWeakPair(const ViewGraph& graph, const RigObservations& obs,
                                       const std::vector<char>& rotated, const std::vector<char>& reached,
                                       std::vector<std::string>* warnings) {
  for (int c = 1; c < graph.num_cameras; ++c) {
    if (!reached[c]) continue;
    const std::vector<int> held_by = PlacingEdges(graph, rotated, c);
    if (held_by.size() != 1) continue;
    const PairEstimate& p = obs.pairs[held_by[0]];
    const TwoViewEstimate& tv = p.two_view;
    if (tv.num_matches <= 0 || tv.num_inliers >= kWeakPairInlierRatio * tv.num_matches) continue;
    const std::string pair = obs.camera_names[p.cam_a] + "-" + obs.camera_names[p.cam_b];
    warnings->push_back(obs.camera_names[c] + " is placed by one pair only, " + pair + ", whose fit explains " +
                        std::to_string(tv.num_inliers) + " of its " + std::to_string(tv.num_matches) + " matches (" +
                        Fixed(100.0 * tv.num_inliers / tv.num_matches, 0) +
                        "%): unrelated or mirrored views can agree with a pose by chance; check the pair's match "
                        "image");
  }
}

}  // namespace

bool RigPreCheck::SomeCameraWithoutFullPose() const {
  return std::find(may_be_placed.begin(), may_be_placed.end(), 0) != may_be_placed.end();
}

RigWork& RigWork::operator+=(const RigWork& other) {
  rig_passes += other.rig_passes;
  rotation_averaging_time_s += other.rotation_averaging_time_s;
  tracks_time_s += other.tracks_time_s;
  positions_time_s += other.positions_time_s;
  bundle_adjustment_time_s += other.bundle_adjustment_time_s;
  synchronisation_check_time_s += other.synchronisation_check_time_s;
  rounds_checked_for_capture_times += other.rounds_checked_for_capture_times;
  start_adjustments_solved += other.start_adjustments_solved;
  start_adjustments_reused += other.start_adjustments_reused;
  return *this;
}

namespace {

// Step 1: the view graph of the pairs and robust rotation averaging over it; the edges found to
// be rotation outliers are deactivated with the reason.
struct RotationStage {
  ViewGraph graph;
  RotationAveragingResult rot;
  // With motion links (motion_links.h): every rotation averaged jointly; rot.cam_from_rig holds its
  // cameras' and this its frames'.
  std::optional<JointRotations> joint;
};

RotationStage AverageCameraRotations(const RigObservations& obs, const RigCalibrationOptions& options,
                                     const std::vector<std::string>& rejected) {
  RotationStage s;
  s.graph = BuildViewGraph(static_cast<int>(obs.cameras.size()), obs.pairs, options.view_graph);
  for (int e = 0; e < static_cast<int>(s.graph.edges.size()); ++e) {
    if (!rejected[e].empty()) s.graph.Deactivate(e, rejected[e]);
  }
  s.rot = AverageRotations(s.graph, 0, options.rotation_averaging);
  for (int e = 0; e < static_cast<int>(s.graph.edges.size()); ++e) {
    if (s.rot.outlier[e]) {
      s.graph.Deactivate(e, "rotation outlier (residual " + Fixed(s.rot.residual_deg[e], 1) + " deg > " +
                                Fixed(options.rotation_averaging.outlier_threshold_deg, 1) + ")");
    }
  }
  if (obs.HasMotionLinks()) {
    s.joint = AverageRotationsWithMotionLinks(obs, s.graph, options.motion);
    s.rot.cam_from_rig = s.joint->rotations.cam_from_rig;
  }
  return s;
}

// Step 2: the rig's rotation per frame from the temporal pairs, or a static rig (identity in every
// frame) without them.
struct RigMotion {
  bool moving = false;
  PerFrame<Eigen::Quaterniond> rig_rotation;
  int temporal_pairs_used = 0;  // successful temporal pairs of cameras with a rotation
};

RigMotion EstimateRigMotion(const RigObservations& obs, const RotationStage& rs, int num_frames) {
  const int n = static_cast<int>(obs.cameras.size());
  const RotationAveragingResult& rot = rs.rot;
  RigMotion m;
  m.moving = num_frames >= 2 && !obs.temporal.empty();
  m.rig_rotation.assign(num_frames, Eigen::Quaterniond::Identity());
  if (!m.moving) return m;
  m.rig_rotation = rs.joint ? rs.joint->rotations.rig_from_world
                            : EstimateRigRotations(num_frames, rot.cam_from_rig, obs.temporal);
  for (const TemporalPairEstimate& t : obs.temporal) {
    if (t.camera < 0 || t.camera >= n || t.frame < 0 || t.frame + 1 >= num_frames) {
      throw std::invalid_argument("EstimateRig: temporal pair out of range");
    }
    if (t.PoseUsable() && rot.cam_from_rig[t.camera]) ++m.temporal_pairs_used;
  }
  return m;
}

// Step 3: tracks over all views from the inliers of the edges still in use (between cameras with
// a rotation) and of the temporal pairs.
std::vector<ViewTrack> TracksOfUsedPairs(const RigObservations& obs, const RotationStage& rs, const RigMotion& motion,
                                         int num_frames, int* num_conflicting) {
  std::vector<PairMatches> used;
  for (size_t p = 0; p < obs.pairs.size(); ++p) {
    const ViewGraphEdge& g = rs.graph.edges[p];
    if (!g.active || !rs.rot.cam_from_rig[g.cam_a] || !rs.rot.cam_from_rig[g.cam_b]) continue;
    if (static_cast<int>(obs.inliers[p].per_frame.size()) != num_frames) {
      throw std::invalid_argument("EstimateRig: inliers of a pair do not have one entry per frame");
    }
    used.push_back(obs.inliers[p]);
  }
  std::vector<TemporalPairEstimate> temporal_used;
  if (motion.moving) {
    for (const TemporalPairEstimate& t : obs.temporal) {
      if (t.two_view.success && rs.rot.cam_from_rig[t.camera]) temporal_used.push_back(t);
    }
  }
  std::vector<CrossTimePairEstimate> cross_time_used;
  for (size_t i = 0; rs.joint && i < obs.cross_time.size(); ++i) {
    if (rs.joint->cross_time_used[i]) cross_time_used.push_back(obs.cross_time[i]);
  }
  return BuildViewTracksAcrossTime(static_cast<int>(obs.cameras.size()), num_frames, used, temporal_used,
                                   cross_time_used, num_conflicting);
}

// Step 4: the bundle adjustment's initial poses, one set per position estimate that found a
// solution (rig_positions.h): from the two-view directions and from the tracks.
struct PoseStart {
  std::string source;
  RigPoses poses;
};

struct PositionStage {
  std::vector<PoseStart> starts;
  double eigenvalue_ratio = 0.0;  // of the track solve
  std::string position_reason;    // why there is no start; empty when there is one
  std::string remedy;             // what would fix the positions the images leave open
  int scale_camera = -1;          // the camera at distance 1 from camera 0; -1: none
  // Per camera (empty without motion links): the axis along which its centre is held, open
  // (motion_links.h HeldCentreAxes).
  PerCamera<Eigen::Vector3d> held_axis;
};

// What a user can change so that the images fix positions they leave open, from how the rig moved.
std::string PositionRemedy(const RigMotion& motion, int num_frames) {
  if (!motion.moving) {
    return num_frames < 2 ? "to place it: several frames while the rig moves (its motion links the cameras' positions), "
                            "or more overlap between neighbouring cameras"
                          : "to place it: matches between consecutive frames (move the rig less between frames), or "
                            "more overlap between neighbouring cameras";
  }
  double turn_deg = 0.0;  // the largest rotation of the rig from frame 0
  for (const auto& q : motion.rig_rotation) {
    if (q && motion.rig_rotation[0]) turn_deg = std::max(turn_deg, RotationDifferenceDeg(*q, *motion.rig_rotation[0]));
  }
  std::string remedy = "to place it: more frames";
  if (turn_deg < 10.0) remedy += ", a path that turns (the rig turned " + Fixed(turn_deg, 1) + " deg)";
  return remedy + ", more overlap between neighbouring cameras, or a higher resolution";
}

PoseStart ToStart(const std::string& source, const RigPositions& positions, const RotationStage& rs,
                  const RigMotion& motion, int scale_camera) {
  const double unit = 1.0 / positions.centre_in_rig[scale_camera]->norm();
  PoseStart s;
  s.source = source;
  PerCamera<Rigid3d>& cam_from_rig = s.poses.cam_from_rig;
  PerFrame<Rigid3d>& rig_from_world = s.poses.rig_from_world;
  cam_from_rig.assign(positions.centre_in_rig.size(), std::nullopt);
  rig_from_world.assign(positions.rig_centre_in_world.size(), std::nullopt);
  for (size_t c = 0; c < cam_from_rig.size(); ++c) {
    if (!positions.centre_in_rig[c] || !rs.rot.cam_from_rig[c]) continue;
    const Eigen::Quaterniond r = *rs.rot.cam_from_rig[c];
    cam_from_rig[c] = Rigid3d(r, -(r * (unit * *positions.centre_in_rig[c])));
  }
  for (size_t k = 0; k < rig_from_world.size(); ++k) {
    if (!positions.rig_centre_in_world[k] || !motion.rig_rotation[k]) continue;
    const Eigen::Quaterniond r = *motion.rig_rotation[k];
    rig_from_world[k] = Rigid3d(r, -(r * (unit * *positions.rig_centre_in_world[k])));
  }
  return s;
}

PositionStage EstimateInitialPoses(const RigObservations& obs, const RotationStage& rs,
                                                const RigMotion& motion, const std::vector<ViewTrack>& tracks,
                                                const RigCalibrationOptions& options) {
  PositionStage s;
  s.remedy = PositionRemedy(motion, static_cast<int>(obs.keypoints.size()));
  if (obs.HasMotionLinks()) s.held_axis = HeldCentreAxes(obs, tracks);
  const RigPositions from_directions = EstimateRigPositionsFromDirections(rs.graph, obs.temporal, rs.rot.cam_from_rig,
                                                                          motion.rig_rotation, !motion.moving);
  const RigPositions from_tracks = EstimateRigPositions(obs.cameras, obs.keypoints, tracks, rs.rot.cam_from_rig,
                                                        motion.rig_rotation, options.positions, !motion.moving,
                                                        s.held_axis);
  s.eigenvalue_ratio = from_tracks.eigenvalue_ratio;
  if (!motion.moving) {
    // Static rig: the pairs' scales are linked only by a parallel-rigid graph or by points seen by
    // three or more cameras.
    int multi_view_tracks = 0;
    for (const ViewTrack& t : tracks) multi_view_tracks += t.observations.size() >= 3;
    if (!EstimateCameraCentres(rs.graph, rs.rot.cam_from_rig, 0).unique && multi_view_tracks < 10) {
      s.position_reason = "not observable: the cameras' pairs do not link their scales (only " +
                          std::to_string(multi_view_tracks) +
                          " points seen by three or more cameras) and there is no rig motion to link them (one "
                          "frame, or no matches between frames); " + s.remedy;
      return s;
    }
  }
  // The unit is a camera whose centre the images fix whole, where there is one.
  for (const bool whole : {true, false}) {
    for (const RigPositions* p : {&from_directions, &from_tracks}) {
      for (int c = 1; c < static_cast<int>(p->centre_in_rig.size()) && p->solved && s.scale_camera < 0; ++c) {
        if (whole && !s.held_axis.empty() && s.held_axis[c]) continue;
        if (p->centre_in_rig[c] && p->centre_in_rig[c]->norm() > 1e-9) s.scale_camera = c;
      }
    }
  }
  // With motion links the same-instant directions do not reach the cameras the motion placed (a
  // start without them would win on a cost over fewer views), nor hold open axes at zero.
  const bool tracks_only = obs.HasMotionLinks() && from_tracks.solved;
  if (s.scale_camera >= 0) {
    if (from_directions.solved && from_directions.centre_in_rig[s.scale_camera] && !tracks_only) {
      s.starts.push_back(ToStart("two-view directions", from_directions, rs, motion, s.scale_camera));
    }
    if (from_tracks.solved && from_tracks.centre_in_rig[s.scale_camera]) {
      s.starts.push_back(ToStart("tracks", from_tracks, rs, motion, s.scale_camera));
    }
  }
  if (s.starts.empty()) {
    s.position_reason = "not observable: " +
                        (!from_directions.reason.empty() ? from_directions.reason : from_tracks.reason) + "; " + s.remedy;
  }
  return s;
}

// The bundle adjustment's model of capture times when offsets or readouts are estimated: the
// frames' timestamps, the offsets started from each camera's own turns; nullopt otherwise. Throws
// std::invalid_argument when they are asked for and the frames cannot carry them.
std::optional<CaptureTiming> TimingModel(const RigObservations& obs, const RigMotion& motion,
                                         const CaptureTimeOptions& options) {
  if (!options.estimate_offsets && !options.estimate_readout) return std::nullopt;
  if (const auto why = WhyNoTimingModel(obs.frame_times_s)) throw std::invalid_argument("capture times: " + *why);
  if (!motion.moving) throw std::invalid_argument("capture times: the rig's motion between frames is not tracked");
  const int n = static_cast<int>(obs.cameras.size());
  CaptureTiming timing;
  timing.frame_times_s = obs.frame_times_s;
  timing.time_offset_s = options.estimate_offsets
                             ? StartTimeOffsets(n, obs.frame_times_s, obs.temporal, options.search)
                             : std::vector<double>(n, 0.0);
  timing.readout_s.assign(n, 0.0);
  timing.readout_bottom_to_top = obs.readout_bottom_to_top;
  timing.estimate_offsets = options.estimate_offsets;
  timing.estimate_readout = options.estimate_readout;
  return timing;
}

// Step 5: the bundle adjustment from every start; the one the images agree with best
// (TruncatedReprojectionCost) is kept. Another start that ends with a camera elsewhere makes that
// camera's position ambiguous (RigCalibrationOptions::max_start_disagreement_deg).
struct AdjustedRig {
  MultiFrameBundleAdjustmentResult ba;
  std::vector<RigStartSummary> starts;
  std::vector<std::string> ambiguous;  // per camera: why its position is ambiguous; empty if not
  // Per camera: why its rotation is ambiguous too (JudgeCamerasHeldByOneRivalledPair); empty if not.
  std::vector<std::string> rotation_ambiguous;
  int solved = 0, reused = 0;  // starts adjusted, and given back by the rounds' cache
};

// The angle (deg) between two estimates of the direction of a camera's centre from camera 0's.
std::optional<double> DirectionDifferenceDeg(const std::optional<Rigid3d>& a, const std::optional<Rigid3d>& b) {
  if (!a || !b) return std::nullopt;
  const Eigen::Vector3d ca = a->SourceOriginInTarget(), cb = b->SourceOriginInTarget();
  if (ca.norm() < 1e-12 || cb.norm() < 1e-12) return std::nullopt;
  return AngleBetweenDeg(ca, cb);
}

AdjustedRig AdjustFromEveryStart(const RigObservations& obs, const std::vector<ViewTrack>& tracks,
                                 const PositionStage& ps, const RigMotion& motion, const RigCalibrationOptions& options,
                                 RigAdjustmentCache* cache) {
  const int n = static_cast<int>(obs.cameras.size());
  AdjustedRig out;
  out.ambiguous.assign(n, "");
  out.rotation_ambiguous.assign(n, "");
  RigBundleAdjustmentOptions ba_options = options.bundle_adjustment;
  ba_options.keep_points = ba_options.keep_points || options.keep_details;
  if (obs.HasMotionLinks()) {
    ba_options.inter_camera_weight = InterCameraWeight(tracks, options.motion.max_inter_camera_weight);
    ba_options.held_centre_axis = ps.held_axis;
  }
  const std::optional<CaptureTiming> timing = TimingModel(obs, motion, options.capture_time);
  // Each start's adjustment is its own single-threaded solve: they run side by side, and each
  // gives the same bits as alone; one an earlier round solved on identical inputs is not solved
  // again. Its cost takes ba_options' error bound and angle, which are options.bundle_adjustment's.
  std::vector<MultiFrameBundleAdjustmentResult> adjusted(ps.starts.size());
  std::vector<char> reused(ps.starts.size(), 0);
  out.starts.resize(ps.starts.size());
  tbb::parallel_for(0, static_cast<int>(ps.starts.size()), [&](int i) {
    AdjustedStart a = cache->Adjust({obs.cameras, obs.keypoints, tracks, ps.starts[i].poses, ps.scale_camera,
                                     ba_options, !motion.moving, timing ? &*timing : nullptr});
    adjusted[i] = std::move(a.ba);
    reused[i] = a.reused;
    RigStartSummary& summary = out.starts[i];
    summary.source = ps.starts[i].source;
    summary.cost = a.cost;
    summary.observations = a.cost_observations;
  });
  out.reused = static_cast<int>(std::count(reused.begin(), reused.end(), 1));
  out.solved = static_cast<int>(adjusted.size()) - out.reused;
  if (adjusted.empty()) return out;
  size_t best = 0;
  for (size_t i = 1; i < adjusted.size(); ++i) {
    if (out.starts[i].cost < out.starts[best].cost) best = i;
  }
  out.starts[best].chosen = true;
  for (size_t i = 0; i < adjusted.size(); ++i) {
    for (int c = 1; c < n; ++c) {
      const auto diff = DirectionDifferenceDeg(adjusted[i].poses.cam_from_rig[c], adjusted[best].poses.cam_from_rig[c]);
      out.starts[i].direction_difference_deg.push_back(diff);
      if (i == best || !diff || *diff <= options.max_start_disagreement_deg) continue;
      if (out.starts[i].cost > options.min_start_cost_ratio * out.starts[best].cost) continue;
      out.ambiguous[c] = "ambiguous: the bundle adjustment started from the " + out.starts[i].source + " puts it " +
                         Fixed(*diff, 1) + " deg away from where the start from the " + out.starts[best].source +
                         " does (reprojection cost " + Fixed(out.starts[i].cost, 0) + " against " +
                         Fixed(out.starts[best].cost, 0) + " px^2; a wrong pair can make the wrong one fit best)";
    }
  }
  out.ba = std::move(adjusted[best]);
  return out;
}

// Step 5b: a camera placed by one pair only, whose matches fit a rival pose about as well
// (TwoViewEstimate::rival), has nothing that decides between the two poses unless the rig's motion
// links it to another camera: its position is ambiguous, and so is its rotation when the rival's
// is more than RigCalibrationOptions::max_rival_rotation_deg away.
void JudgeCamerasHeldByOneRivalledPair(const RigObservations& obs, const RotationStage& rs,
                                       const RigCalibrationOptions& options, AdjustedRig* adjusted) {
  const int n = static_cast<int>(obs.cameras.size());
  std::vector<char> rotated(n, 0), linked_across_time(n, 0);
  for (int c = 0; c < n; ++c) rotated[c] = rs.rot.cam_from_rig[c].has_value();
  for (size_t i = 0; rs.joint && i < obs.cross_time.size() && i < rs.joint->cross_time_used.size(); ++i) {
    const CrossTimePairEstimate& x = obs.cross_time[i];
    if (!rs.joint->cross_time_used[i] || x.cam_a == x.cam_b) continue;
    linked_across_time[x.cam_a] = linked_across_time[x.cam_b] = 1;
  }
  for (int c = 1; c < n; ++c) {
    if (!adjusted->ba.poses.cam_from_rig[c] || linked_across_time[c]) continue;
    const std::vector<int> held_by = PlacingEdges(rs.graph, rotated, c);
    if (held_by.size() != 1 || !obs.pairs[held_by[0]].two_view.rival) continue;
    const PairEstimate& p = obs.pairs[held_by[0]];
    const RivalPose& rival = *p.two_view.rival;
    const std::string why = "ambiguous: its one pair with a baseline, " + obs.camera_names[p.cam_a] + "-" +
                            obs.camera_names[p.cam_b] + ", fits another pose about as well, its baseline " +
                            Fixed(rival.direction_deg, 0) + " deg away and turned " + Fixed(rival.rotation_deg, 1) +
                            " deg (of the matches either explains, that pose fits " +
                            std::to_string(rival.rival_closer) + " closer, this one " +
                            std::to_string(rival.pose_closer) + "): points at one depth in one part of the view, "
                            "where a turn mimics the baseline's parallax";
    if (adjusted->ambiguous[c].empty()) adjusted->ambiguous[c] = why;
    if (rival.rotation_deg > options.max_rival_rotation_deg) adjusted->rotation_ambiguous[c] = why;
  }
}

// Step 6: the positions the bundle adjustment's covariance leaves undetermined are dropped
// (max_direction_std_deg), the unit scale is moved to a camera that kept its position, and a
// known distance makes the result metric.
struct ScaledRig {
  // cam_from_rig nullopt: no position; rig_from_world empty when positions are not observable.
  RigPoses poses;
  std::vector<std::string> undetermined;             // why a camera's adjusted position is dropped
  std::vector<PositionOutcome> position;              // kPlaced, or which of the two dropped it
  std::vector<std::string> rotation_dropped;          // why a camera's rotation is dropped too
  PerCamera<double> direction_std_deg;
  // Per camera whose centre is open along an axis (PositionStage::held_axis): its centre without
  // that component; nullopt otherwise.
  PerCamera<Eigen::Vector3d> partial_centre, open_axis;
  double length_scale = 1.0;  // the bundle adjustment's unit of length in the result's
  int unit_camera = -1;       // whose distance from camera 0 is the unit; -1: none
  ScaleKind scale_kind = ScaleKind::kNone;
  std::string scale;
  std::vector<std::string> warnings;
};

ScaledRig DropUndeterminedAndScale(const RigObservations& obs, AdjustedRig& adjusted, const PositionStage& ps,
                                     const RigCalibrationOptions& options) {
  const int n = static_cast<int>(obs.cameras.size());
  MultiFrameBundleAdjustmentResult& ba = adjusted.ba;
  ScaledRig out;
  out.poses.cam_from_rig = ba.poses.cam_from_rig;
  out.undetermined.assign(n, "");
  out.position.assign(n, PositionOutcome::kPlaced);
  out.rotation_dropped.assign(n, "");
  out.direction_std_deg.assign(n, std::nullopt);
  PerCamera<Rigid3d>& pose = out.poses.cam_from_rig;
  for (int c = 1; c < n && c < static_cast<int>(ba.centre_covariance.size()); ++c) {
    if (!pose[c] || !ba.centre_covariance[c]) continue;
    const double std_deg = DirectionStdDeg(pose[c]->SourceOriginInTarget(), *ba.centre_covariance[c]);
    out.direction_std_deg[c] = std_deg;
    // The bound was measured on deviations that count every residual as independent: it is held
    // against those, not against the wider ones that count residuals moving together by region.
    if (*PlacementDirectionStdDeg(ba, c, pose[c]->SourceOriginInTarget()) > options.max_direction_std_deg) {
      const char* why = HasIntrinsicsShare(ba, c) ? "with the given intrinsics' uncertainty"
                                                  : "cameras close together for the depth of the scene";
      out.undetermined[c] = "not determined: the images fix its direction from " + obs.camera_names[0] + " to +-" +
                            Fixed(std_deg, 1) + " deg only (" + why + "); " + ps.remedy;
      out.position[c] = PositionOutcome::kNotDetermined;
      pose[c].reset();  // its adjusted rotation is kept (from ba)
    }
  }
  for (int c = 1; c < n; ++c) {
    if (!pose[c] || adjusted.ambiguous[c].empty()) continue;
    out.undetermined[c] = adjusted.ambiguous[c] + "; " + ps.remedy;
    out.position[c] = PositionOutcome::kAmbiguous;
    pose[c].reset();
  }
  for (int c = 1; c < n; ++c) {  // whether or not the covariance dropped its position already
    if (adjusted.rotation_ambiguous[c].empty()) continue;
    out.rotation_dropped[c] = adjusted.rotation_ambiguous[c] + "; " + ps.remedy;
    out.position[c] = PositionOutcome::kAmbiguous;
    pose[c].reset();
  }
  int scale_camera = ps.scale_camera;
  if (scale_camera >= 0 && !pose[scale_camera]) {  // the unit was a camera without a position now
    scale_camera = -1;
    for (int c = 1; c < n && scale_camera < 0; ++c) {
      if (pose[c] && pose[c]->translation.norm() > 1e-12) scale_camera = c;
    }
    if (scale_camera >= 0) {
      out.length_scale = 1.0 / pose[scale_camera]->translation.norm();
      ScaleTranslations(out.length_scale, &pose, &ba.poses.rig_from_world);
    }
  }
  if (!ps.starts.empty()) out.poses.rig_from_world = ba.poses.rig_from_world;
  out.unit_camera = scale_camera;
  out.scale_kind = scale_camera >= 0 ? ScaleKind::kUnit : ScaleKind::kNone;
  out.scale = scale_camera >= 0 ? "unit scale: |centre of " + obs.camera_names[scale_camera] + "| = 1"
                                : "no scale (no camera with a position besides " + obs.camera_names[0] + ")";
  if (!options.known_distance) return out;
  const MetricScale metric = ScaleToKnownDistance(obs, *options.known_distance, &pose, &out.poses.rig_from_world);
  if (!metric.why_not.empty()) {
    out.warnings.push_back(metric.Warning());
    return out;
  }
  out.length_scale *= metric.factor;
  out.scale_kind = ScaleKind::kMetric;
  out.scale = metric.scale;
  return out;
}

// Step 6b: a camera placed but for an axis the motion leaves open has no full pose: its centre
// without that component is kept apart, never the held value.
void SetAsideOpenAxes(const RigObservations& obs, const PositionStage& ps, ScaledRig* scaled) {
  scaled->partial_centre.assign(obs.cameras.size(), std::nullopt);
  scaled->open_axis.assign(obs.cameras.size(), std::nullopt);
  for (size_t c = 1; c < ps.held_axis.size(); ++c) {
    if (!ps.held_axis[c] || !scaled->poses.cam_from_rig[c]) continue;
    const Eigen::Vector3d& axis = *ps.held_axis[c];
    const Eigen::Vector3d centre = scaled->poses.cam_from_rig[c]->SourceOriginInTarget();
    scaled->partial_centre[c] = centre - axis * axis.dot(centre);
    scaled->open_axis[c] = axis;
    scaled->position[c] = PositionOutcome::kOpenAlongTurnAxis;
    scaled->undetermined[c] = OpenAxisReason(axis);
    scaled->poses.cam_from_rig[c].reset();
  }
}

// Why edge `e` of the view graph is inactive: `rejected` (EstimateRigOnce), a rotation outlier, or
// what the view graph left out (a failed pair, or one with too few inliers).
EdgeOutcome InactiveEdgeOutcome(const RigObservations& obs, const RotationStage& rs,
                                const std::vector<std::string>& rejected, int e) {
  if (!rejected[e].empty()) return EdgeOutcome::kRejected;
  if (rs.rot.outlier[e]) return EdgeOutcome::kRotationOutlier;
  return obs.pairs[e].two_view.success ? EdgeOutcome::kTooFewInliers : EdgeOutcome::kTwoViewFailed;
}

// Step 7: status per camera (calibrated, rotation only and why, not connected and why) and per
// edge (used or why not), into `result`.
void SetCameraAndEdgeStatus(const RigObservations& obs, const RotationStage& rs, const std::vector<std::string>& rejected,
                            const MultiFrameBundleAdjustmentResult& ba, const ScaledRig& scaled,
                            const std::string& position_reason, RigCalibrationResult* result) {
  const int n = static_cast<int>(obs.cameras.size());
  const ViewGraph& graph = rs.graph;
  const RotationAveragingResult& rot = rs.rot;
  std::vector<char> reached(n, 0), rotated(n, 0);
  for (int c = 0; c < n; ++c) {
    reached[c] = scaled.poses.cam_from_rig[c].has_value();
    rotated[c] = rot.cam_from_rig[c].has_value() && scaled.rotation_dropped[c].empty();
  }
  result->cam_from_rig_rotation = rot.cam_from_rig;
  result->partial_centre.assign(n, std::nullopt);
  result->open_axis.assign(n, std::nullopt);
  for (int c = 0; c < n; ++c) {  // the adjusted rotation, also of a camera whose position is not determined
    if (ba.poses.cam_from_rig[c]) result->cam_from_rig_rotation[c] = ba.poses.cam_from_rig[c]->rotation;
    if (!scaled.rotation_dropped[c].empty()) result->cam_from_rig_rotation[c].reset();
  }
  for (int c = 0; c < n; ++c) {
    result->camera_stats[c].observations = ba.observations_per_camera[c];
    if (scaled.poses.cam_from_rig[c]) {
      result->rig.cameras[c].cam_from_rig = scaled.poses.cam_from_rig[c];
      result->camera_status[c] = {CameraOutcome::kCalibrated, PositionOutcome::kPlaced,
                                  c == 0 ? "reference: rig frame" : ""};
      if (c != 0 && ba.observations_per_camera[c] == 0) {
        result->warnings.push_back(obs.camera_names[c] + " has no bundle-adjustment observation: its pose comes "
                                   "from the view graph alone");
      }
    } else if (rotated[c] && scaled.position[c] == PositionOutcome::kOpenAlongTurnAxis) {
      result->camera_status[c] = {CameraOutcome::kOpenAlongAxis, PositionOutcome::kOpenAlongTurnAxis,
                                  scaled.undetermined[c]};
      result->partial_centre[c] = scaled.partial_centre[c];
      result->open_axis[c] = scaled.open_axis[c];
    } else if (rotated[c]) {
      const bool dropped = !scaled.undetermined[c].empty();
      result->camera_status[c] = {
          CameraOutcome::kRotationOnly, dropped ? scaled.position[c] : PositionOutcome::kNotObservable,
          dropped                    ? scaled.undetermined[c]
          : !position_reason.empty() ? position_reason
                                     : std::string("not observable: no track links its views to the calibrated "
                                                   "cameras' (only rotation-only pairs or too little parallax); to "
                                                   "place it: more overlap with a placed camera, or more frames "
                                                   "while the rig moves")};
    } else if (!scaled.rotation_dropped[c].empty()) {
      result->camera_status[c] = {CameraOutcome::kNotConnected, PositionOutcome::kAmbiguous, scaled.rotation_dropped[c]};
    } else {
      result->camera_status[c] = {CameraOutcome::kNotConnected, PositionOutcome::kNotObservable,
                                  NotConnectedReason(graph, c, rotated, obs.camera_names)};
    }
  }
  WarnAboutCamerasHeldByOneWeakPair(graph, obs, rotated, reached, &result->warnings);
  for (int e = 0; e < static_cast<int>(graph.edges.size()); ++e) {
    const ViewGraphEdge& g = graph.edges[e];
    RigEdgeStats s;
    s.cam_a = obs.camera_names[g.cam_a];
    s.cam_b = obs.camera_names[g.cam_b];
    s.inliers = g.weight;
    const bool placed = reached[g.cam_a] && reached[g.cam_b];
    s.outcome = !g.active                               ? InactiveEdgeOutcome(obs, rs, rejected, e)
                : !(rotated[g.cam_a] && rotated[g.cam_b]) ? EdgeOutcome::kCameraNotCalibrated
                : placed                                  ? EdgeOutcome::kUsed
                                                          : EdgeOutcome::kUsedRotationOnly;
    s.rotation_only = g.rotation_only;
    if (std::isfinite(rot.residual_deg[e])) s.rotation_residual_deg = rot.residual_deg[e];
    s.status = s.Used() ? (placed ? "used" : "used (rotation only)")
                        : g.active ? "not used: camera not calibrated" : g.inactive_reason;
    result->edges.push_back(s);
  }
}

// Steps 1-4, before the bundle adjustment; their counts and times go into `result`.
struct EarlyStages {
  RotationStage rotations;
  RigMotion motion;
  std::vector<ViewTrack> tracks;
  PositionStage initial;
};

EarlyStages RunEarlyStages(const RigObservations& obs, const RigCalibrationOptions& options,
                           const std::vector<std::string>& rejected, RigCalibrationResult* result) {
  const int num_frames = static_cast<int>(obs.keypoints.size());
  EarlyStages s;
  auto start = StageClock::now();
  s.rotations = AverageCameraRotations(obs, options, rejected);
  result->num_rotation_outliers = s.rotations.rot.num_outliers;
  result->work.rotation_averaging_time_s = SecondsSince(start);

  start = StageClock::now();
  s.motion = EstimateRigMotion(obs, s.rotations, num_frames);
  result->num_frames = num_frames;
  result->rig_motion_estimated = s.motion.moving;
  result->num_temporal_pairs_used = s.motion.temporal_pairs_used;
  if (s.rotations.joint) {
    for (char used : s.rotations.joint->cross_time_used) result->num_cross_time_pairs_used += used;
    result->num_rotation_outliers += s.rotations.joint->rotations.num_outliers;
  }
  s.tracks = TracksOfUsedPairs(obs, s.rotations, s.motion, num_frames, &result->num_conflicting_tracks);
  result->num_tracks = static_cast<int>(s.tracks.size());
  result->work.tracks_time_s = SecondsSince(start);

  start = StageClock::now();
  s.initial = EstimateInitialPoses(obs, s.rotations, s.motion, s.tracks, options);
  result->position_eigenvalue_ratio = s.initial.eigenvalue_ratio;
  for (int k = 0; k < num_frames; ++k) result->num_frames_posed += s.motion.rig_rotation[k].has_value();
  result->work.positions_time_s = SecondsSince(start);
  return s;
}

// Which cameras the early stages give a rotation and a start position, and their rotations.
void PreCheckEarlyStages(const EarlyStages& early, int n, RigPreCheck* check) {
  check->cam_from_rig_rotation = early.rotations.rot.cam_from_rig;
  check->may_be_placed.assign(n, 0);
  for (int c = 0; c < n; ++c) {
    const bool positioned = c == 0 || std::any_of(early.initial.starts.begin(), early.initial.starts.end(),
                                                  [c](const PoseStart& s) { return s.poses.cam_from_rig[c].has_value(); });
    check->may_be_placed[c] = check->cam_from_rig_rotation[c] && positioned;
  }
}

// Steps 6-8 of a round from its adjustment: placement, scale, statuses, the capture times as
// `synchronisation` judges them (empty: not checked), and each pair against the rig.
RigCalibrationResult FinishRound(const RigObservations& obs, const RigCalibrationOptions& options,
                                 const std::vector<std::string>& rejected, const EarlyStages& early,
                                 AdjustedRig adjusted, const std::vector<CameraSynchronisation>& synchronisation,
                                 RigCalibrationResult result) {
  const int n = static_cast<int>(obs.cameras.size());
  const int num_frames = static_cast<int>(obs.keypoints.size());
  const auto& [rotations, motion, tracks, initial] = early;
  const MultiFrameBundleAdjustmentResult& ba = adjusted.ba;
  SetRefinedIntrinsics(obs, options, ba, &result);
  ScaledRig scaled = DropUndeterminedAndScale(obs, adjusted, initial, options);
  SetAsideOpenAxes(obs, initial, &scaled);
  const JackknifeSpread jackknife = LargerSpread(ba.frame_jackknife, ba.point_jackknife);
  for (int c = 0; c < n; ++c) {
    RigCameraStats& stats = result.camera_stats[c];
    stats.direction_std_deg = scaled.direction_std_deg[c];
    if (stats.direction_std_deg && c < static_cast<int>(jackknife.direction_std_deg.size())) {
      stats.direction_jackknife_std_deg = jackknife.direction_std_deg[c];
    }
    if (c < static_cast<int>(ba.rotation_stddev_deg.size()) && scaled.rotation_dropped[c].empty()) {
      stats.rotation_std_deg = ba.rotation_stddev_deg[c];
      if (c < static_cast<int>(jackknife.rotation_std_deg.size())) stats.rotation_jackknife_std_deg = jackknife.rotation_std_deg[c];
    }
    SetIntrinsicsShare(ba, c, &stats);
  }
  result.rig_from_world = scaled.poses.rig_from_world;
  result.scale = scaled.scale;
  result.scale_kind = scaled.scale_kind;
  result.unit_camera = scaled.unit_camera;
  if (motion.moving && result.num_frames_posed < num_frames) {
    result.warnings.push_back(std::to_string(num_frames - result.num_frames_posed) + " of " +
                              std::to_string(num_frames) +
                              " frames have no rig pose (no temporal pair chains them to frame 0); their views "
                              "are not used");
  }
  result.warnings.insert(result.warnings.end(), scaled.warnings.begin(), scaled.warnings.end());
  SetCameraAndEdgeStatus(obs, rotations, rejected, ba, scaled, initial.position_reason, &result);
  SetCaptureTimes(obs, options.capture_time, ba, synchronisation, &result);
  CompareEdgesWithRig(obs, &result);
  if (options.keep_details) {
    result.details = std::make_shared<RigCalibrationDetails>();
    RigCalibrationDetails& d = *result.details;
    d.rotation_averaging = rotations.rot.cam_from_rig;
    for (const Eigen::Vector3d& x : ba.points) d.points.push_back(scaled.length_scale * x);
    d.point_observations = ba.point_observations;
    d.initial_residuals_px = ba.initial_residuals_px;
    d.final_residuals_px = ba.final_residuals_px;
  }
  return result;
}

// One round of the rig stages, its adjustments through the rounds' `cache`; `last_round`: the
// rounds keep it whatever its pairs say. With `stop`: nullopt, and `stop` filled but for its work,
// where the early stages leave a camera without a rotation or a start position.
std::optional<RigCalibrationResult> EstimateRigOnce(const RigObservations& obs, const RigCalibrationOptions& options,
                                                    const std::vector<std::string>& rejected, bool last_round,
                                                    RigAdjustmentCache* cache, RigPreCheck* stop) {
  const int n = static_cast<int>(obs.cameras.size());
  const int num_frames = static_cast<int>(obs.keypoints.size());
  RigCalibrationResult result;
  for (int c = 0; c < n; ++c) result.rig.cameras.push_back({obs.camera_names[c], obs.cameras[c], std::nullopt, 0.0});
  result.camera_stats.assign(n, {});
  result.camera_status.assign(n, CameraStatus{});
  const EarlyStages early = RunEarlyStages(obs, options, rejected, &result);
  if (stop) {
    PreCheckEarlyStages(early, n, stop);
    if (stop->SomeCameraWithoutFullPose()) {
      stop->work = result.work;
      return std::nullopt;
    }
  }
  const auto& [rotations, motion, tracks, initial] = early;

  // Step 5: bundle adjustment over all posed views, from every start.
  auto start = StageClock::now();
  AdjustedRig adjusted = AdjustFromEveryStart(obs, tracks, initial, motion, options, cache);
  result.work.start_adjustments_solved = adjusted.solved;
  result.work.start_adjustments_reused = adjusted.reused;
  MultiFrameBundleAdjustmentResult& ba = adjusted.ba;
  if (initial.starts.empty()) {
    ba.poses.cam_from_rig.assign(n, std::nullopt);
    ba.poses.cam_from_rig[0] = Rigid3d();
    ba.poses.rig_from_world.assign(num_frames, std::nullopt);
    ba.poses.rig_from_world[0] = Rigid3d();
    ba.observations_per_camera.assign(n, 0);
  }
  JudgeCamerasHeldByOneRivalledPair(obs, rotations, options, &adjusted);
  result.work.bundle_adjustment_time_s = SecondsSince(start);
  result.position_starts = adjusted.starts;
  SetAdjustmentSummary(ba, &result);

  // The synchronisation check costs about as much as the adjustment, and only the round the rounds
  // keep needs it: a round with a pair to leave out is judged without it. The check only takes
  // poses away, so pairs that agree with the rig without it agree with it too.
  if (!last_round) {
    RigCalibrationResult unchecked = FinishRound(obs, options, rejected, early, adjusted, {}, result);
    if (MostDisagreeingEdge(unchecked, options).first >= 0) return unchecked;
  }
  start = StageClock::now();
  const std::vector<CameraSynchronisation> synchronisation =
      CheckCaptureTimes(obs, options.capture_time, options.bundle_adjustment, motion.moving, tracks,
                        initial.scale_camera, ba);
  result.work.synchronisation_check_time_s = SecondsSince(start);
  result.work.rounds_checked_for_capture_times = 1;
  return FinishRound(obs, options, rejected, early, std::move(adjusted), synchronisation, std::move(result));
}

// Throws std::invalid_argument on bad options (a known distance naming an unknown camera among
// them) or inconsistent observations.
void CheckInputs(const RigObservations& obs, const RigCalibrationOptions& options) {
  options.Check();
  const int n = static_cast<int>(obs.cameras.size());
  if (n < 1 || static_cast<int>(obs.camera_names.size()) != n) {
    throw std::invalid_argument("EstimateRig: one name per camera, at least one camera");
  }
  if (obs.pairs.size() != obs.inliers.size()) throw std::invalid_argument("EstimateRig: pairs and inliers differ in size");
  for (const auto& frame : obs.keypoints) {
    if (frame.size() != obs.cameras.size()) throw std::invalid_argument("EstimateRig: keypoints need every camera per frame");
  }
  if (options.known_distance) KnownDistanceCameras(*options.known_distance, obs.camera_names, "EstimateRig");
}

}  // namespace

// Where the pair-rejection rounds stand: the pairs left out so far and why, the observations with
// the pairs whose direction was left out (a copy made only then), the result of the last round
// completed (nullopt before the first), and the adjustments the rounds solved (shared by the
// copies a resumed pass makes, EstimateRigFrom).
struct RigRounds {
  std::vector<std::string> rejected, direction_left_out;
  std::optional<RigObservations> kept;
  std::optional<RigCalibrationResult> result;
  int round = 0;  // of the estimate to run next: 0 the first, r after r pairs were left out
  std::shared_ptr<RigAdjustmentCache> adjustments = std::make_shared<RigAdjustmentCache>();
};

namespace {

// The rounds from `state` on (EstimateRig), or with `stop` EstimateRigUnlessUnplaced: then nullopt
// where a round's early stages leave a camera unplaced, with `stop` (its `rounds` the state to
// resume from, the work done so far in its `work`).
std::optional<RigCalibrationResult> EstimateRigRounds(const RigObservations& obs, const RigCalibrationOptions& options,
                                                      RigRounds state, RigPreCheck* stop) {
  CheckInputs(obs, options);
  // Every pair the rig used must agree with the rig it helped make: one that does not is left
  // out and the rig made again without it, the worst first.
  // A pair off in its direction only keeps its rotation and matches (max_direction_only_disagreement_deg):
  // in `state.kept` it is a rotation-only pair.
  if (state.rejected.empty()) state.rejected.assign(obs.pairs.size(), "");
  if (state.direction_left_out.empty()) state.direction_left_out.assign(obs.pairs.size(), "");
  for (;;) {
    options.Tell(state.round == 0 ? "placing the rig: rotations, tracks, bundle adjustment"
                                  : "placing the rig again without a pair that disagrees with it");
    std::optional<RigCalibrationResult> next =
        EstimateRigOnce(state.kept ? *state.kept : obs, options, state.rejected,
                        state.round == options.max_rejected_pairs, state.adjustments.get(), stop);
    if (!next) {
      stop->round = state.round;
      if (state.result) {
        stop->work += state.result->work;
        state.result->work = {};  // counted in the stop's work
      }
      stop->rounds = std::make_shared<RigRounds>(std::move(state));
      return std::nullopt;
    }
    if (state.result) next->work += state.result->work;  // a round is part of this pass
    state.result = std::move(next);
    const auto [edge, why] = MostDisagreeingEdge(*state.result, options);
    if (edge < 0 || state.round == options.max_rejected_pairs) break;
    ++state.round;
    const RigEdgeStats& worst = state.result->edges[edge];
    if (worst.rotation_disagreement_deg.value_or(0.0) <= 0.5 * options.max_pair_rotation_disagreement_deg &&
        worst.direction_disagreement_deg.value_or(0.0) <= options.max_direction_only_disagreement_deg) {
      state.direction_left_out[edge] = "rotation used, baseline direction left out: " + why;
      if (!state.kept) state.kept = obs;
      state.kept->pairs[edge].two_view.rotation_only = true;
      state.kept->pairs[edge].two_view.cam_b_from_cam_a.translation.setZero();
    } else {
      state.rejected[edge] = why;
    }
  }
  RigCalibrationResult result = *std::move(state.result);
  result.work.rig_passes = 1;
  for (int e = 0; e < static_cast<int>(result.edges.size()); ++e) {
    RigEdgeStats& s = result.edges[e];
    s.direction_left_out = !state.direction_left_out[e].empty();
    if (s.direction_left_out && s.Used()) {
      s.outcome = EdgeOutcome::kDirectionLeftOut;
      s.status = state.direction_left_out[e];
    }
  }
  return result;
}

}  // namespace

RigCalibrationResult EstimateRig(const RigObservations& obs, const RigCalibrationOptions& options) {
  return *EstimateRigRounds(obs, options, {}, nullptr);
}

RigCalibrationResult EstimateRigFrom(const RigObservations& obs, const RigCalibrationOptions& options,
                                     const RigPreCheck& stop) {
  return *EstimateRigRounds(obs, options, stop.rounds ? *stop.rounds : RigRounds{}, nullptr);
}

std::optional<RigCalibrationResult> EstimateRigUnlessUnplaced(const RigObservations& obs,
                                                              const RigCalibrationOptions& options, RigPreCheck* stop) {
  *stop = RigPreCheck{};
  return EstimateRigRounds(obs, options, {}, stop);
}

void SetRefinedIntrinsics(const RigObservations& obs, const RigCalibrationOptions& options,
                          const MultiFrameBundleAdjustmentResult& ba, RigCalibrationResult* result) {
  const std::vector<Camera>& centres = options.bundle_adjustment.intrinsics_priors.centres;
  for (size_t c = 0; c < ba.intrinsics_stddev.size() && c < ba.cameras.size(); ++c) {
    if (ba.observations_per_camera[c] == 0) continue;
    const Camera& given = centres.empty() ? obs.cameras[c] : centres.at(c);
    result->rig.cameras[c].camera = ba.cameras[c];
    result->camera_stats[c].intrinsics =
        RefinedIntrinsics{given.params(), ba.cameras[c].params(), ba.intrinsics_stddev[c]};
  }
}

void SetAdjustmentSummary(const MultiFrameBundleAdjustmentResult& ba, RigCalibrationResult* result) {
  result->initial_reprojection_rms_px = ba.initial_rms_px;
  result->reprojection_rms_px = ba.reprojection_rms_px;
  result->residual_correlation = ba.residual_correlation;
  result->num_points = ba.num_points;
  result->num_observations = ba.num_observations;
  result->num_filtered_observations = ba.num_filtered_observations;
}

}  // namespace rigsim
