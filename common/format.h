// Numbers in messages: counts with their nouns, fixed digits and standard deviations.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace rigsim {

// `v` with `digits` digits after the point ("%.*f").
inline std::string Fixed(double v, int digits) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", digits, v);
  return text;
}

// " +- s" with `digits` digits after the point, or "" when `s` is unknown (not finite) or rounds
// to zero there: "+- 0.0" says nothing of how well a value is known.
inline std::string PlusMinus(double s, int digits) {
  if (!std::isfinite(s) || std::abs(s) < 0.5 * std::pow(10.0, -digits)) return "";
  return " +- " + Fixed(s, digits);
}

// `n` and its noun, singular for one: Count(1, "frame") is "1 frame", Count(4, "frame") "4 frames";
// `plural` for a noun whose plural is not the singular and "s" ("1 match", "2 matches").
inline std::string Count(long long n, const std::string& singular, const std::string& plural = "") {
  return std::to_string(n) + " " + (n == 1 ? singular : plural.empty() ? singular + "s" : plural);
}

}  // namespace rigsim
