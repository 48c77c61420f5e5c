// The random numbers of the rig generators (mounting errors, placement candidates): splitmix64,
// our own generator, so that a seed gives the same rigs whatever the standard library.
#pragma once

#include <cstdint>

namespace rigsim {

class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  uint64_t Next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double Uniform() { return double(Next() >> 11) * (1.0 / 9007199254740992.0); }
  double Uniform(double a, double b) { return a + (b - a) * Uniform(); }

 private:
  uint64_t state_;
};

}  // namespace rigsim
