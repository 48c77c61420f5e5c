// A hash of text that is the same on every machine and every run (FNV-1a, 64 bit), for names and
// identities written into files: a sweep's cells, the shards of one render.
#pragma once

#include <string>

namespace rigsim {

// 16 lowercase hex digits.
std::string StableHash(const std::string& text);

}  // namespace rigsim
