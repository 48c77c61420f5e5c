#include "rigs/rig_spec.h"

#include <algorithm>
#include <cmath>

namespace rigsim {

namespace {

RingRigOptions RingOf(const RigSpec& s) {
  RingRigOptions o = s.ring;
  o.width = s.width;
  o.height = s.height;
  if (s.hfov_deg) o.hfov_deg = *s.hfov_deg;
  if (s.lens) o.lens = *s.lens;
  o.target_overlap = s.overlap_percent / 100.0;
  return o;
}

void PerturbIfAsked(const RigSpec& s, Rig* rig) {
  if (s.perturbation.rotation_deg > 0 || s.perturbation.translation_m > 0) PerturbRig(*rig, s.perturbation);
}

}  // namespace

Rig BuildPresetRig(const RigSpec& s) {
  if (s.type == "ring") return MakeRingRig(RingOf(s));
  if (s.type == "stereo") {
    StereoRigOptions o = s.stereo;
    o.width = s.width;
    o.height = s.height;
    if (s.hfov_deg) o.hfov_deg = *s.hfov_deg;
    if (s.baseline_m) o.baseline_m = *s.baseline_m;
    if (s.lens) o.lens = *s.lens;
    return MakeStereoRig(o);
  }
  if (s.type == "surround") {
    SurroundRigOptions o = s.surround;
    o.width = s.width;
    o.height = s.height;
    if (s.hfov_deg) o.front_hfov_deg = *s.hfov_deg;
    if (s.lens) o.lens = *s.lens;
    return MakeSurroundRig(o);
  }
  if (s.type == "wide-baseline") {
    WideBaselineRigOptions o = s.wide;
    o.width = s.width;
    o.height = s.height;
    if (s.hfov_deg) o.hfov_deg = *s.hfov_deg;
    if (s.baseline_m) o.baseline_m = *s.baseline_m;
    if (s.lens) o.lens = *s.lens;
    return MakeWideBaselineRig(o);
  }
  throw std::invalid_argument("unknown rig type '" + s.type + "': give ring, stereo, surround or wide-baseline");
}

std::optional<PlacedRig> MakePlacedRig(const RigSpec& s, const Scene* scene) {
  PlacedRig out;
  out.rig = BuildPresetRig(s);
  PerturbIfAsked(s, &out.rig);
  TrajectoryOptions trajectory = s.trajectory;
  if (scene) {
    PlacementOptions p = s.placement;
    if (trajectory.kind == TrajectoryKind::kStraight) p.travel_m = (trajectory.num_frames - 1) * std::abs(trajectory.step_m);
    out.placement = PlaceRig(*scene, out.rig, p);
    if (!out.placement) return std::nullopt;
    trajectory.start_world = out.placement->position_world;
    trajectory.heading_deg = out.placement->heading_deg;
    if (s.type == "ring" && s.overlap_percent > 0) {
      // The spacing for the ground-truth overlap in this scene at this place: sky and occluders
      // change it from the angular value.
      out.rig = MakeRingRigInScene(RingOf(s), *scene, RigFromWorldAt(trajectory.start_world, trajectory.heading_deg));
      PerturbIfAsked(s, &out.rig);
    }
  }
  out.frames = MakeTrajectory(trajectory);
  return out;
}

std::vector<PairOverlap> RigPairOverlaps(const Rig& rig, const Scene* scene, const Rigid3d& rig_from_world) {
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
