#include "common/stable_hash.h"

#include <cinttypes>
#include <cstdint>
#include <cstdio>

namespace rigsim {

std::string StableHash(const std::string& text) {
  uint64_t h = 14695981039346656037ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, h);
  return buf;
}

}  // namespace rigsim
