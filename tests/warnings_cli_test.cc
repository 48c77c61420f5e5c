// What the built binary says instead of making nonsense in silence: make-rig --scene at a place
// where the probe rays see (nearly) nothing warns; a scene without triangles is refused by
// make-rig --scene and rendered by render with a warning; make-rig prints the overlap it achieved
// per pair, naming the figure (the smaller of the two directions), and --overlap with --scene
// gives what render's overlap.json reports.
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "testing/gltf_builder.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

class WarningsCli : public testing::Test {
 protected:
  void SetUp() override { dir_ = temp_.path(); }

  CliResult Run(const std::vector<std::string>& args) { return RunRigsim(args, dir_ / ("run" + std::to_string(runs_++))); }

  // A glTF of one mesh with `xyz` (three floats a vertex, three vertices a triangle), or of no mesh.
  fs::path WriteScene(const std::string& name, const std::vector<float>& xyz) {
    json doc = {{"asset", {{"version", "2.0"}}}, {"scene", 0}, {"scenes", {{{"nodes", json::array()}}}}};
    if (!xyz.empty()) {
      std::vector<uint8_t> bin(xyz.size() * 4);
      std::memcpy(bin.data(), xyz.data(), bin.size());
      doc["scenes"][0]["nodes"] = {0};
      doc["nodes"] = {{{"mesh", 0}, {"extras", {{"class", "road"}}}}};
      doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"mode", 4}}}}}};
      doc["accessors"] = {{{"bufferView", 0}, {"componentType", 5126}, {"count", xyz.size() / 3}, {"type", "VEC3"}}};
      doc["bufferViews"] = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", bin.size()}}};
      doc["buffers"] = {{{"byteLength", bin.size()}, {"uri", DataUri("application/octet-stream", bin)}}};
    }
    const fs::path path = dir_ / name;
    std::ofstream(path) << doc.dump();
    return path;
  }

  const TempDir temp_;
  fs::path dir_;
  int runs_ = 0;
};

// "  cam0-cam1  30.1%" in make-rig's output: the overlap of each pair it prints, in percent.
std::map<std::string, double> PrintedOverlaps(const std::string& out) {
  std::map<std::string, double> pairs;
  const std::regex pair(R"((\w+-\w+)\s+([0-9.]+)%)");
  for (std::sregex_iterator it(out.begin(), out.end(), pair), end; it != end; ++it) pairs[(*it)[1]] = std::stod((*it)[2]);
  return pairs;
}

TEST_F(WarningsCli, MakeRigWarnsWhereTheProbeRaysSeeNoStructure) {
  // A 6 m square of road and nothing else: the rig stands on it, but its cameras see sky.
  const fs::path patch = WriteScene("patch.gltf", {-3, 0, -3, 3, 0, 3, 3, 0, -3, -3, 0, -3, -3, 0, 3, 3, 0, 3});
  const CliResult r = Run({"make-rig", "--cameras", "2", "--width", "64", "--height", "48", "--scene", patch.string(), "--out",
                           (dir_ / "rig").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("(0% of probe rays see structure)"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("warning: " + patch.string() + ": at the best place found, 0% of the probe rays see structure"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("mostly empty sky"), std::string::npos) << r.err;
}

TEST_F(WarningsCli, SceneWithoutTrianglesIsRefusedByMakeRigAndRenderedWithAWarning) {
  const fs::path empty = WriteScene("empty.gltf", {});
  const CliResult placed = Run({"make-rig", "--scene", empty.string(), "--out", (dir_ / "placed").string()});
  EXPECT_EQ(placed.code, 1);
  EXPECT_NE(placed.err.find("rigsim: error: " + empty.string() + ": the scene holds no triangles"), std::string::npos)
      << placed.err;
  EXPECT_FALSE(fs::exists(dir_ / "placed"));

  const fs::path rig = dir_ / "rig";
  ASSERT_EQ(Run({"make-rig", "--cameras", "2", "--width", "64", "--height", "48", "--out", rig.string()}).code, 0);
  const CliResult r = Run({"render", "--scene", empty.string(), "--rig", (rig / "rig.json").string(), "--frames",
                           (rig / "frames.json").string(), "--out", (dir_ / "data").string(), "--spp", "1"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + empty.string() + ": the scene holds no triangles: every view will be empty sky"),
            std::string::npos)
      << r.err;
}

// --overlap with --scene solves for the figure render reports (overlap.json, the smaller of the
// two directions) and make-rig prints what it achieved; render measures the same within 3 points.
TEST_F(WarningsCli, MakeRigOverlapIsWhatRenderReports) {
  const std::string plaza = std::string(RIGSIM_SOURCE_DIR) + "/assets/scenes/plaza.glb";
  const fs::path rig = dir_ / "rig";
  const CliResult made = Run({"make-rig", "ring", "--cameras", "3", "--overlap", "20", "--width", "320", "--height", "180",
                              "--scene", plaza, "--out", rig.string()});
  ASSERT_EQ(made.code, 0) << made.err;
  EXPECT_NE(made.out.find("the smaller of the two directions"), std::string::npos) << made.out;
  const std::map<std::string, double> printed = PrintedOverlaps(made.out);
  ASSERT_EQ(printed.size(), 2u) << made.out;  // cam0-cam1, cam1-cam2: cam0-cam2 shares nothing
  for (const auto& [pair, percent] : printed) EXPECT_NEAR(percent, 20.0, 2.0) << pair;

  const CliResult rendered = Run({"render", "--scene", plaza, "--rig", (rig / "rig.json").string(), "--frames",
                                  (rig / "frames.json").string(), "--out", (dir_ / "data").string(), "--spp", "1"});
  ASSERT_EQ(rendered.code, 0) << rendered.err;
  const json overlap = json::parse(ReadFile(dir_ / "data" / "overlap.json"));
  int neighbours = 0;
  for (const json& p : overlap["pairs"]) {
    const std::string pair = p["a"].get<std::string>() + "-" + p["b"].get<std::string>();
    if (!printed.count(pair)) continue;
    ++neighbours;
    const double truth = 100 * std::min(p["overlap_a_in_b"].get<double>(), p["overlap_b_in_a"].get<double>());
    EXPECT_NEAR(truth, 20.0, 3.0) << pair;
    EXPECT_NEAR(truth, printed.at(pair), 2.0) << pair;
  }
  EXPECT_EQ(neighbours, 2);
}

// Without a scene the figure is the angular one, and make-rig says so.
TEST_F(WarningsCli, MakeRigWithoutASceneSaysItsOverlapIsTheAngularOne) {
  const CliResult r = Run({"make-rig", "ring", "--cameras", "3", "--overlap", "30", "--out", (dir_ / "rig").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("angular overlap for points at infinity (the smaller of the two directions"), std::string::npos) << r.out;
  const std::map<std::string, double> printed = PrintedOverlaps(r.out);
  ASSERT_EQ(printed.size(), 2u) << r.out;
  double mean = 0;
  for (const auto& [pair, percent] : printed) mean += percent / printed.size();
  EXPECT_NEAR(mean, 30.0, 0.5) << r.out;
}

}  // namespace
}  // namespace rigsim
