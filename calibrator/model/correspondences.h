// Keypoints and inlier correspondences as the rig stages take them (rig_calibration.h,
// multi_frame_rig.h): indices into per-frame, per-camera keypoint lists.
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

namespace rigsim {

// Keypoint positions (pixels): [frame][camera][keypoint].
using FrameKeypoints = std::vector<std::vector<std::vector<Eigen::Vector2d>>>;

// Inlier correspondences of one camera pair: per frame, (keypoint index in cam_a, in cam_b).
struct PairMatches {
  int cam_a = -1;
  int cam_b = -1;
  std::vector<std::vector<std::pair<int, int>>> per_frame;
};

}  // namespace rigsim
