#include "gltf/gltf_loader.h"

#include <map>
#include <string>

#include <gtest/gtest.h>

#include "gltf/gltf_test_support.h"
#include "gltf/label_rules.h"
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
  const int misspelt = g.Mesh({{"POSITION", pos}}, -1, 4, 0, {{"class", "biulding"}});
  g.Node({{"name", "root"}, {"extras", {{"class", "building"}}}, {"mesh", plain}, {"children", {1, 2, 3}}});  // 0
  g.Node({{"name", "inherits"}, {"children", {4}}});                                                       // 1
  g.Node({{"name", "mesh_wins"}, {"mesh", mesh_car}});                                                     // 2
  g.Node({{"name", "material_wins"}, {"extras", {{"class", "road"}}}, {"mesh", mesh_car_mat_veg}});        // 3
  g.Node({{"name", "grandchild"}, {"mesh", plain}});                                                       // 4
  g.Node({{"name", "unlabeled"}, {"mesh", plain}});                                                        // 5
  g.Node({{"name", "unknown"}, {"mesh", unknown}});                                                        // 6
  g.Node({{"name", "misspelt"}, {"mesh", misspelt}});                                                      // 7
  g.Scene({0, 5, 6, 7});
  const Scene s = LoadGltf(g.Write(dir, "classes"));
  ASSERT_EQ(s.meshes.size(), 7u);
  // Depth-first order: root, mesh_wins, material_wins... children of root come in order 1 (no mesh) -> 4.
  std::map<std::string, const SceneMesh*> by_name;
  for (const SceneMesh& m : s.meshes) by_name[m.name] = &m;
  EXPECT_EQ(by_name.at("root")->class_id, FindClassByName("building")->id);
  EXPECT_EQ(by_name.at("grandchild")->class_id, FindClassByName("building")->id);
  EXPECT_EQ(by_name.at("mesh_wins")->class_id, FindClassByName("car")->id);
  EXPECT_EQ(by_name.at("material_wins")->class_id, FindClassByName("vegetation")->id);
  EXPECT_EQ(by_name.at("unlabeled")->class_id, kUnlabeledId);
  EXPECT_EQ(by_name.at("unknown")->class_id, kUnlabeledId);
  EXPECT_TRUE(HasWarning(s, "unknown class 'spaceship'; treated as unlabeled"));
  EXPECT_TRUE(HasWarning(s, "unknown class 'biulding' (did you mean 'building'?); treated as unlabeled"));
  // One summary warning for geometry without any class: only the node "unlabeled" (1 triangle).
  int summaries = 0;
  for (const std::string& w : s.warnings) summaries += w.find("have no class") != std::string::npos;
  EXPECT_EQ(summaries, 1);
  EXPECT_TRUE(HasWarning(s, "1 triangles in 1 primitive(s) have no class"));
}

TEST(GltfLoader, ALabelRuleThatLabelsNothingIsNamed) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int mesh = g.Mesh({{"POSITION", pos}}, -1, 4);
  g.Node({{"name", "Car_1"}, {"mesh", mesh}});
  g.Node({{"name", "Tree"}, {"mesh", mesh}});
  g.Scene({0, 1});
  const std::filesystem::path path = g.Write(dir, "rules");
  const LabelRules rules = LabelRules::FromJsonText(R"({"rules": [
      {"match": "node", "glob": "Car*", "class": "car"},
      {"match": "node", "glob": "Lamp*", "class": "pole"},
      {"match": "node", "regex": "Car", "class": "truck"},
      {"match": "node", "regex": "[Tt]ree", "class": "vegetation"}]})", "rules.json");
  GltfLoadOptions options;
  options.label_rules = &rules;
  const Scene s = LoadGltf(path, options);
  EXPECT_TRUE(HasWarning(s, "rules.json: 2 of 4 rules labelled nothing (no name in the scene matches them, or an earlier "
                            "rule matched first): rules[1] (node glob 'Lamp*'), rules[2] (node regex 'Car')"));
  // Every rule used: no warning.
  const LabelRules used = LabelRules::FromJsonText(R"({"rules": [{"match": "node", "glob": "*", "class": "car"}]})", "all.json");
  options.label_rules = &used;
  EXPECT_FALSE(HasWarning(LoadGltf(path, options), "all.json"));
}

}  // namespace
}  // namespace rigsim::gltf_test
