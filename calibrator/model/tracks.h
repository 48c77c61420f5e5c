// Tracks: the views (camera, frame) that see one 3D point, joined from the pairs' matches. The
// rig's bundle adjustment triangulates them; the stages count and weigh them.
#pragma once

#include <vector>

#include "calibrator/model/correspondences.h"
#include "calibrator/model/view_graph.h"

namespace rigsim {

struct ViewObservation {
  int camera = -1;
  int frame = -1;
  int keypoint = -1;
};

// One 3D point (world frame) seen in any views, at most once per view; observations sorted by
// (frame, camera).
struct ViewTrack {
  std::vector<ViewObservation> observations;
};

// Union-find over (camera, frame, keypoint) nodes joined by the same-frame pair matches and the
// temporal matches (only successful temporal pairs count). A set holding two keypoints of one
// view is contradictory: dropped whole and counted in `num_conflicting`. Sets of one view are no
// tracks. Throws std::invalid_argument on indices out of range.
std::vector<ViewTrack> BuildViewTracks(int num_cameras, int num_frames, const std::vector<PairMatches>& pairs,
                                       const std::vector<TemporalPairEstimate>& temporal,
                                       int* num_conflicting = nullptr);

// BuildViewTracks with the inliers of successful cross-time pairs too (motion_links.h): tracks that
// join cameras which never see one thing at the same instant.
std::vector<ViewTrack> BuildViewTracksAcrossTime(int num_cameras, int num_frames, const std::vector<PairMatches>& pairs,
                                                 const std::vector<TemporalPairEstimate>& temporal,
                                                 const std::vector<CrossTimePairEstimate>& cross_time,
                                                 int* num_conflicting = nullptr);

}  // namespace rigsim
