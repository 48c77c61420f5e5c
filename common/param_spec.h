// A described parameter: its name, type, default, allowed values and help, from which a command
// line option, a config file's key and a listing of parameters are all made, and its one check.
// The rig's parameters (rigs/rig_params.h) and a sweep's cell parameters (sweep/sweep_config.h)
// are lists of these.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rigsim {

struct ParamSpec {
  enum class Kind { kInt, kNumber, kBool, kChoice, kText };
  std::string name;
  Kind kind = Kind::kNumber;
  nlohmann::ordered_json default_value;  // null: "not set" (e.g. overlap: use spacing)
  std::vector<std::string> choices;      // kChoice
  double min = 0.0, max = 0.0;           // kInt, kNumber: the allowed range, both ends included
  std::string help;
};

// `value` checked against `spec` and normalised (numbers as doubles, so 30 and 30.0 are one
// value; whole numbers as integers). Null passes when the default is null too. Throws
// std::invalid_argument with the problem in the user's words, without the parameter's name
// ("200 is outside 1 to 95", "'rign' is not one of ring, stereo (did you mean 'ring'?)").
nlohmann::ordered_json CheckParamValue(const ParamSpec& spec, const nlohmann::ordered_json& value);

// The value of command line text for `spec` (a whole number, a number, true/false, or the text),
// checked by CheckParamValue. Throws std::invalid_argument as it does.
nlohmann::ordered_json ParamValueFromText(const ParamSpec& spec, const std::string& text);

// A parameter value for people: text as it is, numbers without trailing zeros ("30", "0.5"),
// null as "unset".
std::string FormatParamValue(const nlohmann::ordered_json& value);

// "a, b, c".
std::string JoinNames(const std::vector<std::string>& names);

// The names of every value of an enum, in order: NamesOf(kAllSemanticModes, SemanticModeName).
template <class Values, class NameOf>
std::vector<std::string> NamesOf(const Values& all, NameOf name_of) {
  std::vector<std::string> names;
  for (const auto& v : all) names.emplace_back(name_of(v));
  return names;
}

}  // namespace rigsim
