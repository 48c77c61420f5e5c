// `rigsim calibrate --intrinsics FILE --refine-intrinsics` on a small rendered dataset (the demo's
// ring at 640x360 over 2 frames): datasheet intrinsics, +-3 % in focal length, +-10 px in the
// principal point, no distortion (the ring's cam1 has strong barrel distortion), are refined
// close to the truth the dataset was rendered with, which stays the dataset's rig.json.
#include <algorithm>
#include <cmath>
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
using Json = nlohmann::json;

class RefineIntrinsicsCli : public ::testing::Test {
 protected:
  // The dataset, rendered once for the suite.
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const CliResult demo = RunRigsim({"demo", "--out", (dir_->path() / "demo").string(), "--width", "640", "--height", "360",
                                      "--frames", "2", "--spp", "1", "--no-report", "--semantics", "none"},
                                     dir_->path() / "demo", std::chrono::seconds(300));
    // Exit 3: a camera the two frames leave undetermined (the demo ring's cam3 can be); the
    // dataset is whole either way. (A failed assertion here would skip the suite's tests.)
    ASSERT_TRUE(demo.code == 0 || demo.code == 3) << demo.out << demo.err;
    // The datasheet: alternating signs per camera.
    Json rig = Json::parse(ReadFile(dir_->path() / "demo" / "rig.json"));
    int i = 0;
    for (Json& cam : rig.at("cameras")) {
      const double s = i++ % 2 == 0 ? 1.0 : -1.0;
      Json& p = cam.at("params");
      p[0] = p[0].get<double>() * (1 + 0.03 * s);
      p[1] = p[1].get<double>() * (1 + 0.03 * s);
      p[2] = p[2].get<double>() + 10 * s;
      p[3] = p[3].get<double>() + 10 * s;
      for (size_t k = 4; k < p.size(); ++k) p[k] = 0.0;
      cam.erase("cam_from_rig");
    }
    std::ofstream(dir_->path() / "datasheet.json") << rig.dump(2);
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path Dir() { return dir_->path(); }
  static TempDir* dir_;
};
TempDir* RefineIntrinsicsCli::dir_ = nullptr;

TEST_F(RefineIntrinsicsCli, DatasheetIntrinsicsAreRefinedTowardsTheTruth) {
  const fs::path out = Dir() / "refined";
  const CliResult r = RunRigsim({"calibrate", (Dir() / "demo").string(), "--semantics", "none", "--intrinsics",
                                 (Dir() / "datasheet.json").string(), "--refine-intrinsics", "--out", out.string()},
                                out, std::chrono::seconds(300));
  // Exit 3: not every camera placed. Two frames at 640x360 leave some positions undetermined once
  // the intrinsics are free too (a camera placed 6.4 deg off at a direction std of 0.79 deg is
  // what the 0.5 deg bound on the std now keeps out).
  ASSERT_TRUE(r.code == 0 || r.code == 3) << r.out << r.err;
  EXPECT_NE(r.out.find("Intrinsics refined in the bundle adjustment"), std::string::npos) << r.out;
  const Json evaluation = Json::parse(ReadFile(out / "evaluation.json"));
  const Json truth = Json::parse(ReadFile(Dir() / "demo" / "rig.json"));
  const Json written = Json::parse(ReadFile(out / "none" / "rig.json"));
  const Json& cameras = evaluation.at("methods").at("none").at("rig").at("cameras");
  ASSERT_EQ(cameras.size(), 4u);
  // Positions sit at the bound of what two frames at 640x360 fix once the intrinsics are free too
  // (cam2's direction std 0.51 deg against the 0.5 deg bound with Embree and OpenCV held to their
  // SSE2 paths; placed on Embree's AVX2 bits): a camera not placed is one whose direction the
  // images leave too loose, never one placed wrong.
  for (const Json& cam : cameras) {
    if (cam.at("calibrated").get<bool>() || cam.at("direction_std_deg").is_null()) continue;
    EXPECT_GT(cam.at("direction_std_deg").get<double>(), 0.5) << cam.dump();
  }
  int refined = 0;
  for (size_t c = 0; c < cameras.size(); ++c) {
    const Json& in = cameras[c].at("intrinsics");
    if (cameras[c].at("observations").get<int>() == 0) {
      // No track links it to the adjusted cameras: its intrinsics stay the datasheet's, and the
      // rotation it keeps rests on them (0.87 deg off, within tolerance, on one render).
      EXPECT_TRUE(in.is_null()) << cameras[c].dump();
      EXPECT_TRUE(cameras[c].at("within_tolerance").get<bool>()) << cameras[c].dump();
      continue;
    }
    ASSERT_FALSE(in.is_null()) << cameras[c].dump();
    ++refined;
    EXPECT_NEAR(in.at("given_focal_error_percent").get<double>(), 3.0, 0.01) << c;
    // Two frames at 640x360 support no more: measured 0.18-0.75 % and 0.5-2.9 px (VALIDATION.md:
    // 1280x720 over 4 frames gives 0.02-0.07 % and 0.4-0.7 px), or 4.1 px at 3.3 standard
    // deviations for a camera whose position the images leave open.
    EXPECT_LT(in.at("focal_error_percent").get<double>(), 1.0) << in.dump();
    const double pp_sd = std::hypot(in.at("stddev")[2].get<double>(), in.at("stddev")[3].get<double>());
    EXPECT_LT(in.at("principal_point_error_px").get<double>(), std::max(4.0, 4.0 * pp_sd)) << in.dump();
    EXPECT_EQ(in.at("stddev").size(), in.at("refined").size()) << c;
    // rig.json, what a user exports, has the refined values; the given ones are the datasheet's.
    EXPECT_EQ(written.at("cameras")[c].at("params"), in.at("refined")) << c;
    EXPECT_NE(in.at("given"), truth.at("cameras")[c].at("params")) << c;
    // Placed within tolerance, or not placed; never placed wrong. Every rotation kept is right.
    if (cameras[c].at("calibrated").get<bool>()) {
      EXPECT_TRUE(cameras[c].at("within_tolerance").get<bool>()) << cameras[c].dump();
    }
    if (!cameras[c].at("rotation_error_deg").is_null()) {
      EXPECT_LT(cameras[c].at("rotation_error_deg").get<double>(), 0.5) << cameras[c].dump();
    }
  }
  EXPECT_GE(refined, 3) << "the adjustment refines the intrinsics of the cameras it observes";
  // The pair table and evaluation.json show the pairs the rig used, estimated again with the
  // refined intrinsics: none marked success far off (the datasheet's own estimates were up to 16 deg
  // off, and were shown).
  for (const Json& pair : evaluation.at("methods").at("none").at("pairs")) {
    if (!pair.at("success").get<bool>()) continue;
    EXPECT_LT(pair.at("rotation_error_deg").get<double>(), 2.0) << pair.dump();
  }
  // The distorted camera's k1 is found from zero.
  EXPECT_NEAR(cameras[1].at("intrinsics").at("refined")[4].get<double>(),
              truth.at("cameras")[1].at("params")[4].get<double>(), 0.03);
}

TEST_F(RefineIntrinsicsCli, WithoutTheFlagTheIntrinsicsAreTheGivenOnes) {
  const fs::path out = Dir() / "given";
  const CliResult r = RunRigsim({"calibrate", (Dir() / "demo").string(), "--semantics", "none", "--intrinsics",
                                 (Dir() / "datasheet.json").string(), "--out", out.string()},
                                out, std::chrono::seconds(300));
  ASSERT_TRUE(r.code == 0 || r.code == 3) << r.out << r.err;
  EXPECT_EQ(r.out.find("Intrinsics refined"), std::string::npos) << r.out;
  const Json datasheet = Json::parse(ReadFile(Dir() / "datasheet.json"));
  const Json written = Json::parse(ReadFile(out / "none" / "rig.json"));
  const Json evaluation = Json::parse(ReadFile(out / "evaluation.json"));
  for (size_t c = 0; c < 4; ++c) {
    EXPECT_EQ(written.at("cameras")[c].at("params"), datasheet.at("cameras")[c].at("params")) << c;
    EXPECT_TRUE(evaluation.at("methods").at("none").at("rig").at("cameras")[c].at("intrinsics").is_null()) << c;
  }
  EXPECT_FALSE(evaluation.contains("intrinsics_error")) << "no --intrinsics-error, no record";
}

// --intrinsics-error 0.02: the calibrator is given rig.json's intrinsics about 2 % off (focal
// lengths), evaluation.json says by how much per camera against the truth, which stays rig.json's,
// and the calibration runs on them.
TEST_F(RefineIntrinsicsCli, AnIntrinsicsErrorGivesTheCalibratorIntrinsicsOffTheTruth) {
  const fs::path out = Dir() / "intrinsics-error";
  const CliResult r = RunRigsim({"calibrate", (Dir() / "demo").string(), "--semantics", "none", "--intrinsics-error",
                                 "0.02", "--out", out.string()},
                                out, std::chrono::seconds(300));
  ASSERT_TRUE(r.code == 0 || r.code == 3) << r.out << r.err;
  EXPECT_NE(r.out.find("Intrinsics given with an error of 2.0 % (seed 1)"), std::string::npos) << r.out;
  const Json evaluation = Json::parse(ReadFile(out / "evaluation.json"));
  const Json truth = Json::parse(ReadFile(Dir() / "demo" / "rig.json"));
  const Json written = Json::parse(ReadFile(out / "none" / "rig.json"));
  const Json& record = evaluation.at("intrinsics_error");
  EXPECT_EQ(record.at("error").get<double>(), 0.02);
  EXPECT_EQ(record.at("seed").get<int>(), 1);
  const Json& cameras = record.at("cameras");
  ASSERT_EQ(cameras.size(), 4u);
  double focal_sum_sq = 0;
  for (size_t c = 0; c < cameras.size(); ++c) {
    const Json& cam = cameras[c];
    const Json& p = truth.at("cameras")[c].at("params");
    EXPECT_EQ(cam.at("name"), truth.at("cameras")[c].at("name"));
    EXPECT_EQ(cam.at("true_params"), p) << "the truth is rig.json's";
    EXPECT_EQ(cam.at("true").at("fx").get<double>(), p[0].get<double>());
    // What the calibrator used is what it was given: the estimate's rig.json has those intrinsics.
    EXPECT_EQ(written.at("cameras")[c].at("params"), cam.at("given_params")) << c;
    const double focal = cam.at("focal_error_percent").get<double>();
    EXPECT_NEAR(focal, 100 * (cam.at("given").at("fx").get<double>() / p[0].get<double>() - 1), 1e-9);
    EXPECT_GT(std::abs(focal), 0.0) << c;
    EXPECT_LT(std::abs(focal), 4 * 2.0) << "within 4 sigma of 2 %: " << cam.dump();
    focal_sum_sq += focal * focal;
    // The principal point moves by 2 % of half the image (6.4 px, 3.6 px) per axis.
    EXPECT_LT(std::abs(cam.at("principal_point_error_px")[0].get<double>()), 4 * 6.4) << cam.dump();
    EXPECT_LT(std::abs(cam.at("principal_point_error_px")[1].get<double>()), 4 * 3.6) << cam.dump();
    EXPECT_NE(cam.at("given_params"), p) << c;
  }
  // About 2 % over the four cameras (seed 1): not 0.2 %, not 20 %.
  const double focal_rms = std::sqrt(focal_sum_sq / 4);
  EXPECT_GT(focal_rms, 0.5);
  EXPECT_LT(focal_rms, 5.0);
  // The calibration ran on them: every camera has its entry and the gauge camera its pose.
  const Json& rig = evaluation.at("methods").at("none").at("rig").at("cameras");
  ASSERT_EQ(rig.size(), 4u);
  EXPECT_TRUE(rig[0].at("calibrated").get<bool>()) << rig[0].dump();
}

// --intrinsics-sd F,P: the intrinsics stay held at the given values, so the poses come out to the
// byte as without it; only the stated deviations grow. The placement bound sees them too: on two
// frames at 640x360 a camera's direction is known to a few tenths of a degree, and at 0.2 % and
// 1 px the given intrinsics alone leave it to about 2 deg, beyond the bound, so at those values
// the cameras are not placed; a camera placed still has the same pose. The small values, 0.002 %
// and 0.01 px, add a few hundredths of a degree: at ten times them a camera near the bound (0.45
// deg on one machine's renders) crossed it. Bad values are refused before anything is written.
TEST_F(RefineIntrinsicsCli, GivenIntrinsicsDeviationsWidenTheStatedDeviationsNotThePoses) {
  const auto calibrate = [&](const fs::path& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {"calibrate", (Dir() / "demo").string(), "--semantics", "none", "--out", out.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return RunRigsim(args, out, std::chrono::seconds(300));
  };
  const auto cameras = [](const fs::path& out) {
    return Json::parse(ReadFile(out / "evaluation.json")).at("methods").at("none").at("rig").at("cameras");
  };
  const fs::path plain = Dir() / "sd-none", small = Dir() / "sd-small", large = Dir() / "sd-large";
  const CliResult a = calibrate(plain, {});
  ASSERT_TRUE(a.code == 0 || a.code == 3) << a.out << a.err;
  const CliResult b = calibrate(small, {"--intrinsics-sd", "0.00002,0.01"});
  ASSERT_TRUE(b.code == 0 || b.code == 3) << b.out << b.err;
  const CliResult c = calibrate(large, {"--intrinsics-sd", "0.002,1"});
  ASSERT_TRUE(c.code == 0 || c.code == 3) << c.out << c.err;
  EXPECT_EQ(a.out.find("given intrinsics' own"), std::string::npos) << a.out;
  EXPECT_NE(c.out.find("Stated deviations include the given intrinsics' own: focal lengths +- 0.20 %, principal "
                       "point +- 1.00 px"),
            std::string::npos)
      << c.out;
  // The estimate (poses, intrinsics) is the same file to the byte.
  EXPECT_EQ(ReadFile(plain / "none" / "rig.json"), ReadFile(small / "none" / "rig.json"));
  EXPECT_EQ(ReadFile(plain / "none" / "frames.json"), ReadFile(small / "none" / "frames.json"));
  const Json eval_a = Json::parse(ReadFile(plain / "evaluation.json"));
  const Json eval_c = Json::parse(ReadFile(large / "evaluation.json"));
  EXPECT_FALSE(eval_a.contains("intrinsics_sd"));
  EXPECT_EQ(eval_c.at("intrinsics_sd").at("focal_fraction").get<double>(), 0.002);
  EXPECT_EQ(eval_c.at("intrinsics_sd").at("principal_point_px").get<double>(), 1.0);
  const Json cams_a = cameras(plain), cams_b = cameras(small), cams_c = cameras(large);
  const Json rig_a = Json::parse(ReadFile(plain / "none" / "rig.json"));
  const Json rig_c = Json::parse(ReadFile(large / "none" / "rig.json"));
  int wider = 0, placed = 0;
  for (size_t i = 1; i < 4; ++i) {
    for (const char* key : {"rotation_std_deg", "direction_std_deg"}) {
      if (cams_a[i].at(key).is_null()) continue;
      ASSERT_FALSE(cams_b[i].at(key).is_null() || cams_c[i].at(key).is_null()) << key << " " << i;
      EXPECT_GT(cams_b[i].at(key).get<double>(), cams_a[i].at(key).get<double>()) << key << " " << i;
      EXPECT_GT(cams_c[i].at(key).get<double>(), cams_b[i].at(key).get<double>()) << key << " " << i;
      ++wider;
    }
    EXPECT_FALSE(cams_a[i].contains("rotation_intrinsics_std_deg")) << i;
    // Where the jackknife states the deviation, the intrinsics' share adds to it in quadrature.
    for (const std::string what : {"rotation", "direction"}) {
      const Json& cam = cams_b[i];
      if (cam.at(what + "_jackknife_std_deg").is_null() || !cam.contains(what + "_intrinsics_std_deg")) continue;
      const double jackknife = cam.at(what + "_jackknife_std_deg").get<double>();
      const double share = cam.at(what + "_intrinsics_std_deg").get<double>();
      EXPECT_GE(cam.at(what + "_std_deg").get<double>(), std::hypot(jackknife, share) * (1 - 1e-12)) << cam.dump();
    }
    placed += cams_a[i].at("calibrated").get<bool>();
    // At 0.2 % and 1 px: the same pose, or none (its direction beyond the placement bound).
    const Json pose = rig_c.at("cameras")[i].value("cam_from_rig", Json());
    const Json pose_a = rig_a.at("cameras")[i].value("cam_from_rig", Json());
    if (!pose.is_null()) EXPECT_EQ(pose.dump(), pose_a.dump()) << i;
    if (pose.is_null() && !pose_a.is_null()) {
      EXPECT_NE(cams_c[i].at("status").get<std::string>().find("with the given intrinsics' uncertainty"), std::string::npos)
          << cams_c[i].dump();
    }
  }
  EXPECT_GE(wider, 3);
  EXPECT_GE(placed, 1);

  for (const std::string bad : {"-0.001,1", "0.5,1", "0.002,-1", "0.002", "0.002,1,3", "x,1"}) {
    const fs::path out = Dir() / "sd-refused";
    const CliResult r = calibrate(out, {"--intrinsics-sd", bad});
    EXPECT_EQ(r.code, 1) << bad << ": " << r.out << r.err;
    EXPECT_NE(r.err.find("--intrinsics-sd"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(bad), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << bad;
  }
  const fs::path out = Dir() / "sd-refined";
  const CliResult r = calibrate(out, {"--intrinsics-sd", "0.002,1", "--refine-intrinsics"});
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("--refine-intrinsics"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(RefineIntrinsicsCli, IntrinsicsOfAnotherRigAreRefused) {
  Json rig = Json::parse(ReadFile(Dir() / "datasheet.json"));
  rig.at("cameras")[2]["name"] = "camX";
  std::ofstream(Dir() / "other.json") << rig.dump(2);
  const fs::path out = Dir() / "refused";
  const CliResult r = RunRigsim({"calibrate", (Dir() / "demo").string(), "--intrinsics", (Dir() / "other.json").string(),
                                 "--out", out.string()},
                                out);
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("no camera 'cam2'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace rigsim
