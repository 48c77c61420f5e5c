#include "evaluation/match_precision.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

// Two pinhole cameras 0.5 m apart looking at a wall 4 m away; the top rows of both see no
// surface (sky).
struct PlaneScene {
  Camera cam = Camera(CameraModelId::kPinhole, 160, 120, {100, 100, 79.5, 59.5});
  Rigid3d b_from_a = Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.5, 0, 0));
  ImageF range_a, range_b;
  ViewPose pose_a{{Rigid3d()}}, pose_b{{b_from_a}};

  static ImageF Range(const Camera& cam) {
    ImageF r(cam.width(), cam.height(), 1, 0.f);
    for (int y = 20; y < cam.height(); ++y) {
      for (int x = 0; x < cam.width(); ++x) {
        const Eigen::Vector3d f = *cam.CamFromImg(Eigen::Vector2d(x, y));
        r.at(x, y) = static_cast<float>(4.0 / f.z());
      }
    }
    return r;
  }
  PlaneScene() : range_a(Range(cam)), range_b(Range(cam)) {}
};

TEST(CrossClassMatches, ComparesTheTrueClassUnderEachKeypoint) {
  // A: left half road (7), right half building (11); B: everything building.
  ImageU8 a(4, 2, 1, 7), b(4, 2, 1, 11);
  for (int y = 0; y < 2; ++y) {
    for (int x = 2; x < 4; ++x) a.at(x, y) = 11;
  }
  const std::vector<Eigen::Vector2d> pa = {{0.2, 0.4}, {2.6, 1.0}, {1.49, 0.0}, {1.51, 0.0}, {-0.6, 0.0}};
  const std::vector<Eigen::Vector2d> pb = {{1.0, 1.0}, {0.0, 0.0}, {3.0, 1.0}, {3.0, 1.0}, {0.0, 0.0}};
  // road-building, building-building, road (x rounds to 1), building (rounds to 2), outside A.
  EXPECT_EQ(CrossClassMatches(pa, pb, a, b), (std::vector<char>{1, 0, 1, 0, 1}));
  MatchPrecisionCounts sum{10, 6, 1, 4, 1};
  sum += MatchPrecisionCounts{5, 5, 0, 2, 2};
  EXPECT_EQ(sum.cross_class, 6);
  EXPECT_EQ(sum.cross_class_correct, 3);
}

TEST(MatchPrecision, PlaneCorrectAndShiftedMatches) {
  const PlaneScene s;
  std::vector<Eigen::Vector2d> pa, pb, pb_shifted;
  for (int y = 30; y < 110; y += 10) {
    for (int x = 30; x < 150; x += 10) {
      const Eigen::Vector2d a(x + 0.3, y - 0.2);
      const Eigen::Vector3d x_a = *s.cam.CamFromImg(a) * (4.0 / s.cam.CamFromImg(a)->z());
      const Eigen::Vector2d b = *s.cam.ImgFromCam(s.b_from_a * x_a);
      if (!s.cam.IsInImage(b)) continue;
      pa.push_back(a);
      pb.push_back(b + Eigen::Vector2d(0.4, -0.3));  // keypoint noise well below 2 px
      pb_shifted.push_back(b + Eigen::Vector2d(3.0, 4.0));  // 5 px away
    }
  }
  ASSERT_GT(pa.size(), 50u);
  const MatchPrecisionCounts good = MatchPrecision(pa, pb, s.cam, s.range_a, s.pose_a, s.cam, s.range_b, s.pose_b);
  EXPECT_EQ(good.evaluated, static_cast<int>(pa.size()));
  EXPECT_EQ(good.correct, good.evaluated);
  EXPECT_DOUBLE_EQ(good.Precision(), 1.0);
  const MatchPrecisionCounts bad = MatchPrecision(pa, pb_shifted, s.cam, s.range_a, s.pose_a, s.cam, s.range_b, s.pose_b);
  EXPECT_EQ(bad.evaluated, good.evaluated);
  EXPECT_EQ(bad.correct, 0);
}

TEST(MatchPrecision, SkyIsAPointAtInfinityAndEmptyIsNaN) {
  const PlaneScene s;
  // Sky pixel (row 5): under a pure translation a point at infinity stays at the same pixel.
  const std::vector<Eigen::Vector2d> pa = {{40, 5}, {40, 5}, {40, 50}};
  const std::vector<Eigen::Vector2d> pb = {{40.5, 5}, {60, 5}, {40, 5}};  // right, wrong, wall->sky
  int at_infinity = 0;
  const std::vector<char> ok =
      CheckMatches(pa, pb, s.cam, s.range_a, s.pose_a, s.cam, s.range_b, s.pose_b, MatchPrecisionOptions(), &at_infinity);
  EXPECT_EQ(ok, (std::vector<char>{1, 0, 0}));
  EXPECT_EQ(at_infinity, 2);
  EXPECT_TRUE(std::isnan(MatchPrecisionCounts().Precision()));
}

// B is a rolling shutter that captures while the rig moves sideways: row y is seen from 1 mm further
// per row (12 cm from top to bottom). Matches made at each row's pose are all correct when B is
// checked per row, and those low in the image are wrong when B is taken at its first row's pose:
// the check must use the pose at each keypoint's capture time.
TEST(MatchPrecision, JudgesEachViewAtItsCaptureTime) {
  const PlaneScene s;
  ViewPose rolling;
  for (int y = 0; y < s.cam.height(); ++y) {
    rolling.cam_from_world_rows.push_back(Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.5 - 0.001 * y, 0, 0)));
  }
  std::vector<Eigen::Vector2d> pa, pb;
  for (int y = 30; y < 120; y += 10) {
    for (int x = 30; x < 150; x += 10) {
      const Eigen::Vector2d a(x, y);
      const Eigen::Vector3d x_world = *s.cam.CamFromImg(a) * (4.0 / s.cam.CamFromImg(a)->z());
      const auto b = ProjectIntoView(x_world, s.cam, rolling);
      if (!b || !s.cam.IsInImage(b->px)) continue;
      pa.push_back(a);
      pb.push_back(b->px);
    }
  }
  ASSERT_GT(pa.size(), 50u);
  const std::vector<char> per_row = CheckMatches(pa, pb, s.cam, s.range_a, s.pose_a, s.cam, s.range_b, rolling, {});
  EXPECT_EQ(std::count(per_row.begin(), per_row.end(), 1), static_cast<long>(pa.size()));
  const ViewPose first_row{{rolling.Row(0)}};
  const std::vector<char> frozen = CheckMatches(pa, pb, s.cam, s.range_a, s.pose_a, s.cam, s.range_b, first_row, {});
  int checked = 0;
  for (size_t i = 0; i < pa.size(); ++i) {
    checked += pb[i].y() >= 100;
    // 1 mm per row moves a point 4 m away by 100 * 0.001 * y / 4 = 0.025 y px.
    if (pb[i].y() >= 100) {
      EXPECT_FALSE(frozen[i]) << "match at row " << pb[i].y();
    }
  }
  EXPECT_GT(checked, 10);
}

}  // namespace
}  // namespace rigsim
