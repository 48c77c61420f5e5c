#include <string>

#include "gltf/label_rules.h"
#include "gltf/loader.h"
#include "labels/cityscapes.h"

namespace rigsim::gltf {

ClassTag Loader::ParseClass(const tinygltf::Value& extras, const std::string& owner) {
  if (!extras.IsObject() || !extras.Has("class")) return std::nullopt;
  const tinygltf::Value& v = extras.Get("class");
  if (!v.IsString()) {
    Warn(owner + ": extras.class is not a string; treated as unlabeled");
    return kUnlabeledId;
  }
  const std::string& name = v.Get<std::string>();
  if (const LabelClass* c = FindClassByName(name)) return c->id;
  Warn(owner + ": unknown class " + Quote(name) + "; treated as unlabeled");
  return kUnlabeledId;
}

void Loader::ParseClasses() {
  for (size_t i = 0; i < model_.nodes.size(); ++i) {
    node_class_.push_back(ParseClass(model_.nodes[i].extras, "node " + std::to_string(i) + " " + Quote(model_.nodes[i].name)));
  }
  for (size_t i = 0; i < model_.meshes.size(); ++i) {
    mesh_class_.push_back(ParseClass(model_.meshes[i].extras, "mesh " + std::to_string(i) + " " + Quote(model_.meshes[i].name)));
  }
  for (size_t i = 0; i < model_.materials.size(); ++i) {
    material_class_.push_back(
        ParseClass(model_.materials[i].extras, "material " + std::to_string(i) + " " + Quote(model_.materials[i].name)));
  }
}

// The class the label rules give a primitive (node names: the node, then its ancestors).
ClassTag Loader::ClassFromLabelRules(int node_index, int mesh_index, int material_index) {
  if (rule_parent_.empty()) {
    rule_parent_.assign(model_.nodes.size(), -1);
    for (size_t i = 0; i < model_.nodes.size(); ++i) {
      for (int c : model_.nodes[i].children) {
        if (c >= 0 && size_t(c) < rule_parent_.size()) rule_parent_[c] = int(i);
      }
    }
  }
  LabelRules::Names names;
  for (int n = node_index, depth = 0; n >= 0 && depth <= int(model_.nodes.size()); n = rule_parent_[n], ++depth) {
    names.node_path.push_back(model_.nodes[n].name);
  }
  names.mesh = model_.meshes[mesh_index].name;
  if (material_index >= 0) names.material = model_.materials[material_index].name;
  return options_.label_rules->Classify(names);
}

}  // namespace rigsim::gltf
