#include "gltf/gltf_loader.h"

#include <map>
#include <string>

#include <gtest/gtest.h>

#include "gltf/gltf_test_support.h"
#include "labels/cityscapes.h"

namespace rigsim::gltf_test {
namespace {

TEST(GltfLoader, ClassesInheritAndOverride) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  g.doc["materials"] = json::array({{{"name", "plain"}}, {{"name", "labelled"}, {"extras", {{"class", "vegetation"}}}}});
  const int plain = g.Mesh({{"POSITION", pos}}, -1, 4, 0);
  const int mesh_car = g.Mesh({{"POSITION", pos}}, -1, 4, 0, {{"class", "car"}});
  const int mesh_car_mat_veg = g.Mesh({{"POSITION", pos}}, -1, 4, 1, {{"class", "car"}});
  const int unknown = g.Mesh({{"POSITION", pos}}, -1, 4, 0, {{"class", "spaceship"}});
  g.Node({{"name", "root"}, {"extras", {{"class", "building"}}}, {"mesh", plain}, {"children", {1, 2, 3}}});  // 0
  g.Node({{"name", "inherits"}, {"children", {4}}});                                                       // 1
  g.Node({{"name", "mesh_wins"}, {"mesh", mesh_car}});                                                     // 2
  g.Node({{"name", "material_wins"}, {"extras", {{"class", "road"}}}, {"mesh", mesh_car_mat_veg}});        // 3
  g.Node({{"name", "grandchild"}, {"mesh", plain}});                                                       // 4
  g.Node({{"name", "unlabeled"}, {"mesh", plain}});                                                        // 5
  g.Node({{"name", "unknown"}, {"mesh", unknown}});                                                        // 6
  g.Scene({0, 5, 6});
  const Scene s = LoadGltf(g.Write(dir, "classes"));
  ASSERT_EQ(s.meshes.size(), 6u);
  // Depth-first order: root, mesh_wins, material_wins... children of root come in order 1 (no mesh) -> 4.
  std::map<std::string, const SceneMesh*> by_name;
  for (const SceneMesh& m : s.meshes) by_name[m.name] = &m;
  EXPECT_EQ(by_name.at("root")->class_id, FindClassByName("building")->id);
  EXPECT_EQ(by_name.at("grandchild")->class_id, FindClassByName("building")->id);
  EXPECT_EQ(by_name.at("mesh_wins")->class_id, FindClassByName("car")->id);
  EXPECT_EQ(by_name.at("material_wins")->class_id, FindClassByName("vegetation")->id);
  EXPECT_EQ(by_name.at("unlabeled")->class_id, kUnlabeledId);
  EXPECT_EQ(by_name.at("unknown")->class_id, kUnlabeledId);
  EXPECT_TRUE(HasWarning(s, "unknown class 'spaceship'"));
  // One summary warning for geometry without any class: only the node "unlabeled" (1 triangle).
  int summaries = 0;
  for (const std::string& w : s.warnings) summaries += w.find("have no class") != std::string::npos;
  EXPECT_EQ(summaries, 1);
  EXPECT_TRUE(HasWarning(s, "1 triangles in 1 primitive(s) have no class"));
}

}  // namespace
}  // namespace rigsim::gltf_test
