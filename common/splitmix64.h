// splitmix64's mixer (Steele, Lea and Flood 2014), the one 64-bit hash behind every seeded random
// number in rigsim (camera rays, photometric errors, procedural textures, rig generators,
// segmentation noise): our own, so that a seed gives the same bytes whatever the standard library.
#pragma once

#include <cstdint>

namespace rigsim {

// What splitmix64 adds to its state at every step (2^64 / golden ratio).
inline constexpr uint64_t kSplitMix64Increment = 0x9E3779B97F4A7C15ull;

// A well-mixed 64-bit hash of `x`: splitmix64's output for the state x + its increment.
constexpr uint64_t SplitMix64(uint64_t x) {
  x += kSplitMix64Increment;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

}  // namespace rigsim
