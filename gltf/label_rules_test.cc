#include "gltf/label_rules.h"

#include <filesystem>
#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "gltf/gltf_loader.h"
#include "gltf/scene_builder.h"
#include "labels/cityscapes.h"
#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

uint8_t Id(const char* name) { return FindClassByName(name)->id; }

// A call that reads `text` as rules.json.
auto Parsing(const std::string& text) {
  return [text] { LabelRules::FromJsonText(text, "rules.json"); };
}

TEST(Glob, Wildcards) {
  EXPECT_TRUE(GlobMatch("Car*", "Car_01"));
  EXPECT_TRUE(GlobMatch("Car*", "Car"));
  EXPECT_FALSE(GlobMatch("Car*", "MyCar"));
  EXPECT_TRUE(GlobMatch("*car*", "my_car_2"));
  EXPECT_TRUE(GlobMatch("tree_??", "tree_12"));
  EXPECT_FALSE(GlobMatch("tree_??", "tree_1"));
  EXPECT_TRUE(GlobMatch("lamp[0-9]", "lamp7"));
  EXPECT_FALSE(GlobMatch("lamp[!0-9]", "lamp7"));
  EXPECT_TRUE(GlobMatch("lamp[!0-9]", "lampX"));
  EXPECT_FALSE(GlobMatch("car", "Car"));  // case-sensitive
  EXPECT_TRUE(GlobMatch("a[b", "a[b"));   // unclosed set: literal
  EXPECT_TRUE(GlobMatch("", ""));
}

TEST(LabelRules, FirstMatchWinsAcrossTargets) {
  const LabelRules rules = LabelRules::FromJsonText(R"({"rules": [
      {"match": "material", "regex": "^asphalt", "class": "road"},
      {"match": "node", "glob": "Car*", "class": "car"},
      {"match": "node", "glob": "*", "class": "building"},
      {"match": "mesh", "glob": "Tree*", "class": "vegetation"}]})", "rules.json");
  ASSERT_EQ(rules.rules().size(), 4u);
  EXPECT_EQ(rules.Classify({{"Car_3"}, "body", "asphalt_dark"}), Id("road"));  // rule 0 comes first
  EXPECT_EQ(rules.Classify({{"Car_3"}, "body", "paint"}), Id("car"));
  EXPECT_EQ(rules.Classify({{"wheel", "Car_3"}, "wheel", ""}), Id("car"));  // an ancestor's name
  EXPECT_EQ(rules.Classify({{"x"}, "Tree1", ""}), Id("building"));          // rule 2 shadows rule 3
  EXPECT_EQ(rules.Match({{""}, "Tree1", ""}), 3u);                          // empty names never match
  EXPECT_EQ(rules.Classify({{}, "", ""}), std::nullopt);
}

// Nested repetition on a name that almost matches: std::regex backtracked exponentially on such
// patterns (a fuzzed rules file hung it for more than 20 s on a 7-character name); RE2 answers at
// once, and correctly.
TEST(LabelRules, NestedRepetitionMatchesWithoutBacktracking) {
  const LabelRules rules = LabelRules::FromJsonText(
      R"({"rules": [{"match": "mesh", "regex": "^(a*)*b$", "class": "car"},
                    {"match": "mesh", "regex": "(x+x+)+y", "class": "road"}]})", "rules.json");
  LabelRules::Names names;
  names.mesh = std::string(64, 'a');
  EXPECT_FALSE(rules.Match(names).has_value());
  names.mesh += "b";
  EXPECT_EQ(rules.Match(names), 0u);
  names.mesh = std::string(64, 'x');
  EXPECT_FALSE(rules.Match(names).has_value());
  names.mesh += "y";
  EXPECT_EQ(rules.Match(names), 1u);
}

TEST(LabelRules, ShippedRulesFileReadsAndClassifies) {
  const LabelRules rules = LabelRules::Read("assets/rules/common_names.json");
  EXPECT_GT(rules.rules().size(), 10u);
  LabelRules::Names names;
  names.node_path = {"Car_01"};
  EXPECT_EQ(rules.Classify(names), FindClassByName("car")->id);
}

TEST(LabelRules, ErrorsNameFileAndRule) {
  using E = std::runtime_error;
  EXPECT_THAT(Parsing(R"({"rules": [{"match": "node", "glob": "a", "class": "car"},
                                    {"match": "node", "glob": "b", "class": "cars"}]})"),
              ThrowsWith<E>("rules.json: rules[1]: unknown class 'cars'"));
  EXPECT_THAT(Parsing(R"({"rules": [{"match": "mesh", "regex": "(unclosed", "class": "car"}]})"),
              ThrowsWith<E>("rules.json: rules[0]: bad regex '(unclosed'"));
  EXPECT_THAT(Parsing(R"({"rules": [{"match": "node", "glob": "a", "class": "car"},)"), ThrowsWith<E>("rules.json: invalid JSON"));
  EXPECT_THAT(Parsing(R"({"rules": [{"match": "scene", "glob": "a", "class": "car"}]})"),
              ThrowsWith<E>("rules[0]: 'match' is 'scene'"));
  EXPECT_THAT(Parsing(R"({"rules": [{"match": "node", "glob": "a", "regex": "a", "class": "car"}]})"),
              ThrowsWith<E>("exactly one of"));
  EXPECT_THAT(Parsing(R"({"rules": [{"match": "node", "glob": "a", "class": "car", "clas": "x"}]})"),
              ThrowsWith<E>("unknown field 'clas'"));
  EXPECT_THAT(Parsing(R"([1, 2])"), ThrowsWith<E>("'rules' array"));
  EXPECT_THAT([] { LabelRules::Read("/nonexistent/rules.json"); }, ThrowsWith<E>("/nonexistent/rules.json"));
}

MeshData Triangle() {
  MeshData m;
  m.positions = {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(1, 0, 0), Eigen::Vector3f(0, 1, 0)};
  m.indices = {0, 1, 2};
  return m;
}

TEST(LabelRules, LoaderUsesRulesOnlyWithoutExtras) {
  SceneBuilder b;
  const int asphalt = b.AddMaterial("asphalt", Eigen::Vector4f::Ones());
  const int paint = b.AddMaterial("paint", Eigen::Vector4f::Ones());
  b.AddNode("Car_1", "", Triangle(), paint);
  b.AddNode("Car_2", "person", Triangle(), paint);  // extras win over rules
  b.AddNode("ground", "", Triangle(), asphalt);
  b.AddNode("mystery", "", Triangle(), paint);
  const TempDir dir;
  b.WriteGlb(dir / "foreign.glb");
  const LabelRules rules = LabelRules::FromJsonText(R"({"rules": [
      {"match": "node", "glob": "Car*", "class": "car"},
      {"match": "material", "regex": "^asphalt$", "class": "road"}]})", "rules.json");
  GltfLoadOptions o;
  o.label_rules = &rules;
  const Scene s = LoadGltf(dir / "foreign.glb", o);
  ASSERT_EQ(s.meshes.size(), 4u);
  EXPECT_EQ(s.meshes[0].class_id, Id("car"));
  EXPECT_EQ(s.meshes[1].class_id, Id("person"));
  EXPECT_EQ(s.meshes[2].class_id, Id("road"));
  EXPECT_EQ(s.meshes[3].class_id, kUnlabeledId);
  int unlabeled_warnings = 0;
  for (const std::string& w : s.warnings) {
    if (w.find("unlabeled") != std::string::npos) {
      ++unlabeled_warnings;
      EXPECT_NE(w.find("1 triangles in 1 primitive(s)"), std::string::npos) << w;
    }
  }
  EXPECT_EQ(unlabeled_warnings, 1);
  // Without rules, three primitives are unlabeled.
  const Scene plain = LoadGltf(dir / "foreign.glb");
  EXPECT_EQ(plain.meshes[0].class_id, kUnlabeledId);
  EXPECT_EQ(plain.meshes[1].class_id, Id("person"));
}

}  // namespace
}  // namespace rigsim
