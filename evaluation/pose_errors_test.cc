#include "evaluation/pose_errors.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

TEST(PoseErrors, KnownOffsets) {
  const Rigid3d gt(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized())),
                   Eigen::Vector3d(0.5, -0.1, 0.2));
  const Rigid3d off(Eigen::AngleAxisd(DegToRad(1.0), Eigen::Vector3d(0, 1, 1).normalized()) * gt.rotation,
                    gt.translation);
  EXPECT_NEAR(RotationErrorDeg(off, gt), 1.0, 1e-9);
  EXPECT_NEAR(RotationErrorDeg(gt, gt), 0.0, 1e-6);
  const Rigid3d flipped(gt.rotation, -3.0 * gt.translation);
  EXPECT_NEAR(TranslationDirectionErrorDeg(flipped, gt).value(), 180.0, 1e-9);
  EXPECT_NEAR(TranslationDirectionErrorDeg(Rigid3d(gt.rotation, 7.0 * gt.translation), gt).value(), 0.0, 1e-9);
  EXPECT_FALSE(TranslationDirectionErrorDeg(gt, Rigid3d(gt.rotation, Eigen::Vector3d::Zero())).has_value());
}

// The direction across an axis ignores both centres' components along the axis and the estimate's
// scale; a true centre on the axis has none.
TEST(PoseErrors, AcrossAxisDirection) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 2).normalized();
  const Eigen::Vector3d across = axis.unitOrthogonal();
  const Eigen::Vector3d turned = Eigen::AngleAxisd(DegToRad(4.0), axis) * across;
  const Eigen::Vector3d truth = 2.0 * across + 5.0 * axis;
  EXPECT_NEAR(AcrossAxisDirectionErrorDeg(axis, 0.1 * turned, truth).value(), 4.0, 1e-9);
  EXPECT_NEAR(AcrossAxisDirectionErrorDeg(axis, 0.1 * turned - 3.0 * axis, truth - 4.0 * axis).value(), 4.0, 1e-9);
  EXPECT_NEAR(AcrossAxisDirectionErrorDeg(-3.0 * axis, turned, truth).value(), 4.0, 1e-9);  // either sign, any length
  EXPECT_FALSE(AcrossAxisDirectionErrorDeg(axis, turned, 3.0 * axis).has_value());
  EXPECT_FALSE(AcrossAxisDirectionErrorDeg(axis, 2.0 * axis, truth).has_value());
  EXPECT_NEAR(AcrossAxis(2.0 * axis, truth).dot(axis), 0.0, 1e-12);
}

TEST(PoseAuc, RecallCurveArea) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_NEAR(PoseAuc({0.0, 0.0}, 5.0), 1.0, 1e-12);
  EXPECT_NEAR(PoseAuc({inf, std::nan("")}, 5.0), 0.0, 1e-12);
  // (0,0) -> (0.5, 0.5) -> flat to 1: 0.125 + 0.25.
  EXPECT_NEAR(PoseAuc({0.5, inf}, 1.0), 0.375, 1e-12);
}

}  // namespace
}  // namespace rigsim
