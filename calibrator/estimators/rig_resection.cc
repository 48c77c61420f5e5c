#include "calibrator/estimators/rig_resection.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "common/format.h"

namespace rigsim {
namespace {

double Log10Binomial(int n, int k) {
  return (std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0)) / std::log(10.0);
}

// The correspondences whose point `cam_from_rig` projects within the threshold of its keypoint.
std::vector<int> InliersOf(const Camera& camera, const std::vector<RigResectionCorrespondence>& c,
                           const Rigid3d& cam_from_rig, double threshold_px) {
  std::vector<int> inliers;
  for (int i = 0; i < static_cast<int>(c.size()); ++i) {
    const Eigen::Vector3d x = cam_from_rig * c[i].x_in_rig;
    if (x.z() <= 0 && camera.max_valid_angle() <= std::numbers::pi / 2) continue;
    const auto px = camera.ImgFromCam(x);
    if (px && (*px - c[i].pixel).norm() <= threshold_px) inliers.push_back(i);
  }
  return inliers;
}

}  // namespace

void RigResectionOptions::Check() const {
  if (!(inlier_threshold_px > 0)) throw std::invalid_argument("RigResectionOptions: inlier_threshold_px must be > 0");
  if (max_iterations < 1) throw std::invalid_argument("RigResectionOptions: max_iterations must be >= 1");
  if (min_inliers < 4) throw std::invalid_argument("RigResectionOptions: min_inliers must be >= 4");
  if (!std::isfinite(max_log10_false_alarms)) {
    throw std::invalid_argument("RigResectionOptions: max_log10_false_alarms must be finite");
  }
}

double Log10FalseAlarms(int n, int k, double p) {
  if (n < 4 || k < 4 || k > n) return std::max(0.0, std::log10(std::max(n - 3, 1)));
  p = std::clamp(p, 1e-300, 1.0);
  return std::log10(n - 3.0) + Log10Binomial(n, k) + Log10Binomial(k, 3) + (k - 3) * std::log10(p);
}

RigResection ResectCameraInRig(const Camera& camera, const std::vector<RigResectionCorrespondence>& correspondences,
                               const RigResectionOptions& options) {
  options.Check();
  RigResection out;
  // The fit sees the keypoints undistorted onto a pinhole of the camera's focal length, so that its
  // threshold is in pixels near the centre; inliers are counted again through the real lens.
  const double f = camera.fx();
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (const RigResectionCorrespondence& c : correspondences) {
    const auto ray = camera.CamFromImg(c.pixel);
    if (!ray || ray->z() < 0.1) continue;  // beyond 84 deg a pinhole projection loses the threshold's meaning
    object.emplace_back(c.x_in_rig.x(), c.x_in_rig.y(), c.x_in_rig.z());
    image.emplace_back(f * ray->x() / ray->z(), f * ray->y() / ray->z());
  }
  const int n = static_cast<int>(correspondences.size());
  if (static_cast<int>(object.size()) < options.min_inliers) {
    out.reason = std::to_string(n) + " matches with placed points, fewer than the " +
                 std::to_string(options.min_inliers) + " a pose needs";
    return out;
  }
  cv::Mat k = (cv::Mat_<double>(3, 3) << f, 0, 0, 0, f, 0, 0, 0, 1);
  cv::UsacParams usac;
  usac.confidence = 0.9999;
  usac.isParallel = false;  // one thread: the same seed gives the same pose
  usac.loIterations = 10;
  usac.loMethod = cv::LOCAL_OPTIM_INNER_LO;
  usac.loSampleSize = 14;
  usac.maxIterations = options.max_iterations;
  usac.neighborsSearch = cv::NEIGH_GRID;
  usac.randomGeneratorState = 1;
  usac.sampler = cv::SAMPLING_UNIFORM;
  usac.score = cv::SCORE_METHOD_MSAC;
  usac.threshold = options.inlier_threshold_px;
  cv::Mat rvec, tvec, cv_inliers;
  bool found = false;
  try {
    found = cv::solvePnPRansac(object, image, k, cv::noArray(), rvec, tvec, cv_inliers, usac);
  } catch (const cv::Exception&) {
    found = false;  // degenerate samples (every point on one line) end here
  }
  if (!found || rvec.empty() || tvec.empty()) {
    out.reason = "no pose explains " + std::to_string(options.min_inliers) + " of its " + std::to_string(n) +
                 " matches with placed points";
    return out;
  }
  cv::Mat r;
  cv::Rodrigues(rvec, r);
  Eigen::Matrix3d rotation;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) rotation(i, j) = r.at<double>(i, j);
  }
  out.cam_from_rig = Rigid3d(rotation, Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2)));
  out.inliers = InliersOf(camera, correspondences, out.cam_from_rig, options.inlier_threshold_px);
  const int inliers = static_cast<int>(out.inliers.size());
  const double disc = std::numbers::pi * options.inlier_threshold_px * options.inlier_threshold_px;
  out.log10_false_alarms = Log10FalseAlarms(n, inliers, disc / (double(camera.width()) * camera.height()));
  if (inliers < options.min_inliers) {
    out.reason = "its best pose explains " + std::to_string(inliers) + " of its " + std::to_string(n) +
                 " matches with placed points, fewer than " + std::to_string(options.min_inliers);
    return out;
  }
  if (out.log10_false_alarms > options.max_log10_false_alarms) {
    out.reason = "its best pose explains " + std::to_string(inliers) + " of its " + std::to_string(n) +
                 " matches with placed points, as many as chance would give (false alarms 10^" +
                 Fixed(out.log10_false_alarms, 1) + ")";
    return out;
  }
  out.success = true;
  return out;
}

}  // namespace rigsim
