#include "calibrator/model/tracks.h"

#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "calibrator/model/union_find.h"

namespace rigsim {

std::vector<ViewTrack> BuildViewTracks(int num_cameras, int num_frames, const std::vector<PairMatches>& pairs,
                                       const std::vector<TemporalPairEstimate>& temporal, int* num_conflicting) {
  return BuildViewTracksAcrossTime(num_cameras, num_frames, pairs, temporal, {}, num_conflicting);
}

std::vector<ViewTrack> BuildViewTracksAcrossTime(int num_cameras, int num_frames, const std::vector<PairMatches>& pairs,
                                                 const std::vector<TemporalPairEstimate>& temporal,
                                                 const std::vector<CrossTimePairEstimate>& cross_time,
                                                 int* num_conflicting) {
  for (const PairMatches& p : pairs) {
    if (p.cam_a < 0 || p.cam_b < 0 || p.cam_a >= num_cameras || p.cam_b >= num_cameras || p.cam_a == p.cam_b ||
        static_cast<int>(p.per_frame.size()) != num_frames) {
      throw std::invalid_argument("BuildViewTracks: bad camera pair (" + std::to_string(p.cam_a) + ", " +
                                  std::to_string(p.cam_b) + ") or number of frames");
    }
  }
  for (const TemporalPairEstimate& t : temporal) {
    if (t.camera < 0 || t.camera >= num_cameras || t.frame < 0 || t.frame + 1 >= num_frames) {
      throw std::invalid_argument("BuildViewTracks: temporal pair (camera " + std::to_string(t.camera) + ", frame " +
                                  std::to_string(t.frame) + ") out of range");
    }
  }
  for (const CrossTimePairEstimate& x : cross_time) {
    if (x.cam_a < 0 || x.cam_b < 0 || x.cam_a >= num_cameras || x.cam_b >= num_cameras || x.frame_a < 0 ||
        x.frame_b < 0 || x.frame_a >= num_frames || x.frame_b >= num_frames ||
        (x.cam_a == x.cam_b && x.frame_a == x.frame_b)) {
      throw std::invalid_argument("BuildViewTracks: cross-time pair out of range");
    }
  }
  std::map<std::tuple<int, int, int>, int> node_of;  // (frame, camera, keypoint) -> id
  std::vector<ViewObservation> nodes;
  UnionFind uf;
  auto node = [&](int cam, int frame, int kp) {
    const auto [it, inserted] = node_of.try_emplace({frame, cam, kp}, static_cast<int>(nodes.size()));
    if (inserted) {
      nodes.push_back({cam, frame, kp});
      uf.Add();
    }
    return it->second;
  };
  for (const PairMatches& p : pairs) {
    for (int f = 0; f < num_frames; ++f) {
      for (const auto& [ka, kb] : p.per_frame[f]) uf.Join(node(p.cam_a, f, ka), node(p.cam_b, f, kb));
    }
  }
  for (const TemporalPairEstimate& t : temporal) {
    if (!t.two_view.success) continue;
    for (const auto& [ka, kb] : t.inliers) uf.Join(node(t.camera, t.frame, ka), node(t.camera, t.frame + 1, kb));
  }
  for (const CrossTimePairEstimate& x : cross_time) {
    if (!x.two_view.success) continue;
    for (const auto& [ka, kb] : x.inliers) uf.Join(node(x.cam_a, x.frame_a, ka), node(x.cam_b, x.frame_b, kb));
  }
  // Nodes are ids in creation order; group by root, observations sorted by (frame, camera, kp).
  std::map<int, std::vector<ViewObservation>> groups;
  for (const auto& [key, id] : node_of) groups[uf.Find(id)].push_back(nodes[id]);
  std::vector<ViewTrack> tracks;
  int conflicting = 0;
  for (auto& [root, obs] : groups) {
    bool conflict = false;
    for (size_t i = 1; i < obs.size(); ++i) {
      conflict = conflict || (obs[i].frame == obs[i - 1].frame && obs[i].camera == obs[i - 1].camera);
    }
    if (conflict) {
      ++conflicting;
      continue;
    }
    if (obs.size() >= 2) tracks.push_back({std::move(obs)});
  }
  if (num_conflicting) *num_conflicting = conflicting;
  return tracks;
}

}  // namespace rigsim
