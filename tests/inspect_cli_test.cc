// `rigsim inspect` through the built binary: what the loader understood of a file (counts, vertex
// colours, unlit and emissive materials, classes, morph targets, GPU instances, compressed meshes,
// warnings), and a clear error naming a file it cannot read.

#include <cstring>
#include <filesystem>
#include <fstream>
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

// One triangle of class `building` with COLOR_0 and an unlit material, and one unclassified
// triangle with a TEXCOORD_1 nothing samples.
fs::path WriteTwoTriangles(const fs::path& dir) {
  GltfBuilder g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int colour = g.Floats({1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1}, "VEC4");
  const int uv1 = g.Floats({0, 0, 1, 0, 0, 1}, "VEC2");
  g.doc["materials"] = json::array({{{"extensions", {{"KHR_materials_unlit", json::object()}}}, {"emissiveFactor", {1, 0.5, 0}}}});
  const int coloured = g.Mesh({{"POSITION", pos}, {"COLOR_0", colour}}, -1, 4, 0);
  g.Node({{"name", "house"}, {"mesh", coloured}, {"extras", {{"class", "building"}}}});
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}, {"TEXCOORD_1", uv1}})}});
  g.Scene({0, 1});
  return g.WriteEmbedded(dir, "two");
}

TEST(InspectCli, ReportsWhatTheLoaderUnderstood) {
  const TempDir dir;
  const CliResult r = RunRigsim({"inspect", WriteTwoTriangles(dir).string()}, dir / "rigsim");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("primitives  2 (1 with vertex colours)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("triangles   2"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("materials   1 (1 OPAQUE, 1 emissive, 1 unlit)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("building"), std::string::npos) << r.out;
  // The unsupported attribute and the unclassified triangle are named.
  EXPECT_NE((r.out + r.err).find("TEXCOORD_1"), std::string::npos) << r.out << r.err;
  EXPECT_NE((r.out + r.err).find("1 triangles in 1 primitive(s) have no class"), std::string::npos) << r.out << r.err;
}

// The fuzz seed with morph targets: one mesh on two nodes, one of them with animated weights.
TEST(InspectCli, ReportsMorphTargetsAndWeightChannels) {
  const TempDir dir;
  const fs::path seed = fs::path(RIGSIM_SOURCE_DIR) / "tests/fuzz_corpus/fuzz_gltf/morphed_quad.gltf";
  const CliResult r = RunRigsim({"inspect", seed.string()}, dir / "rigsim");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("morphs      2 primitives with morph targets, 2 targets in all, 1 with animated weights"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("animations  1 channel (1 of morph weights) on 1 node, keys from 0.00 s to 1.00 s"), std::string::npos)
      << r.out;
  // mesh.weights (0.5) lift the first quad to z 0.25..0.5, node.weights (1) the second to 0.5..1.
  EXPECT_NE(r.out.find("z [0.25, 1.00]"), std::string::npos) << r.out;
  EXPECT_EQ((r.out + r.err).find("morph targets ("), std::string::npos) << "no longer warned as unsupported: " << r.out;
}

// The fuzz seeds with a normal map and with an occlusion map: both are counted, neither warned.
TEST(InspectCli, ReportsNormalAndOcclusionMaps) {
  const TempDir dir;
  const fs::path seeds = fs::path(RIGSIM_SOURCE_DIR) / "tests/fuzz_corpus/fuzz_gltf";
  const CliResult normal = RunRigsim({"inspect", (seeds / "normal_mapped_quad.gltf").string()}, dir / "rigsim_normal");
  ASSERT_EQ(normal.code, 0) << normal.err;
  EXPECT_NE(normal.out.find("materials   1 (1 OPAQUE, 1 normal-mapped)"), std::string::npos) << normal.out;
  const CliResult occluded = RunRigsim({"inspect", (seeds / "occluded_quad.gltf").string()}, dir / "rigsim_occluded");
  ASSERT_EQ(occluded.code, 0) << occluded.err;
  EXPECT_NE(occluded.out.find("materials   1 (1 OPAQUE, 1 with occlusion)"), std::string::npos) << occluded.out;
  EXPECT_EQ((occluded.out + occluded.err).find("occlusionTexture"), std::string::npos) << "no longer warned: " << occluded.out;
}

// The fuzz seed with EXT_mesh_gpu_instancing (required): a house node and a node of three tree
// instances (float translation and scale, normalized-short rotation, one mirrored, an _ID
// attribute), whose node is animated. Every instance is counted, and so is its node.
TEST(InspectCli, ReportsGpuInstances) {
  const TempDir dir;
  const fs::path seed = fs::path(RIGSIM_SOURCE_DIR) / "tests/fuzz_corpus/fuzz_gltf/instanced_quad.gltf";
  const CliResult r = RunRigsim({"inspect", seed.string()}, dir / "rigsim");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("nodes       2 with geometry (4 instances, 3 of them from 1 node via EXT_mesh_gpu_instancing)"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("triangles   8"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("x [0.00, 4.00]  y [0.00, 1.00]  z [-3.00, 2.00]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("vegetation       no                 3          3          6"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("EXT_mesh_gpu_instancing attribute _ID"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("extension EXT_mesh_gpu_instancing"), std::string::npos) << "no longer warned as unsupported: " << r.out;
}

// The fuzz seeds compressed with Draco (one primitive) and meshopt (four buffer views), and one
// compressed with neither.
TEST(InspectCli, ReportsCompressedMeshes) {
  const TempDir dir;
  const fs::path seeds = fs::path(RIGSIM_SOURCE_DIR) / "tests/fuzz_corpus/fuzz_gltf";
  const CliResult draco = RunRigsim({"inspect", (seeds / "draco_grid.glb").string()}, dir / "rigsim_draco");
  ASSERT_EQ(draco.code, 0) << draco.err;
  EXPECT_NE(draco.out.find("compressed  1 primitive by KHR_draco_mesh_compression\n"), std::string::npos) << draco.out;
  EXPECT_NE(draco.out.find("triangles   32"), std::string::npos) << draco.out;
  const CliResult meshopt = RunRigsim({"inspect", (seeds / "meshopt_grid.gltf").string()}, dir / "rigsim_meshopt");
  ASSERT_EQ(meshopt.code, 0) << meshopt.err;
  EXPECT_NE(meshopt.out.find("compressed  4 buffer views by EXT_meshopt_compression\n"), std::string::npos) << meshopt.out;
  EXPECT_NE(meshopt.out.find("triangles   36"), std::string::npos) << meshopt.out;  // two primitives of a 4 x 4 grid
  const CliResult plain = RunRigsim({"inspect", (seeds / "triangle.gltf").string()}, dir / "rigsim_plain");
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_NE(plain.out.find("compressed  none"), std::string::npos) << plain.out;
}

TEST(InspectCli, AnUnreadableFileIsAnErrorNamingIt) {
  const TempDir dir;
  const fs::path bad = dir / "broken.gltf";
  WriteFile(bad, "{ \"asset\": { \"version\": \"2.0\" }, \"meshes\": [");
  const CliResult r = RunRigsim({"inspect", bad.string()}, dir / "rigsim");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find(bad.string()), std::string::npos) << r.err;
  const CliResult missing = RunRigsim({"inspect", (dir / "missing.glb").string()}, dir / "rigsim_missing");
  EXPECT_NE(missing.code, 0);
  EXPECT_NE(missing.err.find("missing.glb"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace rigsim
