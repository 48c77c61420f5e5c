// A rig as `rigsim make-rig` builds it: a preset type with its options, mounting errors, and its
// path over the frames, placed in a scene when one is given (where it stands and, for a ring with
// a target overlap, the spacing that gives that overlap there). The one place where type, lens,
// placement, overlap and trajectory meet: the command line and sweeps both build rigs here, from
// the values of the parameters rigs/rig_params.h describes.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "rigs/lens_residual.h"
#include "rigs/placement.h"
#include "rigs/rig_presets.h"
#include "rigs/trajectories.h"
#include "scene/scene.h"

namespace rigsim {

// A preset, or kFile: the cameras of a rig file (RigSpec::rig_file): a rig.json such as make-rig
// writes, or another tool's calibration (rigs/rig_import.h).
enum class RigType { kRing, kStereo, kSurround, kWideBaseline, kFile };

inline constexpr RigType kPresetRigTypes[] = {RigType::kRing, RigType::kStereo, RigType::kSurround,
                                              RigType::kWideBaseline};
inline constexpr RigType kAllRigTypes[] = {RigType::kRing, RigType::kStereo, RigType::kSurround, RigType::kWideBaseline,
                                           RigType::kFile};

// "ring", "stereo", "surround", "wide-baseline", "file".
std::string_view RigTypeName(RigType type);
// Inverse of RigTypeName; throws std::invalid_argument naming the types.
RigType RigTypeFromName(std::string_view name);

struct RigSpec {
  RigType type = RigType::kRing;
  RingRigOptions ring;
  StereoRigOptions stereo;
  SurroundRigOptions surround;
  WideBaselineRigOptions wide;
  // Set for every type (each type's options are overridden by these when given).
  int width = 1280;
  int height = 720;
  std::optional<double> hfov_deg;    // the type's perspective cameras (surround: the front camera)
  std::optional<double> baseline_m;  // stereo, wide-baseline
  LensOptions lens;                  // every camera's lens; kPreset keeps the type's own
  // Ring: the camera with barrel distortion (ring.k1, ring.k2); unset: cam1 from two cameras on.
  std::optional<int> distorted_camera;
  // Ring: the overlap of neighbours (percent); placed in a scene, the ground-truth overlap there.
  // 0: none at all (the spacing where neighbours' views just part, which no depth changes).
  // Unset: ring.yaw_spacing_deg.
  std::optional<double> overlap_percent;
  RigPerturbation perturbation;
  // Each camera rendered through a lens its model misses by this much at the corners, the model
  // fitted to it in rig.json (rigs/lens_residual.h); off by default.
  LensResidualOptions lens_residual;
  // kFile: the rig file whose cameras (intrinsics, cam_from_rig) make the rig (ReadRigFile); the
  // preset options, image size, field of view, lens and overlap do not apply to it.
  std::string rig_file;
  TrajectoryOptions trajectory;  // start and heading are chosen by the placement in a scene
  PlacementOptions placement;    // in a scene
};

// The rig of the spec's type with the overrides applied, before mounting errors; kFile: ReadRigFile.
Rig BuildPresetRig(const RigSpec& spec);

// The rig of a rig file for placing on a path: a rig.json, or another tool's calibration
// (rigs/rig_import.h: Kalibr, COLMAP, DGP, nuScenes); every camera needs its cam_from_rig. Throws
// std::runtime_error naming the file and the problem.
Rig ReadRigFile(const std::string& path);

struct PlacedRig {
  Rig rig;
  FramesFile frames;
  std::optional<RigPlacement> placement;  // where the placement put it, in a scene
};

// The rig with its mounting errors and its frames; with `scene`, placed in it where the whole path
// stays clear (nullopt when no place qualifies: NoPlaceMessage says why). Throws
// std::invalid_argument on bad options, and NoRoadError when road placement finds no road.
std::optional<PlacedRig> MakePlacedRig(const RigSpec& spec, const Scene* scene);

// Why MakePlacedRig found no place, in the user's words, naming the scene and the path.
std::string NoPlaceMessage(const RigSpec& spec, const std::string& scene_name);

// The overlap of a pair of cameras, the smaller of its two directions (what overlap.json's readers,
// render and calibrate, report).
struct PairOverlap {
  std::string a, b;
  double overlap = 0.0;  // fraction
};

// Every pair of `rig`'s cameras: in `scene`, the ground-truth overlap predicted at `rig_from_world`
// (PredictedOverlaps); without a scene, the angular overlap of points at infinity (AngularOverlap).
// Cameras with a render lens are seen through it, as render sees them.
std::vector<PairOverlap> RigPairOverlaps(const Rig& model_rig, const Scene* scene, const Rigid3d& rig_from_world);

}  // namespace rigsim
