#include "geometry/rig.h"

#include <filesystem>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

Rig TwoCameraRig() {
  Rig rig;
  rig.cameras.push_back({"front", Camera(CameraModelId::kPinhole, 64, 48, {50, 50, 31.5, 23.5}), Rigid3d(), 0.0});
  rig.cameras.push_back({"left",
                         Camera(CameraModelId::kOpenCV, 64, 48, {40, 41, 32, 24, -0.1, 0.01, 0.001, 0.002}),
                         Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY())),
                                 Eigen::Vector3d(0.2, 0, -0.1)),
                         0.004});
  return rig;
}

TEST(Rig, JsonRoundTripKeepsEverything) {
  const Rig rig = TwoCameraRig();
  const Rig back = RigFromJsonText(RigToJsonText(rig), "test");
  ASSERT_EQ(back.cameras.size(), 2u);
  EXPECT_EQ(back.cameras[1].name, "left");
  EXPECT_EQ(back.cameras[1].camera.model(), CameraModelId::kOpenCV);
  EXPECT_EQ(back.cameras[1].camera.params(), rig.cameras[1].camera.params());
  EXPECT_DOUBLE_EQ(back.cameras[1].time_offset_s, 0.004);
  ASSERT_TRUE(back.cameras[1].cam_from_rig.has_value());
  EXPECT_LT(RotationDifferenceDeg(back.cameras[1].cam_from_rig->rotation, rig.cameras[1].cam_from_rig->rotation), 1e-9);
  EXPECT_LT((back.cameras[1].cam_from_rig->translation - rig.cameras[1].cam_from_rig->translation).norm(), 1e-12);
  EXPECT_EQ(back.FindCamera("left"), 1);
  EXPECT_EQ(back.FindCamera("right"), -1);
}

TEST(Rig, TimingRoundTripsAndIsWrittenOnlyWhenOn) {
  Rig rig = TwoCameraRig();
  EXPECT_EQ(RigToJsonText(rig).find("readout"), std::string::npos);  // off: the file is as before
  EXPECT_EQ(RigToJsonText(rig).find("exposure_s"), std::string::npos);
  rig.cameras[1].readout_s = 0.03;
  rig.cameras[1].readout_bottom_to_top = true;
  rig.cameras[1].exposure_s = 0.002;
  const Rig back = RigFromJsonText(RigToJsonText(rig), "test");
  EXPECT_DOUBLE_EQ(back.cameras[1].readout_s, 0.03);
  EXPECT_TRUE(back.cameras[1].readout_bottom_to_top);
  EXPECT_DOUBLE_EQ(back.cameras[1].exposure_s, 0.002);
  EXPECT_FALSE(back.cameras[0].CaptureSpansTime());
  EXPECT_TRUE(back.cameras[1].CaptureSpansTime());
  // Bottom to top: the last row (47) first, at the offset; row 0 last, 47/48 of the readout later.
  EXPECT_DOUBLE_EQ(back.cameras[1].RowTime(47), 0.004);
  EXPECT_DOUBLE_EQ(back.cameras[1].RowTime(0), 0.004 + 47 * 0.03 / 48);
}

TEST(Rig, BadTimingIsRefusedNamingTheField) {
  const std::string head = R"({"cameras":[{"name":"a","model":"PINHOLE","width":10,"height":10,"params":[5,5,4.5,4.5],)";
  for (const std::string& bad : {std::string(R"("readout_s": -1)"), std::string(R"("exposure_s": -0.1)"),
                                 std::string(R"("readout_direction": "left-to-right")")}) {
    try {
      RigFromJsonText(head + bad + "}]}", "rig.json");
      ADD_FAILURE() << bad;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(bad.substr(1, bad.find('"', 1) - 1)), std::string::npos) << e.what();
    }
  }
}

// A call that reads `text` as my/rig.json.
auto Parsing(const std::string& text) {
  return [text] { RigFromJsonText(text, "my/rig.json"); };
}

TEST(Rig, RenderLensRoundTripsAndIsWrittenOnlyWhenSet) {
  Rig rig = TwoCameraRig();
  EXPECT_EQ(RigToJsonText(rig).find("render_lens"), std::string::npos);  // unset: the file is as before
  const Camera lens(CameraModelId::kFullOpenCV, 64, 48, {40, 41, 32, 24, -0.1, 0.01, 0.001, 0.002, 0.03, 0, 0, 0});
  rig.cameras[1].render_lens = lens;
  const Rig back = RigFromJsonText(RigToJsonText(rig), "test");
  EXPECT_FALSE(back.cameras[0].render_lens.has_value());
  ASSERT_TRUE(back.cameras[1].render_lens.has_value());
  EXPECT_EQ(back.cameras[1].render_lens->model(), CameraModelId::kFullOpenCV);
  EXPECT_EQ(back.cameras[1].render_lens->params(), lens.params());
  EXPECT_EQ(back.cameras[1].camera.params(), rig.cameras[1].camera.params());  // the model stays the user's
  EXPECT_EQ(&back.cameras[0].RenderedCamera(), &back.cameras[0].camera);
  // As rendered: the lens in the model's place, the model untouched in the original.
  const Rig rendered = back.AsRendered();
  EXPECT_EQ(rendered.cameras[1].camera.model(), CameraModelId::kFullOpenCV);
  EXPECT_EQ(rendered.cameras[1].camera.params(), lens.params());
  EXPECT_FALSE(rendered.cameras[1].render_lens.has_value());
  EXPECT_EQ(rendered.cameras[0].camera.params(), back.cameras[0].camera.params());
}

TEST(Rig, BadRenderLensIsRefusedNamingTheField) {
  using E = std::runtime_error;
  const std::string head = R"({"cameras":[{"name":"a","model":"PINHOLE","width":10,"height":10,"params":[5,5,4.5,4.5],)";
  EXPECT_THAT(Parsing(head + R"("render_lens": 3}]})"), ThrowsWith<E>("my/rig.json", "render_lens", "'a'", "object"));
  EXPECT_THAT(Parsing(head + R"("render_lens": {"params": [5,5,4.5,4.5]}}]})"),
              ThrowsWith<E>("my/rig.json", "render_lens", "model"));
  EXPECT_THAT(Parsing(head + R"("render_lens": {"model": "FISH", "params": [5,5,4.5,4.5]}}]})"),
              ThrowsWith<E>("my/rig.json", "render_lens", "FISH"));
  EXPECT_THAT(Parsing(head + R"("render_lens": {"model": "OPENCV", "params": [5,5,4.5,4.5]}}]})"),
              ThrowsWith<E>("my/rig.json", "render_lens", "8 parameters"));
}

TEST(Rig, PosesAreOptionalForRealPhotos) {
  const Rig rig = RigFromJsonText(
      R"({"cameras":[{"name":"a","model":"PINHOLE","width":10,"height":10,"params":[5,5,4.5,4.5]}]})", "rig.json");
  EXPECT_FALSE(rig.cameras[0].cam_from_rig.has_value());
  EXPECT_FALSE(rig.HasAllPoses());
}

TEST(Rig, BadJsonNamesTheFileAndTheProblem) {
  using E = std::runtime_error;
  EXPECT_THAT(Parsing("{\"cameras\": ["), ThrowsWith<E>("my/rig.json", "invalid JSON"));
  EXPECT_THAT(Parsing("{\"cameras\": []}"), ThrowsWith<E>("my/rig.json", "empty"));
  EXPECT_THAT(Parsing(R"({"cameras":[{"name":"a","width":10,"height":10,"params":[5,5,4.5,4.5]}]})"),
              ThrowsWith<E>("my/rig.json", "model"));
  EXPECT_THAT(Parsing(R"({"cameras":[{"name":"a","model":"PINHOLE","width":"ten","height":10,"params":[5,5,4.5,4.5]}]})"),
              ThrowsWith<E>("my/rig.json", "width"));
  EXPECT_THAT(Parsing(R"({"cameras":[{"name":"a","model":"PINHOLE","width":10,"height":10,"params":[-5,5,4.5,4.5]}]})"),
              ThrowsWith<E>("my/rig.json", "focal"));
  // Integer fields take integers that fit: nlohmann would cast these with undefined behaviour.
  EXPECT_THAT(Parsing(R"({"cameras":[{"name":"a","model":"PINHOLE","width":10,"height":489999999999999999999999999999,"params":[5,5,4.5,4.5]}]})"),
              ThrowsWith<E>("my/rig.json", "height: must be an integer"));
  EXPECT_THAT(Parsing(R"({"cameras":[{"name":"a","model":"PINHOLE","width":10.5,"height":10,"params":[5,5,4.5,4.5]}]})"),
              ThrowsWith<E>("my/rig.json", "width: must be an integer"));
  EXPECT_THAT(Parsing(R"({"cameras":[{"name":"a","model":"PINHOLE","width":18446744073709551615,"height":10,"params":[5,5,4.5,4.5]}]})"),
              ThrowsWith<E>("my/rig.json", "width: out of range"));
  EXPECT_THAT(Parsing(R"({"cameras":[{"name":"a","model":"OPENCV","width":10,"height":10,"params":[5,5,4.5,4.5]}]})"),
              ThrowsWith<E>("my/rig.json", "8 parameters"));
  EXPECT_THAT(Parsing(R"({"cameras":[{"name":"a","model":"PINHOLE","width":10,"height":10,"params":[5,5,4.5,4.5]},
                                     {"name":"a","model":"PINHOLE","width":10,"height":10,"params":[5,5,4.5,4.5]}]})"),
              ThrowsWith<E>("my/rig.json", "duplicate"));
  EXPECT_THAT(Parsing(R"({"cameras":[{"name":"a","model":"PINHOLE","width":10,"height":10,"params":[5,5,4.5,4.5],
                          "cam_from_rig":{"rotation_wxyz":[2,0,0,0],"translation":[0,0,0]}}]})"),
              ThrowsWith<E>("my/rig.json", "unit quaternion"));
}

// The real-rig folders' truth_rig.json names cam_from_rig's quaternion "rotation", w first: it reads
// as the same rig as with "rotation_wxyz", and writes back as rigsim's own key.
TEST(Rig, ARotationUnderTheKeyRotationReadsWFirst) {
  // A turn about an axis off every coordinate axis: read x first, the pose would be another.
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, -1.0, 0.3).normalized()));
  const auto text = [&](const std::string& key) {
    nlohmann::json camera = {{"name", "a"}, {"model", "PINHOLE"}, {"width", 10}, {"height", 10}, {"params", {5, 5, 4.5, 4.5}}};
    camera["cam_from_rig"] = {{key, {q.w(), q.x(), q.y(), q.z()}}, {"translation", {0.1, -0.2, 0.3}}};
    return nlohmann::json{{"cameras", {camera}}}.dump();
  };
  const Rig truth = RigFromJsonText(text("rotation"), "truth_rig.json");
  ASSERT_TRUE(truth.cameras[0].cam_from_rig.has_value());
  EXPECT_LT(RotationDifferenceDeg(truth.cameras[0].cam_from_rig->rotation, q), 1e-9);
  EXPECT_EQ(truth.cameras[0].cam_from_rig->translation, Eigen::Vector3d(0.1, -0.2, 0.3));
  const std::string written = RigToJsonText(truth);
  EXPECT_NE(written.find("\"rotation_wxyz\""), std::string::npos) << written;
  EXPECT_EQ(written.find("\"rotation\""), std::string::npos) << written;
  EXPECT_EQ(RigToJsonText(RigFromJsonText(text("rotation_wxyz"), "rig.json")), written);
  // Both keys: which one holds is not known. A bad quaternion is named by the file's key.
  using E = std::runtime_error;
  nlohmann::json both = nlohmann::json::parse(text("rotation"));
  both["cameras"][0]["cam_from_rig"]["rotation_wxyz"] = {1, 0, 0, 0};
  EXPECT_THAT(Parsing(both.dump()),
              ThrowsWith<E>("my/rig.json: cameras[0].cam_from_rig ('a'): has both \"rotation_wxyz\" and \"rotation\""));
  EXPECT_THAT(Parsing(R"({"cameras":[{"name":"a","model":"PINHOLE","width":10,"height":10,"params":[5,5,4.5,4.5],
                          "cam_from_rig":{"rotation":[2,0,0,0],"translation":[0,0,0]}}]})"),
              ThrowsWith<E>("my/rig.json: cameras[0].cam_from_rig: rotation is not a unit quaternion"));
}

TEST(Rig, WriteAndReadAFile) {
  const TempDir dir;
  WriteRig(TwoCameraRig(), dir / "rig.json");
  EXPECT_EQ(ReadRig(dir / "rig.json").cameras.size(), 2u);
  EXPECT_THROW(ReadRig(dir / "missing.json"), std::runtime_error);
}

}  // namespace
}  // namespace rigsim
