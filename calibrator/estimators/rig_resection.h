// A camera's pose in the rig from its keypoints matched to points the rest of the rig already
// placed. The camera is fixed in the rig, so every frame's 2D-3D pairs, carried into the rig frame
// of that frame, make one perspective-n-point problem: a robust fit (OpenCV's USAC, seeded), then
// how likely that many inliers are by chance (an a contrario count of false alarms).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "geometry/rigid3.h"

namespace rigsim {

struct RigResectionCorrespondence {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();     // the camera's keypoint (px)
  Eigen::Vector3d x_in_rig = Eigen::Vector3d::Zero();  // its point, in the rig frame of the keypoint's frame
};

struct RigResectionOptions {
  // A correspondence whose point projects farther than this from its keypoint is an outlier (px).
  double inlier_threshold_px = 4.0;
  int max_iterations = 10000;
  // A pose is kept with at least this many inliers, and when the expected number of poses with as
  // many inliers among random keypoints (Log10FalseAlarms) is below 10^max_log10_false_alarms.
  int min_inliers = 12;
  double max_log10_false_alarms = -3.0;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct RigResection {
  bool success = false;
  Rigid3d cam_from_rig;
  std::vector<int> inliers;  // indices into the correspondences
  double log10_false_alarms = 0.0;
  std::string reason;  // why not, with its figures; empty on success
};

// The pose of `camera` in the rig from `correspondences`. Never throws on data; throws
// std::invalid_argument on bad options.
RigResection ResectCameraInRig(const Camera& camera, const std::vector<RigResectionCorrespondence>& correspondences,
                               const RigResectionOptions& options);

// log10 of the number of false alarms of a pose with `k` inliers among `n` correspondences when a
// wrong correspondence lands within the inlier radius with probability `p` (the disc's share of the
// image): (n - 3) C(n, k) C(k, 3) p^(k - 3), the minimal sample being 3.
double Log10FalseAlarms(int n, int k, double p);

}  // namespace rigsim
