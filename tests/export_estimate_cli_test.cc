// The README's workflow on a small rig, through the built binary: make-rig, render, calibrate,
// then export the estimate. The exported cameras must sit where the truth has them after one
// similarity transform (the images fix a rig only up to one), to within the calibration's own
// error: an estimate's cam_from_rig combined with the truth's rig poses would put them metres off.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;
using Json = nlohmann::json;

// COLMAP images.txt: image name -> camera centre in the model's world.
std::map<std::string, Eigen::Vector3d> ColmapCentres(const fs::path& images_txt) {
  std::map<std::string, Eigen::Vector3d> centres;
  std::ifstream in(images_txt);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    int id = 0, camera = 0;
    double qw, qx, qy, qz, tx, ty, tz;
    std::string name;
    if (!(s >> id >> qw >> qx >> qy >> qz >> tx >> ty >> tz >> camera >> name)) continue;
    const Eigen::Quaterniond q(qw, qx, qy, qz);
    centres[name] = -(q.normalized().conjugate() * Eigen::Vector3d(tx, ty, tz));
  }
  return centres;
}

class ExportEstimate : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const fs::path d = dir_->path();
    auto run = [](const std::vector<std::string>& args, const fs::path& log, std::initializer_list<int> ok) {
      const CliResult r = RunRigsim(args, log, std::chrono::seconds(300));
      ASSERT_TRUE(std::find(ok.begin(), ok.end(), r.code) != ok.end()) << args[0] << ": " << r.out << r.err;
    };
    run({"make-rig", "ring", "--cameras", "4", "--width", "640", "--height", "360", "--trajectory", "circle",
         "--circle-radius", "12", "--frames", "3", "--rig-out", (d / "rig.json").string(), "--frames-out",
         (d / "frames.json").string()},
        d / "make-rig", {0});
    run({"render", "--scene", std::string(RIGSIM_SOURCE_DIR) + "/assets/scenes/street.glb", "--rig",
         (d / "rig.json").string(), "--frames", (d / "frames.json").string(), "--out", (d / "data").string(), "--spp", "1"},
        d / "render", {0});
    // 3: some camera without a full pose; what was placed is still exported.
    calibrate_ = new CliResult(RunRigsim({"calibrate", (d / "data").string(), "--semantics", "none"}, d / "calibrate",
                                         std::chrono::seconds(300)));
    ASSERT_TRUE(calibrate_->code == 0 || calibrate_->code == 3) << calibrate_->out << calibrate_->err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    delete calibrate_;
  }
  static TempDir* dir_;
  static CliResult* calibrate_;
};
TempDir* ExportEstimate::dir_ = nullptr;
CliResult* ExportEstimate::calibrate_ = nullptr;

// What calibrate prints of this run: a circle at a steady speed hides time, so the cameras it
// places hold only if synchronised, and says so; the ring's pairs that share nothing are one line;
// the summary says which pairs its medians count.
TEST_F(ExportEstimate, CalibrateSaysWhatItsTablesCount) {
  const std::string& out = calibrate_->out;
  EXPECT_NE(out.find("calibrated if synchronised: the rig's path cannot show whether it captured with cam0"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("(3 if synchronised)"), std::string::npos) << out;
  EXPECT_NE(out.find("pairs screened out in every method"), std::string::npos) << out;
  EXPECT_EQ(out.find("screened out (no shared view"), std::string::npos) << "one line, not a row per pair\n" << out;
  EXPECT_NE(out.find("pairs of at least 5% overlap solved"), std::string::npos) << out;
  const Json evaluation = Json::parse(ReadFile(dir_->path() / "data" / "calibration" / "evaluation.json"));
  for (const Json& cam : evaluation.at("methods").at("none").at("rig").at("cameras")) {
    EXPECT_EQ(cam.at("holds_if_synchronised"), cam.at("name") != "cam0" && cam.at("calibrated").get<bool>()) << cam.dump();
  }
  // evaluate counts them apart and none as confidently wrong.
  const CliResult evaluated =
      RunRigsim({"evaluate", (dir_->path() / "data").string(), (dir_->path() / "data" / "calibration").string(), "--json",
                 (dir_->path() / "scores.json").string()},
                dir_->path() / "scores");
  ASSERT_EQ(evaluated.code, 0) << evaluated.err;
  const Json scores = Json::parse(ReadFile(dir_->path() / "scores.json"));
  const Json& summary = scores.at("methods").at("none").at("summary");
  EXPECT_GE(summary.at("cameras_if_synchronised").get<int>(), 1) << summary.dump();
  EXPECT_EQ(summary.at("confidently_wrong"), 0) << summary.dump();
}

TEST_F(ExportEstimate, CameraCentresAgreeWithTheTruthAfterOneSimilarity) {
  const fs::path d = dir_->path();
  const fs::path estimate = d / "data" / "calibration" / "none" / "rig.json";
  const CliResult exported = RunRigsim({"export", (d / "data").string(), "--format", "all", "--rig", estimate.string(),
                                        "--out", (d / "estimate").string()},
                                       d / "export");
  ASSERT_EQ(exported.code, 0) << exported.out << exported.err;
  EXPECT_NE(exported.out.find("lengths not in metres"), std::string::npos) << exported.out;

  // Truth: every image's camera centre in the world.
  const Rig truth = ReadRig(d / "data" / "rig.json");
  const FramesFile frames = ReadFrames(d / "data" / "frames.json");
  const std::map<std::string, Eigen::Vector3d> centres = ColmapCentres(d / "estimate" / "colmap" / "images.txt");
  ASSERT_GE(centres.size(), 4u) << "at least two cameras at two frames";
  Eigen::Matrix3Xd from(3, centres.size()), to(3, centres.size());
  int i = 0;
  for (const auto& [name, centre] : centres) {
    const std::string cam = name.substr(0, name.find('/'));
    const std::string frame = fs::path(name).stem().string();
    const auto f = std::find_if(frames.frames.begin(), frames.frames.end(), [&](const Frame& x) { return x.name == frame; });
    ASSERT_NE(f, frames.frames.end()) << name;
    const Rigid3d cam_from_world = *truth.cameras[truth.FindCamera(cam)].cam_from_rig * *f->rig_from_world;
    from.col(i) = centre;
    to.col(i) = cam_from_world.SourceOriginInTarget();
    ++i;
  }
  const Eigen::Matrix4d sim = Eigen::umeyama(from, to, true);
  const Eigen::Matrix3Xd aligned = (sim.topLeftCorner<3, 3>() * from).colwise() + sim.topRightCorner<3, 1>();
  const double worst = (aligned - to).colwise().norm().maxCoeff();

  // The calibration's own error: each placed camera's direction error at its distance from cam0.
  const Json evaluation = Json::parse(ReadFile(d / "data" / "calibration" / "evaluation.json"));
  double own = 0.0;
  for (const Json& cam : evaluation.at("methods").at("none").at("rig").at("cameras")) {
    const Json dir = cam.value("translation_direction_error_deg", Json());
    if (!dir.is_number()) continue;
    const RigCamera& rc = truth.cameras[truth.FindCamera(cam.at("name").get<std::string>())];
    const double baseline = (rc.cam_from_rig->SourceOriginInTarget() - truth.cameras[0].cam_from_rig->SourceOriginInTarget()).norm();
    own = std::max(own, baseline * std::tan(dir.get<double>() * M_PI / 180.0));
  }
  // Three times that, and 2 cm for the rig's poses along the path (12 m circle, 2 m steps).
  EXPECT_LT(worst, 3.0 * own + 0.02) << "own error " << own << " m";

  // Every file says it is an estimate in its own unit, and evaluate reads rigsim's camchain so.
  EXPECT_NE(ReadFile(d / "estimate" / "camchain.yaml").find("# rigsim length unit: not metres"), std::string::npos);
  EXPECT_NE(ReadFile(d / "estimate" / "opencv.yaml").find("# rigsim length unit: not metres"), std::string::npos);
  EXPECT_NE(ReadFile(d / "estimate" / "colmap" / "images.txt").find("# rigsim length unit: not metres"), std::string::npos);
  EXPECT_TRUE(Json::parse(ReadFile(d / "estimate" / "transforms.json")).contains("rigsim_estimate"));
  const CliResult evaluated = RunRigsim({"evaluate", (d / "data").string(), (d / "estimate" / "camchain.yaml").string()},
                                        d / "evaluate");
  ASSERT_EQ(evaluated.code, 0) << evaluated.out << evaluated.err;
  EXPECT_NE(evaluated.out.find("not metres"), std::string::npos) << evaluated.out;
  EXPECT_EQ(evaluated.out.find("taken as metric"), std::string::npos) << evaluated.out;
}

// report --calibration makes the report of that calibration: its features too, and says so in its
// "Made by" line (the command it records).
TEST_F(ExportEstimate, TheReportOfACalibrationTakesItsFeaturesAndNamesIt) {
  const fs::path d = dir_->path();
  const CliResult calibrated = RunRigsim({"calibrate", (d / "data").string(), "--semantics", "none", "--features",
                                          "rootsift", "--out", (d / "rootsift").string()},
                                         d / "rootsift", std::chrono::seconds(300));
  ASSERT_TRUE(calibrated.code == 0 || calibrated.code == 3) << calibrated.err;
  EXPECT_EQ(Json::parse(ReadFile(d / "rootsift" / "evaluation.json")).at("features"), "rootsift");
  const CliResult report = RunRigsim({"report", (d / "data").string(), "--calibration", (d / "rootsift").string(), "--out",
                                      (d / "report").string()},
                                     d / "report", std::chrono::seconds(300));
  ASSERT_EQ(report.code, 0) << report.err;
  EXPECT_EQ(report.err.find("differs from"), std::string::npos) << "the same options, the same estimate\n" << report.err;
  const std::string data = ReadFile(d / "report" / "data" / "report.js");
  EXPECT_NE(data.find("--calibration " + (d / "rootsift").string() + " --features rootsift"), std::string::npos)
      << data.substr(0, 2000);
}

TEST_F(ExportEstimate, WithoutItsRigPosesAnEstimateIsRefusedAndNothingIsWritten) {
  const fs::path d = dir_->path();
  const fs::path copy = d / "copy";
  fs::create_directories(copy);
  fs::copy_file(d / "data" / "calibration" / "none" / "rig.json", copy / "rig.json");
  const CliResult r = RunRigsim({"export", (d / "data").string(), "--format", "colmap", "--rig", (copy / "rig.json").string(),
                                 "--out", (d / "refused").string()},
                                d / "refused");
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find((copy / "rig.json").string() + ": a calibration estimate"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("are missing"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "refused"));
  EXPECT_TRUE(StagingFolders(d / "refused").empty());
  // Kalibr and OpenCV need no rig poses: they are written.
  const CliResult k = RunRigsim({"export", (d / "data").string(), "--format", "kalibr,opencv", "--rig",
                                 (copy / "rig.json").string(), "--out", (d / "intrinsics").string()},
                                d / "intrinsics");
  EXPECT_EQ(k.code, 0) << k.out << k.err;
}

// The per-camera errors and verdicts of an evaluate --json, by camera name, per method.
std::map<std::string, Json> CamerasByName(const Json& scores) {
  std::map<std::string, Json> out;
  for (const auto& [method, m] : scores.at("methods").items()) {
    for (const Json& cam : m.at("cameras")) out[method + "/" + cam.at("name").get<std::string>()] = cam;
  }
  return out;
}

// `evaluate FOLDER --truth RIG` scores a calibration folder as `evaluate DATASET FOLDER` does, with
// the dataset's rig.json as RIG, and with the truth exported as a Kalibr camchain (read by
// make-rig's importer) to the camchain's precision.
TEST_F(ExportEstimate, EvaluateAgainstARigFileScoresAsAgainstTheDataset) {
  const fs::path d = dir_->path();
  const fs::path folder = d / "data" / "calibration";
  const CliResult by_dataset =
      RunRigsim({"evaluate", (d / "data").string(), folder.string(), "--json", (d / "by_dataset.json").string()},
                d / "by_dataset");
  ASSERT_EQ(by_dataset.code, 0) << by_dataset.err;
  const CliResult by_truth = RunRigsim({"evaluate", folder.string(), "--truth", (d / "data" / "rig.json").string(),
                                        "--json", (d / "by_truth.json").string()},
                                       d / "by_truth");
  ASSERT_EQ(by_truth.code, 0) << by_truth.err;
  const Json a = Json::parse(ReadFile(d / "by_dataset.json")), b = Json::parse(ReadFile(d / "by_truth.json"));
  EXPECT_EQ(a.at("methods"), b.at("methods"));  // the same cameras in the same order: the same scores
  EXPECT_EQ(b.at("not_scored").at("only_in_truth"), Json::array());
  // The same table, but for the lines naming the truth and the JSON file.
  const auto table = [](const std::string& out) {
    const size_t start = out.find('\n');
    return out.substr(start, out.find("scores written to") - start);
  };
  EXPECT_EQ(table(by_dataset.out), table(by_truth.out));
  EXPECT_NE(by_truth.out.find("against the truth in " + (d / "data" / "rig.json").string()), std::string::npos)
      << by_truth.out;

  // The truth as a Kalibr camchain (metric, cam0 its rig frame).
  const CliResult exported = RunRigsim(
      {"export", (d / "data").string(), "--format", "kalibr", "--out", (d / "truth_kalibr").string()}, d / "export_truth");
  ASSERT_EQ(exported.code, 0) << exported.out << exported.err;
  const CliResult by_kalibr = RunRigsim({"evaluate", folder.string(), "--truth",
                                         (d / "truth_kalibr" / "camchain.yaml").string(), "--json",
                                         (d / "by_kalibr.json").string()},
                                        d / "by_kalibr");
  ASSERT_EQ(by_kalibr.code, 0) << by_kalibr.err;
  const std::map<std::string, Json> want = CamerasByName(a), got = CamerasByName(Json::parse(ReadFile(d / "by_kalibr.json")));
  ASSERT_EQ(want.size(), got.size());
  int compared = 0;
  for (const auto& [key, cam] : want) {
    const Json& other = got.at(key);
    EXPECT_EQ(cam.at("posed"), other.at("posed")) << key;
    EXPECT_EQ(cam.at("overconfident"), other.at("overconfident")) << key;
    for (const char* error : {"rotation_error_deg", "translation_direction_error_deg"}) {
      ASSERT_EQ(cam.at(error).is_null(), other.at(error).is_null()) << key << " " << error;
      if (cam.at(error).is_null()) continue;
      EXPECT_NEAR(cam.at(error).get<double>(), other.at(error).get<double>(), 1e-6) << key << " " << error;
      ++compared;
    }
  }
  EXPECT_GE(compared, 1);

  // A COLMAP model of the estimate: its frames are its images' stems.
  const CliResult colmap = RunRigsim({"export", (d / "data").string(), "--format", "colmap", "--rig",
                                      (folder / "none" / "rig.json").string(), "--out", (d / "est_colmap").string()},
                                     d / "export_colmap");
  ASSERT_EQ(colmap.code, 0) << colmap.out << colmap.err;
  const fs::path model = d / "est_colmap" / "colmap";
  const CliResult colmap_dataset = RunRigsim(
      {"evaluate", (d / "data").string(), model.string(), "--json", (d / "colmap_dataset.json").string()}, d / "cd");
  const CliResult colmap_truth = RunRigsim({"evaluate", model.string(), "--truth", (d / "data" / "rig.json").string(),
                                            "--json", (d / "colmap_truth.json").string()},
                                           d / "ct");
  ASSERT_EQ(colmap_dataset.code, 0) << colmap_dataset.err;
  ASSERT_EQ(colmap_truth.code, 0) << colmap_truth.err;
  EXPECT_EQ(Json::parse(ReadFile(d / "colmap_dataset.json")).at("methods"),
            Json::parse(ReadFile(d / "colmap_truth.json")).at("methods"));
}

// Cameras are matched by name: those on one side only are named as not scored; none in common, a
// truth without poses, --truth beside DATASET, or no ESTIMATE are refused, and --json is not written.
TEST_F(ExportEstimate, EvaluateAgainstARigFileMatchesCamerasByNameAndRefusesBadInput) {
  const fs::path d = dir_->path();
  const fs::path folder = d / "data" / "calibration";
  Json rig = Json::parse(ReadFile(d / "data" / "rig.json"));
  // cam3 left out, and a camera the estimate does not have.
  Json partial = rig;
  Json cameras = Json::array();
  for (const Json& cam : rig.at("cameras")) {
    if (cam.at("name") != "cam3") cameras.push_back(cam);
  }
  Json extra = cameras[1];
  extra["name"] = "cam_roof";
  cameras.push_back(extra);
  partial["cameras"] = cameras;
  WriteFile(d / "partial.json", partial.dump());
  const CliResult part = RunRigsim({"evaluate", folder.string(), "--truth", (d / "partial.json").string(), "--json",
                                    (d / "partial_scores.json").string()},
                                   d / "partial");
  ASSERT_EQ(part.code, 0) << part.err;
  EXPECT_NE(part.out.find("not scored, only in the truth: cam_roof"), std::string::npos) << part.out;
  EXPECT_NE(part.out.find("not scored, only in the estimate: cam3"), std::string::npos) << part.out;
  const Json scores = Json::parse(ReadFile(d / "partial_scores.json"));
  EXPECT_EQ(scores.at("not_scored").at("only_in_estimate"), Json::array({"cam3"}));
  EXPECT_EQ(scores.at("methods").at("none").at("cameras").size(), 3u);

  const auto refused = [&](const std::vector<std::string>& args, const std::string& says) {
    const fs::path json = d / "refused.json";
    std::vector<std::string> all = args;
    all.insert(all.end(), {"--json", json.string()});
    const CliResult r = RunRigsim(all, d / "refused");
    EXPECT_EQ(r.code, 1) << r.out << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(json)) << args[1];
  };
  Json strangers = rig;
  for (size_t i = 0; i < strangers["cameras"].size(); ++i) strangers["cameras"][i]["name"] = "front" + std::to_string(i);
  WriteFile(d / "strangers.json", strangers.dump());
  refused({"evaluate", folder.string(), "--truth", (d / "strangers.json").string()},
          "no camera of it is in " + folder.string() + ": the truth has front0, front1, front2, front3; the estimate "
          "has cam0, cam1, cam2, cam3 (cameras are matched by name)");
  Json unposed = rig;
  unposed["cameras"][2].erase("cam_from_rig");
  WriteFile(d / "unposed.json", unposed.dump());
  refused({"evaluate", folder.string(), "--truth", (d / "unposed.json").string()},
          "has no pose (cam_from_rig) for cam2");
  refused({"evaluate", (d / "data").string(), folder.string(), "--truth", (d / "data" / "rig.json").string()},
          "--truth replaces DATASET");
  refused({"evaluate", "--truth", (d / "data" / "rig.json").string()}, "ESTIMATE is required");
  refused({"evaluate", folder.string()}, "needs DATASET ESTIMATE, or ESTIMATE --truth RIG");
  WriteFile(d / "notes.txt", "not a rig");
  refused({"evaluate", folder.string(), "--truth", (d / "notes.txt").string()}, "notes.txt");
}

}  // namespace
}  // namespace rigsim
