// A ring whose cameras read their rows out over 30 ms while a handheld rig moves, through the built
// binary: taken as captured at one instant, no camera is placed, each says it has a rolling
// shutter and what fixes it, and the capture-time table shows the readouts the check measured.
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

TEST(CaptureTimeCli, ARollingShutterIsFoundAndNamedNeverCalibrated) {
  const TempDir dir;
  const std::string street = std::string(RIGSIM_SOURCE_DIR) + "/assets/scenes/street.glb";
  // Neighbours sharing 40 % of their views: at the ring's default overlap the distorted views'
  // pairs are near the two-view stage's limits, and whether they join the rig (without which no
  // readout is measured) changed between two machines' renders (BENCHMARKS.md).
  const CliResult rig = RunRigsim({"make-rig", "ring", "--scene", street, "--width", "640", "--height", "360", "--overlap",
                                   "40", "--trajectory", "handheld", "--frames", "6", "--readout", "0.03", "--out",
                                   (dir / "rig").string()},
                                  dir / "make-rig");
  ASSERT_EQ(rig.code, 0) << rig.err;
  const CliResult render = RunRigsim({"render", "--scene", street, "--rig", (dir / "rig" / "rig.json").string(), "--frames",
                                      (dir / "rig" / "frames.json").string(), "--out", (dir / "data").string(), "--spp", "1"},
                                     dir / "render", std::chrono::seconds(300));
  ASSERT_EQ(render.code, 0) << render.err;
  const CliResult calibrate =
      RunRigsim({"calibrate", (dir / "data").string(), "--semantics", "none"}, dir / "calibrate", std::chrono::seconds(300));
  ASSERT_EQ(calibrate.code, 3) << "no camera but the reference may be placed\n" << calibrate.out << calibrate.err;
  EXPECT_NE(calibrate.out.find("(a rolling shutter) while the rig moves, so a pose taken as captured at one instant"),
            std::string::npos)
      << calibrate.out;
  EXPECT_NE(calibrate.out.find("--estimate-time-offsets --rolling-shutter"), std::string::npos) << calibrate.out;
  EXPECT_NE(calibrate.out.find("measured by the synchronisation check"), std::string::npos) << calibrate.out;
  const nlohmann::json evaluation = nlohmann::json::parse(ReadFile(dir / "data" / "calibration" / "evaluation.json"));
  const nlohmann::json& rig_result = evaluation.at("methods").at("none").at("rig");
  EXPECT_EQ(rig_result.at("summary").at("cameras_calibrated"), 1) << rig_result.at("summary").dump();
  int read_out = 0;
  for (const nlohmann::json& cam : rig_result.at("cameras")) {
    if (!cam.contains("capture_time") || !cam["capture_time"].is_object()) continue;
    const nlohmann::json readout = cam["capture_time"].value("readout_ms", nlohmann::json());
    if (readout.is_number() && std::abs(readout.get<double>() - 30.0) < 3.0) ++read_out;
  }
  EXPECT_GE(read_out, 2) << rig_result.at("cameras").dump();
}

}  // namespace
}  // namespace rigsim
