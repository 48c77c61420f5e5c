// The rig's parameters are described once (rigs/rig_params.h): make-rig's options, the sweep's
// cell parameters and `sweep --list-params` all come from that description, so make-rig and a
// sweep cell with the same values build the same rig on the same path, through the built binary.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "gltf/gltf_loader.h"
#include "rigs/rig_params.h"
#include "sweep/cell_runner.h"
#include "sweep/sweep_config.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// The option make-rig takes for a parameter: its first long name.
std::string LongFlag(const RigParam& p) {
  const std::string flags = p.Flags();
  const size_t at = flags.find("--");
  return flags.substr(at, flags.find(',', at) - at);
}

TEST(OneDescription, MakeRigAndASweepCellBuildTheSameRigFromTheSameValues) {
  const TempDir dir;
  const fs::path scene_file = fs::path(RIGSIM_SOURCE_DIR) / "assets/scenes/street.glb";
  const Scene scene = LoadGltf(scene_file);
  // Values away from both defaults, two rig types.
  const SweepConfig config = ParseSweepConfig(Json::parse(R"({
    "name": "same-rig",
    "base": {"width": 160, "height": 96, "frames": 2, "step": 1.5, "circle_radius": -9, "spacing": 55, "radius": 0.3},
    "seeds": [4],
    "zip": {"rig": ["ring", "surround"], "lens": ["opencv", "preset"], "distortion": [-0.1, -0.1],
            "fisheye_fov": [190, 170], "lens_residual": [0.3, 0], "placement": ["road", "structure"]}
  })"), "test");
  for (const SweepCell& cell : ExpandCells(config)) {
    SCOPED_TRACE(cell.params.dump());
    std::optional<PlacedRig> placed = MakePlacedRig(CellRigSpec(cell.params, dir.path()), &scene);
    ASSERT_TRUE(placed.has_value());
    placed->frames.scene = scene_file.filename().string();  // make-rig names the scene it placed the rig in
    const fs::path sweep_dir = dir / ("sweep" + std::to_string(cell.index));
    fs::create_directories(sweep_dir);
    WriteRig(placed->rig, sweep_dir / "rig.json");
    WriteFrames(placed->frames, sweep_dir / "frames.json");

    std::vector<std::string> args = {"make-rig"};
    for (const RigParam& p : RigParams()) {
      if (!p.in_sweep || CellParam(cell.params, p.spec.name).is_null()) continue;
      args.push_back(LongFlag(p));
      args.push_back(FormatParamValue(CellParam(cell.params, p.spec.name)));
    }
    const fs::path out = dir / ("make-rig" + std::to_string(cell.index));
    for (const std::string& a : std::vector<std::string>{"--scene", scene_file.string(), "--seed",
                                                          cell.params.at("seed").dump(), "--out", out.string()}) {
      args.push_back(a);
    }
    const CliResult r = RunRigsim(args, out.string() + "-log");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(ReadFile(out / "rig.json"), ReadFile(sweep_dir / "rig.json"));
    EXPECT_EQ(ReadFile(out / "frames.json"), ReadFile(sweep_dir / "frames.json"));
  }
}

TEST(OneDescription, ListParamsListsEveryCellParameterWithItsHelp) {
  const TempDir dir;
  const CliResult r = RunRigsim({"sweep", "--list-params"}, dir / "list");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const ParamSpec& p : CellParamSpecs()) {
    EXPECT_NE(r.out.find("  " + p.name + " "), std::string::npos) << p.name;
    EXPECT_NE(r.out.find(p.help), std::string::npos) << p.name;
  }
}

TEST(OneDescription, MakeRigOffersEveryRigParameterWithItsHelp) {
  const TempDir dir;
  const CliResult r = RunRigsim({"make-rig", "--help"}, dir / "help");
  ASSERT_EQ(r.code, 0) << r.err;
  std::string help = r.out;
  // CLI11 wraps nothing but joins words with single spaces: compare without line breaks.
  for (char& c : help) c = c == '\n' ? ' ' : c;
  for (const RigParam& p : RigParams()) {
    EXPECT_NE(help.find(LongFlag(p)), std::string::npos) << p.spec.name;
    EXPECT_NE(help.find(p.spec.help), std::string::npos) << p.spec.name;
  }
  // Every path and rig type has its line in the description, with what it is for.
  for (TrajectoryKind k : kNamedTrajectoryKinds) {
    EXPECT_NE(r.out.find("\n  " + std::string(TrajectoryKindName(k)) + " "), std::string::npos) << TrajectoryKindName(k);
  }
  for (RigType t : kAllRigTypes) {
    EXPECT_NE(r.out.find("\n  " + std::string(RigTypeName(t)) + " "), std::string::npos) << RigTypeName(t);
  }
}

}  // namespace
}  // namespace rigsim
