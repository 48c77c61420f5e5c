#include "gltf/label_rules.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <re2/re2.h>

#include "labels/cityscapes.h"

namespace rigsim {
namespace {

// Matches a bracket set starting at pattern[p] == '['; advances p past ']'. Returns nullopt when
// the set is not closed (then '[' is an ordinary character).
std::optional<bool> MatchSet(const std::string& pattern, size_t& p, char c) {
  size_t i = p + 1;
  bool negate = false;
  if (i < pattern.size() && (pattern[i] == '!' || pattern[i] == '^')) {
    negate = true;
    ++i;
  }
  bool found = false;
  bool first = true;
  for (; i < pattern.size() && (first || pattern[i] != ']'); ++i, first = false) {
    if (i + 2 < pattern.size() && pattern[i + 1] == '-' && pattern[i + 2] != ']') {
      if (pattern[i] <= c && c <= pattern[i + 2]) found = true;
      i += 2;
    } else if (pattern[i] == c) {
      found = true;
    }
  }
  if (i >= pattern.size()) return std::nullopt;
  p = i + 1;
  return found != negate;
}

bool GlobFrom(const std::string& pattern, size_t p, const std::string& name, size_t n) {
  while (p < pattern.size()) {
    const char pc = pattern[p];
    if (pc == '*') {
      while (p < pattern.size() && pattern[p] == '*') ++p;
      if (p == pattern.size()) return true;
      for (size_t k = n; k <= name.size(); ++k) {
        if (GlobFrom(pattern, p, name, k)) return true;
      }
      return false;
    }
    if (n >= name.size()) return false;
    if (pc == '?') {
      ++p;
      ++n;
      continue;
    }
    if (pc == '[') {
      size_t q = p;
      if (const std::optional<bool> m = MatchSet(pattern, q, name[n])) {
        if (!*m) return false;
        p = q;
        ++n;
        continue;
      }
    }
    if (pc != name[n]) return false;
    ++p;
    ++n;
  }
  return n == name.size();
}

}  // namespace

bool GlobMatch(const std::string& pattern, const std::string& name) { return GlobFrom(pattern, 0, name, 0); }

LabelRules LabelRules::FromJsonText(const std::string& text, const std::string& source) {
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // also out_of_range: "1e999" (found by fuzzing)
    throw std::runtime_error(source + ": invalid JSON: " + e.what());
  }
  if (!root.is_object() || !root.contains("rules") || !root["rules"].is_array()) {
    throw std::runtime_error(source + ": expected an object with a 'rules' array");
  }
  LabelRules out;
  out.source_ = source;
  const nlohmann::json& rules = root["rules"];
  for (size_t i = 0; i < rules.size(); ++i) {
    const nlohmann::json& r = rules[i];
    const std::string where = source + ": rules[" + std::to_string(i) + "]: ";
    if (!r.is_object()) throw std::runtime_error(where + "expected an object");
    for (const auto& [key, value] : r.items()) {
      if (key != "match" && key != "glob" && key != "regex" && key != "class") {
        throw std::runtime_error(where + "unknown field '" + key + "' (expected match, glob or regex, class)");
      }
    }
    LabelRule rule;
    if (!r.contains("match") || !r["match"].is_string()) throw std::runtime_error(where + "'match' must be \"node\", \"mesh\" or \"material\"");
    const std::string match = r["match"].get<std::string>();
    if (match == "node") rule.target = LabelRuleTarget::kNode;
    else if (match == "mesh") rule.target = LabelRuleTarget::kMesh;
    else if (match == "material") rule.target = LabelRuleTarget::kMaterial;
    else throw std::runtime_error(where + "'match' is '" + match + "'; expected \"node\", \"mesh\" or \"material\"");
    const bool has_glob = r.contains("glob"), has_regex = r.contains("regex");
    if (has_glob == has_regex) throw std::runtime_error(where + "needs exactly one of 'glob' and 'regex'");
    const nlohmann::json& pat = has_glob ? r["glob"] : r["regex"];
    if (!pat.is_string()) throw std::runtime_error(where + "'" + std::string(has_glob ? "glob" : "regex") + "' must be a string");
    rule.pattern = pat.get<std::string>();
    rule.is_regex = has_regex;
    if (!r.contains("class") || !r["class"].is_string()) throw std::runtime_error(where + "'class' must be a Cityscapes class name");
    const std::string cls = r["class"].get<std::string>();
    const LabelClass* c = FindClassByName(cls);
    if (!c) throw std::runtime_error(where + "unknown class '" + cls + "'" + ClassNameSuggestion(cls) + "; the classes are Cityscapes'");
    rule.class_id = c->id;
    std::shared_ptr<const re2::RE2> re;
    if (rule.is_regex) {
      re2::RE2::Options options;
      options.set_log_errors(false);  // the error goes into our message instead
      re = std::make_shared<const re2::RE2>(rule.pattern, options);
      if (!re->ok()) throw std::runtime_error(where + "bad regex '" + rule.pattern + "': " + re->error());
    }
    out.rules_.push_back(std::move(rule));
    out.regexes_.push_back(std::move(re));
  }
  return out;
}

LabelRules LabelRules::Read(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open label rules file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return FromJsonText(ss.str(), path.string());
}

bool LabelRules::Matches(size_t i, const std::string& name) const {
  if (name.empty()) return false;
  return rules_[i].is_regex ? re2::RE2::PartialMatch(name, *regexes_[i]) : GlobMatch(rules_[i].pattern, name);
}

std::optional<size_t> LabelRules::Match(const Names& names) const {
  for (size_t i = 0; i < rules_.size(); ++i) {
    switch (rules_[i].target) {
      case LabelRuleTarget::kNode:
        for (const std::string& n : names.node_path) {
          if (Matches(i, n)) return i;
        }
        break;
      case LabelRuleTarget::kMesh:
        if (Matches(i, names.mesh)) return i;
        break;
      case LabelRuleTarget::kMaterial:
        if (Matches(i, names.material)) return i;
        break;
    }
  }
  return std::nullopt;
}

std::optional<uint8_t> LabelRules::Classify(const Names& names) const {
  if (const std::optional<size_t> i = Match(names)) return rules_[*i].class_id;
  return std::nullopt;
}

}  // namespace rigsim
