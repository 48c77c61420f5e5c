// Built-in sweeps (`rigsim sweep --suite NAME`).
//
// thesis: the four claims of the thesis rigsim was built to test (semantic masking gives a larger
// share of correct matches, fewer wrong matches between different classes, faster matching and
// calibration, and pose accuracy equal or better), asked across overlap (5-50%), baseline (a
// wide-baseline pair 0.1-5 m apart, toed in 30 deg), lens (pinhole to a 190 deg fisheye), label
// noise (the truth to 10 px boundary shifts with 30% confusion) and the three preset scenes, for
// none, mask, gated, mask+gated and COLMAP; the overlap study goes down to none (0 %) across
// frame counts (3, 12, 30) and paths (straight, circle, handheld), to map where calibration breaks
// along overlap x motion; and a dynamics study (animated worlds, traffic x time offset x rolling
// shutter on a handheld path) asks the claims where the unreliable classes really move. Sizes: full (3 seeds, every value), small (1 seed, two values per study,
// 3 frames, none and mask and COLMAP).
//
// Both suites render through a sensor preset (SuiteInputs::sensor, `automotive` unless asked
// otherwise): an automotive camera's noise, defocus and JPEG, the preset measured against a real car
// rig's photos (VALIDATION.md, "Real rigs imported as twins"); `ideal`'s noise-free, sharp, lossless
// renders are easier than real photos. `ideal` leaves the config as it is without a
// sensor, so its cells are those of a suite without one. The rig's own car (ego_vehicle) is off
// unless asked for: the thesis's rigs (a ring, a wide-baseline pair up to 5 m apart, a 190 deg
// fisheye, handheld paths) and a motion suite's rig are not known to be a car's.
//
// motion: which path calibrates a user's own rig (SuiteInputs::rig_file, a rig.json with every
// camera's intrinsics and cam_from_rig): the rig through every named path (rigs/trajectories.h) at
// 3, 12 and 30 frames (a study per frame count), in the street or SuiteInputs::scene, over 3 seeds.
// Sizes: full (none, mask and COLMAP), small (3 and 12 frames, none).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rigsim {

std::vector<std::string> SuiteNames();
std::vector<std::string> SuiteSizes();
// The sensor preset the suites render with unless told otherwise.
inline constexpr char kSuiteDefaultSensor[] = "automotive";

// What a suite takes from the command line: motion's rig (an absolute path, as the cells record
// it) and its scene (a preset or a file; empty: the street); for either suite the sensor preset
// (render --sensor) and whether the rig's own car is around the rig (make-rig --ego-vehicle).
struct SuiteInputs {
  std::string rig_file;
  std::string scene;
  std::string sensor = kSuiteDefaultSensor;
  bool ego_vehicle = false;
};

// The suite's config as a sweep config file would hold it. Throws std::invalid_argument naming
// the suites (or sizes, or sensor presets) when `name` (or `size`, or `inputs.sensor`) is unknown,
// when motion has no rig, or when thesis is given one.
nlohmann::ordered_json SuiteConfig(const std::string& name, const std::string& size, const SuiteInputs& inputs = {});

// The thesis's claims as a config's `claims` holds them; also what a config without claims tests.
nlohmann::ordered_json ThesisClaimsJson();

}  // namespace rigsim
