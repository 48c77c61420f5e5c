// Match precision (DESIGN.md "Evaluation"): a match (keypoint in A, keypoint in B) is correct
// when A's keypoint, lifted with A's true range image and projected into B with the true pose
// (at the two views' capture times) and camera model, lands within max_error_px of B's keypoint and is not occluded in B
// (dataset/ground_truth.h TransferPixel). Every match is decided, none is dropped:
//   - lifted point outside B's image or occluded in B: incorrect (B cannot see that point, so
//     whatever B's keypoint shows, it is another point);
//   - no surface at A's pixel (sky, background; range 0): the point is at infinity; it is correct
//     when the rotation alone carries its bearing within max_error_px of B's keypoint and B has
//     no surface there either. Such matches are also counted apart (at_infinity).
// Precision = correct / evaluated. Counts rather than a bare ratio, so frames and pairs can be
// pooled exactly.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "dataset/ground_truth.h"
#include "geometry/camera.h"
#include "geometry/image.h"
#include "geometry/rigid3.h"

namespace rigsim {

struct MatchPrecisionOptions {
  // A transferred keypoint within this distance (px) of its partner is correct.
  double max_error_px = 2.0;
  // Occlusion tolerance of the transfer.
  DepthTransferOptions transfer;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct MatchPrecisionCounts {
  int evaluated = 0;    // matches checked
  int correct = 0;      // of those, correct
  int at_infinity = 0;  // of the evaluated, A's pixel had no surface (checked as a point at infinity)
  // Of the evaluated, matches whose two keypoints lie on different true classes (the thesis's
  // "cross-class matches"), and of those the correct ones (a class boundary, not an error).
  // Counted only when both label images are known.
  int cross_class = 0;
  int cross_class_correct = 0;

  double Precision() const;  // NaN when nothing was evaluated
  MatchPrecisionCounts& operator+=(const MatchPrecisionCounts& o);
};

// The true class under each keypoint (nearest pixel) differs between A and B: one flag per match.
std::vector<char> CrossClassMatches(const std::vector<Eigen::Vector2d>& px_a, const std::vector<Eigen::Vector2d>& px_b,
                                    const ImageU8& labels_a, const ImageU8& labels_b);

// One flag per match (1 = correct). `range_a`, `range_b`: the true range images of A and B;
// `pose_a`, `pose_b`: the views' true poses at their capture times (metric; per row for a rolling
// shutter, dataset/capture_poses.h), so that a match between cameras that capture at different
// times, or while the rig moves, is checked against where each camera was.
std::vector<char> CheckMatches(const std::vector<Eigen::Vector2d>& px_a, const std::vector<Eigen::Vector2d>& px_b,
                               const Camera& cam_a, const ImageF& range_a, const ViewPose& pose_a, const Camera& cam_b,
                               const ImageF& range_b, const ViewPose& pose_b, const MatchPrecisionOptions& options,
                               int* num_at_infinity = nullptr);

MatchPrecisionCounts MatchPrecision(const std::vector<Eigen::Vector2d>& px_a, const std::vector<Eigen::Vector2d>& px_b,
                                    const Camera& cam_a, const ImageF& range_a, const ViewPose& pose_a,
                                    const Camera& cam_b, const ImageF& range_b, const ViewPose& pose_b,
                                    const MatchPrecisionOptions& options = {});

}  // namespace rigsim
