#include <optional>
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
  Warn(owner + ": unknown class " + Quote(name) + ClassNameSuggestion(name) + "; treated as unlabeled");
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
  const LabelRules& rules = *options_.label_rules;
  rule_uses_.resize(rules.rules().size(), 0);
  ++rule_lookups_;
  const std::optional<size_t> rule = rules.Match(names);
  if (!rule) return std::nullopt;
  ++rule_uses_[*rule];
  return rules.rules()[*rule].class_id;
}

// A rule that labels nothing is most likely a misspelt name: each is named, once per load.
void Loader::ReportUnusedLabelRules() {
  if (options_.label_rules == nullptr || options_.label_rules->rules().empty()) return;
  const LabelRules& rules = *options_.label_rules;
  if (rule_lookups_ == 0) {
    Warn(rules.source() + ": no rule used: every primitive has a class from extras.class, which wins over the rules");
    return;
  }
  rule_uses_.resize(rules.rules().size(), 0);
  std::string unused;
  size_t count = 0;
  for (size_t i = 0; i < rules.rules().size(); ++i) {
    if (rule_uses_[i] > 0) continue;
    if (++count <= 5) {
      const LabelRule& r = rules.rules()[i];
      const char* target = r.target == LabelRuleTarget::kNode ? "node" : r.target == LabelRuleTarget::kMesh ? "mesh" : "material";
      unused += (unused.empty() ? "" : ", ") + std::string("rules[") + std::to_string(i) + "] (" + target + " " +
                (r.is_regex ? "regex" : "glob") + " '" + r.pattern + "')";
    }
  }
  if (count == 0) return;
  if (count > 5) unused += " and " + std::to_string(count - 5) + " more";
  Warn(rules.source() + ": " + std::to_string(count) + " of " + std::to_string(rules.rules().size()) +
       " rules labelled nothing (no name in the scene matches them, or an earlier rule matched first): " + unused);
}

}  // namespace rigsim::gltf
