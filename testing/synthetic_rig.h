// Synthetic rig datasets for estimator tests, in the manner of COLMAP's SynthesizeDataset
// (src/colmap/scene/synthetic.h): a rig of cameras of any model, its poses over frames, 3D points
// around its path, each view's noisy observations mixed with distractors, and the truth.
//
//   SyntheticRigOptions o;
//   o.cameras = {pinhole, fisheye, pinhole, fisheye};
//   o.num_frames = 4;
//   o.step_m = {0, 0, 2};                 // 2 m forward per frame
//   o.seed = TestSeed();                  // seeded from the running test's name
//   SyntheticRig s = SynthesizeRig(o);
//   s.keypoints[frame][camera];           // what a detector would have found
//   s.CandidateMatches({0, 0}, {0, 1});   // true matches of views (frame 0, cam0) and (0, cam1) and wrong ones
//   s.rig, s.rig_from_world;              // the truth to compare an estimate with
//
// Conventions (geometry/rigid3.h): camera 0 is the rig frame (the calibrator's gauge), and frame 0's
// rig frame is the world. The same options give the same dataset, byte for byte.
#pragma once

#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/camera.h"
#include "geometry/rig.h"
#include "geometry/rigid3.h"

namespace rigsim {

struct SyntheticRigOptions {
  // The cameras, on a horizontal ring looking outwards: camera i at yaw i * yaw_step_deg about the
  // rig's y axis, ring_radius_m out along its view; each mount turned at random by up to
  // max_tilt_deg about its x and z axes and moved by up to max_offset_m along each axis.
  std::vector<Camera> cameras;
  double ring_radius_m = 0.3;
  double yaw_step_deg = 0.0;  // 0: 360 / the number of cameras
  double max_tilt_deg = 0.0;
  double max_offset_m = 0.0;
  // Cameras that see points of their own, which no other camera sees: cameras with no overlap.
  std::vector<int> isolated_cameras;

  // The rig's motion: at frame k it has moved k * step_m (in the world) and turned k * turn_deg
  // about the world's y axis.
  int num_frames = 1;
  Eigen::Vector3d step_m = Eigen::Vector3d::Zero();
  double turn_deg = 0.0;
  // Or any path: the rig's pose per frame (rig_from_world, frame 0's the identity), one per frame,
  // instead of step_m and turn_deg.
  std::vector<Rigid3d> path;
  // When each camera captures: frame k at k * frame_interval_s, camera c time_offset_s[c] after it,
  // row y of its image y / height * readout_s[c] after that (a rolling shutter); the rig between
  // frames as the renderer moves it (geometry/pose_interpolation.h). Empty: at the frame's time.
  double frame_interval_s = 0.1;
  std::vector<double> time_offset_s;
  std::vector<double> readout_s;

  // The points: num_points around the rig's path, seen in every frame, or, with
  // new_points_every_frame, num_points of its own around each frame's rig. A point lies in a random
  // direction within max_elevation_deg of the horizontal, min_distance_m to max_distance_m from a
  // random place on the path (extended by path_margin_m at both ends) or from the frame's rig.
  int num_points = 1000;
  bool new_points_every_frame = false;
  double min_distance_m = 3.0;
  double max_distance_m = 18.0;
  double max_elevation_deg = 30.0;
  double path_margin_m = 5.0;

  // Each view: every point in the image, projected, plus Gaussian noise (noise_px per coordinate),
  // and distractor_fraction as many keypoints again of no point, uniform over the image; shuffled,
  // so that keypoint indices say nothing.
  double noise_px = 0.3;
  double distractor_fraction = 0.1;

  // CandidateMatches: outlier_fraction as many wrong matches as true ones, at least min_outliers.
  double outlier_fraction = 0.05;
  int min_outliers = 6;

  uint32_t seed = 0;

  // Throws std::invalid_argument naming the field that is out of range.
  void Check() const;
};

// One image of the dataset.
struct SyntheticView {
  int frame = 0;
  int camera = 0;
};

struct SyntheticRig {
  SyntheticRigOptions options;
  Rig rig;                              // the truth: cameras "cam0", "cam1", ..., cam0 at the rig frame
  std::vector<Rigid3d> rig_from_world;  // per frame; frame 0's is the identity
  std::vector<Eigen::Vector3d> points;  // in the world
  // Per frame and camera: the keypoints (noisy projections and distractors) and the point each is
  // of (an index into `points`; -1 for a distractor).
  std::vector<std::vector<std::vector<Eigen::Vector2d>>> keypoints;
  std::vector<std::vector<std::vector<int>>> point_of;
  // The generator after synthesis; CandidateMatches draws from it, so the same calls in the same
  // order give the same matches.
  std::mt19937 rng;

  // The pose at the frame's time (what a synchronised camera sees).
  Rigid3d CamFromWorld(SyntheticView v) const;
  // The rig's pose at any time (frame k at k * frame_interval_s), as the observations took it.
  Rigid3d RigFromWorldAt(double time_s) const;
  // The true correspondences (keypoint of a, keypoint of b), in the order of the points.
  std::vector<std::pair<int, int>> TrueMatches(SyntheticView a, SyntheticView b) const;
  // The true correspondences and wrong ones (random keypoint pairs; options' outlier_fraction, at
  // least min_outliers), shuffled: what a matcher hands to a robust estimator.
  std::vector<std::pair<int, int>> CandidateMatches(SyntheticView a, SyntheticView b);
};

SyntheticRig SynthesizeRig(const SyntheticRigOptions& options);

// A path for SyntheticRigOptions::path, rig_from_world per frame (frame 0's the identity): between
// frames the rig moves step_m along its forward axis (z), then turns about its own axes, by
// yaw_deg * (1 + yaw_variation * s_k) about y, pitch_deg * s_k about x and roll_deg * c_k about z
// (s_k, c_k: sines of the frame number, so that no two steps turn alike). yaw_variation 0 and no
// pitch or roll is a circle.
std::vector<Rigid3d> TurningPath(int frames, double step_m, double yaw_deg, double yaw_variation, double pitch_deg,
                                 double roll_deg);

// A seed from the running test's name ("Suite.Name"; "Suite" inside SetUpTestSuite), FNV-1a:
// reproducible, and independent between tests.
uint32_t TestSeed();
std::mt19937 TestRng();

// A rotation uniform over all rotations.
Eigen::Quaterniond RandomRotation(std::mt19937& rng);
// A rotation of exactly `deg` about a uniformly random axis.
Eigen::Quaterniond RandomRotationBy(std::mt19937& rng, double deg);
// cam_from_rig of `n` cameras: camera 0 at the rig frame, the others at uniformly random
// orientations with centres drawn from N(0, 1 m) per axis.
std::vector<Rigid3d> RandomCamFromRig(int n, std::mt19937& rng);

}  // namespace rigsim
