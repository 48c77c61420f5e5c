#include "testing/synthetic_rig.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "geometry/pose_interpolation.h"
#include "testing/test_name.h"

namespace rigsim {
namespace {

// cam_from_rig of the ring's cameras, camera 0 then made the rig frame.
std::vector<Rigid3d> RingPoses(const SyntheticRigOptions& o, std::mt19937& rng) {
  const int n = static_cast<int>(o.cameras.size());
  const double step = o.yaw_step_deg != 0.0 ? o.yaw_step_deg : 360.0 / n;
  std::uniform_real_distribution<double> tilt(-DegToRad(o.max_tilt_deg), DegToRad(o.max_tilt_deg));
  std::uniform_real_distribution<double> offset(-o.max_offset_m, o.max_offset_m);
  std::vector<Rigid3d> cam_from_rig;
  for (int i = 0; i < n; ++i) {
    const double yaw = DegToRad(step * i);
    const double tilt_x = tilt(rng), tilt_z = tilt(rng);
    const Eigen::Matrix3d rig_from_cam = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) *
                                          Eigen::AngleAxisd(tilt_x, Eigen::Vector3d::UnitX()) *
                                          Eigen::AngleAxisd(tilt_z, Eigen::Vector3d::UnitZ()))
                                             .toRotationMatrix();
    const double dx = offset(rng), dy = offset(rng), dz = offset(rng);
    const Eigen::Vector3d centre =
        o.ring_radius_m * Eigen::Vector3d(std::sin(yaw), 0, std::cos(yaw)) + Eigen::Vector3d(dx, dy, dz);
    const Eigen::Matrix3d r = rig_from_cam.transpose();
    cam_from_rig.push_back(Rigid3d(r, -r * centre));
  }
  const Rigid3d rig_from_cam0 = cam_from_rig[0].Inverse();
  for (Rigid3d& pose : cam_from_rig) pose = pose * rig_from_cam0;
  return cam_from_rig;
}

// `count` points around `anchor()` (a place drawn anew for each point).
template <typename Anchor>
void AddPoints(const SyntheticRigOptions& o, int count, Anchor anchor, std::mt19937& rng, std::vector<Eigen::Vector3d>* points,
               std::vector<int>* indices) {
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < count; ++i) {
    const double azimuth = 2 * std::numbers::pi * u(rng);
    const double elevation = DegToRad(o.max_elevation_deg * (2 * u(rng) - 1));
    const double distance = o.min_distance_m + (o.max_distance_m - o.min_distance_m) * u(rng);
    const Eigen::Vector3d direction(std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                                    std::cos(elevation) * std::cos(azimuth));
    indices->push_back(static_cast<int>(points->size()));
    points->push_back(anchor() + distance * direction);
  }
}

// The keypoints of one view of `visible` (indices into `points`), with distractors, shuffled.
// `cam_from_world_at_row(y)`: the view's pose when image row y is captured (a rolling shutter), the
// projection iterated to the row it lands on.
template <typename PoseAtRow>
void Observe(const SyntheticRigOptions& o, const Camera& camera, PoseAtRow cam_from_world_at_row,
             const std::vector<Eigen::Vector3d>& points, const std::vector<int>& visible, std::mt19937& rng,
             std::vector<Eigen::Vector2d>* keypoints, std::vector<int>* point_of) {
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> noise(0, 1);
  std::vector<Eigen::Vector2d> kps;
  std::vector<int> owner;
  for (int i : visible) {
    auto px = camera.ImgFromCam(cam_from_world_at_row(0.5 * (camera.height() - 1)) * points[i]);
    for (int iter = 0; iter < 6 && px; ++iter) px = camera.ImgFromCam(cam_from_world_at_row(px->y()) * points[i]);
    if (!px || !camera.IsInImage(*px)) continue;
    const double nx = noise(rng), ny = noise(rng);
    kps.push_back(*px + o.noise_px * Eigen::Vector2d(nx, ny));
    owner.push_back(i);
  }
  const int distractors = static_cast<int>(o.distractor_fraction * kps.size());
  for (int i = 0; i < distractors; ++i) {
    const double x = camera.width() * u(rng) - 0.5, y = camera.height() * u(rng) - 0.5;
    kps.push_back(Eigen::Vector2d(x, y));
    owner.push_back(-1);
  }
  std::vector<int> order(kps.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::shuffle(order.begin(), order.end(), rng);
  for (int i : order) {
    keypoints->push_back(kps[i]);
    point_of->push_back(owner[i]);
  }
}

// keypoint_of[point] of one view (-1 where the view has none).
std::vector<int> KeypointOf(const std::vector<int>& point_of, size_t num_points) {
  std::vector<int> keypoint_of(num_points, -1);
  for (size_t k = 0; k < point_of.size(); ++k) {
    if (point_of[k] >= 0) keypoint_of[point_of[k]] = static_cast<int>(k);
  }
  return keypoint_of;
}

}  // namespace

void SyntheticRigOptions::Check() const {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("SyntheticRigOptions: " + what);
  };
  require(!cameras.empty(), "cameras: at least one camera");
  for (int c : isolated_cameras) {
    require(c >= 0 && c < static_cast<int>(cameras.size()), "isolated_cameras: " + std::to_string(c) + " is not a camera");
  }
  require(num_frames >= 1, "num_frames must be at least 1");
  require(path.empty() || static_cast<int>(path.size()) == num_frames, "path: one pose per frame");
  require(time_offset_s.empty() || time_offset_s.size() == cameras.size(), "time_offset_s: one per camera, or none");
  require(readout_s.empty() || readout_s.size() == cameras.size(), "readout_s: one per camera, or none");
  require(frame_interval_s > 0, "frame_interval_s must be > 0");
  require(num_points >= 0, "num_points must not be negative");
  require(min_distance_m > 0 && max_distance_m >= min_distance_m, "min_distance_m..max_distance_m must be a positive range");
  require(max_elevation_deg >= 0 && max_elevation_deg <= 90, "max_elevation_deg must be in [0, 90]");
  require(path_margin_m >= 0, "path_margin_m must not be negative");
  require(noise_px >= 0 && distractor_fraction >= 0 && outlier_fraction >= 0 && min_outliers >= 0,
          "noise_px, distractor_fraction, outlier_fraction and min_outliers must not be negative");
  require(ring_radius_m >= 0 && max_tilt_deg >= 0 && max_offset_m >= 0,
          "ring_radius_m, max_tilt_deg and max_offset_m must not be negative");
}

SyntheticRig SynthesizeRig(const SyntheticRigOptions& o) {
  o.Check();
  SyntheticRig s;
  s.options = o;
  s.rng.seed(o.seed);
  std::mt19937& rng = s.rng;
  const int n = static_cast<int>(o.cameras.size());

  const std::vector<Rigid3d> cam_from_rig = RingPoses(o, rng);
  for (int c = 0; c < n; ++c) s.rig.cameras.push_back({"cam" + std::to_string(c), o.cameras[c], cam_from_rig[c], 0.0});
  std::vector<Eigen::Vector3d> rig_centre;
  for (int k = 0; k < o.num_frames; ++k) {
    if (!o.path.empty()) {
      s.rig_from_world.push_back(o.path[k]);
      rig_centre.push_back(o.path[k].SourceOriginInTarget());
      continue;
    }
    const Eigen::Matrix3d world_from_rig =
        Eigen::AngleAxisd(DegToRad(o.turn_deg * k), Eigen::Vector3d::UnitY()).toRotationMatrix();
    rig_centre.push_back(k * o.step_m);
    s.rig_from_world.push_back(Rigid3d(world_from_rig, rig_centre.back()).Inverse());
  }

  // Point sets: set 0 is seen by the cameras that are not isolated, set 1 + i by isolated camera i
  // alone; per frame (new_points_every_frame) or once for every frame.
  const int num_sets = 1 + static_cast<int>(o.isolated_cameras.size());
  std::vector<int> set_of_camera(n, 0);
  for (size_t i = 0; i < o.isolated_cameras.size(); ++i) set_of_camera[o.isolated_cameras[i]] = 1 + static_cast<int>(i);
  const int point_frames = o.new_points_every_frame ? o.num_frames : 1;
  std::vector<std::vector<std::vector<int>>> sets(point_frames, std::vector<std::vector<int>>(num_sets));  // [frame][set]
  const Eigen::Vector3d path = rig_centre.back() - rig_centre.front();
  const Eigen::Vector3d along = path.norm() > 0 ? Eigen::Vector3d(path.normalized()) : Eigen::Vector3d::UnitZ();
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < point_frames; ++k) {
    for (int set = 0; set < num_sets; ++set) {
      if (o.new_points_every_frame) {
        AddPoints(o, o.num_points, [&] { return rig_centre[k]; }, rng, &s.points, &sets[k][set]);
      } else {
        const double length = path.norm() + 2 * o.path_margin_m;
        AddPoints(o, o.num_points, [&] { return rig_centre.front() + (length * u(rng) - o.path_margin_m) * along; }, rng,
                  &s.points, &sets[k][set]);
      }
    }
  }

  s.keypoints.assign(o.num_frames, std::vector<std::vector<Eigen::Vector2d>>(n));
  s.point_of.assign(o.num_frames, std::vector<std::vector<int>>(n));
  for (int k = 0; k < o.num_frames; ++k) {
    for (int c = 0; c < n; ++c) {
      const std::vector<int>& visible = sets[o.new_points_every_frame ? k : 0][set_of_camera[c]];
      const double offset = o.time_offset_s.empty() ? 0.0 : o.time_offset_s[c];
      const double readout = o.readout_s.empty() ? 0.0 : o.readout_s[c];
      auto pose_at_row = [&, k, c, offset, readout](double row) {
        if (offset == 0.0 && readout == 0.0) return s.CamFromWorld({k, c});
        return *s.rig.cameras[c].cam_from_rig *
               s.RigFromWorldAt(k * o.frame_interval_s + offset + row / o.cameras[c].height() * readout);
      };
      Observe(o, o.cameras[c], pose_at_row, s.points, visible, rng, &s.keypoints[k][c], &s.point_of[k][c]);
    }
  }
  return s;
}

std::vector<Rigid3d> TurningPath(int frames, double step_m, double yaw_deg, double yaw_variation, double pitch_deg,
                                 double roll_deg) {
  std::vector<Rigid3d> path;
  Rigid3d world_from_rig;
  for (int k = 0; k < frames; ++k) {
    path.push_back(world_from_rig.Inverse());
    const double s = std::sin(0.9 * k + 0.3), c = std::cos(1.3 * k);
    const Eigen::Quaterniond turn =
        Eigen::AngleAxisd(DegToRad(yaw_deg * (1.0 + yaw_variation * s)), Eigen::Vector3d::UnitY()) *
        Eigen::AngleAxisd(DegToRad(pitch_deg * s), Eigen::Vector3d::UnitX()) *
        Eigen::AngleAxisd(DegToRad(roll_deg * c), Eigen::Vector3d::UnitZ());
    world_from_rig = world_from_rig * Rigid3d(turn, Eigen::Vector3d(0, 0, step_m));
  }
  return path;
}

Rigid3d SyntheticRig::RigFromWorldAt(double time_s) const {
  const double dt = options.frame_interval_s;
  const int frames = static_cast<int>(rig_from_world.size());
  if (frames == 1) return rig_from_world[0];
  const int a = std::clamp(static_cast<int>(std::floor(time_s / dt)), 0, frames - 2);
  Rigid3d out;
  InterpolateRigFromWorld<double>(rig_from_world[a].rotation, rig_from_world[a].translation,
                                  rig_from_world[a + 1].rotation, rig_from_world[a + 1].translation,
                                  time_s / dt - a, &out.rotation, &out.translation);
  return out;
}

Rigid3d SyntheticRig::CamFromWorld(SyntheticView v) const {
  return *rig.cameras[v.camera].cam_from_rig * rig_from_world[v.frame];
}

std::vector<std::pair<int, int>> SyntheticRig::TrueMatches(SyntheticView a, SyntheticView b) const {
  const std::vector<int> in_a = KeypointOf(point_of[a.frame][a.camera], points.size());
  const std::vector<int> in_b = KeypointOf(point_of[b.frame][b.camera], points.size());
  std::vector<std::pair<int, int>> matches;
  for (size_t i = 0; i < points.size(); ++i) {
    if (in_a[i] >= 0 && in_b[i] >= 0) matches.push_back({in_a[i], in_b[i]});
  }
  return matches;
}

std::vector<std::pair<int, int>> SyntheticRig::CandidateMatches(SyntheticView a, SyntheticView b) {
  std::vector<std::pair<int, int>> matches = TrueMatches(a, b);
  const int na = static_cast<int>(keypoints[a.frame][a.camera].size());
  const int nb = static_cast<int>(keypoints[b.frame][b.camera].size());
  const int outliers = std::max(options.min_outliers, static_cast<int>(options.outlier_fraction * matches.size()));
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < outliers && na > 0 && nb > 0; ++i) {
    const int ka = static_cast<int>(u(rng) * na) % na;
    const int kb = static_cast<int>(u(rng) * nb) % nb;
    matches.push_back({ka, kb});
  }
  std::shuffle(matches.begin(), matches.end(), rng);
  return matches;
}

uint32_t TestSeed() {
  uint32_t h = 2166136261u;  // FNV-1a
  for (char c : CurrentTest().name) h = (h ^ static_cast<uint8_t>(c)) * 16777619u;
  return h;
}

std::mt19937 TestRng() { return std::mt19937(TestSeed()); }

Eigen::Quaterniond RandomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0, 1);
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized();
}

Eigen::Quaterniond RandomRotationBy(std::mt19937& rng, double deg) {
  std::normal_distribution<double> n(0, 1);
  const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  return Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(deg), axis));
}

std::vector<Rigid3d> RandomCamFromRig(int n, std::mt19937& rng) {
  std::normal_distribution<double> g(0, 1);
  std::vector<Rigid3d> cam_from_rig(n);
  for (int c = 1; c < n; ++c) {
    const Eigen::Quaterniond q = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized();
    const Eigen::Vector3d centre(g(rng), g(rng), g(rng));
    cam_from_rig[c] = Rigid3d(q, -(q * centre));
  }
  return cam_from_rig;
}

}  // namespace rigsim
