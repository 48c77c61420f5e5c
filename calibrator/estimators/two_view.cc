#include "calibrator/estimators/two_view.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <ceres/sphere_manifold.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "calibrator/estimators/cost_functions.h"
#include "common/format.h"

namespace rigsim {
namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  double m = v[mid];
  if (v.size() % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + mid));
  return m;
}

// Angular distance (radians) of a correspondence from the epipolar geometry: the larger of the
// two one-sided angles.
double EpipolarAngle(const Rigid3d& b_from_a, const Eigen::Vector3d& fa, const Eigen::Vector3d& fb) {
  const Eigen::Vector2d r = EpipolarAngularResidual(b_from_a, fa, fb);
  return std::asin(std::min(1.0, r.cwiseAbs().maxCoeff()));
}

double RotationAngle(const Eigen::Matrix3d& r, const Eigen::Vector3d& fa, const Eigen::Vector3d& fb) {
  const Eigen::Vector3d rfa = r * fa;
  return std::atan2(rfa.cross(fb).norm(), rfa.dot(fb));
}

// Least-squares rotation with fb ~ R fa (Kabsch / Wahba).
Eigen::Matrix3d KabschRotation(const std::vector<Eigen::Vector3d>& fa, const std::vector<Eigen::Vector3d>& fb,
                               const std::vector<int>& idx) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (int i : idx) m += fb[i] * fa[i].transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

struct RotationFit {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  std::vector<int> inliers;
};

// Pure-rotation model by 2-point RANSAC, then least squares on the inliers (twice, as the inlier
// set settles). Seeded: the same input gives the same answer.
RotationFit FitRotation(const std::vector<Eigen::Vector3d>& fa, const std::vector<Eigen::Vector3d>& fb,
                        const std::vector<int>& valid, double thr, const TwoViewOptions& options) {
  RotationFit best;
  const int n = static_cast<int>(valid.size());
  if (n < 2) return best;
  std::mt19937 rng(options.rotation_ransac_seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  auto inliers_of = [&](const Eigen::Matrix3d& r) {
    std::vector<int> in;
    for (int i : valid) {
      if (RotationAngle(r, fa[i], fb[i]) < thr) in.push_back(i);
    }
    return in;
  };
  for (int it = 0; it < options.rotation_ransac_iterations; ++it) {
    const int i = pick(rng);
    int j = pick(rng);
    if (i == j) j = (j + 1) % n;
    const int a = valid[i], b = valid[j];
    if (fa[a].cross(fa[b]).norm() < 1e-3) continue;  // nearly parallel: rotation undetermined
    const Eigen::Matrix3d r = KabschRotation(fa, fb, {a, b});
    std::vector<int> in = inliers_of(r);
    if (in.size() > best.inliers.size()) {
      best.rotation = r;
      best.inliers = std::move(in);
    }
  }
  for (int round = 0; round < 2 && best.inliers.size() >= 2; ++round) {
    const Eigen::Matrix3d r = KabschRotation(fa, fb, best.inliers);
    std::vector<int> in = inliers_of(r);
    if (in.size() < best.inliers.size()) break;
    best.rotation = r;
    best.inliers = std::move(in);
  }
  return best;
}

// The homography H maps bearings of A to bearings of B up to a positive scale for points on its
// plane (x_b = (R + t n^T / d) x_a for a point x_a on the plane n^T x = d). Its angular error is
// the larger of the forward (H f_a against f_b) and backward (H^-1 f_b against f_a) angles;
// defined on the whole sphere, so fisheye bearings beyond 90 degrees count too.
struct HomographyFit {
  Eigen::Matrix3d h = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d h_inv = Eigen::Matrix3d::Identity();
  bool valid = false;
};

double HomographyAngle(const HomographyFit& fit, const Eigen::Vector3d& fa, const Eigen::Vector3d& fb) {
  const Eigen::Vector3d fwd = fit.h * fa;
  const Eigen::Vector3d bwd = fit.h_inv * fb;
  return std::max(std::atan2(fwd.cross(fb).norm(), fwd.dot(fb)), std::atan2(bwd.cross(fa).norm(), bwd.dot(fa)));
}

// Homography by OpenCV's USAC MAGSAC++ on the normalised coordinates of the bearings in front of
// both cameras (pa, pb), then its inliers among all valid bearings under the angular error above.
HomographyFit FitHomography(const std::vector<cv::Point2d>& pa, const std::vector<cv::Point2d>& pb,
                            const std::vector<int>& front, const std::vector<Eigen::Vector3d>& fa,
                            const std::vector<Eigen::Vector3d>& fb, double thr, const TwoViewOptions& options) {
  HomographyFit fit;
  if (pa.size() < 4) return fit;
  // OpenCV 4.6's MAGSAC++ homography finds nothing when the threshold is tiny (normalised
  // coordinates: ~0.002; seen: 0 inliers where RANSAC finds 300 of 400), and works once the data
  // is scaled so that the threshold is 1. Fit in the scaled coordinates, then H = S^-1 H' S.
  const double scale = 1.0 / thr;
  std::vector<cv::Point2d> sa, sb;
  sa.reserve(pa.size());
  sb.reserve(pb.size());
  for (size_t i = 0; i < pa.size(); ++i) {
    sa.push_back(pa[i] * scale);
    sb.push_back(pb[i] * scale);
  }
  cv::Mat h_cv;
  try {
    h_cv = cv::findHomography(sa, sb, cv::USAC_MAGSAC, 1.0, cv::noArray(), options.ransac_max_iterations,
                              options.ransac_confidence);
  } catch (const cv::Exception&) {
    return fit;  // degenerate samples everywhere: no homography, so not planar
  }
  if (h_cv.rows != 3 || h_cv.cols != 3) return fit;
  Eigen::Matrix3d h_scaled;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) h_scaled(y, x) = h_cv.at<double>(y, x);
  const Eigen::DiagonalMatrix<double, 3> s(scale, scale, 1.0), s_inv(1.0 / scale, 1.0 / scale, 1.0);
  fit.h = s_inv * h_scaled * s;
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(fit.h);
  if (!lu.isInvertible()) return fit;
  // OpenCV scales H to h33 = 1, which may flip its sign: take the sign that maps the bearings
  // the fit used forwards, not backwards.
  int forward = 0;
  for (int i : front) forward += (fit.h * fa[i]).dot(fb[i]) > 0 ? 1 : -1;
  if (forward < 0) fit.h = -fit.h;
  fit.h_inv = fit.h.inverse();
  fit.valid = true;
  return fit;
}

// The four poses one essential matrix allows: (R, t), (R, -t) and the "twisted pair" (H R, +-t),
// H the half turn about the baseline. Their epipolar errors are the same, so neither RANSAC's
// fit nor the refinement can choose; only the side of the cameras the points lie on can.
// Counts, per pose, the inliers whose two rays meet in front of both cameras, over the inliers
// whose rays meet at min_angle_rad or more (closer to parallel, a point could be on either side
// by noise). Bearings beyond 90 degrees (fisheyes) count: depth is along the ray.
struct Cheirality {
  Rigid3d pose;
  int in_front = 0;       // of `pose`
  int second_best = 0;    // in front under the best of the other three
  int informative = 0;    // inliers whose rays meet at min_angle_rad or more
};

Cheirality ResolveCheirality(const Rigid3d& pose, const std::vector<Eigen::Vector3d>& fa,
                             const std::vector<Eigen::Vector3d>& fb, const std::vector<int>& inliers,
                             double min_angle_rad) {
  const Eigen::Vector3d t = pose.translation.normalized();
  const Eigen::Matrix3d half_turn = 2.0 * t * t.transpose() - Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d r = pose.rotation.toRotationMatrix();
  const Rigid3d candidates[4] = {Rigid3d(r, t), Rigid3d(r, -t), Rigid3d(half_turn * r, t), Rigid3d(half_turn * r, -t)};
  int counts[4] = {0, 0, 0, 0};
  Cheirality out;
  for (int i : inliers) {
    const Eigen::Vector3d rfa = r * fa[i];
    if (std::atan2(rfa.cross(fb[i]).norm(), rfa.dot(fb[i])) < min_angle_rad) continue;
    ++out.informative;
    for (int c = 0; c < 4; ++c) {
      // lambda_b fb = lambda_a R fa + t, least squares in (lambda_a, lambda_b).
      Eigen::Matrix<double, 3, 2> a;
      a.col(0) = candidates[c].rotation * fa[i];
      a.col(1) = -fb[i];
      const Eigen::Vector2d depth = (a.transpose() * a).ldlt().solve(-a.transpose() * candidates[c].translation);
      counts[c] += depth.x() > 0 && depth.y() > 0;
    }
  }
  int best = 0;
  for (int c = 1; c < 4; ++c) {
    if (counts[c] > counts[best]) best = c;
  }
  out.pose = candidates[best];
  out.in_front = counts[best];
  for (int c = 0; c < 4; ++c) {
    if (c != best) out.second_best = std::max(out.second_best, counts[c]);
  }
  return out;
}

// The valid correspondences within `limit` (radians) of `pose`'s epipolar geometry.
std::vector<int> EpipolarInliers(const Rigid3d& pose, const std::vector<Eigen::Vector3d>& fa,
                                 const std::vector<Eigen::Vector3d>& fb, const std::vector<int>& valid, double limit) {
  std::vector<int> in;
  for (int i : valid) {
    if (EpipolarAngle(pose, fa[i], fb[i]) < limit) in.push_back(i);
  }
  return in;
}

// Refines `pose` (when options.refine) and returns its inliers: two rounds of refining on a generous
// neighbourhood (the Cauchy loss tempers it) and selecting again.
std::vector<int> RefineOnInliers(const std::vector<Eigen::Vector3d>& fa, const std::vector<Eigen::Vector3d>& fb,
                                 const std::vector<int>& valid, double thr, const TwoViewOptions& options, Rigid3d* pose) {
  std::vector<int> inliers = EpipolarInliers(*pose, fa, fb, valid, thr);
  for (int round = 0; options.refine && round < 2; ++round) {
    const std::vector<int> near = EpipolarInliers(*pose, fa, fb, valid, 3.0 * thr);
    if (static_cast<int>(near.size()) < 5) break;
    std::vector<Eigen::Vector3d> ra, rb;
    for (int i : near) {
      ra.push_back(fa[i]);
      rb.push_back(fb[i]);
    }
    *pose = RefineRelativePose(ra, rb, *pose, thr, options.refine_max_iterations);
    inliers = EpipolarInliers(*pose, fa, fb, valid, thr);
  }
  return inliers;
}

// The poses of the homography's decomposition (Malis and Vargas, through OpenCV, K = I) whose
// rotation differs from `chosen`'s by more than options.min_planar_alternative_deg and that, refined
// like the essential matrix's pose and with their cheirality resolved the same way, explain at
// least options.planar_ratio times `chosen_inliers` of the matches: the other answer a plane allows,
// which the matches alone do not rule out.
std::vector<Rigid3d> OtherPlanarPoses(const HomographyFit& fit, const Rigid3d& chosen, int chosen_inliers,
                                      const std::vector<Eigen::Vector3d>& fa, const std::vector<Eigen::Vector3d>& fb,
                                      const std::vector<int>& valid, double thr, const TwoViewOptions& options) {
  cv::Mat h(3, 3, CV_64F);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) h.at<double>(y, x) = fit.h(y, x);
  std::vector<cv::Mat> rotations, translations, normals;
  try {
    cv::decomposeHomographyMat(h, cv::Mat::eye(3, 3, CV_64F), rotations, translations, normals);
  } catch (const cv::Exception&) {
    return {};
  }
  std::vector<Rigid3d> out;
  for (size_t s = 0; s < rotations.size(); ++s) {
    Eigen::Matrix3d r;
    Eigen::Vector3d t;
    for (int y = 0; y < 3; ++y) {
      for (int x = 0; x < 3; ++x) r(y, x) = rotations[s].at<double>(y, x);
      t(y) = translations[s].at<double>(y);
    }
    if (!(t.norm() > 1e-9)) continue;  // a pure rotation has no other answer
    Rigid3d pose(r, t.normalized());
    auto differs = [&](const Rigid3d& other) {
      return RotationDifferenceDeg(pose.rotation, other.rotation) > options.min_planar_alternative_deg;
    };
    if (!differs(chosen)) continue;
    const std::vector<int> inliers = RefineOnInliers(fa, fb, valid, thr, options, &pose);
    if (inliers.size() < options.planar_ratio * chosen_inliers) continue;
    const Cheirality side = ResolveCheirality(pose, fa, fb, inliers, options.cheirality_min_angle_factor * thr);
    if (side.in_front < options.min_cheirality_points) continue;
    pose = side.pose;
    if (differs(chosen) && std::all_of(out.begin(), out.end(), differs)) out.push_back(pose);
  }
  return out;
}

TwoViewResult Fail(TwoViewResult r, TwoViewFailure failure, const std::string& why) {
  r.estimate.success = false;
  r.estimate.failure = failure;
  r.estimate.failure_reason = why;
  return r;
}

// The strongest rival of `pose` (TwoViewOptions::rival_*), or nullopt. Seeds on a Fibonacci
// sphere (deterministic); the refinement runs on every k-th valid match so that at most
// rival_max_matches take part, and each minimum is scored on all of them.
std::optional<RivalPose> StrongestRival(const Rigid3d& pose, const std::vector<int>& pose_inlier_set,
                                        const std::vector<Eigen::Vector3d>& fa,
                                        const std::vector<Eigen::Vector3d>& fb, const std::vector<int>& valid,
                                        double thr, const TwoViewOptions& options) {
  if (options.rival_seeds == 0 || pose.translation.norm() == 0.0) return std::nullopt;
  const size_t stride = (valid.size() + options.rival_max_matches - 1) / options.rival_max_matches;
  std::vector<Eigen::Vector3d> sa, sb;
  for (size_t j = 0; j < valid.size(); j += std::max<size_t>(1, stride)) {
    sa.push_back(fa[valid[j]]);
    sb.push_back(fb[valid[j]]);
  }
  const Eigen::Vector3d t = pose.translation.normalized();
  const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
  std::vector<char> in_pose(fa.size(), 0), in_either;
  for (int i : pose_inlier_set) in_pose[i] = 1;
  std::optional<RivalPose> best;
  for (int k = 0; k < options.rival_seeds; ++k) {
    const double z = 1.0 - (k + 0.5) * 2.0 / options.rival_seeds;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const Eigen::Vector3d seed(r * std::cos(golden_angle * k), r * std::sin(golden_angle * k), z);
    if (std::abs(seed.dot(t)) > std::cos(DegToRad(options.rival_min_direction_deg))) continue;  // +-t: the pose itself
    const Rigid3d refined = RefineRelativePose(sa, sb, Rigid3d(pose.rotation, seed), thr, options.refine_max_iterations);
    const std::vector<int> inliers = EpipolarInliers(refined, fa, fb, valid, thr);
    // A sign test over the matches either pose explains: which of the two fits each one closer.
    // Were the two equally right, each would be as likely to fit a match closer.
    in_either = in_pose;
    for (int i : inliers) in_either[i] = 1;
    int rival_closer = 0, pose_closer = 0;
    for (int i : valid) {
      if (!in_either[i]) continue;
      const double by_pose = EpipolarAngle(pose, fa[i], fb[i]), by_rival = EpipolarAngle(refined, fa[i], fb[i]);
      pose_closer += by_pose < by_rival;
      rival_closer += by_rival < by_pose;
    }
    if (pose_closer - rival_closer > options.rival_sign_test_sigma * std::sqrt(double(pose_closer + rival_closer))) continue;
    // The sign of a translation and the twisted pair fit the matches alike: the rival is the one of
    // its four poses that puts the most inliers in front, as for the reported pose.
    const Rigid3d rival =
        ResolveCheirality(refined, fa, fb, inliers, options.cheirality_min_angle_factor * thr).pose;
    const double direction = RadToDeg(std::acos(std::clamp(rival.translation.normalized().dot(t), -1.0, 1.0)));
    if (direction <= options.rival_min_direction_deg) continue;
    if (best && static_cast<int>(inliers.size()) <= best->inliers) continue;
    best = RivalPose{direction, RotationDifferenceDeg(rival.rotation, pose.rotation), static_cast<int>(inliers.size()),
                     rival_closer, pose_closer};
  }
  return best;
}

}  // namespace

void TwoViewOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("TwoViewOptions: " + why); };
  if (min_matches < 5) fail("min_matches must be >= 5 (the essential matrix needs 5)");
  if (min_inliers < 5) fail("min_inliers must be >= 5");
  if (!(min_inlier_ratio >= 0 && min_inlier_ratio < 1)) fail("min_inlier_ratio must be in [0, 1)");
  if (!(max_error_px > 0)) fail("max_error_px must be > 0");
  if (!(ransac_confidence > 0 && ransac_confidence < 1)) fail("ransac_confidence must be in (0, 1)");
  if (ransac_max_iterations < 1) fail("ransac_max_iterations must be >= 1");
  if (!(min_bearing_z > 0 && min_bearing_z < 1)) fail("min_bearing_z must be in (0, 1)");
  if (refine_max_iterations < 1) fail("refine_max_iterations must be >= 1");
  if (!(rotation_only_ratio > 0)) fail("rotation_only_ratio must be > 0");
  if (!(planar_ratio > 0)) fail("planar_ratio must be > 0");
  if (!(min_planar_alternative_deg > 0)) fail("min_planar_alternative_deg must be > 0");
  if (rotation_ransac_iterations < 1) fail("rotation_ransac_iterations must be >= 1");
  if (!(cheirality_min_angle_factor > 0)) fail("cheirality_min_angle_factor must be > 0");
  if (min_cheirality_points < 1) fail("min_cheirality_points must be >= 1");
  if (!(cheirality_margin >= 1)) fail("cheirality_margin must be >= 1");
  if (rival_seeds < 0) fail("rival_seeds must be >= 0");
  if (rival_max_matches < 5) fail("rival_max_matches must be >= 5");
  if (!(rival_min_direction_deg > 0 && rival_min_direction_deg < 180)) fail("rival_min_direction_deg must be in (0, 180)");
  if (!(rival_sign_test_sigma >= 0)) fail("rival_sign_test_sigma must be >= 0");
}

TwoViewOptions WithoutRivalSearch(TwoViewOptions options) {
  options.rival_seeds = 0;
  return options;
}

Eigen::Vector2d EpipolarAngularResidual(const Rigid3d& cam_b_from_cam_a, const Eigen::Vector3d& bearing_a,
                                        const Eigen::Vector3d& bearing_b) {
  const EpipolarAngularCost cost(bearing_a, bearing_b);
  const Eigen::Vector3d t = cam_b_from_cam_a.translation.normalized();
  Eigen::Vector2d r;
  cost(cam_b_from_cam_a.rotation.coeffs().data(), t.data(), r.data());
  return r;
}

Rigid3d RefineRelativePose(const std::vector<Eigen::Vector3d>& bearings_a,
                           const std::vector<Eigen::Vector3d>& bearings_b, const Rigid3d& initial,
                           double loss_scale_rad, int max_iterations, RefinementSummary* summary) {
  if (bearings_a.size() != bearings_b.size()) throw std::invalid_argument("RefineRelativePose: size mismatch");
  if (initial.translation.norm() == 0.0) throw std::invalid_argument("RefineRelativePose: zero translation");
  Eigen::Quaterniond q = initial.rotation.normalized();
  Eigen::Vector3d t = initial.translation.normalized();

  if (bearings_a.empty()) return Rigid3d(q, t);

  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::TAKE_OWNERSHIP;  // shared; Ceres counts references
  ceres::Problem problem(problem_options);
  ceres::LossFunction* loss = new ceres::CauchyLoss(loss_scale_rad);
  for (size_t i = 0; i < bearings_a.size(); ++i) {
    problem.AddResidualBlock(EpipolarAngularCost::Create(bearings_a[i], bearings_b[i]), loss, q.coeffs().data(), t.data());
  }
  problem.SetManifold(q.coeffs().data(), new ceres::EigenQuaternionManifold);
  problem.SetManifold(t.data(), new ceres::SphereManifold<3>);

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = max_iterations;
  solver_options.num_threads = 1;  // callers parallelise over pairs; also keeps it deterministic
  solver_options.function_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-14;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary ceres_summary;
  QuietCeresLogs();
  ceres::Solve(solver_options, &problem, &ceres_summary);
  if (summary != nullptr) {
    summary->initial_cost = ceres_summary.initial_cost;
    summary->final_cost = ceres_summary.final_cost;
    summary->iterations = static_cast<int>(ceres_summary.iterations.size());
  }
  return Rigid3d(q.normalized(), t.normalized());
}

namespace {

// The essential matrix's pose (unit translation) from normalised coordinates of bearings in front
// of both cameras, or why there is none.
struct EssentialFit {
  std::optional<Rigid3d> pose;
  TwoViewFailure failure = TwoViewFailure::kNone;
  std::string failure_reason;
};
EssentialFit FitEssential(const std::vector<cv::Point2d>& pa, const std::vector<cv::Point2d>& pb, double thr,
                          const TwoViewOptions& options) {
  EssentialFit fit;
  if (static_cast<int>(pa.size()) < std::max(5, options.min_matches)) {
    fit.failure = TwoViewFailure::kTooFewInFront;
    fit.failure_reason = "too few correspondences in front of both cameras for the essential matrix (" +
                         std::to_string(pa.size()) + ")";
    return fit;
  }
  try {
    const cv::Mat k = cv::Mat::eye(3, 3, CV_64F);
    cv::Mat mask;
    // With K = I, USAC's threshold (pixels divided by the mean focal length) is our angle.
    cv::Mat e = cv::findEssentialMat(pa, pb, k, cv::USAC_MAGSAC, options.ransac_confidence, thr,
                                     options.ransac_max_iterations, mask);
    if (e.rows < 3 || e.cols != 3) {
      fit.failure = TwoViewFailure::kNoEssentialMatrix;
      fit.failure_reason = "essential matrix estimation found no model";
      return fit;
    }
    cv::Mat r_cv, t_cv;
    const int good = cv::recoverPose(e.rowRange(0, 3), pa, pb, k, r_cv, t_cv, mask);
    if (good < 5) {
      fit.failure = TwoViewFailure::kPoseRecoveryFailed;
      fit.failure_reason = "pose recovery left " + std::to_string(good) + " points in front of both cameras";
      return fit;
    }
    Eigen::Matrix3d r;
    Eigen::Vector3d t;
    for (int y = 0; y < 3; ++y) {
      for (int x = 0; x < 3; ++x) r(y, x) = r_cv.at<double>(y, x);
      t(y) = t_cv.at<double>(y);
    }
    fit.pose = Rigid3d(r, t.normalized());
  } catch (const cv::Exception& ex) {
    fit.failure = TwoViewFailure::kEssentialMatrixError;
    fit.failure_reason = std::string("essential matrix estimation failed: ") + ex.what();
  }
  return fit;
}

}  // namespace

TwoViewResult EstimateRelativePoseFromBearings(const std::vector<Eigen::Vector3d>& fa,
                                               const std::vector<Eigen::Vector3d>& fb, double thr,
                                               const TwoViewOptions& options) {
  options.Check();
  if (fa.size() != fb.size()) throw std::invalid_argument("EstimateRelativePoseFromBearings: size mismatch");
  if (!(thr > 0)) throw std::invalid_argument("EstimateRelativePoseFromBearings: threshold must be > 0");
  const int n = static_cast<int>(fa.size());
  TwoViewResult result;
  TwoViewEstimate& est = result.estimate;
  est.num_matches = n;
  result.inlier_mask.assign(n, 0);

  std::vector<int> valid;
  for (int i = 0; i < n; ++i) {
    if (fa[i].allFinite() && fb[i].allFinite() && fa[i].norm() > 0.5 && fb[i].norm() > 0.5) valid.push_back(i);
  }
  result.num_valid = static_cast<int>(valid.size());
  if (result.num_valid < options.min_matches) {
    std::ostringstream why;
    why << "too few matches: " << result.num_valid << " valid of " << n << " (need " << options.min_matches << ")";
    return Fail(result, TwoViewFailure::kTooFewMatches, why.str());
  }

  // Pure-rotation model, fitted alongside the essential matrix to detect unobservable translation.
  const RotationFit rot = FitRotation(fa, fb, valid, thr, options);
  result.num_rotation_inliers = static_cast<int>(rot.inliers.size());

  // Essential matrix on the bearings in front of both cameras, as normalised coordinates.
  std::vector<int> front;
  std::vector<cv::Point2d> pa, pb;
  for (int i : valid) {
    if (fa[i].z() > options.min_bearing_z * fa[i].norm() && fb[i].z() > options.min_bearing_z * fb[i].norm()) {
      front.push_back(i);
      pa.emplace_back(fa[i].x() / fa[i].z(), fa[i].y() / fa[i].z());
      pb.emplace_back(fb[i].x() / fb[i].z(), fb[i].y() / fb[i].z());
    }
  }
  const EssentialFit essential = FitEssential(pa, pb, thr, options);
  const bool have_pose = essential.pose.has_value();
  Rigid3d pose = essential.pose.value_or(Rigid3d());
  std::vector<int> inliers;
  if (have_pose) {
    inliers = RefineOnInliers(fa, fb, valid, thr, options, &pose);
    result.num_essential_inliers = static_cast<int>(inliers.size());
    // Which of the four poses of the essential matrix: the one that puts the most inliers in front
    // of both cameras, counted over every inlier of every frame (pose recovery saw only the
    // bearings in front of both image planes, and RANSAC's inliers of them).
    const Cheirality side = ResolveCheirality(pose, fa, fb, inliers, options.cheirality_min_angle_factor * thr);
    pose = side.pose;
    est.cheirality_points = side.informative;
    est.points_in_front = side.in_front;
    est.points_in_front_otherwise = side.second_best;
  }

  const int required_inliers =
      std::max(options.min_inliers, static_cast<int>(std::ceil(options.min_inlier_ratio * result.num_valid)));
  const bool rotation_explains = result.num_rotation_inliers >= required_inliers &&
                                 result.num_rotation_inliers >= options.rotation_only_ratio * result.num_essential_inliers;
  if (rotation_explains) {
    est.rotation_only = true;
    est.pair_type = PairType::kRotationOnly;
    est.cam_b_from_cam_a = Rigid3d(rot.rotation, Eigen::Vector3d::Zero());
    std::vector<double> res;
    for (int i : rot.inliers) {
      result.inlier_mask[i] = 1;
      res.push_back(RotationAngle(rot.rotation, fa[i], fb[i]));
    }
    est.num_inliers = result.num_rotation_inliers;
    est.median_residual_deg = RadToDeg(Median(res));
    est.success = true;
    est.failure = TwoViewFailure::kNone;
    return result;
  }
  if (!have_pose) return Fail(result, essential.failure, essential.failure_reason);
  if (result.num_essential_inliers < required_inliers) {
    std::ostringstream why;
    why << "no consistent geometry: " << result.num_essential_inliers << " inliers of " << result.num_valid
        << " matches (need " << required_inliers << ")";
    return Fail(result, TwoViewFailure::kTooFewInliers, why.str());
  }
  if (est.points_in_front < options.min_cheirality_points ||
      est.points_in_front < options.cheirality_margin * est.points_in_front_otherwise) {
    std::ostringstream why;
    why << "the matches do not say which way the baseline points: of " << est.cheirality_points
        << " inliers with parallax, " << est.points_in_front << " lie in front of both cameras under the best pose and "
        << est.points_in_front_otherwise << " under another (too little parallax, or matches of repeated structure)";
    return Fail(result, TwoViewFailure::kCheiralityUndecided, why.str());
  }
  est.cam_b_from_cam_a = pose;

  // Planar pairs: a homography explaining about as many matches as the essential matrix. The
  // pose stays the essential matrix's; the type says how far to trust it.
  const double thr_h = thr * std::sqrt(5.991 / 3.841);  // chi-square 95%: 2 dof vs 1 dof
  const HomographyFit hfit = FitHomography(pa, pb, front, fa, fb, thr_h, options);
  if (hfit.valid) {
    for (int i : valid) est.num_homography_inliers += HomographyAngle(hfit, fa[i], fb[i]) < thr_h;
  }
  if (est.num_homography_inliers >= required_inliers &&
      est.num_homography_inliers >= options.planar_ratio * result.num_essential_inliers) {
    est.pair_type = PairType::kPlanar;
    est.planar_alternatives = OtherPlanarPoses(hfit, pose, result.num_essential_inliers, fa, fb, valid, thr, options);
  }
  // A plane fits a family of poses; a planar pair reports the homography's other pose instead.
  if (est.pair_type != PairType::kPlanar) est.rival = StrongestRival(pose, inliers, fa, fb, valid, thr, options);

  std::vector<double> res;
  for (int i : inliers) {
    result.inlier_mask[i] = 1;
    res.push_back(EpipolarAngle(pose, fa[i], fb[i]));
  }
  est.num_inliers = result.num_essential_inliers;
  est.median_residual_deg = RadToDeg(Median(res));
  est.success = true;
  est.failure = TwoViewFailure::kNone;
  return result;
}

TwoViewResult EstimateRelativePose(const Camera& cam_a, const std::vector<Eigen::Vector2d>& px_a,
                                   const Camera& cam_b, const std::vector<Eigen::Vector2d>& px_b,
                                   const TwoViewOptions& options) {
  options.Check();
  if (px_a.size() != px_b.size()) throw std::invalid_argument("EstimateRelativePose: size mismatch");
  // Pixels outside a lens's valid region get a zero bearing: they count as invalid.
  std::vector<Eigen::Vector3d> fa(px_a.size(), Eigen::Vector3d::Zero()), fb(px_b.size(), Eigen::Vector3d::Zero());
  for (size_t i = 0; i < px_a.size(); ++i) {
    const auto ba = cam_a.CamFromImg(px_a[i]);
    const auto bb = cam_b.CamFromImg(px_b[i]);
    if (ba && bb) {
      fa[i] = *ba;
      fb[i] = *bb;
    }
  }
  const double mean_focal = 0.25 * (cam_a.fx() + cam_a.fy() + cam_b.fx() + cam_b.fy());
  return EstimateRelativePoseFromBearings(fa, fb, options.max_error_px / mean_focal, options);
}

}  // namespace rigsim
