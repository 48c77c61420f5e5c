// The test toolkit checked the way the tests rely on it.
#include <unistd.h>

#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "testing/expect_error.h"
#include "testing/gltf_builder.h"
#include "testing/synthetic_rig.h"
#include "testing/temp_dir.h"
#include "testing/test_name.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

TEST(TempDir, IsFreshNamedAfterTheTestAndTheProcessAndGoneAfterAPassingTest) {
  fs::path kept;
  {
    const TempDir dir;
    kept = dir.path();
    EXPECT_EQ(dir.path().filename().string(), "rigsim_TempDir.IsFreshNamedAfterTheTestAndTheProcessAndGoneAfterAPassingTest_" +
                                                  std::to_string(::getpid()));
    ASSERT_TRUE(fs::is_directory(dir));
    EXPECT_TRUE(fs::is_empty(dir));
    WriteFile(dir / "a.txt", "a");
    const TempDir second;  // alive at once: a folder of its own
    EXPECT_EQ(second.string(), dir.string() + "_2");
    EXPECT_TRUE(fs::is_empty(second));
  }
  EXPECT_FALSE(fs::exists(kept));
  const TempDir again;  // the name is free again
  EXPECT_EQ(again.path(), kept);
  EXPECT_TRUE(fs::is_empty(again));
}

class TempDirOfASuite : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    EXPECT_EQ(CurrentTest().name, "TempDirOfASuite");
    EXPECT_TRUE(CurrentTest().whole_suite);
    shared_ = new TempDir();
  }
  static void TearDownTestSuite() {
    const fs::path path = shared_->path();
    delete shared_;
    EXPECT_FALSE(fs::exists(path));
  }
  static TempDir* shared_;
};
TempDir* TempDirOfASuite::shared_ = nullptr;

TEST_F(TempDirOfASuite, IsNamedAfterTheSuite) {
  EXPECT_EQ(CurrentTest().name, "TempDirOfASuite.IsNamedAfterTheSuite");
  EXPECT_FALSE(CurrentTest().whole_suite);
  EXPECT_EQ(shared_->path().filename().string(), "rigsim_TempDirOfASuite_" + std::to_string(::getpid()));
  EXPECT_TRUE(fs::is_directory(*shared_));
}

TEST(Files, WriteAndReadBytesAsTheyAre) {
  const TempDir dir;
  const std::string bytes("line\r\n\0\xff", 8);
  WriteFile(dir / "f.bin", bytes);
  EXPECT_EQ(ReadFile(dir / "f.bin"), bytes);
  EXPECT_EQ(ReadFile(dir / "missing"), "");
  EXPECT_THAT([&] { WriteFile(dir / "no" / "such" / "folder", "x"); }, ThrowsWith<std::runtime_error>("cannot write"));
}

// What a matcher says about `call`: the readable failure a test would print.
template <typename Matcher, typename Call>
std::string Explain(const Matcher& matcher, const Call& call, bool* matched) {
  ::testing::StringMatchResultListener listener;
  *matched = ::testing::ExplainMatchResult(matcher, call, &listener);
  return listener.str();
}

TEST(ExpectError, MatchesTheTypeAndTheMessageAndSaysWhatHappenedInstead) {
  auto throws = [] { throw std::invalid_argument("rig.json: camera 'x': focal lengths must be positive"); };
  EXPECT_THAT(throws, ThrowsWith<std::invalid_argument>("focal lengths"));
  EXPECT_THAT(throws, ThrowsWith<std::logic_error>("focal lengths"));  // a base class
  EXPECT_THAT(throws, ThrowsWith("camera 'x'"));
  EXPECT_THAT(throws, ThrowsExactly<std::invalid_argument>("rig.json: camera 'x': focal lengths must be positive"));
  EXPECT_THAT(throws, ThrowsNaming<std::invalid_argument>(fs::path("rig.json"), "must be positive"));

  bool matched = true;
  EXPECT_THAT(Explain(ThrowsWith<std::invalid_argument>("negative"), throws, &matched),
              ::testing::HasSubstr("focal lengths must be positive"));  // the actual message
  EXPECT_FALSE(matched);
  Explain(ThrowsExactly<std::invalid_argument>("focal lengths must be positive"), throws, &matched);
  EXPECT_FALSE(matched);
  Explain(ThrowsNaming<std::invalid_argument>(fs::path("camera"), "focal"), throws, &matched);
  EXPECT_FALSE(matched);  // contains the file, does not start with it
  EXPECT_THAT(Explain(ThrowsWith<std::runtime_error>("focal"), throws, &matched), ::testing::HasSubstr("invalid_argument"));
  EXPECT_FALSE(matched);
  EXPECT_THAT(Explain(ThrowsWith<std::runtime_error>("x"), [] {}, &matched), ::testing::HasSubstr("does not throw"));
  EXPECT_FALSE(matched);

  EXPECT_EQ(ErrorMessage<std::invalid_argument>(throws), "rig.json: camera 'x': focal lengths must be positive");
  EXPECT_EQ(ErrorMessage<std::invalid_argument>([] {}), "");
}

TEST(GltfBuilder, DataUriIsBase64) {
  EXPECT_EQ(DataUri("text/plain", {'M', 'a', 'n'}), "data:text/plain;base64,TWFu");
  EXPECT_EQ(DataUri("text/plain", {'M', 'a'}), "data:text/plain;base64,TWE=");
  EXPECT_EQ(DataUri("text/plain", {'M'}), "data:text/plain;base64,TQ==");
  EXPECT_EQ(TinyPngUri().rfind("data:image/png;base64,iVBORw0KGgo", 0), 0u);  // the PNG signature
}

TEST(GltfBuilder, WritesTheDocumentWithItsBufferBesideItOrEmbedded) {
  const TempDir dir;
  GltfBuilder g;
  const int bytes = g.Accessor<uint8_t>({1, 2, 3}, kGltfUByte, "SCALAR", 3);
  const int pos = g.Positions(kUnitQuad);
  EXPECT_EQ(g.doc["bufferViews"][pos]["byteOffset"], 4);  // aligned to 4 bytes
  EXPECT_EQ(g.bin.size(), 4u + 48u);
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}}, bytes, 4)}});
  g.Scene({0});
  g.extra_buffers.push_back({{"byteLength", 8}, {"uri", "other.bin"}});

  const fs::path gltf = g.Write(dir, "quad");
  EXPECT_EQ(gltf, dir / "quad.gltf");
  const json written = json::parse(ReadFile(gltf));
  EXPECT_EQ(written["buffers"][0], json({{"byteLength", 52}, {"uri", "quad.bin"}}));
  EXPECT_EQ(written["buffers"][1]["uri"], "other.bin");
  EXPECT_EQ(ReadFile(dir / "quad.bin"), std::string(g.bin.begin(), g.bin.end()));
  EXPECT_EQ(written["meshes"][0]["primitives"][0], json({{"attributes", {{"POSITION", 1}}}, {"indices", 0}, {"mode", 4}}));
  EXPECT_EQ(written["scenes"][0]["nodes"], json({0}));

  const json embedded = json::parse(ReadFile(g.WriteEmbedded(dir, "embedded")));
  EXPECT_EQ(embedded["buffers"][0]["uri"], DataUri("application/octet-stream", g.bin));
  EXPECT_FALSE(fs::exists(dir / "embedded.bin"));

  g.doc["buffers"] = {{{"byteLength", 52}, {"uri", "missing.bin"}}};  // a test's own buffers stay
  EXPECT_EQ(json::parse(ReadFile(g.Write(dir, "own")))["buffers"], g.doc["buffers"]);
}

TEST(GltfBuilder, GlbHoldsTheDocumentAndTheBufferInAlignedChunks) {
  const TempDir dir;
  GltfBuilder g;
  g.Triangle({0, 0, 0, 1, 0, 0, 0, 1, 0}, "building");
  g.Accessor<uint8_t>({7}, kGltfUByte, "SCALAR", 1);  // leaves `bin` at 37 bytes
  const std::string glb = ReadFile(g.WriteGlb(dir, "t"));
  auto u32 = [&](size_t at) { return uint32_t(uint8_t(glb[at])) | uint32_t(uint8_t(glb[at + 1])) << 8 |
                                     uint32_t(uint8_t(glb[at + 2])) << 16 | uint32_t(uint8_t(glb[at + 3])) << 24; };
  EXPECT_EQ(glb.substr(0, 4), "glTF");
  EXPECT_EQ(u32(4), 2u);
  EXPECT_EQ(u32(8), glb.size());
  const uint32_t json_length = u32(12);
  EXPECT_EQ(u32(16), 0x4E4F534Au);  // "JSON"
  EXPECT_EQ(json_length % 4, 0u);
  const json doc = json::parse(glb.substr(20, json_length));
  EXPECT_EQ(doc["buffers"], json({{{"byteLength", 37}}}));
  EXPECT_EQ(doc["nodes"][0]["extras"]["class"], "building");
  const size_t bin_at = 20 + json_length;
  EXPECT_EQ(u32(bin_at), 40u);  // padded to 4 bytes
  EXPECT_EQ(u32(bin_at + 4), 0x004E4942u);  // "BIN"
  EXPECT_EQ(glb.substr(bin_at + 8, 37), std::string(g.bin.begin(), g.bin.end()));
}

TEST(GltfBuilder, ShapesAreClassedRootNodes) {
  GltfBuilder g;
  g.Scene({});
  const int quad =
      g.Quad({Eigen::Vector3d(0, 0, 0), {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, "road", 0, {4, Eigen::Vector4f(1, 0, 0, 1)});
  const int square = g.Square({0, 0, -5}, {1, 0, 0}, {0, 1, 0}, 2.0, "building");
  EXPECT_EQ(g.doc["scenes"][0]["nodes"], json({quad, square}));
  const json& prim = g.doc["meshes"][0]["primitives"][0];
  EXPECT_EQ(prim["material"], 0);
  EXPECT_EQ(g.doc["accessors"][prim["attributes"]["POSITION"].get<int>()]["count"], 6);
  EXPECT_EQ(g.doc["accessors"][prim["attributes"]["TEXCOORD_0"].get<int>()]["type"], "VEC2");
  EXPECT_EQ(g.doc["accessors"][prim["attributes"]["COLOR_0"].get<int>()]["type"], "VEC4");
  EXPECT_FALSE(g.doc["meshes"][1]["primitives"][0]["attributes"].contains("TEXCOORD_0"));  // no material
  EXPECT_EQ(g.doc["nodes"][square]["extras"]["class"], "building");
}

SyntheticRigOptions SmallRig() {
  SyntheticRigOptions o;
  const Camera pinhole(CameraModelId::kPinhole, 320, 240, {150, 150, 159.5, 119.5});
  const Camera fisheye(CameraModelId::kOpenCVFisheye, 320, 240, {90, 90, 160, 120, 0.02, -0.005, 0.001, 0.0});
  o.cameras = {pinhole, fisheye, pinhole};
  o.max_tilt_deg = 3;
  o.max_offset_m = 0.02;
  o.num_frames = 3;
  o.step_m = Eigen::Vector3d(0, 0, 1.5);
  o.turn_deg = 2;
  o.num_points = 400;
  o.seed = 7;
  return o;
}

TEST(SynthesizeRig, ObservationsAreTheTruthsProjectionsWithTheirNoiseAndDistractors) {
  SyntheticRigOptions o = SmallRig();
  o.noise_px = 0.0;
  const SyntheticRig s = SynthesizeRig(o);
  ASSERT_EQ(s.rig.cameras.size(), 3u);
  EXPECT_EQ(s.rig.cameras[2].name, "cam2");
  EXPECT_LT(s.rig.cameras[0].cam_from_rig->translation.norm(), 1e-12);  // camera 0 is the rig frame
  EXPECT_LT(RotationDifferenceDeg(s.rig.cameras[0].cam_from_rig->rotation, Eigen::Quaterniond::Identity()), 1e-12);
  ASSERT_EQ(s.rig_from_world.size(), 3u);
  EXPECT_LT(s.rig_from_world[0].translation.norm(), 1e-12);  // frame 0 is the world
  EXPECT_NEAR(s.rig_from_world[2].SourceOriginInTarget().z(), 3.0, 1e-12);
  EXPECT_NEAR(RotationDifferenceDeg(s.rig_from_world[2].rotation, Eigen::Quaterniond::Identity()), 4.0, 1e-9);
  // The ring: centres 0.3 m (give or take the offsets) from the ring's centre, 120 deg apart.
  const double d01 = (s.rig.cameras[1].cam_from_rig->SourceOriginInTarget()).norm();
  EXPECT_NEAR(d01, 0.3 * std::sqrt(3.0), 0.1);
  ASSERT_EQ(s.points.size(), 400u);
  for (int k = 0; k < 3; ++k) {
    for (int c = 0; c < 3; ++c) {
      const Camera& camera = s.rig.cameras[c].camera;
      const auto& kps = s.keypoints[k][c];
      ASSERT_EQ(kps.size(), s.point_of[k][c].size());
      int projections = 0, distractors = 0;
      for (size_t i = 0; i < kps.size(); ++i) {
        EXPECT_TRUE(camera.IsInImage(kps[i]));
        const int p = s.point_of[k][c][i];
        if (p < 0) {
          ++distractors;
          continue;
        }
        ++projections;
        const auto px = camera.ImgFromCam(s.CamFromWorld({k, c}) * s.points[p]);
        ASSERT_TRUE(px.has_value());
        EXPECT_LT((*px - kps[i]).norm(), 1e-9);
      }
      EXPECT_GT(projections, 40) << k << " " << c;
      EXPECT_EQ(distractors, int(0.1 * projections));
    }
  }
}

TEST(SynthesizeRig, NoiseHasTheGivenSpreadAndTheSameSeedGivesTheSameData) {
  const SyntheticRig a = SynthesizeRig(SmallRig());
  const SyntheticRig b = SynthesizeRig(SmallRig());
  EXPECT_EQ(a.keypoints, b.keypoints);
  EXPECT_EQ(a.point_of, b.point_of);
  SyntheticRigOptions other = SmallRig();
  other.seed = 8;
  EXPECT_NE(SynthesizeRig(other).keypoints, a.keypoints);
  double sum = 0;
  int count = 0;
  for (int c = 0; c < 3; ++c) {
    for (size_t i = 0; i < a.keypoints[1][c].size(); ++i) {
      const int p = a.point_of[1][c][i];
      if (p < 0) continue;
      sum += (*a.rig.cameras[c].camera.ImgFromCam(a.CamFromWorld({1, c}) * a.points[p]) - a.keypoints[1][c][i]).squaredNorm();
      count += 2;
    }
  }
  EXPECT_NEAR(std::sqrt(sum / count), 0.3, 0.03);
}

TEST(SynthesizeRig, MatchesPairTheKeypointsOfOnePointAndOutliersAreAdded) {
  SyntheticRig s = SynthesizeRig(SmallRig());
  const auto truth = s.TrueMatches({0, 0}, {1, 1});  // across cameras and frames
  ASSERT_GT(truth.size(), 20u);
  for (const auto& [a, b] : truth) EXPECT_EQ(s.point_of[0][0][a], s.point_of[1][1][b]);
  const auto candidates = s.CandidateMatches({0, 0}, {1, 1});
  EXPECT_EQ(candidates.size(), truth.size() + std::max<size_t>(6, size_t(0.05 * truth.size())));
  EXPECT_EQ(std::set(candidates.begin(), candidates.end()).count(truth.front()), 1u);
}

TEST(SynthesizeRig, IsolatedCamerasAndSceneChangesShareNoPoint) {
  SyntheticRigOptions o = SmallRig();
  o.isolated_cameras = {2};
  o.new_points_every_frame = true;
  o.step_m.setZero();
  o.turn_deg = 0;
  const SyntheticRig s = SynthesizeRig(o);
  EXPECT_EQ(s.points.size(), 3u * 2u * 400u);  // per frame: the shared set and camera 2's
  EXPECT_GT(s.TrueMatches({0, 0}, {0, 1}).size(), 20u);
  EXPECT_TRUE(s.TrueMatches({0, 0}, {0, 2}).empty());
  EXPECT_TRUE(s.TrueMatches({0, 1}, {0, 2}).empty());
  EXPECT_TRUE(s.TrueMatches({0, 0}, {1, 0}).empty());  // a new scene every frame
  EXPECT_FALSE(s.keypoints[0][2].empty());
}

TEST(SynthesizeRig, BadOptionsAreNamed) {
  SyntheticRigOptions o = SmallRig();
  o.isolated_cameras = {3};
  EXPECT_THAT([&] { SynthesizeRig(o); }, ThrowsWith<std::invalid_argument>("isolated_cameras: 3 is not a camera"));
  o = SmallRig();
  o.cameras.clear();
  EXPECT_THAT([&] { SynthesizeRig(o); }, ThrowsWith<std::invalid_argument>("cameras"));
}

TEST(TestSeed, IsTheFnv1aOfTheTestsName) {
  uint32_t h = 2166136261u;
  for (char c : std::string("TestSeed.IsTheFnv1aOfTheTestsName")) h = (h ^ uint8_t(c)) * 16777619u;
  EXPECT_EQ(TestSeed(), h);
  std::mt19937 a = TestRng(), b(h);
  EXPECT_EQ(a(), b());
}

TEST(RandomPoses, RotationsAreUnitAndOfTheGivenAngle) {
  std::mt19937 rng = TestRng();
  EXPECT_NEAR(RandomRotation(rng).norm(), 1.0, 1e-12);
  EXPECT_NEAR(RotationDifferenceDeg(RandomRotationBy(rng, 30.0), Eigen::Quaterniond::Identity()), 30.0, 1e-9);
  const std::vector<Rigid3d> rig = RandomCamFromRig(4, rng);
  ASSERT_EQ(rig.size(), 4u);
  EXPECT_EQ(rig[0].translation, Eigen::Vector3d::Zero());
  EXPECT_GT(RotationDifferenceDeg(rig[1].rotation, rig[2].rotation), 0.0);
}

}  // namespace
}  // namespace rigsim
