#include "calibrator/stages/rig_edges.h"

#include <algorithm>

#include "calibrator/estimators/capture_time.h"
#include "common/format.h"
#include "geometry/rigid3.h"

namespace rigsim {

void CompareEdgesWithRig(const RigObservations& obs, RigCalibrationResult* result) {
  for (int e = 0; e < static_cast<int>(result->edges.size()); ++e) {
    RigEdgeStats& s = result->edges[e];
    const PairEstimate& p = obs.pairs[e];
    if (!s.Used() || !p.two_view.success) continue;
    const auto& qa = result->cam_from_rig_rotation[p.cam_a];
    const auto& qb = result->cam_from_rig_rotation[p.cam_b];
    if (!qa || !qb) continue;
    // Cameras that capture at different times (estimated offsets) see each other across the rig's
    // motion between their captures, on average over the frames the pair pooled.
    const RigCamera& ca = result->rig.cameras[p.cam_a];
    const RigCamera& cb = result->rig.cameras[p.cam_b];
    const double apart_s = cb.time_offset_s + 0.5 * cb.readout_s - ca.time_offset_s - 0.5 * ca.readout_s;
    const Rigid3d between =
        apart_s != 0 ? MeanRigChange(result->rig_from_world, obs.frame_times_s, apart_s).value_or(Rigid3d()) : Rigid3d();
    s.rotation_disagreement_deg =
        RotationDifferenceDeg(*qb * between.rotation * qa->conjugate(), p.two_view.cam_b_from_cam_a.rotation);
    const auto& pa = ca.cam_from_rig;
    const auto& pb = cb.cam_from_rig;
    if (!pa || !pb || p.two_view.rotation_only) continue;
    const Eigen::Vector3d t_rig = (*pb * between * pa->Inverse()).translation;
    if (t_rig.norm() > 1e-12) s.direction_disagreement_deg = AngleBetweenDeg(t_rig, p.two_view.cam_b_from_cam_a.translation);
  }
}

std::pair<int, std::string> MostDisagreeingEdge(const RigCalibrationResult& r, const RigCalibrationOptions& options) {
  int worst = -1;
  double worst_excess = 1.0;
  for (int e = 0; e < static_cast<int>(r.edges.size()); ++e) {
    const RigEdgeStats& s = r.edges[e];
    if (!s.Used()) continue;
    const double excess = std::max(s.rotation_disagreement_deg.value_or(0.0) / options.max_pair_rotation_disagreement_deg,
                                   s.direction_disagreement_deg.value_or(0.0) / options.max_pair_direction_disagreement_deg);
    if (excess > worst_excess) {
      worst_excess = excess;
      worst = e;
    }
  }
  if (worst < 0) return {-1, ""};
  const RigEdgeStats& s = r.edges[worst];
  std::string why = "disagrees with the rig: its rotation is " + Fixed(s.rotation_disagreement_deg.value_or(0.0), 2) +
                    " deg off the rig's";
  if (s.direction_disagreement_deg) why += ", its baseline direction " + Fixed(*s.direction_disagreement_deg, 1) + " deg";
  why += " (a wrong match of repeated structure, or a mirror-image pose)";
  return {worst, why};
}

}  // namespace rigsim
