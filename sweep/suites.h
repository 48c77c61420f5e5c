// Built-in sweeps (`rigsim sweep --suite NAME`).
//
// thesis: the four claims of the thesis rigsim was built to test (semantic masking gives a larger
// share of correct matches, fewer wrong matches between different classes, faster matching and
// calibration, and pose accuracy equal or better), asked across overlap (5-50%), baseline (a
// wide-baseline pair 0.1-5 m apart, toed in 30 deg), lens (pinhole to a 190 deg fisheye), label
// noise (the truth to 10 px boundary shifts with 30% confusion) and the three preset scenes, for
// none, mask, gated, mask+gated and COLMAP. Sizes: full (3 seeds, every value), small (1 seed,
// two values per study, none and mask and COLMAP).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rigsim {

std::vector<std::string> SuiteNames();
std::vector<std::string> SuiteSizes();
// The suite's config as a sweep config file would hold it. Throws std::invalid_argument naming
// the suites (or sizes) when `name` (or `size`) is unknown.
nlohmann::ordered_json SuiteConfig(const std::string& name, const std::string& size);

// The thesis's claims as a config's `claims` holds them; also what a config without claims tests.
nlohmann::ordered_json ThesisClaimsJson();

}  // namespace rigsim
