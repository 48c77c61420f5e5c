// Four frames of a circle at constant speed, cameras 30, 60 and 90 ms after camera 0 (the time-offset
// sweep's cell at 30 ms, seed 2), through the built binary. Taken as synchronised, the adjustment
// bends the rig's path to fit, and the freed offsets stop at zero, where every capture meets a frame
// and the path between frames has a corner, with standard deviations of a few tenths of a
// millisecond: the cameras were called calibrated 2.9-8.6 deg off. Solved again from moved offsets,
// the offsets leave zero; no camera is called calibrated there, synchronised or estimated.
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

TEST(CaptureTimeCli, AnOffsetStoppedAtZeroIsNeverTakenForSynchronised) {
  const TempDir dir;
  const fs::path street = dir / "street-2.glb";
  const CliResult scene =
      RunRigsim({"generate-scene", "--preset", "street", "--seed", "2", "--out", street.string()}, dir / "scene");
  ASSERT_EQ(scene.code, 0) << scene.err;
  const CliResult rig = RunRigsim(
      {"make-rig", "ring", "--cameras", "4", "--scene", street.string(), "--width", "640", "--height", "360", "--frames",
       "4", "--trajectory", "circle", "--circle-radius", "12", "--step", "2", "--time-offset", "cam1=0.03", "cam2=0.06",
       "cam3=0.09", "--seed", "2", "--out", (dir / "rig").string()},
      dir / "make-rig");
  ASSERT_EQ(rig.code, 0) << rig.err;
  const CliResult render = RunRigsim({"render", "--scene", street.string(), "--rig", (dir / "rig" / "rig.json").string(),
                                      "--frames", (dir / "rig" / "frames.json").string(), "--out", (dir / "data").string(),
                                      "--spp", "1"},
                                     dir / "render", std::chrono::seconds(300));
  ASSERT_EQ(render.code, 0) << render.err;
  for (const bool estimated : {false, true}) {
    const std::string out = (dir / (estimated ? "estimated" : "synchronised")).string();
    std::vector<std::string> args = {"calibrate", (dir / "data").string(), "--semantics", "none", "--out", out};
    if (estimated) args.push_back("--estimate-time-offsets");
    const CliResult calibrate = RunRigsim(args, dir / ("calibrate-" + std::to_string(estimated)), std::chrono::seconds(300));
    ASSERT_TRUE(calibrate.code == 0 || calibrate.code == 3) << calibrate.out << calibrate.err;
    const nlohmann::json evaluation = nlohmann::json::parse(ReadFile(fs::path(out) / "evaluation.json"));
    const nlohmann::json& cameras = evaluation.at("methods").at("none").at("rig").at("cameras");
    int placed = 0, offsets_found = 0;
    for (size_t c = 1; c < cameras.size(); ++c) {
      const nlohmann::json& cam = cameras[c];
      if (cam.value("calibrated", false) && !cam.value("holds_if_synchronised", false)) {
        ++placed;
        const nlohmann::json error = cam.value("rotation_error_deg", nlohmann::json());
        EXPECT_TRUE(error.is_number() && error.get<double>() < 1.0) << "calibrated but wrong: " << cam.dump();
      }
      // The measured offset, or where a solve from moved offsets ended fitting as well.
      const nlohmann::json time = cam.value("capture_time", nlohmann::json());
      for (const char* key : {"time_offset_ms", "time_offset_also_fits_ms"}) {
        if (time.is_object() && time.value(key, nlohmann::json()).is_number() &&
            std::abs(time[key].get<double>() - 30.0 * c) < 15.0) {
          ++offsets_found;
          break;
        }
      }
      // An offset shown undetermined names where else the images put it.
      if (time.is_object() && !time.value("time_offset_determined", true)) {
        EXPECT_TRUE(time.value("time_offset_also_fits_ms", nlohmann::json()).is_number()) << cam.dump();
      }
    }
    EXPECT_EQ(placed, 0) << (estimated ? "estimated: " : "synchronised: ") << calibrate.out;
    // Synchronised, the restarts find each camera's offset (within 15 ms; a path that hides time
    // shows it only through the corners of the path between frames), though it may fit no better
    // than the offset the check stopped at: then both are reported and the offset is undetermined.
    if (!estimated) EXPECT_GE(offsets_found, 2) << calibrate.out;
  }
}

}  // namespace
}  // namespace rigsim
