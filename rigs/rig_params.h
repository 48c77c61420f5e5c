// One description of every parameter of a rig: its type, cameras and lenses, image size, mounting
// errors and path over the frames. `rigsim make-rig`'s options, the sweep's cell parameters
// (sweep/sweep_config.h CellParamSpecs) and `rigsim sweep --list-params` are made from it, and
// RigSpecFromParams turns values of it into the RigSpec both build their rig from
// (rigs/rig_spec.h). A new rig parameter is one entry in RigParams() (rigs/rig_params.cc).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/param_spec.h"
#include "rigs/rig_spec.h"

namespace rigsim {

// Where a parameter sits: make-rig's --from-gltf takes the image size and mounting errors but not
// the rest; the sweep's results list the rig's parameters, then how it renders, then its path.
enum class RigParamGroup { kRig, kImage, kMounting, kPath };

struct RigParam {
  ParamSpec spec;  // name (a sweep config's key, a results column), type, make-rig's default, range, help
  RigParamGroup group = RigParamGroup::kRig;
  // make-rig's option names in CLI11's form ("type,--type"); empty: "--" and the name with '-' for '_'.
  std::string flags;
  bool in_sweep = true;  // also a cell parameter of sweeps (a column of their results)
  // The sweep's default where it differs from make-rig's: a sweep renders many cells, so smaller
  // images and a turning path of three frames, which fixes each camera's place in the rig.
  std::optional<nlohmann::ordered_json> sweep_default;
  // Writes a checked, non-null value into the spec.
  void (*apply)(const nlohmann::ordered_json& value, RigSpec& spec) = nullptr;

  std::string Flags() const;         // make-rig's option names, as CLI11 takes them
  ParamSpec SweepSpec() const;       // spec with the sweep's default
};

// Every rig parameter, in the order of the sweep's results within each group.
const std::vector<RigParam>& RigParams();

// The RigSpec that `values` (an object: parameter name -> value) describe: each parameter's value,
// or its default (make-rig's) when `values` does not name it; null leaves it unset. Values are
// checked (CheckParamValue). Throws std::invalid_argument naming an unknown parameter or a refused
// value ("cameras: 0 is outside 1 to 64").
RigSpec RigSpecFromParams(const nlohmann::ordered_json& values);

}  // namespace rigsim
