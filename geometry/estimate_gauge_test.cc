#include "geometry/estimate_gauge.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "testing/expect_error.h"

namespace rigsim {
namespace {

Rig OneCameraRig() {
  Rig rig;
  rig.cameras.push_back({"cam0", Camera(CameraModelId::kPinhole, 64, 48, {50, 50, 31.5, 23.5}), Rigid3d(), 0.0});
  return rig;
}

EstimateGauge UnitGauge() {
  EstimateGauge g;
  g.rig_frame = "cam0";
  g.scale = "unit scale: |centre of cam1| = 1";
  g.frames = "frames.json";
  return g;
}

TEST(EstimateGauge, RoundTripsThroughRigJsonAndTheRigStillReads) {
  const std::string text = EstimateRigToJsonText(OneCameraRig(), UnitGauge());
  const std::optional<EstimateGauge> back = EstimateGaugeFromJsonText(text, "rig.json");
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->rig_frame, "cam0");
  EXPECT_EQ(back->world, "the rig frame at the first frame");
  EXPECT_EQ(back->scale, "unit scale: |centre of cam1| = 1");
  EXPECT_FALSE(back->metric);
  EXPECT_EQ(back->frames, "frames.json");
  EXPECT_EQ(RigFromJsonText(text, "rig.json").cameras.size(), 1u);
}

TEST(EstimateGauge, ARigAsBuiltHasNone) {
  EXPECT_FALSE(EstimateGaugeFromJsonText(RigToJsonText(OneCameraRig()), "rig.json").has_value());
}

TEST(EstimateGauge, AMalformedRecordNamesTheFileAndTheField) {
  EXPECT_THAT([] { EstimateGaugeFromJsonText(R"({"cameras": [], "estimate": {"rig_frame": "cam0"}})", "est/rig.json"); },
              ThrowsExactly<std::runtime_error>("est/rig.json: estimate: missing field 'world'"));
  EXPECT_THAT([] { EstimateGaugeFromJsonText(R"({"cameras": [], "estimate": 3})", "est/rig.json"); },
              ThrowsExactly<std::runtime_error>("est/rig.json: 'estimate' must be an object"));
}

TEST(EstimateGauge, CommentsSayTheUnitAndReadBack) {
  EstimateGauge g = UnitGauge();
  const std::string unit = EstimateGaugeComment(g);
  EXPECT_NE(unit.find("not metres: unit scale: |centre of cam1| = 1"), std::string::npos) << unit;
  EXPECT_EQ(MetricMarkInComments("cam0:\n  x: 1\n" + unit), false);
  g.metric = true;
  g.scale = "metric: |cam0 - cam1| = 0.5000 m";
  EXPECT_EQ(MetricMarkInComments(EstimateGaugeComment(g) + "cam0:\n"), true);
  EXPECT_FALSE(MetricMarkInComments("cam0:\n  camera_model: pinhole\n# another comment\n").has_value());
}

}  // namespace
}  // namespace rigsim
