#include "calibrator/estimators/rig_turns.h"

#include <limits>
#include <stdexcept>

#include "calibrator/model/rig_state.h"
#include "common/format.h"
#include "geometry/rigid3.h"

namespace rigsim {
namespace {

using Quat = Eigen::Quaterniond;

// One camera's pair at one step: its own pose first, then its planar alternatives.
struct StepPoses {
  int pair = -1;  // index into the temporal pairs; -1 without a successful pair
  std::vector<Rigid3d> poses;
};
using CameraSteps = std::vector<StepPoses>;  // per step

std::vector<CameraSteps> StepsOf(int num_cameras, int num_frames, const std::vector<TemporalPairEstimate>& temporal) {
  std::vector<CameraSteps> steps(num_cameras, CameraSteps(std::max(num_frames - 1, 0)));
  for (int i = 0; i < static_cast<int>(temporal.size()); ++i) {
    const TemporalPairEstimate& t = temporal[i];
    if (t.camera < 0 || t.camera >= num_cameras || t.frame < 0 || t.frame + 1 >= num_frames) {
      throw std::invalid_argument("ResolveStepsByTheRig: temporal pair out of range");
    }
    if (!t.two_view.success) continue;
    StepPoses& s = steps[t.camera][t.frame];
    s.pair = i;
    s.poses = {t.two_view.cam_b_from_cam_a};
    s.poses.insert(s.poses.end(), t.two_view.planar_alternatives.begin(), t.two_view.planar_alternatives.end());
  }
  return steps;
}

double TurnDeg(const Quat& q) { return RadToDeg(RotationVector(q).norm()); }

// The pose of `poses` nearest `predicted` in rotation: its index and the angle (deg).
std::pair<int, double> Nearest(const std::vector<Rigid3d>& poses, const Quat& predicted) {
  std::pair<int, double> best{-1, std::numeric_limits<double>::infinity()};
  for (int i = 0; i < static_cast<int>(poses.size()); ++i) {
    const double d = RotationDifferenceDeg(poses[i].rotation, predicted);
    if (d < best.second) best = {i, d};
  }
  return best;
}

// How many of camera c's steps agree with camera 0's under mounting x (some pose of each within the
// tolerance of R_c = x R_0 x^T), and the sum of the agreeing steps' angles.
std::pair<int, double> Agreement(const CameraSteps& c, const CameraSteps& ref, const Quat& x, double tol) {
  std::pair<int, double> out{0, 0.0};
  for (size_t k = 0; k < c.size(); ++k) {
    double best = std::numeric_limits<double>::infinity();
    for (const Rigid3d& r : ref[k].poses) best = std::min(best, Nearest(c[k].poses, x * r.rotation * x.conjugate()).second);
    if (best <= tol) {
      ++out.first;
      out.second += best;
    }
  }
  return out;
}

// The mounting taking the axes of camera 0's turns to camera c's, from the agreeing steps (weighted
// by the turn: a small turn's axis is noise).
Quat MountingFromAgreeingSteps(const CameraSteps& c, const CameraSteps& ref, const Quat& x, double tol) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (size_t k = 0; k < c.size(); ++k) {
    for (const Rigid3d& r : ref[k].poses) {
      const auto [i, d] = Nearest(c[k].poses, x * r.rotation * x.conjugate());
      if (i < 0 || d > tol) continue;
      const Eigen::Vector3d a = RotationVector(r.rotation), b = RotationVector(c[k].poses[i].rotation);
      m += b * a.transpose();  // |b| |a|: weighted by the turns
    }
  }
  return Quat(NearestRotation(m)).normalized();
}

// Camera c's mounting against camera 0 (RANSAC over pairs of steps and their poses); nullopt when
// fewer than options.min_agreeing_steps steps agree.
std::optional<Quat> FindMounting(const CameraSteps& c, const CameraSteps& ref, const RigTurnOptions& options) {
  const double tol = options.max_disagreement_deg;
  std::vector<int> turned;  // steps both cameras have, that turned
  for (size_t k = 0; k < c.size(); ++k) {
    if (c[k].pair >= 0 && ref[k].pair >= 0 && TurnDeg(ref[k].poses[0].rotation) >= options.min_turn_deg) turned.push_back(k);
  }
  std::optional<Quat> best;
  std::pair<int, double> best_score{0, 0.0};
  auto consider = [&](const Quat& x) {
    const auto score = Agreement(c, ref, x, tol);
    if (score.first > best_score.first || (score.first == best_score.first && best && score.second < best_score.second)) {
      best = x;
      best_score = score;
    }
  };
  for (size_t i = 0; i < turned.size(); ++i) {
    for (size_t j = i + 1; j < turned.size(); ++j) {
      const StepPoses &ck = c[turned[i]], &cl = c[turned[j]], &rk = ref[turned[i]], &rl = ref[turned[j]];
      for (const Rigid3d& a0 : rk.poses)
        for (const Rigid3d& b0 : ck.poses)
          for (const Rigid3d& a1 : rl.poses)
            for (const Rigid3d& b1 : cl.poses) {
              // A camera turns by the rig's angle: a hypothesis that breaks it is not tried.
              if (std::abs(TurnDeg(a0.rotation) - TurnDeg(b0.rotation)) > tol ||
                  std::abs(TurnDeg(a1.rotation) - TurnDeg(b1.rotation)) > tol) {
                continue;
              }
              const Eigen::Matrix3d m = RotationVector(b0.rotation).normalized() * RotationVector(a0.rotation).normalized().transpose() +
                                        RotationVector(b1.rotation).normalized() * RotationVector(a1.rotation).normalized().transpose();
              consider(Quat(NearestRotation(m)).normalized());
            }
    }
  }
  if (!best) return std::nullopt;
  consider(MountingFromAgreeingSteps(c, ref, *best, tol));
  if (best_score.first < options.min_agreeing_steps) return std::nullopt;
  return best;
}

// The rig's turn at step k in camera 0's axes: the pose (seen through its camera's mounting) that the
// most cameras have a pose within the tolerance of, averaged over those; nullopt below two cameras.
std::optional<Quat> RigTurnAt(int k, const std::vector<CameraSteps>& steps, const PerCamera<Quat>& mounting,
                              double tol) {
  std::vector<std::vector<Quat>> seen(steps.size());  // per camera, its poses in camera 0's axes
  for (size_t c = 0; c < steps.size(); ++c) {
    if (!mounting[c]) continue;
    for (const Rigid3d& p : steps[c][k].poses) seen[c].push_back(mounting[c]->conjugate() * p.rotation * *mounting[c]);
  }
  std::vector<Quat> best_agreeing;
  for (size_t c = 0; c < seen.size(); ++c) {
    for (const Quat& q : seen[c]) {
      std::vector<Quat> agreeing;
      for (size_t d = 0; d < seen.size(); ++d) {
        const Quat* nearest = nullptr;
        for (const Quat& o : seen[d]) {
          if (RotationDifferenceDeg(o, q) <= tol && (!nearest || RotationDifferenceDeg(o, q) < RotationDifferenceDeg(*nearest, q))) {
            nearest = &o;
          }
        }
        if (nearest) agreeing.push_back(*nearest);
      }
      if (agreeing.size() > best_agreeing.size()) best_agreeing = agreeing;
    }
  }
  if (best_agreeing.size() < 2) return std::nullopt;
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (const Quat& q : best_agreeing) sum += q.toRotationMatrix();
  return Quat(NearestRotation(sum)).normalized();
}

}  // namespace

void RigTurnOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("RigTurnOptions: " + why); };
  if (!(max_disagreement_deg > 0)) fail("max_disagreement_deg must be > 0");
  if (!(min_turn_deg >= 0)) fail("min_turn_deg must be >= 0");
  if (min_agreeing_steps < 2) fail("min_agreeing_steps must be >= 2");
}

RigTurns ResolveStepsByTheRig(const std::vector<TemporalPairEstimate>& temporal,
                              const PerCamera<Eigen::Quaterniond>& known_cam_from_rig, int num_frames,
                              const RigTurnOptions& options) {
  options.Check();
  const int num_cameras = static_cast<int>(known_cam_from_rig.size());
  const std::vector<CameraSteps> steps = StepsOf(num_cameras, num_frames, temporal);
  const int num_steps = std::max(num_frames - 1, 0);
  RigTurns out;
  out.temporal = temporal;
  out.cam_from_rig.assign(num_cameras, std::nullopt);
  if (num_cameras > 0) out.cam_from_rig[0] = Quat::Identity();
  for (int c = 1; c < num_cameras; ++c) {
    out.cam_from_rig[c] = known_cam_from_rig[c] ? known_cam_from_rig[c] : FindMounting(steps[c], steps[0], options);
  }
  for (int k = 0; k < num_steps; ++k) out.rig_turn.push_back(RigTurnAt(k, steps, out.cam_from_rig, options.max_disagreement_deg));

  out.choice.assign(num_cameras, std::vector<StepChoice>(num_steps, StepChoice::kNone));
  out.step_rotation.assign(num_cameras, PerFrame<Quat>(num_steps));
  for (int c = 0; c < num_cameras; ++c) {
    for (int k = 0; k < num_steps; ++k) {
      const StepPoses& s = steps[c][k];
      const auto& x = out.cam_from_rig[c];
      if (s.pair < 0) {
        if (x && out.rig_turn[k]) out.step_rotation[c][k] = *x * *out.rig_turn[k] * x->conjugate();
        continue;
      }
      if (!x || !out.rig_turn[k]) {
        out.choice[c][k] = StepChoice::kUndecided;
        out.step_rotation[c][k] = s.poses[0].rotation;
        continue;
      }
      const Quat predicted = *x * *out.rig_turn[k] * x->conjugate();
      const auto [i, d] = Nearest(s.poses, predicted);
      TwoViewEstimate& tv = out.temporal[s.pair].two_view;
      if (d > options.max_disagreement_deg) {
        out.choice[c][k] = StepChoice::kDisagrees;
        out.step_rotation[c][k] = predicted;
        out.temporal[s.pair].pose_left_out = "its turn is " + Fixed(RotationDifferenceDeg(s.poses[0].rotation, predicted), 1) +
                            " deg from the rig's between these frames (seen by the other cameras), and no other pose "
                            "of its matches agrees";
        ++out.pairs_disagreeing;
        continue;
      }
      out.step_rotation[c][k] = s.poses[i].rotation;
      out.choice[c][k] = i == 0 ? StepChoice::kAgrees : StepChoice::kAlternative;
      if (i > 0) {
        std::swap(tv.cam_b_from_cam_a, tv.planar_alternatives[i - 1]);
        ++out.alternatives_taken;
      }
    }
  }
  out.rig_from_world.assign(std::max(num_frames, 0), std::nullopt);
  if (num_frames > 0) out.rig_from_world[0] = Quat::Identity();
  for (int k = 0; k < num_steps && out.rig_from_world[k]; ++k) {
    const std::optional<Quat> turn = out.rig_turn[k] ? out.rig_turn[k] : out.step_rotation[0][k];
    if (turn) out.rig_from_world[k + 1] = (*turn * *out.rig_from_world[k]).normalized();
  }
  return out;
}

}  // namespace rigsim
