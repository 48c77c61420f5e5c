#include "calibrator/calibrator_test_support.h"

#include <map>
#include <utility>
#include <vector>

namespace rigsim {

ViewPairMatcher SyntheticMatcher(const SyntheticRig& s) {
  return [&s](int cam_a, int frame_a, int cam_b, int frame_b) {
    std::vector<std::pair<int, int>> m = s.TrueMatches({frame_a, cam_a}, {frame_b, cam_b});
    const int na = static_cast<int>(s.keypoints[frame_a][cam_a].size());
    const int nb = static_cast<int>(s.keypoints[frame_b][cam_b].size());
    const int wrong = static_cast<int>(m.size()) / 20 + 6;
    for (int i = 0; i < wrong && na > 0 && nb > 0; ++i) {
      m.push_back({(i * 7919 + 31 * frame_a + cam_a) % na, (i * 104729 + 17 * frame_b + cam_b) % nb});
    }
    return m;
  };
}

RigObservations ObserveSyntheticRig(SyntheticRig& s, const SyntheticObservationOptions& options) {
  const int cameras = static_cast<int>(s.rig.cameras.size());
  const int frames = static_cast<int>(s.rig_from_world.size());
  RigObservations obs;
  for (const RigCamera& rc : s.rig.cameras) {
    obs.camera_names.push_back(rc.name);
    obs.cameras.push_back(rc.camera);
  }
  obs.keypoints = s.keypoints;
  for (int a = 0; a < cameras; ++a) {
    for (int b = a + 1; b < cameras; ++b) {
      std::vector<std::vector<std::pair<int, int>>> per_frame;
      for (int k = 0; k < frames; ++k) per_frame.push_back(s.CandidateMatches({k, a}, {k, b}));
      auto [estimate, inliers] = EstimatePairFromMatches(obs.cameras, obs.keypoints, a, b, per_frame, options.two_view);
      obs.pairs.push_back(estimate);
      obs.inliers.push_back(std::move(inliers));
      obs.matches.push_back({a, b, std::move(per_frame)});
    }
  }
  for (int c = 0; c < cameras && options.temporal_pairs; ++c) {
    const Camera& camera = obs.cameras[c];
    for (int k = 0; k + 1 < frames; ++k) {
      const std::vector<std::pair<int, int>> m = s.CandidateMatches({k, c}, {k + 1, c});
      std::vector<Eigen::Vector2d> pa, pb;
      for (const auto& [i, j] : m) {
        pa.push_back(s.keypoints[k][c][i]);
        pb.push_back(s.keypoints[k + 1][c][j]);
      }
      const TwoViewResult tv = EstimateRelativePose(camera, pa, camera, pb, options.two_view);
      TemporalPairEstimate t;
      t.camera = c;
      t.frame = k;
      t.two_view = tv.estimate;
      t.matches = m;
      for (size_t i = 0; i < m.size() && tv.estimate.success; ++i) {
        if (tv.inlier_mask[i]) t.inliers.push_back(m[i]);
      }
      obs.temporal.push_back(std::move(t));
    }
  }
  return obs;
}

TimedRing::TimedRing(const std::vector<Rigid3d>& path, double noise_px, uint32_t seed,
                     const std::vector<double>& offsets_s, const std::vector<double>& readouts_s) {
  SyntheticRigOptions o;
  o.cameras.assign(3, Camera(CameraModelId::kPinhole, 640, 480, {300, 300, 319.5, 239.5}));
  o.ring_radius_m = 0.3;
  o.yaw_step_deg = 45.0;
  o.max_tilt_deg = 2.0;
  o.num_frames = static_cast<int>(path.size());
  o.path = path;
  o.num_points = 1500;
  o.noise_px = noise_px;
  o.distractor_fraction = 0.0;
  o.time_offset_s = offsets_s;
  o.readout_s = readouts_s;
  o.seed = seed;
  s = SynthesizeRig(o);
  std::map<int, ViewTrack> by_point;
  for (int k = 0; k < o.num_frames; ++k) {
    for (int c = 0; c < 3; ++c) {
      for (size_t i = 0; i < s.point_of[k][c].size(); ++i) {
        if (s.point_of[k][c][i] >= 0) by_point[s.point_of[k][c][i]].observations.push_back({c, k, static_cast<int>(i)});
      }
    }
  }
  for (auto& [point, track] : by_point) {
    if (track.observations.size() >= 2) tracks.push_back(track);
  }
  for (const RigCamera& rc : s.rig.cameras) cameras.push_back(rc.camera);
  for (int k = 0; k < o.num_frames; ++k) timing.frame_times_s.push_back(k * o.frame_interval_s);
  timing.time_offset_s.assign(3, 0.0);
  timing.readout_s.assign(3, 0.0);
  timing.estimate_offsets = true;
  timing.estimate_readout = true;
}

MultiFrameBundleAdjustmentResult TimedRing::Adjust(const CaptureTiming* with) const {
  std::vector<std::optional<Rigid3d>> cam_from_rig, rig_from_world;
  for (const RigCamera& rc : s.rig.cameras) cam_from_rig.push_back(*rc.cam_from_rig);
  for (const Rigid3d& p : s.rig_from_world) rig_from_world.push_back(p);
  RigBundleAdjustmentOptions options;
  options.filter_rounds = 0;
  return MultiFrameRigBundleAdjust(cameras, s.keypoints, tracks, {cam_from_rig, rig_from_world}, 1, options, false, with);
}

std::vector<CameraErrors> ErrorsAgainst(const Rig& truth, const RigCalibrationResult& result) {
  RigEstimate e;
  e.metric = result.scale_kind == ScaleKind::kMetric;
  for (size_t c = 0; c < result.rig.cameras.size(); ++c) {
    e.cam_from_rig.push_back(result.rig.cameras[c].cam_from_rig);
    e.rotation_only.push_back(e.cam_from_rig.back() ? std::nullopt : result.cam_from_rig_rotation.at(c));
    const bool open = c < result.open_axis.size() && result.open_axis[c] && result.partial_centre[c];
    e.open_axis.push_back(open ? std::optional<OpenAxisCentre>({*result.open_axis[c], *result.partial_centre[c]})
                               : std::nullopt);
  }
  return CalibrationCameraErrors(truth, e);
}

TwoCameraDrive MakeTwoCameraDrive(int frames, std::mt19937& rng) {
  TwoCameraDrive d;
  const Camera cam(CameraModelId::kPinhole, 640, 480, {400, 400, 319.5, 239.5});
  d.cameras = {cam, cam};
  const Eigen::Matrix3d r1 = Eigen::AngleAxisd(20.0 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  d.truth.cam_from_rig = {Rigid3d(), Rigid3d(r1, -(r1 * Eigen::Vector3d(1.0, 0.0, 0.1)))};
  for (int k = 0; k < frames; ++k) {
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(3.0 * k * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    d.truth.rig_from_world.push_back(Rigid3d(turn, -(turn * Eigen::Vector3d(0.5 * k, 0.0, 0.0))));
  }
  std::uniform_real_distribution<double> x(-4.0, 7.0), y(-2.0, 2.0), z(4.0, 12.0);
  while (d.points.size() < 400) {
    const Eigen::Vector3d p(x(rng), y(rng), z(rng));
    ViewTrack t;
    for (int k = 0; k < frames; ++k) {
      for (int c = 0; c < 2; ++c) {
        const Eigen::Vector3d in_cam = d.truth.CamFromWorld(c, k) * p;
        const auto px = cam.ImgFromCam(in_cam);
        if (in_cam.z() > 0 && px && cam.IsInImage(*px)) t.observations.push_back({c, k, static_cast<int>(d.points.size())});
      }
    }
    if (t.observations.size() < 3) continue;
    d.tracks.push_back(t);
    d.points.push_back(p);
  }
  return d;
}

FrameKeypoints ObserveTwoCameraDrive(const TwoCameraDrive& d, double noise_px, std::mt19937& rng, int jolted_frame,
                                     const Rigid3d& jolt) {
  std::normal_distribution<double> noise(0.0, noise_px);
  const int frames = static_cast<int>(d.truth.rig_from_world.size());
  FrameKeypoints kp(frames, std::vector<std::vector<Eigen::Vector2d>>(2));
  for (int k = 0; k < frames; ++k) {
    for (int c = 0; c < 2; ++c) {
      const Rigid3d cam_from_world =
          (k == jolted_frame && c == 1 ? jolt : Rigid3d()) * d.truth.CamFromWorld(c, k);
      for (const Eigen::Vector3d& p : d.points) {
        const Eigen::Vector2d px = d.cameras[c].ImgFromCam(cam_from_world * p).value_or(Eigen::Vector2d::Zero());
        kp[k][c].push_back(px + Eigen::Vector2d(noise(rng), noise(rng)));
      }
    }
  }
  return kp;
}

}  // namespace rigsim
