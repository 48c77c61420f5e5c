#include "calibrator/estimators/cross_time_candidates.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>

#include "geometry/rigid3.h"

namespace rigsim {
namespace {

// The grid of a's pixels carried into b, and the largest angle (deg) at which two views of one
// point still match (descriptors are not invariant to much more).
constexpr int kGridX = 12, kGridY = 7;
constexpr double kMaxViewAngleDeg = 40.0;

bool Known(const CrossTimeCandidateInputs& in, int cam, int frame) {
  return in.cam_from_rig[cam] && in.rig_from_world[frame];
}

// The rig's turn from frame t to t' (rotation vector of rig(t')_from_rig(t)).
Eigen::Vector3d Turn(const CrossTimeCandidateInputs& in, int t, int u) {
  return RotationVector(*in.rig_from_world[u] * in.rig_from_world[t]->conjugate());
}

double Travel(const CrossTimeCandidateInputs& in, int t, int u) {
  const auto& a = in.rig_centre_in_world[t];
  const auto& b = in.rig_centre_in_world[u];
  return a && b ? (*a - *b).norm() : std::abs(u - t);
}

// Predicted view pairs of one camera pair: best overlap first, spread over the path.
void Predicted(const CrossTimeCandidateInputs& in, int a, int b, const CrossTimeCandidateOptions& o,
               std::vector<CrossTimeCandidate>* out) {
  const int num_frames = static_cast<int>(in.rig_from_world.size());
  std::vector<CrossTimeCandidate> scored;
  for (int t = 0; t < num_frames; ++t) {
    for (int u = 0; u < num_frames; ++u) {
      if (t == u || (a == b && std::abs(u - t) < o.min_frame_gap) || (a == b && u < t)) continue;
      const auto overlap = PredictedViewOverlap(in, a, t, b, u);
      if (overlap && *overlap >= o.min_predicted_overlap) scored.push_back({a, t, b, u, overlap});
    }
  }
  std::stable_sort(scored.begin(), scored.end(), [](const CrossTimeCandidate& x, const CrossTimeCandidate& y) {
    return *x.predicted_overlap > *y.predicted_overlap;
  });
  std::vector<CrossTimeCandidate> kept;
  for (const CrossTimeCandidate& c : scored) {
    if (static_cast<int>(kept.size()) >= o.max_per_camera_pair) break;
    const bool near_kept = std::any_of(kept.begin(), kept.end(), [&](const CrossTimeCandidate& k) {
      return std::abs(k.frame_a - c.frame_a) <= 1 && std::abs(k.frame_b - c.frame_b) <= 1;
    });
    if (!near_kept) kept.push_back(c);
  }
  out->insert(out->end(), kept.begin(), kept.end());
}

// Search view pairs of one camera pair: one per bin of the rig's turn, smallest turns first.
void Search(const CrossTimeCandidateInputs& in, int a, int b, const CrossTimeCandidateOptions& o,
            std::vector<CrossTimeCandidate>* out) {
  const int num_frames = static_cast<int>(in.rig_from_world.size());
  const double bin = DegToRad(o.turn_bin_deg);
  std::map<std::tuple<long, long, long>, std::pair<int, int>> best;  // bin -> (t, t')
  for (int t = 0; t < num_frames; ++t) {
    for (int u = 0; u < num_frames; ++u) {
      if (t == u || !in.rig_from_world[t] || !in.rig_from_world[u]) continue;
      const Eigen::Vector3d w = Turn(in, t, u);
      const std::tuple<long, long, long> key{std::lround(w.x() / bin), std::lround(w.y() / bin), std::lround(w.z() / bin)};
      const auto it = best.find(key);
      if (it == best.end() || Travel(in, t, u) < Travel(in, it->second.first, it->second.second)) best[key] = {t, u};
    }
  }
  std::vector<std::pair<double, std::pair<int, int>>> bins;
  for (const auto& [key, tu] : best) bins.push_back({Turn(in, tu.first, tu.second).norm(), tu});
  std::stable_sort(bins.begin(), bins.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  for (int i = 0; i < static_cast<int>(bins.size()) && i < o.max_search_per_camera_pair; ++i) {
    out->push_back({a, bins[i].second.first, b, bins[i].second.second, std::nullopt});
  }
}

}  // namespace

void CrossTimeCandidateOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("CrossTimeCandidateOptions: " + why); };
  if (!(min_predicted_overlap > 0 && min_predicted_overlap <= 1)) fail("min_predicted_overlap must be in (0, 1]");
  if (max_per_camera_pair < 0) fail("max_per_camera_pair must be >= 0");
  if (!(turn_bin_deg > 0)) fail("turn_bin_deg must be > 0");
  if (max_search_per_camera_pair < 0) fail("max_search_per_camera_pair must be >= 0");
  if (min_frame_gap < 2) fail("min_frame_gap must be >= 2");
}

std::optional<double> PredictedViewOverlap(const CrossTimeCandidateInputs& in, int a, int t, int b, int u) {
  if (!Known(in, a, t) || !Known(in, b, u)) return std::nullopt;
  const Camera& ca = in.cameras[a];
  const Camera& cb = in.cameras[b];
  const Eigen::Quaterniond world_from_a = (*in.cam_from_rig[a] * *in.rig_from_world[t]).conjugate();
  const Eigen::Quaterniond b_from_world = *in.cam_from_rig[b] * *in.rig_from_world[u];
  const bool finite = in.scene_depth && in.rig_centre_in_world[t] && in.rig_centre_in_world[u];
  int seen = 0, samples = 0;
  for (int i = 0; i < kGridX; ++i) {
    for (int j = 0; j < kGridY; ++j) {
      const Eigen::Vector2d px((i + 0.5) * ca.width() / kGridX - 0.5, (j + 0.5) * ca.height() / kGridY - 0.5);
      const auto f = ca.CamFromImg(px);
      if (!f) continue;
      ++samples;
      const Eigen::Vector3d d = world_from_a * f->normalized();
      Eigen::Vector3d ray_b = b_from_world * d;  // at infinity
      if (finite) {
        const Eigen::Vector3d x = *in.rig_centre_in_world[t] + *in.scene_depth * d;
        const Eigen::Vector3d from_b = x - *in.rig_centre_in_world[u];
        if (AngleBetweenDeg(d, from_b) > kMaxViewAngleDeg) continue;
        ray_b = b_from_world * from_b;
      }
      const auto pb = cb.ImgFromCam(ray_b);
      if (pb && pb->x() >= -0.5 && pb->y() >= -0.5 && pb->x() < cb.width() - 0.5 && pb->y() < cb.height() - 0.5) ++seen;
    }
  }
  return samples > 0 ? std::optional<double>(double(seen) / samples) : std::nullopt;
}

std::vector<CrossTimeCandidate> SelectCrossTimeCandidates(const CrossTimeCandidateInputs& in,
                                                          const CrossTimeCandidateOptions& options) {
  options.Check();
  const int n = static_cast<int>(in.cameras.size());
  const int num_frames = static_cast<int>(in.rig_from_world.size());
  if (static_cast<int>(in.cam_from_rig.size()) != n) {
    throw std::invalid_argument("SelectCrossTimeCandidates: one rotation entry per camera");
  }
  if (static_cast<int>(in.rig_centre_in_world.size()) != num_frames && !in.rig_centre_in_world.empty()) {
    throw std::invalid_argument("SelectCrossTimeCandidates: one centre entry per frame, or none");
  }
  CrossTimeCandidateInputs inputs = in;
  inputs.rig_centre_in_world.resize(num_frames);
  std::vector<CrossTimeCandidate> out;
  for (int a = 0; a < n; ++a) {
    for (int b = a; b < n; ++b) {
      if (inputs.cam_from_rig[a] && inputs.cam_from_rig[b]) {
        Predicted(inputs, a, b, options, &out);
      } else if (a != b) {
        Search(inputs, a, b, options, &out);
      }
    }
  }
  return out;
}

}  // namespace rigsim
