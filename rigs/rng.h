// The random numbers of the rig generators (mounting errors, placement candidates): splitmix64,
// our own generator, so that a seed gives the same rigs whatever the standard library.
#pragma once

#include <cstdint>

#include "common/splitmix64.h"

namespace rigsim {

class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  uint64_t Next() {
    const uint64_t x = state_;
    state_ += kSplitMix64Increment;
    return SplitMix64(x);
  }
  double Uniform() { return double(Next() >> 11) * (1.0 / 9007199254740992.0); }
  double Uniform(double a, double b) { return a + (b - a) * Uniform(); }

 private:
  uint64_t state_;
};

}  // namespace rigsim
