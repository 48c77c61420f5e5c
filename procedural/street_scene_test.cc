#include "procedural/street_scene.h"

#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "gltf/gltf_loader.h"
#include "labels/cityscapes.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

// Tests run from the repository root.
const std::filesystem::path kAsset = "assets/scenes/street.glb";

TEST(StreetScene, ShippedAssetLoadsWithEveryClass) {
  ASSERT_TRUE(std::filesystem::exists(kAsset)) << "run from the repository root";
  const Scene s = LoadGltf(kAsset);
  std::set<uint8_t> classes;
  std::set<uint16_t> instances;
  for (const SceneMesh& m : s.meshes) {
    classes.insert(m.class_id);
    instances.insert(m.instance_id);
    EXPECT_NE(m.class_id, kUnlabeledId) << m.name;
    EXPECT_FALSE(m.texcoords.empty()) << m.name;
    EXPECT_GE(m.material, 0) << m.name;
  }
  for (const char* name : {"road", "sidewalk", "building", "wall", "fence", "pole", "traffic sign", "car", "person", "vegetation"}) {
    EXPECT_TRUE(classes.count(FindClassByName(name)->id)) << name;
  }
  EXPECT_FALSE(classes.count(kSkyId));  // rays that miss are sky
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  EXPECT_GT(instances.size(), 50u);
  EXPECT_LT(std::filesystem::file_size(kAsset), 16u * 1024 * 1024);
}

TEST(StreetScene, SurroundsTheOrigin) {
  const Scene s = LoadGltf(kAsset);
  // Structure on both sides (x) and at both ends (z) of the street, nothing at the rig position.
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9f), hi = -lo;
  for (const SceneMesh& m : s.meshes) {
    for (const Eigen::Vector3f& p : m.positions) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  EXPECT_LE(lo.x(), -9.f);
  EXPECT_GE(hi.x(), 9.f);
  EXPECT_LE(lo.z(), -60.f);
  EXPECT_GE(hi.z(), 60.f);
  EXPECT_NEAR(lo.y(), 0.f, 1e-4f);
  EXPECT_GT(hi.y(), 8.f);
}

TEST(StreetScene, ShippedAssetMatchesTheCode) {
  const TempDir dir;
  WriteStreetScene(dir / "street.glb", 1);
  const std::string fresh = ReadFile(dir / "street.glb");
  EXPECT_EQ(fresh.size(), std::filesystem::file_size(kAsset));
  EXPECT_TRUE(fresh == ReadFile(kAsset))
      << "assets/scenes/street.glb is out of date: regenerate it with rigsim_make_street_scene assets/scenes/street.glb 1";
}

TEST(StreetScene, SeedChangesTheScene) {
  EXPECT_NE(StreetSceneGlb(1), StreetSceneGlb(2));
}

}  // namespace
}  // namespace rigsim
