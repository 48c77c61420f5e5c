// `make-rig --ego-vehicle` and `render` with it, through the built binary: the body file beside
// rig.json and named there, `ego vehicle` labels in the side cameras' lower part, a rig without it
// as before, and the refusals (no --out; a missing or misnamed body file).
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dataset/image_io.h"
#include "testing/gltf_builder.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

CliResult RunIn(const TempDir& dir, const std::vector<std::string>& args) { return RunRigsim(args, dir.path() / "rigsim"); }

// A road 400 m across (the plane y = 0) for the rig to drive on.
fs::path WriteRoad(const TempDir& dir) {
  GltfBuilder g;
  g.Mesh({{"POSITION", g.Positions({-200, 0, -200, 200, 0, 200, 200, 0, -200, -200, 0, -200, -200, 0, 200, 200, 0, 200})}});
  g.Node({{"mesh", 0}, {"extras", {{"class", "road"}}}});
  g.Scene({0});
  return g.WriteEmbedded(dir.path(), "road");
}

int CountLabel(const ImageU8& label, int id, int y_begin, int y_end) {
  int n = 0;
  for (int y = y_begin; y < y_end; ++y) {
    for (int x = 0; x < label.width; ++x) n += label.at(x, y) == id;
  }
  return n;
}

TEST(EgoVehicleCli, MakeRigWritesTheBodyAndRenderShowsIt) {
  const TempDir dir;
  const fs::path road = WriteRoad(dir);
  const std::vector<std::string> rig_args = {"make-rig", "surround", "--width", "96", "--height", "64", "--frames", "2"};
  std::vector<std::string> with = rig_args, without = rig_args;
  with.insert(with.end(), {"--ego-vehicle", "--out", (dir.path() / "car").string()});
  without.insert(without.end(), {"--out", (dir.path() / "bare").string()});
  const CliResult made = RunIn(dir, with);
  ASSERT_EQ(made.code, 0) << made.err;
  EXPECT_NE(made.out.find("ego_vehicle.glb"), std::string::npos) << made.out;
  EXPECT_TRUE(fs::is_regular_file(dir.path() / "car/ego_vehicle.glb"));
  EXPECT_EQ(json::parse(ReadFile(dir.path() / "car/rig.json")).value("ego_vehicle", ""), "ego_vehicle.glb");
  ASSERT_EQ(RunIn(dir, without).code, 0);
  EXPECT_FALSE(json::parse(ReadFile(dir.path() / "bare/rig.json")).contains("ego_vehicle"));
  // The same cameras with and without the body.
  json cams_with = json::parse(ReadFile(dir.path() / "car/rig.json"));
  cams_with.erase("ego_vehicle");
  EXPECT_EQ(cams_with, json::parse(ReadFile(dir.path() / "bare/rig.json")));

  for (const std::string rig : {"car", "bare"}) {
    const CliResult rendered = RunIn(dir, {"render", "--scene", road.string(), "--rig", (dir.path() / rig / "rig.json").string(),
                                         "--frames", (dir.path() / rig / "frames.json").string(), "--out",
                                         (dir.path() / (rig + "_data")).string(), "--spp", "1"});
    ASSERT_EQ(rendered.code, 0) << rendered.err;
  }
  // The dataset's rig.json names no body file (the dataset holds none).
  EXPECT_FALSE(json::parse(ReadFile(dir.path() / "car_data/rig.json")).contains("ego_vehicle"));
  for (const std::string cam : {"left", "right"}) {
    for (const std::string frame : {"000000", "000001"}) {
      const ImageU8 label = ReadImageU8(dir.path() / "car_data/labels" / cam / (frame + ".png"), 1);
      EXPECT_EQ(CountLabel(label, 1, 0, label.height / 2), 0) << cam << " " << frame;
      EXPECT_GT(CountLabel(label, 1, label.height / 2, label.height), label.width) << cam << " " << frame;
      const ImageU8 bare = ReadImageU8(dir.path() / "bare_data/labels" / cam / (frame + ".png"), 1);
      EXPECT_EQ(CountLabel(bare, 1, 0, bare.height), 0);
    }
  }
}

TEST(EgoVehicleCli, BadInputIsRefused) {
  const TempDir dir;
  const CliResult no_out = RunIn(dir, {"make-rig", "--ego-vehicle", "--rig-out", (dir.path() / "r.json").string(), "--frames-out",
                                     (dir.path() / "f.json").string()});
  EXPECT_NE(no_out.code, 0);
  EXPECT_NE(no_out.err.find("--ego-vehicle writes ego_vehicle.glb beside rig.json: give --out DIR"), std::string::npos) << no_out.err;
  EXPECT_FALSE(fs::exists(dir.path() / "r.json"));

  const fs::path road = WriteRoad(dir);
  ASSERT_EQ(RunIn(dir, {"make-rig", "--width", "32", "--height", "24", "--ego-vehicle", "--out", (dir.path() / "car").string()}).code, 0);
  fs::remove(dir.path() / "car/ego_vehicle.glb");
  const std::vector<std::string> render = {"render", "--scene", road.string(), "--rig", (dir.path() / "car/rig.json").string(),
                                           "--frames", (dir.path() / "car/frames.json").string(), "--out",
                                           (dir.path() / "data").string()};
  const CliResult missing = RunIn(dir, render);
  EXPECT_NE(missing.code, 0);
  EXPECT_NE(missing.err.find("ego_vehicle 'ego_vehicle.glb': no such file beside it"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(dir.path() / "data"));

  json rig = json::parse(ReadFile(dir.path() / "car/rig.json"));
  rig["ego_vehicle"] = "../elsewhere.glb";
  WriteFile(dir.path() / "car/rig.json", rig.dump());
  const CliResult outside = RunIn(dir, render);
  EXPECT_NE(outside.code, 0);
  EXPECT_NE(outside.err.find("ego_vehicle '../elsewhere.glb' must be the name of a file beside rig.json"), std::string::npos)
      << outside.err;
}

}  // namespace
}  // namespace rigsim
