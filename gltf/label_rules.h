// Label rules: semantic classes for glTF files that carry no `extras.class`, decided from the
// names of nodes, meshes and materials.
//
// File format (JSON):
//   { "rules": [
//       { "match": "node",     "glob":  "Car*",          "class": "car" },
//       { "match": "material", "regex": "(?:asphalt|road)", "class": "road" },
//       { "match": "mesh",     "glob":  "tree_??",       "class": "vegetation" } ] }
//
//  - `match` says which name is tested: "node" (the node carrying the mesh, then each of its
//    ancestors, nearest first), "mesh" or "material" (of the primitive).
//  - `glob` matches the whole name: `*` any run of characters, `?` one character, `[abc]` /
//    `[a-z]` / `[!abc]` a character set; case-sensitive. `regex` is a regular expression in RE2's
//    syntax (Perl-like: classes, alternation, anchors, (?:...), repetition; no backreferences or
//    lookaround) searched anywhere in the name (anchor it with ^...$ to match the whole name).
//    RE2 matches in time linear in the name: a rules file cannot make loading hang, as
//    std::regex's backtracking did on nested repetitions.
//  - `class` is a Cityscapes class name (labels/cityscapes.h).
//  - Rules are tried in file order; the first that matches decides. The loader consults them only
//    for primitives without a class from extras (extras always win).
// Errors name the file and the rule index: "<file>: rules[2]: unknown class 'cars'".
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <memory>
#include <string>
#include <vector>

namespace re2 {
class RE2;
}

namespace rigsim {

enum class LabelRuleTarget { kNode, kMesh, kMaterial };

struct LabelRule {
  LabelRuleTarget target = LabelRuleTarget::kNode;
  std::string pattern;     // the glob or the regex as written
  bool is_regex = false;
  uint8_t class_id = 0;    // Cityscapes label id
};

class LabelRules {
 public:
  LabelRules() = default;
  // Parses rules; throws std::runtime_error("<source>: ...") naming the rule index on any problem.
  static LabelRules FromJsonText(const std::string& text, const std::string& source);
  static LabelRules Read(const std::filesystem::path& path);

  // The names a primitive is known by. node_path: the node carrying the mesh first, then its
  // ancestors up to the root; empty names never match.
  struct Names {
    std::vector<std::string> node_path;
    std::string mesh;
    std::string material;
  };
  // Index of the first rule that matches, if any.
  std::optional<size_t> Match(const Names& names) const;
  // Class id of the first matching rule, if any.
  std::optional<uint8_t> Classify(const Names& names) const;

  const std::vector<LabelRule>& rules() const { return rules_; }
  const std::string& source() const { return source_; }

 private:
  bool Matches(size_t i, const std::string& name) const;

  std::string source_;
  std::vector<LabelRule> rules_;
  std::vector<std::shared_ptr<const re2::RE2>> regexes_;  // one per rule (null for globs)
};

// Shell-style glob match of the whole `name` (see above). Exposed for tests and tools.
bool GlobMatch(const std::string& pattern, const std::string& name);

}  // namespace rigsim
