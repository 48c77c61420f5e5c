// Procedural scene presets: seeded worlds written as labelled .glb (class extras per node, one
// instance per node), each stressing calibration in its own way:
//   street   a street canyon: repetitive facades, parked cars, a few people and trees
//            (the built-in asset, procedural/street_scene.h);
//   plaza    an open square: distant buildings, much sky and vegetation (alpha-masked foliage
//            cards), many people, a bus and an advertising wall carrying the same poster;
//   parking  a parking lot: ground-dominated views, rows of identical car models, light poles,
//            a supermarket whose poster also covers a bus.
// All presets share the generated, never-tiled textures of procedural/textures.h. With
// `animated` the world moves (procedural/motion.h, glTF LINEAR translation and rotation channels
// over 60 s): people walk back and forth with a gait, cars drive their lanes at `traffic` vehicles
// per 100 m of lane (the street's and the parking's lane cars first, then more cars; those not
// driving stay parked), buses drive to their stop when there is traffic, trees sway in the wind.
// The sky is the renderer's, not geometry: it has no clouds to drift. The static scene is the
// same with and without animation (the motion draws from its own random stream and extra cars
// come last). World: glTF (+Y up, metres); the origin is a free spot on the ground from
// which a rig at 1.6 m sees structure in every direction. With `glass` and `wet`, the facades'
// windows are glass and puddles lie on the street's road and the parking's asphalt (the plaza is
// paved: it gets glass only), glossy surfaces that mirror the world (procedural/glass_and_water.h);
// they draw from their own stream, so the rest of the world is the same with and without them,
// and without them (the default, and the shipped scenes) the world is as it was.
// Deterministic: same options, same bytes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace rigsim {

// Traffic in animated presets: moving vehicles per 100 m of lane. The default keeps the moving
// cars the presets had before traffic was a parameter (street 5, parking 2); the maximum keeps
// 6 m between cars.
inline constexpr double kDefaultTraffic = 2.0;
inline constexpr double kMaxTraffic = 15.0;
// The most of a road puddles may cover: a street after rain, with dry asphalt between the puddles
// (the placement of puddles that never overlap fills up near a quarter).
inline constexpr double kMaxWet = 0.2;

enum class ScenePreset { kStreet, kPlaza, kParking };

// "street", "plaza", "parking"
std::string_view ScenePresetName(ScenePreset preset);
// Throws std::invalid_argument naming the presets when `name` is unknown.
ScenePreset ScenePresetFromName(std::string_view name);
std::vector<ScenePreset> AllScenePresets();

struct ScenePresetOptions {
  ScenePreset preset = ScenePreset::kStreet;
  uint64_t seed = 1;      // every random choice derives from it
  bool animated = false;  // people walk, vehicles drive, trees sway
  double traffic = kDefaultTraffic;  // animated only: 0 (no vehicle moves) to kMaxTraffic
  bool glass = false;  // the facades' windows are glass that mirrors the world
  double wet = 0.0;    // the share of the road (street, parking) puddles cover: 0 to kMaxWet
  void Check() const;     // throws std::invalid_argument
};

// The .glb bytes of a preset.
std::vector<uint8_t> ScenePresetGlb(const ScenePresetOptions& options);
// Writes them to `path`; throws std::runtime_error("<path>: ...") on I/O errors.
void WriteScenePreset(const ScenePresetOptions& options, const std::filesystem::path& path);

}  // namespace rigsim
