#include "rigs/rig_spec.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "common/param_spec.h"
#include "rigs/rig_import.h"

namespace rigsim {

namespace {

RingRigOptions RingOf(const RigSpec& s) {
  RingRigOptions o = s.ring;
  o.width = s.width;
  o.height = s.height;
  if (s.hfov_deg) o.hfov_deg = *s.hfov_deg;
  o.distorted_camera = s.distorted_camera.value_or(o.num_cameras >= 2 ? 1 : -1);
  o.lens = s.lens;
  if (s.overlap_percent && *s.overlap_percent > 0) {
    o.target_overlap = *s.overlap_percent / 100.0;
  } else if (s.overlap_percent) {
    // Outward-facing cameras whose edge rays are parallel share nothing at any depth.
    o.yaw_spacing_deg = RingSpacingForOverlap(o, 0.0);
    if (o.num_cameras * o.yaw_spacing_deg > 360.0 + 1e-9) {
      char why[200];
      std::snprintf(why, sizeof why, "overlap 0: %d cameras need %.1f deg each to share nothing, more than 360 deg all "
                    "round (the last would overlap the first); use fewer cameras or a narrower hfov", o.num_cameras,
                    o.yaw_spacing_deg);
      throw std::invalid_argument(why);
    }
  }
  return o;
}

void PerturbIfAsked(const RigSpec& s, Rig* rig) {
  if (s.perturbation.rotation_deg > 0 || s.perturbation.translation_m > 0) PerturbRig(*rig, s.perturbation);
}

}  // namespace

std::string_view RigTypeName(RigType type) {
  switch (type) {
    case RigType::kRing: return "ring";
    case RigType::kStereo: return "stereo";
    case RigType::kSurround: return "surround";
    case RigType::kWideBaseline: return "wide-baseline";
    case RigType::kFile: return "file";
  }
  throw std::invalid_argument("RigTypeName: invalid rig type " + std::to_string(static_cast<int>(type)));
}

RigType RigTypeFromName(std::string_view name) {
  for (RigType t : kAllRigTypes) {
    if (RigTypeName(t) == name) return t;
  }
  throw std::invalid_argument("unknown rig type '" + std::string(name) + "': give " +
                              JoinNames(NamesOf(kAllRigTypes, RigTypeName)));
}

Rig BuildPresetRig(const RigSpec& s) {
  switch (s.type) {
    case RigType::kRing: return MakeRingRig(RingOf(s));
    case RigType::kStereo: {
      StereoRigOptions o = s.stereo;
      o.width = s.width;
      o.height = s.height;
      if (s.hfov_deg) o.hfov_deg = *s.hfov_deg;
      if (s.baseline_m) o.baseline_m = *s.baseline_m;
      o.lens = s.lens;
      return MakeStereoRig(o);
    }
    case RigType::kSurround: {
      SurroundRigOptions o = s.surround;
      o.width = s.width;
      o.height = s.height;
      if (s.hfov_deg) o.front_hfov_deg = *s.hfov_deg;
      o.lens = s.lens;
      return MakeSurroundRig(o);
    }
    case RigType::kWideBaseline: {
      WideBaselineRigOptions o = s.wide;
      o.width = s.width;
      o.height = s.height;
      if (s.hfov_deg) o.hfov_deg = *s.hfov_deg;
      if (s.baseline_m) o.baseline_m = *s.baseline_m;
      o.lens = s.lens;
      return MakeWideBaselineRig(o);
    }
    case RigType::kFile:
      if (s.rig_file.empty()) throw std::invalid_argument("rig file: give the rig file to use (rig_file, --rig-file)");
      return ReadRigFile(s.rig_file);
  }
  throw std::invalid_argument("BuildPresetRig: invalid rig type " + std::to_string(static_cast<int>(s.type)));
}

Rig ReadRigFile(const std::string& path) {
  if (!std::filesystem::exists(path)) throw std::runtime_error(path + ": rig file not found");
  Rig rig = ImportRig(path);
  for (const RigCamera& c : rig.cameras) {
    if (!c.cam_from_rig) {
      throw std::runtime_error(path + ": camera '" + c.name + "' has no cam_from_rig: a rig to move along a path needs "
                               "where every camera sits on it (rigsim make-rig writes it)");
    }
  }
  return rig;
}

std::string NoPlaceMessage(const RigSpec& s, const std::string& scene_name) {
  if (s.placement.mode == PlacementMode::kRoad) {
    char footprint[32];
    std::snprintf(footprint, sizeof(footprint), "%g", 2 * s.placement.half_width_m);
    return scene_name + ": no spot on the road where the rig stands in a lane and its " + DescribePath(s.trajectory) +
           " keeps its " + footprint + " m wide footprint on the road and clear of the scene's geometry: the path "
           "needs the road's room; try a shorter --step or fewer --frames, a straight path or a gentler circle (larger "
           "--circle-radius), a loop or figure-eight whose circle fits within the road (smaller --circle-radius), or a "
           "scene with more road";
  }
  char clearance[32];
  std::snprintf(clearance, sizeof(clearance), "%g", s.placement.min_clearance_m);
  return scene_name + ": no place where the rig stands on the ground with " + clearance +
         " m clearance and its " + DescribePath(s.trajectory) +
         " stays clear of the scene's geometry; try a smaller radius, fewer frames, another path or scene, or a smaller "
         "clearance";
}

std::optional<PlacedRig> MakePlacedRig(const RigSpec& s, const Scene* scene) {
  PlacedRig out;
  out.rig = BuildPresetRig(s);
  PerturbIfAsked(s, &out.rig);
  TrajectoryOptions trajectory = s.trajectory;
  if (scene) {
    PlacementOptions p = s.placement;
    if (trajectory.kind == TrajectoryKind::kStraight) p.travel_m = (trajectory.num_frames - 1) * std::abs(trajectory.step_m);
    out.placement = PlaceRig(*scene, out.rig, p, &trajectory);
    if (!out.placement) return std::nullopt;
    trajectory.start_world = out.placement->position_world;
    trajectory.heading_deg = out.placement->heading_deg;
    if (s.type == RigType::kRing && s.overlap_percent.value_or(0) > 0) {
      // The spacing for the ground-truth overlap in this scene at this place: sky and occluders
      // change it from the angular value.
      out.rig = MakeRingRigInScene(RingOf(s), *scene, RigFromWorldAt(trajectory.start_world, trajectory.heading_deg));
      PerturbIfAsked(s, &out.rig);
    }
  }
  // Last, so that the placement and the ring's spacing are the model's as without it.
  ApplyLensResidual(out.rig, s.lens_residual);
  out.frames = MakeTrajectory(trajectory);
  return out;
}

std::vector<PairOverlap> RigPairOverlaps(const Rig& model_rig, const Scene* scene, const Rigid3d& rig_from_world) {
  const Rig rig = model_rig.AsRendered();  // the overlap the images will have: through the render lenses
  const int n = int(rig.cameras.size());
  Eigen::MatrixXd overlap = Eigen::MatrixXd::Zero(n, n);
  if (scene != nullptr) {
    overlap = PredictedOverlaps(*scene, rig, rig_from_world);
  } else {
    for (int a = 0; a < n; ++a) {
      for (int b = a + 1; b < n; ++b) {
        const RigCamera& ca = rig.cameras[a];
        const RigCamera& cb = rig.cameras[b];
        const Eigen::Matrix3d b_from_a = (*cb.cam_from_rig * ca.cam_from_rig->Inverse()).RotationMatrix();
        overlap(a, b) = std::min(AngularOverlap(ca.camera, cb.camera, b_from_a), AngularOverlap(cb.camera, ca.camera, b_from_a.transpose()));
      }
    }
  }
  std::vector<PairOverlap> pairs;
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) pairs.push_back({rig.cameras[a].name, rig.cameras[b].name, overlap(a, b)});
  }
  return pairs;
}

}  // namespace rigsim
