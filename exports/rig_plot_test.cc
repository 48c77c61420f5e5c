#include "exports/rig_plot.h"

#include <map>
#include <regex>
#include <stdexcept>
#include <string>
#include <utility>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

using Centres = std::map<std::pair<std::string, std::string>, Eigen::Vector2d>;  // (class, camera) -> page

Centres CirclesOf(const std::string& svg) {
  Centres out;
  const std::regex circle(R"re(<circle class="(\w+)" data-camera="([^"]+)" cx="([-\d.]+)" cy="([-\d.]+)")re");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), circle); it != std::sregex_iterator(); ++it) {
    out[{(*it)[1], (*it)[2]}] = Eigen::Vector2d(std::stod((*it)[3]), std::stod((*it)[4]));
  }
  return out;
}

Rigid3d Yaw(double deg, const Eigen::Vector3d& centre_in_rig) {  // a camera turned about the rig's y axis
  const Eigen::Quaterniond rig_from_cam(Eigen::AngleAxisd(deg * M_PI / 180, Eigen::Vector3d::UnitY()));
  return Rigid3d(rig_from_cam, centre_in_rig).Inverse();
}

// The truth: cam0, cam1 1 m to cam0's right, cam2 1 m ahead of cam0 and turned 90 degrees, in a
// rig frame that is not cam0's (turned by 30 degrees and offset), so the plot must change frames.
Rig Truth() {
  const Camera camera(CameraModelId::kPinhole, 640, 480, {400, 400, 319.5, 239.5});
  const Rigid3d cam0_from_rig = Yaw(30, {0.3, 0.1, -0.2});
  auto placed = [&](double yaw, const Eigen::Vector3d& centre_in_cam0) {  // given in cam0's frame
    return Yaw(yaw, centre_in_cam0) * cam0_from_rig;
  };
  Rig rig;
  rig.cameras.push_back({"cam0", camera, cam0_from_rig, 0.0});
  rig.cameras.push_back({"cam1", camera, placed(0, {1, 0, 0}), 0.0});
  rig.cameras.push_back({"cam2", camera, placed(90, {0, 0, 1}), 0.0});
  return rig;
}

// A unit-scale estimate in cam0's frame at half the true size, cam2 with a rotation only.
RigPlotInput HalfScaleEstimate() {
  const Rig truth = Truth();
  RigPlotInput in;
  in.title = "test <rig> & co";
  in.truth = truth;
  in.estimate = truth;
  const Rigid3d rig_from_cam0 = truth.cameras[0].cam_from_rig->Inverse();
  for (RigCamera& c : in.estimate.cameras) {
    Rigid3d cam_from_cam0 = *c.cam_from_rig * rig_from_cam0;
    cam_from_cam0.translation *= 0.5;
    c.cam_from_rig = cam_from_cam0;
  }
  in.rotation_only = {std::nullopt, std::nullopt, in.estimate.cameras[2].cam_from_rig->rotation};
  in.estimate.cameras[2].cam_from_rig.reset();
  return in;
}

TEST(RigPlot, EstimateAndTruthMeetInTheFirstCamerasFrameSeenFromAbove) {
  const std::string svg = RigTopDownSvg(HalfScaleEstimate());
  ASSERT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("test &lt;rig&gt; &amp; co"), std::string::npos) << "the title is escaped";
  const Centres c = CirclesOf(svg);
  ASSERT_EQ(c.size(), 5u) << svg;  // three true centres, two estimated
  const Eigen::Vector2d t0 = c.at({"truth", "cam0"}), t1 = c.at({"truth", "cam1"}), t2 = c.at({"truth", "cam2"});
  EXPECT_GT(t1.x() - t0.x(), 50) << "cam1 is to cam0's right";
  EXPECT_NEAR(t1.y(), t0.y(), 0.2);
  EXPECT_LT(t2.y() - t0.y(), -50) << "cam2 is ahead of cam0: up the page";
  EXPECT_NEAR(t2.x(), t0.x(), 0.2);
  EXPECT_NEAR((t1 - t0).norm(), (t2 - t0).norm(), 0.2) << "one scale on both axes";
  // The half-size unit-scale estimate is scaled onto the truth.
  EXPECT_LT((c.at({"estimate", "cam0"}) - t0).norm(), 0.2);
  EXPECT_LT((c.at({"estimate", "cam1"}) - t1).norm(), 0.2);
  EXPECT_EQ(c.count({"estimate", "cam2"}), 0u) << "no position estimated";
  EXPECT_NE(svg.find("stroke-dasharray"), std::string::npos) << "cam2's rotation drawn dashed";
  EXPECT_NE(svg.find(" m</text>"), std::string::npos) << "scaled to the truth: a scale bar in metres";
}

TEST(RigPlot, AMetricEstimateIsNotRescaled) {
  RigPlotInput in = HalfScaleEstimate();
  in.metric = true;
  const Centres c = CirclesOf(RigTopDownSvg(in));
  const Eigen::Vector2d t0 = c.at({"truth", "cam0"}), t1 = c.at({"truth", "cam1"});
  const Eigen::Vector2d e1 = c.at({"estimate", "cam1"});
  EXPECT_NEAR((e1 - t0).norm(), 0.5 * (t1 - t0).norm(), 0.3) << "drawn at its own (half) size";
}

TEST(RigPlot, WithoutTruthTheEstimateAloneInUnits) {
  RigPlotInput in = HalfScaleEstimate();
  in.truth.reset();
  const std::string svg = RigTopDownSvg(in);
  const Centres c = CirclesOf(svg);
  EXPECT_EQ(c.size(), 2u);
  EXPECT_NE(svg.find(" units</text>"), std::string::npos);
}

TEST(RigPlot, MismatchedCamerasAreRefused) {
  RigPlotInput in = HalfScaleEstimate();
  in.truth->cameras[1].name = "other";
  EXPECT_THROW(RigTopDownSvg(in), std::invalid_argument);
  in = HalfScaleEstimate();
  in.truth->cameras.pop_back();
  EXPECT_THROW(RigTopDownSvg(in), std::invalid_argument);
  in = HalfScaleEstimate();
  in.estimate.cameras[0].cam_from_rig.reset();
  EXPECT_THROW(RigTopDownSvg(in), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
