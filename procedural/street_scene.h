// The built-in procedural street scene, written as a labelled .glb.
//
// Layout (glTF world: +Y up, metres): a road along Z (x in [-5, 5], z in [-60, 60]), sidewalks
// raised 0.15 m on both sides (|x| in [5, 9]), building facades at |x| = 9 (one alley closed by
// a wall on each side), buildings closing both ends at |z| = 60, street lamps, traffic signs, a
// railing, parked cars, people and trees. The origin is in the middle of the road, so a rig at
// ~1.6 m height sees structure in every horizontal direction. There is no sky geometry.
//
// Every surface has its own seeded texture (multi-octave value noise, bricks, windows, signs,
// glyphs, cracks, markings), never tiled, so that feature detectors find many distinct
// keypoints; facades near the origin carry ~72 texels per metre.
//
// Deterministic: the same seed gives a byte-identical file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace rigsim {

// Writes the street for `seed` to `glb_path`. Throws std::runtime_error on I/O errors.
void WriteStreetScene(const std::filesystem::path& glb_path, uint64_t seed);

// Returns the same bytes WriteStreetScene would write.
std::vector<uint8_t> StreetSceneGlb(uint64_t seed);
// With `animated`, the street moves (procedural/presets.h says how): people walk, `traffic` cars
// per 100 m of lane drive, trees sway. With `glass` its windows are glass, and puddles cover about
// `wet` (0 to kMaxWet) of its road (procedural/glass_and_water.h); the rest is the same either way.
std::vector<uint8_t> StreetSceneGlb(uint64_t seed, bool animated, double traffic, bool glass = false, double wet = 0.0);

}  // namespace rigsim
