// The built `rigsim` binary on bad input and when interrupted. Every failure exits
// non-zero with a message naming the file and the problem, and leaves no output behind: neither
// --out / evaluation.json nor a hidden staging folder. A render killed by SIGKILL or SIGINT leaves
// the previous dataset intact (or none); a staging folder left by SIGKILL is removed by the next run.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "geometry/rig.h"
#include "gltf/scene_builder.h"
#include "rigs/rig_presets.h"
#include "rigs/trajectories.h"
#include "testing/gltf_builder.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// A one-triangle glTF document with its buffer as a data URI (the tests corrupt it).
GltfBuilder TriangleGltf(const std::vector<float>& xyz = {-5, 0, -5, 5, 0, -5, 0, 5, -5}) {
  GltfBuilder g;
  g.Triangle(xyz, "building");
  return g;
}

class RigsimCli : public testing::Test {
 protected:
  // Shared inputs: a small scene, a 2-camera rig, frames, and one rendered dataset.
  static void SetUpTestSuite() {
    base_ = new TempDir();
    SceneBuilder b;
    MeshData wall;
    wall.positions = {{-20, -5, -8}, {20, -5, -8}, {20, 15, -8}, {-20, 15, -8}};
    wall.indices = {0, 1, 2, 0, 2, 3};
    b.AddNode("wall", "building", wall, b.AddMaterial("brick", Eigen::Vector4f(0.7f, 0.3f, 0.2f, 1)));
    MeshData ground;
    ground.positions = {{-20, 0, 5}, {20, 0, 5}, {20, 0, -8}, {-20, 0, -8}};
    ground.indices = {0, 1, 2, 0, 2, 3};
    b.AddNode("road", "road", ground, b.AddMaterial("asphalt", Eigen::Vector4f(0.3f, 0.3f, 0.3f, 1)));
    b.WriteGlb(*base_ / "scene.glb");
    RingRigOptions ring;
    ring.num_cameras = 2;
    ring.width = 96;
    ring.height = 64;
    ring.yaw_spacing_deg = 30;
    ring.hfov_deg = 90;
    ring.distorted_camera = -1;
    WriteRig(MakeRingRig(ring), *base_ / "rig.json");
    WriteFrames(MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 0), 0.0, 1, 0.5), *base_ / "frames.json");
    ring.width = 320;
    ring.height = 240;
    WriteRig(MakeRingRig(ring), *base_ / "rig_big.json");
    WriteFrames(MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 0), 0.0, 400, 0.01), *base_ / "frames_long.json");
    RigsimProcess p({"render", "--scene", (*base_ / "scene.glb").string(), "--rig", (*base_ / "rig.json").string(), "--frames",
               (*base_ / "frames.json").string(), "--out", (*base_ / "dataset").string(), "--spp", "1"},
              *base_ / "setup");
    ASSERT_EQ(p.Wait(), 0) << p.err();
  }
  static void TearDownTestSuite() { delete base_; }

  static fs::path base() { return base_->path(); }

  CliResult Run(const std::vector<std::string>& args) { return RunRigsim(args, dir_ / ("run" + std::to_string(runs_++))); }
  std::vector<std::string> RenderArgs(const fs::path& scene, const fs::path& rig, const fs::path& frames, const fs::path& out) {
    return {"render", "--scene", scene.string(), "--rig", rig.string(), "--frames", frames.string(), "--out", out.string(),
            "--spp", "1"};
  }
  // `rigsim render` of `scene` with the shared rig and frames fails naming `file` and `part`, and
  // leaves nothing.
  void ExpectRenderFails(const fs::path& scene, const fs::path& rig, const fs::path& frames, const std::string& file,
                         const std::string& part) {
    const fs::path out = dir_ / "out";
    const CliResult r = Run(RenderArgs(scene, rig, frames, out));
    EXPECT_NE(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("error: " + file + ": "), std::string::npos) << "message does not start with the file: " << r.err;
    EXPECT_NE(r.err.find(part), std::string::npos) << "message does not say '" << part << "': " << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(StagingFolders(out).empty());
  }
  void ExpectSceneFails(const fs::path& scene, const std::string& part) {
    ExpectRenderFails(scene, base() / "rig.json", base() / "frames.json", scene.string(), part);
  }
  fs::path WriteGltf(const std::string& name, const GltfBuilder& g) { return g.WriteEmbedded(dir_, name); }
  // A copy of the rendered dataset to corrupt.
  fs::path CopyDataset() {
    const fs::path copy = dir_ / "dataset";
    fs::copy(base() / "dataset", copy, fs::copy_options::recursive);
    return copy;
  }
  // `rigsim calibrate` fails naming `file` and `part` and writes no evaluation.json.
  void ExpectCalibrateFails(const fs::path& dataset, const std::string& semantics, const fs::path& file,
                            const std::string& part) {
    const CliResult r = Run({"calibrate", dataset.string(), "--semantics", semantics, "--threads", "1"});
    EXPECT_NE(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("error: " + file.string() + ": "), std::string::npos) << "message does not start with the file: " << r.err;
    EXPECT_NE(r.err.find(part), std::string::npos) << "message does not say '" << part << "': " << r.err;
    EXPECT_FALSE(fs::exists(dataset / "evaluation.json"));
  }

  static TempDir* base_;  // the shared inputs and dataset
  const TempDir dir_;     // each test's files
  int runs_ = 0;
};
TempDir* RigsimCli::base_ = nullptr;

TEST_F(RigsimCli, RendersTheValidInputs) {
  // The reference the failures are measured against: the shared dataset is complete.
  const DatasetLayout layout(base() / "dataset");
  EXPECT_TRUE(fs::exists(layout.Depth("cam1", "000000")));
  EXPECT_TRUE(fs::exists(layout.OverlapJson()));
  EXPECT_TRUE(StagingFolders(base() / "dataset").empty());
}

// --traffic moves the cars of an animated preset: without --animated, or outside 0..15 vehicles
// per 100 m of lane, generate-scene stops before writing anything.
TEST_F(RigsimCli, GenerateSceneTrafficNeedsAnAnimatedSceneAndARange) {
  const fs::path out = dir_ / "street.glb";
  for (const std::vector<std::string>& extra : std::vector<std::vector<std::string>>{
           {"--traffic", "3"}, {"--animated", "--traffic", "16"}, {"--animated", "--traffic", "-1"}}) {
    std::vector<std::string> args = {"generate-scene", "--preset", "street", "--out", out.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const CliResult r = Run(args);
    EXPECT_NE(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("--traffic"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(out.string() + ".tmp"));
  }
}

// --wet is a share of the road, 0 to 0.2: outside it generate-scene stops before writing anything.
TEST_F(RigsimCli, GenerateSceneWetNeedsARange) {
  const fs::path out = dir_ / "street.glb";
  for (const std::string wet : {"0.5", "-0.1", "wet"}) {
    const CliResult r = Run({"generate-scene", "--preset", "street", "--glass", "--wet", wet, "--out", out.string()});
    EXPECT_NE(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("--wet"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(out.string() + ".tmp"));
  }
}

TEST_F(RigsimCli, TruncatedGlb) {
  const std::string glb = ReadFile(base() / "scene.glb");
  const fs::path cut = dir_ / "cut.glb";
  WriteFile(cut, glb.substr(0, glb.size() - 40));
  ExpectSceneFails(cut, "invalid .glb");
}

TEST_F(RigsimCli, AccessorOutOfRange) {
  GltfBuilder g = TriangleGltf();
  g.doc["accessors"][0]["count"] = 4;  // the bufferView holds 3 vertices
  ExpectSceneFails(WriteGltf("range", g), "out of range of bufferView 0");
}

TEST_F(RigsimCli, MissingBufferFile) {
  GltfBuilder g = TriangleGltf();
  g.doc["buffers"] = {{{"byteLength", g.bin.size()}, {"uri", "missing.bin"}}};
  ExpectSceneFails(WriteGltf("buffer", g), "missing.bin");
}

TEST_F(RigsimCli, MissingImageFile) {
  GltfBuilder g = TriangleGltf();
  g.doc["images"] = {{{"uri", "missing_texture.png"}}};
  g.doc["textures"] = {{{"source", 0}}};
  g.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  g.doc["meshes"][0]["primitives"][0]["material"] = 0;
  ExpectSceneFails(WriteGltf("image", g), "missing_texture.png");
}

TEST_F(RigsimCli, RecursiveNodeGraph) {
  GltfBuilder g = TriangleGltf();
  g.doc["nodes"][0]["children"] = {1};
  g.doc["nodes"].push_back({{"children", {0}}});
  ExpectSceneFails(WriteGltf("cycle", g), "reached twice");
}

TEST_F(RigsimCli, NanAndInfiniteVertices) {
  ExpectSceneFails(WriteGltf("nan", TriangleGltf({0, 0, 0, std::numeric_limits<float>::quiet_NaN(), 0, 0, 0, 1, 0})),
                   "vertex 1 is not finite");
  ExpectSceneFails(WriteGltf("inf", TriangleGltf({0, 0, 0, 1, 0, 0, 0, -std::numeric_limits<float>::infinity(), 0})),
                   "vertex 2 is not finite");
}

TEST_F(RigsimCli, NonTrianglePrimitivesAreSkippedWithAWarning) {
  GltfBuilder g = TriangleGltf();
  g.doc["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", 0}}}, {"mode", 1}});  // lines
  const fs::path out = dir_ / "out";
  const CliResult r = Run(RenderArgs(WriteGltf("lines", g), base() / "rig.json", base() / "frames.json", out));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: mesh 0 primitive 1: lines primitive (mode 1) skipped"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(DatasetLayout(out).Image("cam0", "000000")));
}

TEST_F(RigsimCli, AbsurdDeclaredCount) {
  GltfBuilder g = TriangleGltf();
  g.doc["accessors"][0]["count"] = 3000000000ull;
  ExpectSceneFails(WriteGltf("count", g), "exceeds the limit");
}

TEST_F(RigsimCli, RigWithNegativeFocalLength) {
  json rig = json::parse(ReadFile(base() / "rig.json"));
  rig["cameras"][1]["params"][0] = -80.0;
  const fs::path path = dir_ / "rig.json";
  WriteFile(path, rig.dump());
  ExpectRenderFails(base() / "scene.glb", path, base() / "frames.json", path.string(), "focal lengths must be positive");
}

TEST_F(RigsimCli, RigWhoseDistortionCannotBeInvertedOverTheImage) {
  json rig = json::parse(ReadFile(base() / "rig.json"));
  const double f = rig["cameras"][0]["params"][0];
  rig["cameras"][0]["model"] = "OPENCV";
  rig["cameras"][0]["params"] = {f, f, 47.5, 31.5, -0.6, 0.0, 0.0, 0.0};  // folds back inside the image
  const fs::path path = dir_ / "rig.json";
  WriteFile(path, rig.dump());
  ExpectRenderFails(base() / "scene.glb", path, base() / "frames.json", path.string(),
                    "camera 'cam0': OPENCV distortion cannot be inverted over the 96x64 image");
  // calibrate applies the same rule to the dataset's rig.json
  const fs::path dataset = CopyDataset();
  WriteFile(dataset / "rig.json", rig.dump());
  ExpectCalibrateFails(dataset, "none", dataset / "rig.json", "distortion cannot be inverted");
}

TEST_F(RigsimCli, FisheyeWithImageCircleInsideTheSensorOnlyWarns) {
  json rig = json::parse(ReadFile(base() / "rig.json"));
  rig["cameras"][0]["model"] = "OPENCV_FISHEYE";
  rig["cameras"][0]["params"] = {25.0, 25.0, 47.5, 31.5, -0.2, 0.0, 0.0, 0.0};  // circle of radius 21 px
  const fs::path path = dir_ / "rig.json";
  WriteFile(path, rig.dump());
  const CliResult r = Run(RenderArgs(base() / "scene.glb", path, base() / "frames.json", dir_ / "out"));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("camera 'cam0': "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("outside the fisheye's valid image circle"), std::string::npos) << r.err;
}

TEST_F(RigsimCli, MalformedRigAndFramesJson) {
  const fs::path rig = dir_ / "rig.json", frames = dir_ / "frames.json";
  WriteFile(rig, "{\"cameras\": [");
  ExpectRenderFails(base() / "scene.glb", rig, base() / "frames.json", rig.string(), "invalid JSON");
  WriteFile(frames, R"({"frames": [{"name": "a/b"}]})");
  ExpectRenderFails(base() / "scene.glb", base() / "rig.json", frames, frames.string(), "not a valid file stem");
  WriteFile(frames, "[]");
  ExpectRenderFails(base() / "scene.glb", base() / "rig.json", frames, frames.string(), "expected an object with a 'frames' array");
}

TEST_F(RigsimCli, CalibrateMalformedJsonInTheDataset) {
  const fs::path dataset = CopyDataset();
  WriteFile(dataset / "overlap.json", "{\"pairs\": [{\"a\": \"cam0\"");
  ExpectCalibrateFails(dataset, "none", dataset / "overlap.json", "invalid JSON");
  fs::copy_file(base() / "dataset" / "overlap.json", dataset / "overlap.json", fs::copy_options::overwrite_existing);
  WriteFile(dataset / "frames.json", "{\"frames\": 7}");
  ExpectCalibrateFails(dataset, "none", dataset / "frames.json", "'frames' array");
  fs::copy_file(base() / "dataset" / "frames.json", dataset / "frames.json", fs::copy_options::overwrite_existing);
  WriteFile(dataset / "rig.json", "");
  ExpectCalibrateFails(dataset, "none", dataset / "rig.json", "invalid JSON");
}

TEST_F(RigsimCli, CalibrateMissingImage) {
  const fs::path dataset = CopyDataset();
  const fs::path image = DatasetLayout(dataset).Image("cam1", "000000");
  fs::remove(image);
  ExpectCalibrateFails(dataset, "none", fs::path(image).replace_extension(".*"),
                       "image missing (camera 'cam1', frame '000000'; tried .png .jpg");
}

// A rig that calibrates only in part: the results are written (they say why), and the exit code
// tells a script so.
TEST_F(RigsimCli, CalibrateExitsWith3WhenACameraGetsNoPose) {
  const fs::path dataset = CopyDataset();
  const fs::path image = DatasetLayout(dataset).Image("cam1", "000000");
  WriteImage(image, ImageU8(96, 64, 3, 128));  // featureless: cam1 cannot be placed
  const fs::path out = dir_ / "calibration";
  const CliResult r = Run({"calibrate", dataset.string(), "--semantics", "none", "--out", out.string()});
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("rigsim: not every camera was calibrated (none: cam1)"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out / "evaluation.json"));
  EXPECT_TRUE(fs::exists(out / "none" / "rig.json"));
  EXPECT_NE(r.out.find("not connected"), std::string::npos) << r.out;
}

// A camera name mistyped in --known-distance is reported before the photos are even looked at
// (the missing photo here would fail the run otherwise), naming it and the rig's cameras.
TEST_F(RigsimCli, CalibrateKnownDistanceNamingAnUnknownCameraFailsFirst) {
  const fs::path dataset = CopyDataset();
  fs::remove(DatasetLayout(dataset).Image("cam1", "000000"));
  const CliResult r = Run({"calibrate", dataset.string(), "--semantics", "none", "--known-distance", "cam0", "cam9", "0.5"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("error: --known-distance: no camera 'cam9' in " + (dataset / "rig.json").string()), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("its cameras are cam0, cam1"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dataset / "calibration"));
}

// Exports name each camera's photos as they are (mixed .png/.jpg across cameras), and leave out
// the cameras an estimate has no pose for, as calibrate's own exports do.
TEST_F(RigsimCli, ExportNamesEachCamerasPhotosAndLeavesOutCamerasWithoutAPose) {
  const fs::path dataset = CopyDataset();
  const DatasetLayout layout(dataset);
  const fs::path png = layout.Image("cam1", "000000");
  WriteImage(fs::path(png).replace_extension(".jpg"), ReadImageU8(png));
  fs::remove(png);
  const CliResult r = Run({"export", dataset.string(), "--format", "colmap,nerfstudio", "--out", (dir_ / "all").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string images = ReadFile(dir_ / "all" / "colmap" / "images.txt");
  EXPECT_NE(images.find(" cam0/000000.png\n"), std::string::npos) << images;
  EXPECT_NE(images.find(" cam1/000000.jpg\n"), std::string::npos) << images;
  const json transforms = json::parse(ReadFile(dir_ / "all" / "transforms.json"));
  EXPECT_EQ(transforms["frames"][1]["file_path"].get<std::string>().substr(std::string("../").size()),
            (fs::path("dataset") / "images" / "cam1" / "000000.jpg").string())
      << transforms["frames"][1]["file_path"];

  Rig estimate = ReadRig(layout.RigJson());
  estimate.cameras[1].cam_from_rig.reset();  // not calibrated
  WriteRig(estimate, dir_ / "estimate.json");
  const CliResult e = Run({"export", dataset.string(), "--rig", (dir_ / "estimate.json").string(), "--format", "opencv,kalibr",
                           "--out", (dir_ / "estimate").string()});
  ASSERT_EQ(e.code, 0) << e.err;
  EXPECT_NE(e.err.find("leaving out the cameras without cam_from_rig (not calibrated): cam1"), std::string::npos) << e.err;
  const std::string yaml = ReadFile(dir_ / "estimate" / "opencv.yaml");
  EXPECT_NE(yaml.find("num_cameras: 1"), std::string::npos) << yaml;
  EXPECT_EQ(yaml.find("cam1"), std::string::npos) << yaml;
  EXPECT_NE(ReadFile(dir_ / "estimate" / "camchain.yaml").find("cam0"), std::string::npos);
}

// The colmap and nerfstudio exports name every photo: a missing one stops the export, naming it,
// and nothing is written; the formats that name no photo still export.
TEST_F(RigsimCli, ExportRefusesToNameAMissingPhoto) {
  const fs::path dataset = CopyDataset();
  fs::remove(DatasetLayout(dataset).Image("cam1", "000000"));
  const fs::path out = dir_ / "export";
  const CliResult r = Run({"export", dataset.string(), "--format", "colmap,nerfstudio", "--out", out.string()});
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("error: " + (dataset / "images").string() +
                       ": 1 of the 2 photos the colmap and nerfstudio exports name are missing (cam1/000000.*); "),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(StagingFolders(out).empty());
  const CliResult kalibr = Run({"export", dataset.string(), "--format", "kalibr", "--out", out.string()});
  EXPECT_EQ(kalibr.code, 0) << kalibr.err;
}

// A camera that captures between frames needs the rig's path between them, so frames at one time
// are refused naming the frames file and the frames: render's --frames before the scene is loaded,
// a dataset's frames.json before calibrate's run.
TEST_F(RigsimCli, FramesSharingATimestampAreNamedWithTheirFile) {
  Rig rig = ReadRig(base() / "rig.json");
  rig.cameras[1].time_offset_s = 0.01;
  WriteRig(rig, dir_ / "rig.json");
  FramesFile frames = MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 0), 0.0, 3, 0.5);
  frames.frames[2].timestamp_s = frames.frames[0].timestamp_s;
  WriteFrames(frames, dir_ / "frames.json");
  const std::string share = "frames '" + frames.frames[0].name + "' and '" + frames.frames[2].name + "' share timestamp_s";
  ExpectRenderFails(base() / "scene.glb", dir_ / "rig.json", dir_ / "frames.json", (dir_ / "frames.json").string(), share);
  const fs::path dataset = CopyDataset();
  WriteRig(rig, dataset / "rig.json");
  WriteFrames(frames, dataset / "frames.json");
  ExpectCalibrateFails(dataset, "none", dataset / "frames.json", share);
}

TEST_F(RigsimCli, AMistypedSemanticModeIsNamedWithTheModeMeant) {
  const fs::path out = dir_ / "calibration";
  const CliResult r = Run({"calibrate", (base() / "dataset").string(), "--semantics", "none,nonee", "--out", out.string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("error: --semantics: unknown semantic mode 'nonee' (did you mean 'none'?); the modes are none, mask, "
                       "gated, mask+gated"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out));
}

// evaluate gives position errors in metres (the truth's, after fitting the scale of an estimate
// that is not metric, which it says) and a calibration folder's modes in calibrate's order.
TEST_F(RigsimCli, EvaluateGivesPositionsInMetresAndModesInCalibratesOrder) {
  const fs::path dataset = base() / "dataset";
  const fs::path calibration = dir_ / "calibration";  // as calibrate writes it: the modes by name
  for (const char* mode : {"mask", "none"}) {
    fs::create_directories(calibration / mode);
    fs::copy_file(dataset / "rig.json", calibration / mode / "rig.json");
  }
  WriteFile(calibration / "evaluation.json", R"({"methods": {"mask": {}, "none": {}}})");
  const CliResult r = Run({"evaluate", dataset.string(), calibration.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_NE(r.out.find("\nmask: "), std::string::npos) << r.out;
  EXPECT_LT(r.out.find("\nnone: "), r.out.find("\nmask: ")) << r.out;
  EXPECT_LT(r.out.find("none    "), r.out.find("mask    ")) << r.out;
  EXPECT_NE(r.out.find(" 0.000 m  full pose"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("pos_err: in the truth's metres after fitting the estimate's scale (x1): the estimate is not metric"),
            std::string::npos)
      << r.out;
  const CliResult metric = Run({"evaluate", dataset.string(), (dataset / "rig.json").string(), "--scale", "metric"});
  ASSERT_EQ(metric.code, 0) << metric.err;
  EXPECT_NE(metric.out.find(" 0.000 m  full pose"), std::string::npos) << metric.out;
  EXPECT_EQ(metric.out.find("after fitting"), std::string::npos) << metric.out;
}

// --truth-sd takes the truth's accuracy as ROT_DEG,POS_M: the summary says it counted it, JSON
// records it, and anything else is refused naming the option, with no --json written.
TEST_F(RigsimCli, EvaluateTakesTheTruthsAccuracyOrSaysWhatItNeeds) {
  const fs::path dataset = base() / "dataset";
  const fs::path json = dir_ / "scores.json";
  for (const std::string bad : {"0.02", "0.02,-1", "a,b", "0.02,0.003,1"}) {
    const CliResult r = Run({"evaluate", dataset.string(), (dataset / "rig.json").string(), "--truth-sd", bad, "--json",
                             json.string()});
    EXPECT_EQ(r.code, 1) << bad;
    EXPECT_NE(r.err.find("--truth-sd " + bad + ": needs two numbers, ROT_DEG,POS_M, each 0 or more"), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(json)) << bad;
  }
  const CliResult r = Run({"evaluate", dataset.string(), (dataset / "rig.json").string(), "--truth-sd", "0.02,0.003",
                           "--json", json.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json scores = nlohmann::json::parse(ReadFile(json));
  const nlohmann::json& accuracy = scores["methods"].begin().value()["summary"]["truth_accuracy"];
  EXPECT_DOUBLE_EQ(accuracy["rotation_deg"].get<double>(), 0.02) << scores.dump();
  EXPECT_DOUBLE_EQ(accuracy["position_m"].get<double>(), 0.003) << scores.dump();
}

// Messages count in words: one frame, one semantic mode, never "1 frames".
TEST_F(RigsimCli, CountsOfOneAreSingular) {
  const CliResult rig = Run({"make-rig", "ring", "--cameras", "2", "--frames", "1", "--out", (dir_ / "rig").string()});
  EXPECT_EQ(rig.code, 0) << rig.err;
  EXPECT_NE(rig.out.find("2 cameras) and "), std::string::npos) << rig.out;
  EXPECT_NE(rig.out.find("(1 frame, "), std::string::npos) << rig.out;
  const fs::path out = dir_ / "out";
  const CliResult render = Run(RenderArgs(base() / "scene.glb", base() / "rig.json", base() / "frames.json", out));
  EXPECT_EQ(render.code, 0) << render.err;
  EXPECT_NE(render.out.find("rendered 2 views (2 cameras x 1 frame, 1 spp)"), std::string::npos) << render.out;
  const CliResult calibrate = Run({"calibrate", out.string(), "--semantics", "none", "--threads", "1"});
  EXPECT_NE(calibrate.err.find("(1 semantic mode)"), std::string::npos) << calibrate.err;
  EXPECT_NE(calibrate.out.find("(matches of 1 frame pooled)"), std::string::npos) << calibrate.out;
  for (const std::string& text : {rig.out, render.out, render.err, calibrate.out, calibrate.err}) {
    EXPECT_EQ(text.find(" 1 frames"), std::string::npos) << text;
    EXPECT_EQ(text.find(" 1 semantic modes"), std::string::npos) << text;
  }
}

TEST_F(RigsimCli, CalibrateImageOfTheWrongSize) {
  const fs::path dataset = CopyDataset();
  const fs::path image = DatasetLayout(dataset).Image("cam1", "000000");
  WriteImage(image, ImageU8(50, 40, 3, 100));
  ExpectCalibrateFails(dataset, "none", image, "50x40");
}

TEST_F(RigsimCli, CalibrateLabelImageWithUnknownIds) {
  const fs::path dataset = CopyDataset();
  const fs::path labels = DatasetLayout(dataset).Label("cam0", "000000");
  ImageU8 ids = ReadImageU8(labels, 1);
  ids.at(10, 20) = 250;
  WriteImage(labels, ids);
  ExpectCalibrateFails(dataset, "mask", labels, "pixel (10, 20) has label id 250");
}

TEST_F(RigsimCli, ExistingDatasetIsNotOverwrittenWithoutForce) {
  const fs::path out = CopyDataset();
  const std::string frames_before = ReadFile(out / "frames.json");
  const CliResult r = Run(RenderArgs(base() / "scene.glb", base() / "rig.json", base() / "frames_long.json", out));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find(out.string() + ": already exists (use --force to replace it)"), std::string::npos) << r.err;
  EXPECT_EQ(ReadFile(out / "frames.json"), frames_before);
  EXPECT_TRUE(StagingFolders(out).empty());
}

// Starts a long render into `out` and returns once its staging folder holds the first complete view.
std::optional<RigsimProcess> StartLongRenderAndWaitForFirstView(const std::vector<std::string>& args, const fs::path& out,
                                                          const fs::path& log) {
  std::optional<RigsimProcess> p(std::in_place, args, log);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    for (const fs::path& staging : StagingFolders(out)) {
      if (fs::exists(DatasetLayout(staging).Depth("cam0", "000000"))) return p;
    }
    int status = 0;
    if (waitpid(p->pid(), &status, WNOHANG) != 0) {
      ADD_FAILURE() << "rigsim ended before writing its first view: " << p->err();
      return std::nullopt;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ADD_FAILURE() << "no view written in 60 s";
  kill(p->pid(), SIGKILL);
  p->Wait();
  return std::nullopt;
}

TEST_F(RigsimCli, SigkillLeavesThePreviousDatasetOrNoneAndTheNextRunCleansUp) {
  const std::vector<std::string> long_render = RenderArgs(base() / "scene.glb", base() / "rig_big.json",
                                                          base() / "frames_long.json", dir_ / "fresh");
  {  // no previous output: none afterwards
    auto p = StartLongRenderAndWaitForFirstView(long_render, dir_ / "fresh", dir_ / "kill_fresh");
    ASSERT_TRUE(p);
    kill(p->pid(), SIGKILL);
    EXPECT_EQ(p->Wait(), 128 + SIGKILL);
    EXPECT_FALSE(fs::exists(dir_ / "fresh"));
    EXPECT_EQ(StagingFolders(dir_ / "fresh").size(), 1u);  // the killed run's: removed by the next one
  }
  {  // a previous dataset replaced with --force: intact afterwards
    const fs::path out = CopyDataset();
    const std::string frames_before = ReadFile(out / "frames.json");
    std::vector<std::string> args = RenderArgs(base() / "scene.glb", base() / "rig_big.json", base() / "frames_long.json", out);
    args.push_back("--force");
    auto p = StartLongRenderAndWaitForFirstView(args, out, dir_ / "kill_force");
    ASSERT_TRUE(p);
    kill(p->pid(), SIGKILL);
    EXPECT_EQ(p->Wait(), 128 + SIGKILL);
    EXPECT_EQ(ReadFile(out / "frames.json"), frames_before);
    EXPECT_TRUE(fs::exists(DatasetLayout(out).Depth("cam1", "000000")));
  }
  // The next run into the same place removes the dead run's staging folder and completes.
  const CliResult r = Run(RenderArgs(base() / "scene.glb", base() / "rig.json", base() / "frames.json", dir_ / "fresh"));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(StagingFolders(dir_ / "fresh").empty());
  EXPECT_TRUE(fs::exists(DatasetLayout(dir_ / "fresh").OverlapJson()));
}

TEST_F(RigsimCli, SigintStopsCleanlyAndKeepsThePreviousDataset) {
  const fs::path out = CopyDataset();
  const std::string frames_before = ReadFile(out / "frames.json");
  std::vector<std::string> args = RenderArgs(base() / "scene.glb", base() / "rig_big.json", base() / "frames_long.json", out);
  args.push_back("--force");
  auto p = StartLongRenderAndWaitForFirstView(args, out, dir_ / "interrupt");
  ASSERT_TRUE(p);
  kill(p->pid(), SIGINT);
  EXPECT_EQ(p->Wait(), 128 + SIGINT);
  EXPECT_NE(p->err().find("interrupted by SIGINT; the output was not written"), std::string::npos) << p->err();
  EXPECT_TRUE(StagingFolders(out).empty());  // removed on the way out
  EXPECT_EQ(ReadFile(out / "frames.json"), frames_before);
  EXPECT_TRUE(fs::exists(DatasetLayout(out).Depth("cam1", "000000")));
}

}  // namespace
}  // namespace rigsim
