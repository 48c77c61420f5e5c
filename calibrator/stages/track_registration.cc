#include "calibrator/stages/track_registration.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include <tbb/parallel_for.h>

#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/model/tracks.h"
#include "common/format.h"

namespace rigsim {
namespace {

// The views the rig stage posed: cameras with a full pose, frames with a rig pose.
struct PlacedViews {
  RigPoses poses;
  std::vector<char> camera_placed;
  std::vector<int> frames;  // posed, in order
};

PlacedViews PlacedViewsOf(const RigCalibrationResult& placed, int n, int num_frames) {
  PlacedViews v;
  v.poses.cam_from_rig.assign(n, std::nullopt);
  v.poses.rig_from_world.assign(num_frames, std::nullopt);
  v.camera_placed.assign(n, 0);
  for (int c = 0; c < n && c < static_cast<int>(placed.rig.cameras.size()); ++c) {
    if (!HasFullPose(placed.camera_status[c].outcome) || !placed.rig.cameras[c].cam_from_rig) continue;
    v.poses.cam_from_rig[c] = placed.rig.cameras[c].cam_from_rig;
    v.camera_placed[c] = 1;
  }
  for (int f = 0; f < num_frames && f < static_cast<int>(placed.rig_from_world.size()); ++f) {
    if (!placed.rig_from_world[f]) continue;
    v.poses.rig_from_world[f] = placed.rig_from_world[f];
    v.frames.push_back(f);
  }
  return v;
}

// Placed points (world frame), and per view (frame * n + camera) which keypoint sees which point.
struct PlacedPoints {
  std::vector<Eigen::Vector3d> x;
  std::vector<std::unordered_map<int, int>> point_of;
};

PlacedPoints TriangulatePlacedTracks(const RigObservations& obs, const PlacedViews& views,
                                     const std::vector<ViewTrack>& tracks, const TrackRegistrationOptions& options) {
  const int n = static_cast<int>(obs.cameras.size());
  PlacedPoints out;
  out.point_of.resize(obs.keypoints.size() * n);
  const double min_angle = DegToRad(options.min_triangulation_angle_deg);
  for (const ViewTrack& t : tracks) {
    std::vector<Eigen::Vector3d> origins, dirs;
    std::vector<const ViewObservation*> used;
    for (const ViewObservation& o : t.observations) {
      if (!views.poses.Posed(o.camera, o.frame)) continue;
      const auto ray = obs.cameras[o.camera].CamFromImg(obs.keypoints[o.frame][o.camera][o.keypoint]);
      if (!ray) continue;
      const Rigid3d world_from_cam = views.poses.CamFromWorld(o.camera, o.frame).Inverse();
      origins.push_back(world_from_cam.translation);
      dirs.push_back((world_from_cam.rotation * *ray).normalized());
      used.push_back(&o);
    }
    const auto x = TriangulateRays(origins, dirs, min_angle);
    if (!x) continue;
    const bool fits = std::all_of(used.begin(), used.end(), [&](const ViewObservation* o) {
      const auto px = obs.cameras[o->camera].ImgFromCam(views.poses.CamFromWorld(o->camera, o->frame) * *x);
      return px && (*px - obs.keypoints[o->frame][o->camera][o->keypoint]).norm() <= options.max_track_error_px;
    });
    if (!fits) continue;
    const int id = static_cast<int>(out.x.size());
    out.x.push_back(*x);
    for (const ViewObservation* o : used) out.point_of[o->frame * n + o->camera].emplace(o->keypoint, id);
  }
  return out;
}

// With camera 0 the only placed camera, the rig stage poses no frame (nothing fixes a second
// camera's distance). Camera 0 is the rig frame, so its own motion is the rig's: frame 1 from its
// two-view estimate with frame 0 (a step of unit length), each later frame by resection against
// the points its earlier frames triangulate, as long as each step has a pose.
void PoseFramesFromReferenceMotion(const RigObservations& obs, const RigCalibrationResult& placed,
                                   const TrackRegistrationOptions& options, PlacedViews* views) {
  const int num_frames = static_cast<int>(obs.keypoints.size());
  const TemporalPairEstimate* first = nullptr;
  for (const TemporalPairEstimate& t : obs.temporal) {
    if (t.camera == 0 && t.frame == 0 && t.PoseUsable() && !t.two_view.rotation_only) first = &t;
  }
  if (num_frames < 2 || first == nullptr) return;
  views->poses.rig_from_world.assign(num_frames, std::nullopt);
  views->poses.rig_from_world[0] = Rigid3d();
  views->poses.rig_from_world[1] = first->two_view.cam_b_from_cam_a;
  views->frames = {0, 1};
  for (int f = 2; f < num_frames; ++f) {
    const TemporalPairEstimate* into = nullptr;
    for (const TemporalPairEstimate& t : obs.temporal) {
      if (t.camera == 0 && t.frame == f - 1 && t.two_view.success) into = &t;
    }
    if (into == nullptr) break;
    const PlacedPoints points =
        TriangulatePlacedTracks(obs, *views, TracksOfCameras(obs, placed, views->camera_placed), options);
    const int n = static_cast<int>(obs.cameras.size());
    const auto& point_of = points.point_of[(f - 1) * n];
    std::vector<RigResectionCorrespondence> correspondences;
    for (const auto& [ka, kb] : into->inliers) {
      const auto it = point_of.find(ka);
      if (it != point_of.end()) correspondences.push_back({obs.keypoints[f][0][kb], points.x[it->second]});
    }
    // Camera 0 is the rig frame: its pose in the world is the rig's.
    const RigResection r = ResectCameraInRig(obs.cameras[0], correspondences, options.resection);
    if (!r.success) break;
    views->poses.rig_from_world[f] = r.cam_from_rig;
    views->frames.push_back(f);
  }
}

// One view pair matched for a camera: its view (camera, frame) with a placed view.
struct ViewPairJob {
  int frame = -1;
  int other_camera = -1, other_frame = -1;
  std::vector<std::pair<int, int>> matches;
};

std::vector<ViewPairJob> ViewPairsOf(const PlacedViews& views, int camera, const TrackRegistrationOptions& options) {
  std::vector<ViewPairJob> jobs;
  for (int f : views.frames) {
    for (int p = 0; p < static_cast<int>(views.camera_placed.size()); ++p) {
      if (!views.camera_placed[p] || p == camera) continue;
      for (int g : views.frames) {
        if (std::abs(g - f) <= options.frame_reach) jobs.push_back({f, p, g, {}});
      }
    }
  }
  // Spread over the frames: every k-th of the pairs in frame order.
  const int max_jobs = options.max_view_pairs_per_camera;
  if (static_cast<int>(jobs.size()) <= max_jobs) return jobs;
  std::vector<ViewPairJob> spread;
  for (int i = 0; i < max_jobs; ++i) spread.push_back(jobs[static_cast<size_t>(i) * jobs.size() / max_jobs]);
  return spread;
}

// Camera `c`'s pose in the rig from its view pairs' matches with placed points.
CameraRegistration Register(const RigObservations& obs, const RigCalibrationResult& placed, const PlacedViews& views,
                            const PlacedPoints& points, int c, std::vector<ViewPairJob> jobs,
                            const TrackRegistrationOptions& options) {
  const int n = static_cast<int>(obs.cameras.size());
  CameraRegistration reg;
  reg.camera = c;
  reg.view_pairs_matched = static_cast<int>(jobs.size());
  std::vector<RigResectionCorrespondence> correspondences;
  std::vector<std::pair<int, int>> source;  // per correspondence: (job, match)
  for (int j = 0; j < static_cast<int>(jobs.size()); ++j) {
    const ViewPairJob& job = jobs[j];
    const auto& point_of = points.point_of[job.other_frame * n + job.other_camera];
    const Rigid3d& rig_from_world = *views.poses.rig_from_world[job.frame];
    for (int m = 0; m < static_cast<int>(job.matches.size()); ++m) {
      const auto it = point_of.find(job.matches[m].second);
      if (it == point_of.end()) continue;
      correspondences.push_back({obs.keypoints[job.frame][c][job.matches[m].first], rig_from_world * points.x[it->second]});
      source.emplace_back(j, m);
    }
  }
  reg.correspondences = static_cast<int>(correspondences.size());
  const RigResection r = ResectCameraInRig(obs.cameras[c], correspondences, options.resection);
  reg.inliers = static_cast<int>(r.inliers.size());
  reg.log10_false_alarms = r.log10_false_alarms;
  if (!r.success) {
    reg.reason = r.reason;
    return reg;
  }
  const auto& known = placed.cam_from_rig_rotation.size() > static_cast<size_t>(c) ? placed.cam_from_rig_rotation[c]
                                                                                   : std::nullopt;
  if (known) {
    const double d = RotationDifferenceDeg(*known, r.cam_from_rig.rotation);
    if (d > options.max_rotation_disagreement_deg) {
      reg.reason = "the pose its " + std::to_string(reg.inliers) + " matches with placed points give is turned " +
                   Fixed(d, 1) + " deg from the rotation its pairs give";
      return reg;
    }
  }
  reg.registered = true;
  reg.cam_from_rig = r.cam_from_rig;
  std::vector<std::vector<std::pair<int, int>>> inliers(jobs.size());
  for (int i : r.inliers) inliers[source[i].first].push_back(jobs[source[i].first].matches[source[i].second]);
  for (int j = 0; j < static_cast<int>(jobs.size()); ++j) {
    if (static_cast<int>(inliers[j].size()) < options.min_view_pair_inliers) continue;
    const ViewPairJob& job = jobs[j];
    CrossTimePairEstimate x;
    x.cam_a = c;
    x.frame_a = job.frame;
    x.cam_b = job.other_camera;
    x.frame_b = job.other_frame;
    const Rigid3d a_from_world = r.cam_from_rig * *views.poses.rig_from_world[job.frame];
    Rigid3d b_from_a = views.poses.CamFromWorld(job.other_camera, job.other_frame) * a_from_world.Inverse();
    TwoViewEstimate& tv = x.two_view;
    tv.success = true;
    tv.failure = TwoViewFailure::kNone;
    const double baseline = b_from_a.translation.norm();
    tv.rotation_only = !(baseline > 1e-9);
    tv.pair_type = tv.rotation_only ? PairType::kRotationOnly : PairType::kGeneral;
    if (!tv.rotation_only) b_from_a.translation /= baseline;
    else b_from_a.translation.setZero();
    tv.cam_b_from_cam_a = b_from_a;
    tv.num_matches = static_cast<int>(job.matches.size());
    tv.num_inliers = static_cast<int>(inliers[j].size());
    x.inliers = std::move(inliers[j]);
    reg.view_pairs.push_back(std::move(x));
  }
  return reg;
}

}  // namespace

bool TrackRegistration::AnyRegistered() const {
  return std::any_of(cameras.begin(), cameras.end(), [](const CameraRegistration& c) { return c.registered; });
}

TrackRegistration RegisterCamerasThroughTracks(const RigObservations& obs, const RigCalibrationResult& placed,
                                               const ViewPairMatcher& match, const TrackRegistrationOptions& options) {
  options.Check();
  const int n = static_cast<int>(obs.cameras.size());
  const int num_frames = static_cast<int>(obs.keypoints.size());
  if (static_cast<int>(placed.camera_status.size()) != n) {
    throw std::invalid_argument("RegisterCamerasThroughTracks: the result has another number of cameras");
  }
  TrackRegistration out;
  PlacedViews views = PlacedViewsOf(placed, n, num_frames);
  if (views.frames.size() < 2 && std::count(views.camera_placed.begin(), views.camera_placed.end(), 1) == 1) {
    PoseFramesFromReferenceMotion(obs, placed, options, &views);
  }
  if (views.frames.empty()) {
    out.why_none = "no frame has a rig pose to register it against: the reference camera's own motion has no baseline "
                   "(the rig stood still or only turned)";
    return out;
  }
  out.placed_poses = views.poses;
  const PlacedPoints points = TriangulatePlacedTracks(obs, views, TracksOfCameras(obs, placed, views.camera_placed), options);
  if (points.x.empty()) {
    out.why_none = "the placed cameras' views give no point to register it against: their rays meet at under " +
                   Fixed(options.min_triangulation_angle_deg, 1) +
                   " deg (the rig stood still or only turned, and no pair with a baseline was placed)";
    return out;
  }
  for (int c = 1; c < n; ++c) {
    if (views.camera_placed[c]) continue;
    const CameraOutcome o = placed.camera_status[c].outcome;
    if (o != CameraOutcome::kNotConnected && o != CameraOutcome::kRotationOnly) continue;
    std::vector<ViewPairJob> jobs = ViewPairsOf(views, c, options);
    tbb::parallel_for(0, static_cast<int>(jobs.size()), [&](int j) {
      jobs[j].matches = match(c, jobs[j].frame, jobs[j].other_camera, jobs[j].other_frame);
    });
    out.cameras.push_back(Register(obs, placed, views, points, c, std::move(jobs), options));
  }
  return out;
}

std::vector<ViewTrack> TracksOfCameras(const RigObservations& obs, const RigCalibrationResult& placed,
                                       const std::vector<char>& cameras) {
  const int num_frames = static_cast<int>(obs.keypoints.size());
  std::vector<PairMatches> pairs;
  for (size_t p = 0; p < obs.pairs.size(); ++p) {
    const PairEstimate& e = obs.pairs[p];
    if (!cameras[e.cam_a] || !cameras[e.cam_b] || !e.two_view.success) continue;
    if (p < placed.edges.size() && !placed.edges[p].Used()) continue;
    if (static_cast<int>(obs.inliers[p].per_frame.size()) == num_frames) pairs.push_back(obs.inliers[p]);
  }
  std::vector<TemporalPairEstimate> temporal;
  for (const TemporalPairEstimate& t : obs.temporal) {
    if (t.two_view.success && cameras[t.camera]) temporal.push_back(t);
  }
  std::vector<CrossTimePairEstimate> cross_time;
  for (const CrossTimePairEstimate& x : obs.cross_time) {
    if (x.two_view.success && cameras[x.cam_a] && cameras[x.cam_b]) cross_time.push_back(x);
  }
  return BuildViewTracksAcrossTime(static_cast<int>(obs.cameras.size()), num_frames, pairs, temporal, cross_time);
}

RigObservations WithRegisteredViewPairs(const RigObservations& obs, const TrackRegistration& registration) {
  RigObservations out = obs;
  for (const CameraRegistration& r : registration.cameras) {
    if (r.registered) out.cross_time.insert(out.cross_time.end(), r.view_pairs.begin(), r.view_pairs.end());
  }
  return out;
}

}  // namespace rigsim
