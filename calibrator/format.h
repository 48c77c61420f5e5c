// Numbers in the calibrator's messages.
#pragma once

#include <cstdio>
#include <string>

namespace rigsim {

// `v` with `digits` digits after the point ("%.*f").
inline std::string Fixed(double v, int digits) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", digits, v);
  return text;
}

}  // namespace rigsim
