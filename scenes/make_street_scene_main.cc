// Writes the built-in street scene: rigsim_make_street_scene OUT.glb [SEED]
// The shipped asset is assets/scenes/street.glb with seed 1 (scenes_test checks it is up to date).
#include <cstdint>
#include <exception>
#include <iostream>
#include <string>

#include "scenes/street_scene.h"

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::cerr << "usage: " << argv[0] << " OUT.glb [SEED=1]\n";
    return 2;
  }
  try {
    const uint64_t seed = argc == 3 ? std::stoull(argv[2]) : 1;
    rigsim::WriteStreetScene(argv[1], seed);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
