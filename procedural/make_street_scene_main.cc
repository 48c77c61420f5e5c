// Writes the built-in street scene, or another preset: rigsim_make_street_scene OUT.glb [SEED [PRESET]]
// The shipped asset is assets/scenes/street.glb with seed 1 (procedural_test checks it is up to date);
// assets/scenes/plaza.glb and parking.glb are the presets of the same name with seed 1.
#include <cstdint>
#include <exception>
#include <iostream>
#include <string>

#include "procedural/presets.h"
#include "procedural/street_scene.h"

int main(int argc, char** argv) {
  if (argc < 2 || argc > 4) {
    std::cerr << "usage: " << argv[0] << " OUT.glb [SEED=1 [PRESET=street]]\n";
    return 2;
  }
  try {
    const uint64_t seed = argc >= 3 ? std::stoull(argv[2]) : 1;
    if (argc == 4) {
      rigsim::WriteScenePreset({rigsim::ScenePresetFromName(argv[3]), seed, false}, argv[1]);
    } else {
      rigsim::WriteStreetScene(argv[1], seed);
    }
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
