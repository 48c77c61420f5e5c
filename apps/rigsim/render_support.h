// What the render and demo commands share: render options on the command line, loading a
// scene with its warnings shown, and rendering with progress and a summary.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "renderer/photometric.h"
#include "renderer/render_dataset.h"
#include "renderer/renderer.h"
#include "scene/scene.h"

namespace rigsim::cli {

struct RenderSettings {
  int samples_per_pixel = 4;
  uint64_t seed = 1;
  int threads = 0;
  RenderOptions ToRenderOptions() const;
};

void AddRenderSettingsOptions(CLI::App& cmd, RenderSettings& settings);

// Per-camera photometric variation (renderer/photometric.h): --photometric turns on the default
// magnitudes, and each magnitude can be set on its own (alone it turns on only itself).
struct PhotometricSettings {
  bool defaults = false;  // --photometric
  std::optional<double> exposure_sigma, white_balance_sigma, vignetting, shot_noise, read_noise;
  // Off (all zero) unless asked for, or `base` (a sensor preset's) with the magnitudes given on the
  // command line; seeded with the render seed. Throws std::invalid_argument.
  PhotometricOptions ToOptions(uint64_t seed, const PhotometricOptions& base = {}) const;
};

void AddPhotometricOptions(CLI::App& cmd, PhotometricSettings& settings);

// --sensor PRESET (renderer/sensor_model.h) and the lens and JPEG values that override the preset's.
struct SensorSettings {
  std::string preset = "ideal";
  std::optional<double> f_number, focus_distance, pixel_pitch;
  std::optional<int> jpeg_quality;
};

void AddSensorOptions(CLI::App& cmd, SensorSettings& settings);

// Sets the job's photometric options, defocus, JPEG and preset name from --sensor, --photometric
// and their overrides. Throws std::invalid_argument for an unknown preset (naming the presets) and
// for --photometric with a preset other than ideal.
void ApplySensorSettings(const SensorSettings& sensor, const PhotometricSettings& photometric, uint64_t seed, RenderJob& job);

// The render command line of the sensor and photometric options as given (for Slurm's tasks).
std::vector<std::string> SensorArgs(const SensorSettings& sensor, const PhotometricSettings& photometric);

// --rules RULES.json: Cityscapes classes for a glTF without extras.class, from node, mesh or
// material names (gltf/label_rules.h; docs/scenes-and-rigs.md, 'Labelling a foreign glTF with a rules file').
void AddLabelRulesOption(CLI::App& cmd, std::string& rules_path);

// Loads a glTF file, labelled by the rules file when `rules_path` is not empty, and prints its
// size, the rules used and every loader warning to stderr.
Scene LoadSceneVerbose(const std::filesystem::path& path, const std::string& rules_path = "");

// Throws std::runtime_error naming the file when a camera of `rig` has no cam_from_rig or a frame
// of `frames` no rig_from_world: rendering needs both, and a rig to be calibrated has neither.
void RequirePoses(const Rig& rig, const std::filesystem::path& rig_path, const FramesFile& frames,
                  const std::filesystem::path& frames_path, const std::string& command);

// Renders with a progress line, then prints time and the ground-truth overlap per pair.
void RenderAndReport(const RenderJob& job, const std::filesystem::path& out, bool force);

}  // namespace rigsim::cli
