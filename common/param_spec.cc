#include "common/param_spec.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstdio>
#include <stdexcept>

#include "common/did_you_mean.h"

namespace rigsim {

using Json = nlohmann::ordered_json;

namespace {

[[noreturn]] void Refuse(const std::string& why) { throw std::invalid_argument(why); }

std::string Number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string Range(const ParamSpec& spec) { return Number(spec.min) + " to " + Number(spec.max); }

}  // namespace

Json CheckParamValue(const ParamSpec& spec, const Json& v) {
  using K = ParamSpec::Kind;
  if (v.is_null()) {
    if (!spec.default_value.is_null()) Refuse("'" + spec.name + "' cannot be unset (null)");
    return nullptr;
  }
  switch (spec.kind) {
    case K::kInt: {
      if (!v.is_number_integer()) Refuse("must be a whole number, got " + v.dump());
      const double x = v.get<double>();
      if (x < spec.min || x > spec.max) Refuse(FormatParamValue(v) + " is outside " + Range(spec));
      return v.get<int64_t>();
    }
    case K::kNumber: {
      if (!v.is_number()) Refuse("must be a number, got " + v.dump());
      const double x = v.get<double>();
      if (!std::isfinite(x) || x < spec.min || x > spec.max) Refuse(FormatParamValue(v) + " is outside " + Range(spec));
      return x;
    }
    case K::kBool:
      if (!v.is_boolean()) Refuse("must be true or false, got " + v.dump());
      return v;
    case K::kChoice: {
      if (!v.is_string()) Refuse("must be one of " + JoinNames(spec.choices) + ", got " + v.dump());
      const std::string s = v.get<std::string>();
      for (const std::string& c : spec.choices) {
        if (c == s) return v;
      }
      Refuse("'" + s + "' is not one of " + JoinNames(spec.choices) + DidYouMean(s, spec.choices));
    }
    case K::kText:
      if (!v.is_string() || v.get<std::string>().empty()) Refuse("must be a non-empty text");
      return v;
  }
  return v;
}

Json ParamValueFromText(const ParamSpec& spec, const std::string& text) {
  using K = ParamSpec::Kind;
  switch (spec.kind) {
    case K::kInt: {
      char* end = nullptr;
      errno = 0;
      const long long x = std::strtoll(text.c_str(), &end, 10);
      if (text.empty() || *end != '\0' || errno == ERANGE) Refuse("'" + text + "' is not a whole number");
      return CheckParamValue(spec, int64_t(x));
    }
    case K::kNumber: {
      char* end = nullptr;
      const double x = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0') Refuse("'" + text + "' is not a number");
      return CheckParamValue(spec, x);
    }
    case K::kBool:
      if (text != "true" && text != "false") Refuse("give true or false (got '" + text + "')");
      return CheckParamValue(spec, text == "true");
    case K::kChoice:
    case K::kText:
      return CheckParamValue(spec, text);
  }
  return nullptr;
}

std::string FormatParamValue(const Json& v) {
  if (v.is_null()) return "unset";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) return Number(v.get<double>());
  return v.dump();
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  return list;
}

}  // namespace rigsim
