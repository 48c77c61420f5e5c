// A ring whose cameras share little of their views at the same instant, driven round a turn: the
// same-instant pairs place only the reference camera; the rig's motion (calibrator/stages/motion_links.h:
// hand-eye starts, views matched across time) must place every camera, within the evaluation's
// tolerance, and none outside it.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

// Without the motion stage only cam0 is placed here (the other three cameras are not connected).
TEST(LowOverlapCalibration, AFourCameraRingAtTwoPercentOverlapIsPlacedFromItsMotion) {
  const TempDir dir;
  const std::string scene = std::string(RIGSIM_SOURCE_DIR) + "/assets/scenes/street.glb";
  const CliResult rig = RunRigsim({"make-rig", "ring", "--cameras", "4", "--overlap", "2", "--width", "640", "--height",
                                   "360", "--frames", "12", "--trajectory", "circle", "--circle-radius", "8", "--step",
                                   "2", "--scene", scene, "--seed", "4", "--out", (dir / "rig").string()},
                                  dir / "make-rig");
  ASSERT_EQ(rig.code, 0) << rig.err;
  const CliResult render = RunRigsim({"render", "--scene", scene, "--rig", (dir / "rig" / "rig.json").string(),
                                      "--frames", (dir / "rig" / "frames.json").string(), "--out",
                                      (dir / "data").string(), "--spp", "1"},
                                     dir / "render", std::chrono::seconds(300));
  ASSERT_EQ(render.code, 0) << render.err;
  const CliResult calibrate = RunRigsim(
      {"calibrate", (dir / "data").string(), "--semantics", "none", "--out", (dir / "calibration").string()},
      dir / "calibrate", std::chrono::seconds(300));
  ASSERT_EQ(calibrate.code, 0) << calibrate.out << calibrate.err;  // 0: every camera has a full pose
  const nlohmann::json evaluation = nlohmann::json::parse(ReadFile(dir / "calibration" / "evaluation.json"));
  const nlohmann::json& summary = evaluation.at("methods").at("none").at("rig").at("summary");
  EXPECT_EQ(summary.at("cameras_calibrated"), 4) << summary.dump();
  EXPECT_EQ(summary.at("cameras_within_tolerance"), 4) << summary.dump();
  EXPECT_EQ(summary.at("cameras_calibrated_outside_tolerance"), 0) << summary.dump();
  EXPECT_GT(summary.at("motion_links").at("cross_time_pairs_used"), 0) << summary.dump();
  // The early stages already leave cam1-cam3 without a pose: the rig is made once, with the links.
  EXPECT_EQ(evaluation.at("methods").at("none").at("rig").at("timing").at("rig_passes"), 1);

  // With refined intrinsics too: both of its passes run with the links.
  const CliResult refined = RunRigsim({"calibrate", (dir / "data").string(), "--semantics", "none", "--refine-intrinsics",
                                       "--out", (dir / "refined").string()},
                                      dir / "refined", std::chrono::seconds(300));
  ASSERT_EQ(refined.code, 0) << refined.out << refined.err;
  const nlohmann::json refined_evaluation = nlohmann::json::parse(ReadFile(dir / "refined" / "evaluation.json"));
  const nlohmann::json& refined_summary = refined_evaluation.at("methods").at("none").at("rig").at("summary");
  EXPECT_EQ(refined_summary.at("cameras_calibrated"), 4) << refined_summary.dump();
  EXPECT_EQ(refined_summary.at("cameras_within_tolerance"), 4) << refined_summary.dump();
  EXPECT_GT(refined_summary.at("motion_links").at("cross_time_pairs_used"), 0) << refined_summary.dump();
}

}  // namespace
}  // namespace rigsim
