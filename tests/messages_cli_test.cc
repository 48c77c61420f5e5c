// What the built binary says when the user errs: every refusal exits 1 (the option parser's too),
// names the option or the file in the words of the command line, and suggests the name the user
// probably meant (commands, options, choices, classes, cameras). A label rule that labels nothing
// is a warning, not silence.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

const std::string kStreet = std::string(RIGSIM_SOURCE_DIR) + "/assets/scenes/street.glb";

class MessagesCli : public testing::Test {
 protected:
  void SetUp() override { dir_ = temp_.path(); }

  CliResult Run(const std::vector<std::string>& args) { return RunRigsim(args, dir_ / ("run" + std::to_string(runs_++))); }

  // `args` exits 1 and its error message says `part`.
  void ExpectError(const std::vector<std::string>& args, const std::string& part) {
    const CliResult r = Run(args);
    std::string command;
    for (const std::string& a : args) command += " " + a;
    EXPECT_EQ(r.code, 1) << command << ": " << r.err;
    EXPECT_NE(r.err.find("rigsim: error: " + part), std::string::npos) << command << " does not say '" << part << "': " << r.err;
  }

  // A 2-camera rig (cam0, cam1) and a dataset rendered from it.
  fs::path Dataset() {
    const fs::path rig = dir_ / "rig";
    EXPECT_EQ(Run({"make-rig", "ring", "--cameras", "2", "--width", "64", "--height", "48", "--frames", "1", "--out", rig.string()}).code, 0);
    const CliResult r = Run({"render", "--scene", kStreet, "--rig", (rig / "rig.json").string(), "--frames",
                             (rig / "frames.json").string(), "--out", (dir_ / "data").string(), "--spp", "1"});
    EXPECT_EQ(r.code, 0) << r.err;
    return dir_ / "data";
  }

  const TempDir temp_;
  fs::path dir_;
  int runs_ = 0;
};

TEST_F(MessagesCli, OptionParserErrorsExitWith1AndSuggestTheNameMeant) {
  fs::create_directories(dir_ / "data");
  const std::string data = (dir_ / "data").string();
  ExpectError({"calibrat", "data"}, "unknown command 'calibrat' (did you mean 'calibrate'?)");
  ExpectError({"calibrate", data, "--fetures", "orb"}, "unknown option --fetures (did you mean '--features'?)");
  ExpectError({"calibrate", data, "--features", "sfit"}, "--features: 'sfit' is not one of sift, rootsift, orb, akaze (did you mean 'sift'?)");
  ExpectError({"calibrate", data, "--max-features", "-3"}, "--max-features: must be more than 0 (got -3)");
  ExpectError({"calibrate", data, "--ratio", "2"}, "--ratio: 2 is outside 0.1 to 1");
  ExpectError({"calibrate", data, "--known-distance", "cam0", "cam1"}, "--known-distance: takes 3 values, got 2");
  ExpectError({"calibrate"}, "DATASET is required");
  ExpectError({"render", "--scene", (dir_ / "missing.glb").string()}, "--scene: no such file: " + (dir_ / "missing.glb").string());
  ExpectError({"make-rig", "rnig", "--out", (dir_ / "r").string()}, "--type: 'rnig' is not one of ring, stereo, surround, wide-baseline, file (did you mean 'ring'?)");
  ExpectError({"make-rig", "--out", (dir_ / "a").string(), "--rig-out", (dir_ / "b").string()}, "--rig-out cannot be given with --out");
  ExpectError({}, "give a command: demo, make-rig, render, render-merge, calibrate");
  ExpectError({"make-rig", "--cameras", "2", "--time-offset", "cam7=0.01", "--out", (dir_ / "t").string()},
              "--time-offset: no camera named 'cam7' in the rig (did you mean 'cam0'?); its cameras are cam0, cam1");
  ExpectError({"make-rig", "--cameras", "3", "--time-offset", "0", "0.03", "0.06", "--out", (dir_ / "t").string()},
              "--time-offset: give one plain VALUE (every camera) or CAMERA=VALUE per camera, e.g. --time-offset cam1=0.03 "
              "cam2=0.06; several plain values are not read in camera order");
}

TEST_F(MessagesCli, CalibrateSpeaksOfItsOptionsNotOfTheLibrary) {
  const fs::path data = Dataset();
  const CliResult zero = Run({"calibrate", data.string(), "--known-distance", "cam0", "cam1", "0"});
  EXPECT_EQ(zero.code, 1);
  EXPECT_NE(zero.err.find("rigsim: error: --known-distance: the distance must be more than 0 metres (got 0)"), std::string::npos)
      << zero.err;
  EXPECT_EQ(zero.err.find("Options"), std::string::npos) << "an internal name: " << zero.err;
  ExpectError({"calibrate", data.string(), "--known-distance", "cam0", "cam7", "1"},
              "--known-distance: no camera 'cam7' in " + (data / "rig.json").string() + " (did you mean 'cam0'?); its cameras are cam0, cam1");
  ExpectError({"calibrate", data.string(), "--reliable", "road,buildng"}, "--reliable: unknown class 'buildng' (did you mean 'building'?)");
  for (const std::string bad : {"-0.01", "nan", "inf", "0.6", "2%"}) {
    ExpectError({"calibrate", data.string(), "--intrinsics-error", bad},
                "--intrinsics-error: must be 0 to 0.5, a fraction (0.01 is 1 %) (got " + bad + ")");
  }
  EXPECT_FALSE(fs::exists(data / "calibration"));
}

TEST_F(MessagesCli, RenderNamesTheFileThatLacksAPose) {
  const fs::path rig = dir_ / "rig";
  ASSERT_EQ(Run({"make-rig", "ring", "--cameras", "2", "--width", "64", "--height", "48", "--out", rig.string()}).code, 0);
  nlohmann::json frames = nlohmann::json::parse(ReadFile(rig / "frames.json"));
  frames["frames"][0]["name"] = "0001";
  frames["frames"][0].erase("rig_from_world");
  std::ofstream(dir_ / "frames.json") << frames.dump();
  ExpectError({"render", "--scene", kStreet, "--rig", (rig / "rig.json").string(), "--frames", (dir_ / "frames.json").string(),
               "--out", (dir_ / "out").string()},
              (dir_ / "frames.json").string() + ": frames[0] ('0001') has no rig_from_world");
  nlohmann::json cameras = nlohmann::json::parse(ReadFile(rig / "rig.json"));
  cameras["cameras"][1].erase("cam_from_rig");
  std::ofstream(dir_ / "rig.json") << cameras.dump();
  ExpectError({"render", "--scene", kStreet, "--rig", (dir_ / "rig.json").string(), "--frames", (rig / "frames.json").string(),
               "--out", (dir_ / "out").string()},
              (dir_ / "rig.json").string() + ": camera 'cam1' has no cam_from_rig");
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// A camera folder named otherwise than the camera in rig.json: the message names the folder it
// looked for, the nearest there is and what the folder holds; for photos and for label folders.
TEST_F(MessagesCli, AMisnamedCameraFolderIsNamedWithTheNearest) {
  const fs::path data = Dataset();
  fs::rename(data / "images" / "cam1", data / "images" / "Cam1");
  ExpectError({"calibrate", data.string(), "--semantics", "none", "--out", (dir_ / "out").string()},
              (data / "images" / "cam1").string() + ": no such folder: the photos of camera 'cam1' of rig.json go in "
              "images/cam1/ (did you mean 'Cam1'?); images/ holds Cam1, cam0 (a folder per camera, named as in rig.json)");
  fs::rename(data / "images" / "Cam1", data / "images" / "cam1");
  fs::create_directories(dir_ / "labels");
  fs::copy(data / "labels" / "cam0", dir_ / "labels" / "cam0");
  fs::copy(data / "labels" / "cam1", dir_ / "labels" / "CAM1");
  ExpectError({"calibrate", data.string(), "--semantics", "mask", "--labels", (dir_ / "labels").string(), "--out", (dir_ / "out").string()},
              (dir_ / "labels" / "cam1").string() + ": no such folder: the label images of camera 'cam1' of rig.json go in "
              "labels/cam1/ (did you mean 'CAM1'?)");
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(MessagesCli, MisspeltClassesAndRulesThatLabelNothingAreNamed) {
  // A rules file with a misspelt class is refused, suggesting the class.
  std::ofstream(dir_ / "typo.json") << R"({"rules": [{"match": "node", "glob": "*", "class": "buildng"}]})";
  ExpectError({"inspect", kStreet, "--rules", (dir_ / "typo.json").string()},
              (dir_ / "typo.json").string() + ": rules[0]: unknown class 'buildng' (did you mean 'building'?)");
  // The street has extras.class everywhere: rules never decide anything there, and a warning says so.
  std::ofstream(dir_ / "rules.json") << R"({"rules": [{"match": "node", "glob": "Car*", "class": "car"}]})";
  const CliResult r = Run({"inspect", kStreet, "--rules", (dir_ / "rules.json").string()});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE((r.out + r.err).find((dir_ / "rules.json").string() + ": no rule used"), std::string::npos) << r.out << r.err;
}

}  // namespace
}  // namespace rigsim
