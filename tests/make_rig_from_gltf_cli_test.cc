// `rigsim make-rig --from-gltf` through the built binary: the written rig and frames are the ones
// RigFromSceneCameras computes, output is atomic (--out DIR, --force), and errors name the file
// and leave nothing behind.

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "gltf/gltf_loader.h"
#include "gltf/scene_cameras.h"
#include "testing/gltf_builder.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// Each run's output beside the test's scratch files.
CliResult RunRigsim(const fs::path& dir, const std::vector<std::string>& args) { return rigsim::RunRigsim(args, dir / "rigsim"); }

bool HasStagingFolder(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().filename().string().find(".partial-") != std::string::npos) return true;
  }
  return false;
}

class MakeRigFromGltf : public testing::Test {
 protected:
  void SetUp() override {
    // Two perspective cameras (the second on a turned, scaled parent, aspect ratio 2) and an
    // orthographic one.
    const json doc = GltfCamerasDocument();
    scene_ = dir_ / "cameras.gltf";
    WriteFile(scene_, doc.dump(1));
    json none = doc;
    none.erase("cameras");
    for (json& n : none["nodes"]) n.erase("camera");
    no_cameras_ = dir_ / "no_cameras.gltf";
    WriteFile(no_cameras_, none.dump(1));
  }

  const TempDir dir_;
  fs::path scene_, no_cameras_;
};

TEST_F(MakeRigFromGltf, WritesTheFilesCamerasAsRigAndOneFrame) {
  const fs::path out = dir_ / "rig";
  const CliResult r = RunRigsim(dir_, {"make-rig", "--from-gltf", scene_.string(), "--width", "640", "--height", "480", "--out", out.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("'top'"), std::string::npos) << "the skipped orthographic camera is named: " << r.err;
  EXPECT_NE(r.err.find("640x320"), std::string::npos) << "the aspect-ratio warning suggests a size: " << r.err;
  const Rig rig = ReadRig(out / "rig.json");
  const FramesFile frames = ReadFrames(out / "frames.json");
  const SceneCameraRig expected = RigFromSceneCameras(LoadGltf(scene_), 640, 480);
  ASSERT_EQ(rig.cameras.size(), 2u);
  ASSERT_EQ(frames.frames.size(), 1u);
  EXPECT_EQ(frames.scene, "cameras.gltf");
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(rig.cameras[i].name, expected.rig.cameras[i].name);
    EXPECT_EQ(rig.cameras[i].camera.model(), CameraModelId::kPinhole);
    for (size_t k = 0; k < 4; ++k) EXPECT_NEAR(rig.cameras[i].camera.params()[k], expected.rig.cameras[i].camera.params()[k], 1e-9);
    // cam_from_world as render computes it equals the file's camera pose.
    const Rigid3d cam_from_world = *rig.cameras[i].cam_from_rig * *frames.frames[0].rig_from_world;
    const Rigid3d truth = *expected.rig.cameras[i].cam_from_rig * *expected.frames.frames[0].rig_from_world;
    EXPECT_LT(RotationDifferenceDeg(cam_from_world.rotation, truth.rotation), 1e-9);
    EXPECT_LT((cam_from_world.translation - truth.translation).norm(), 1e-9);
  }
  EXPECT_EQ(rig.cameras[0].name, "front");
  EXPECT_EQ(rig.cameras[1].name, "back");

  // The folder exists now: refused without --force (and left as it was), replaced with it.
  const std::string before = ReadFile(out / "rig.json");
  const CliResult again = RunRigsim(dir_, {"make-rig", "--from-gltf", scene_.string(), "--width", "320", "--height", "240", "--out", out.string()});
  EXPECT_NE(again.code, 0);
  EXPECT_NE(again.err.find("already exists (use --force"), std::string::npos) << again.err;
  EXPECT_EQ(ReadFile(out / "rig.json"), before);
  const CliResult forced = RunRigsim(dir_, {"make-rig", "--from-gltf", scene_.string(), "--width", "320", "--height", "240", "--out", out.string(), "--force"});
  ASSERT_EQ(forced.code, 0) << forced.err;
  EXPECT_EQ(ReadRig(out / "rig.json").cameras[0].camera.width(), 320);
  EXPECT_FALSE(HasStagingFolder(dir_));

  // The classic pair of output files works too.
  const CliResult files = RunRigsim(dir_, {"make-rig", "--from-gltf", scene_.string(), "--rig-out", (dir_ / "r.json").string(),
                                  "--frames-out", (dir_ / "f.json").string()});
  ASSERT_EQ(files.code, 0) << files.err;
  EXPECT_EQ(ReadRig(dir_ / "r.json").cameras.size(), 2u);
}

TEST_F(MakeRigFromGltf, AFileWithoutCamerasIsAnErrorNamingItAndWritesNothing) {
  const fs::path out = dir_ / "rig";
  const CliResult r = RunRigsim(dir_, {"make-rig", "--from-gltf", no_cameras_.string(), "--out", out.string()});
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find(no_cameras_.string() + ": no perspective camera"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(HasStagingFolder(dir_));
}

// The loader's warnings are printed too: the cameras it skips (under a mirroring parent, yfov 0),
// and those it keeps at their rest pose (animated) or approximates (sheared). When it skipped
// every camera, the error says so instead of claiming the file has none.
TEST_F(MakeRigFromGltf, TheLoadersWarningsArePrintedAndSkippedCamerasCounted) {
  const json camera = {{"type", "perspective"}, {"perspective", {{"yfov", 1.0}, {"znear", 0.1}}}};
  json zero_fov = camera;
  zero_fov["perspective"]["yfov"] = 0.0;
  GltfBuilder g;
  g.doc["cameras"] = {camera, zero_fov};
  g.doc["nodes"] = {{{"name", "mirror"}, {"scale", {1, 1, -1}}, {"children", {1}}},
                    {{"name", "mirrored"}, {"camera", 0}},
                    {{"name", "no_fov"}, {"camera", 1}},
                    {{"name", "shear"}, {"scale", {1, 3, 1}}, {"children", {4}}},
                    {{"name", "sheared"}, {"camera", 0}, {"rotation", {0, 0, std::sin(0.3), std::cos(0.3)}}},
                    {{"name", "moving"}, {"camera", 0}}};
  g.Scene({0, 2, 3, 5});
  const int times = g.Floats({0, 1}, "SCALAR");
  g.doc["accessors"][times]["min"] = {0};
  g.doc["accessors"][times]["max"] = {1};
  const int moves = g.Floats({0, 0, 0, 1, 0, 0}, "VEC3");
  g.doc["animations"] = {{{"samplers", {{{"input", times}, {"output", moves}}}},
                          {"channels", {{{"sampler", 0}, {"target", {{"node", 5}, {"path", "translation"}}}}}}}};
  const fs::path mixed = g.WriteEmbedded(dir_, "mixed");
  const CliResult r = RunRigsim(dir_, {"make-rig", "--from-gltf", mixed.string(), "--out", (dir_ / "mixed").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(ReadRig(dir_ / "mixed" / "rig.json").cameras.size(), 2u);
  for (const char* warning : {"node 1 'mirrored' (camera 0): the node's transform mirrors", "node 2 'no_fov' (camera 1): yfov",
                              "node 4 'sheared' (camera 0): the node's transform shears",
                              "node 5 'moving' (camera 0): is animated; cameras are loaded at their rest pose"}) {
    EXPECT_NE(r.err.find(warning), std::string::npos) << warning << " in:\n" << r.err;
  }

  g.Scene({0, 2});  // two unusable cameras; two more outside the loaded scene
  const fs::path skipped = g.WriteEmbedded(dir_, "skipped");
  const CliResult none = RunRigsim(dir_, {"make-rig", "--from-gltf", skipped.string(), "--out", (dir_ / "skipped").string()});
  EXPECT_NE(none.code, 0);
  EXPECT_NE(none.err.find(skipped.string() + ": no perspective camera in the loaded scene (4 camera node(s) skipped by the loader; its warnings say why)"),
            std::string::npos) << none.err;
  EXPECT_EQ(none.err.find("places no camera"), std::string::npos) << none.err;
  EXPECT_NE(none.err.find("'mirrored' (camera 0): the node's transform mirrors"), std::string::npos) << none.err;
  EXPECT_FALSE(fs::exists(dir_ / "skipped"));
}

TEST_F(MakeRigFromGltf, ConflictingOrMissingOptionsAreRefused) {
  // A rig type or a trajectory makes no sense with cameras taken from the file.
  CliResult r = RunRigsim(dir_, {"make-rig", "ring", "--from-gltf", scene_.string(), "--out", (dir_ / "a").string()});
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("excludes --from-gltf"), std::string::npos) << r.err;
  r = RunRigsim(dir_, {"make-rig", "--from-gltf", scene_.string(), "--frames", "3", "--out", (dir_ / "a").string()});
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("--frames excludes --from-gltf"), std::string::npos) << r.err;
  // Somewhere to write is required: --out, or both files.
  r = RunRigsim(dir_, {"make-rig", "--from-gltf", scene_.string(), "--rig-out", (dir_ / "r.json").string()});
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("give --out DIR, or both --rig-out FILE and --frames-out FILE"), std::string::npos) << r.err;
  r = RunRigsim(dir_, {"make-rig", "--out", (dir_ / "a").string(), "--rig-out", (dir_ / "r.json").string()});
  EXPECT_NE(r.code, 0);
  EXPECT_FALSE(fs::exists(dir_ / "a"));
  EXPECT_FALSE(fs::exists(dir_ / "r.json"));
}

}  // namespace
}  // namespace rigsim
