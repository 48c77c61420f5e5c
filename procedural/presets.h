// Procedural scene presets: seeded worlds written as labelled .glb (class extras per node, one
// instance per node), each stressing calibration in its own way:
//   street   a street canyon: repetitive facades, parked cars, a few people and trees
//            (the built-in asset, procedural/street_scene.h);
//   plaza    an open square: distant buildings, much sky and vegetation (alpha-masked foliage
//            cards), many people, a bus and an advertising wall carrying the same poster;
//   parking  a parking lot: ground-dominated views, rows of identical car models, light poles,
//            a supermarket whose poster also covers a bus.
// All presets share the generated, never-tiled textures of procedural/textures.h. With
// `animated`, cars and people get glTF translation animations (LINEAR); the static geometry is
// the same as without. World: glTF (+Y up, metres); the origin is a free spot on the ground from
// which a rig at 1.6 m sees structure in every direction. Deterministic: same options, same bytes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace rigsim {

enum class ScenePreset { kStreet, kPlaza, kParking };

// "street", "plaza", "parking"
std::string_view ScenePresetName(ScenePreset preset);
// Throws std::invalid_argument naming the presets when `name` is unknown.
ScenePreset ScenePresetFromName(std::string_view name);
std::vector<ScenePreset> AllScenePresets();

struct ScenePresetOptions {
  ScenePreset preset = ScenePreset::kStreet;
  uint64_t seed = 1;      // every random choice derives from it
  bool animated = false;  // add translation animations to cars and people
  void Check() const;     // throws std::invalid_argument
};

// The .glb bytes of a preset.
std::vector<uint8_t> ScenePresetGlb(const ScenePresetOptions& options);
// Writes them to `path`; throws std::runtime_error("<path>: ...") on I/O errors.
void WriteScenePreset(const ScenePresetOptions& options, const std::filesystem::path& path);

}  // namespace rigsim
