#include "geometry/json_io.h"

#include <limits>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

TEST(JsonIo, OptionalNumberIsNullWhenUnknownOrNotFinite) {
  EXPECT_EQ(json_io::OptionalNumber(0.25), json_io::Json(0.25));
  EXPECT_TRUE(json_io::OptionalNumber(std::nullopt).is_null());
  EXPECT_TRUE(json_io::OptionalNumber(std::numeric_limits<double>::infinity()).is_null());
  EXPECT_TRUE(json_io::OptionalNumber(std::numeric_limits<double>::quiet_NaN()).is_null());
}

TEST(JsonIo, PoseRoundTrip) {
  const Rigid3d pose(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())), Eigen::Vector3d(1, -2, 3));
  const json_io::Json j = json_io::PoseToJson(pose);
  EXPECT_DOUBLE_EQ(j["rotation_wxyz"][0].get<double>(), pose.rotation.w());
  const Rigid3d back = json_io::PoseFromJson(j, "test", "pose");
  EXPECT_TRUE(back.rotation.isApprox(pose.rotation));
  EXPECT_TRUE(back.translation.isApprox(pose.translation));
}

}  // namespace
}  // namespace rigsim
