// Registration through tracks: a camera that no pair places, placed against the points the placed
// cameras' tracks fix, as an incremental SfM registers an image. Its keypoints in every frame are
// matched with the placed cameras' views of the same and nearby frames; a keypoint matched to a
// keypoint of a triangulated track sees that point. The camera is fixed in the rig, so all frames'
// correspondences make one resection (estimators/rig_resection.h): many weak view pairs, none of
// which passes a pair's test alone, can together fix a camera. The registered camera's inlier
// matches become view pairs (RigObservations::cross_time), and the rig with the registered cameras
// is adjusted as it stands (registered_rig_adjustment.h).
#pragma once

#include <string>
#include <vector>

#include "calibrator/model/rig_observations.h"
#include "calibrator/model/tracks.h"
#include "calibrator/stages/motion_links.h"
#include "calibrator/stages/rig_options.h"
#include "calibrator/stages/rig_result.h"

namespace rigsim {

struct CameraRegistration {
  int camera = -1;
  bool registered = false;
  Rigid3d cam_from_rig;        // in `placed`'s rig frame and unit; set when registered
  int view_pairs_matched = 0;  // with placed views
  int correspondences = 0;     // keypoints matched to placed points
  int inliers = 0;
  double log10_false_alarms = 0.0;
  std::string reason;  // why not registered, with figures; empty when registered
  // The inlier matches, one entry per view pair with min_view_pair_inliers of them, as the rig stage
  // takes view pairs (two_view from the registered pose).
  std::vector<CrossTimePairEstimate> view_pairs;
};

struct TrackRegistration {
  std::vector<CameraRegistration> cameras;  // one per camera without a full pose in `placed`
  // The rig the cameras were registered into: `placed`'s placed cameras and the frames posed
  // (`placed`'s, or the reference camera's own motion's).
  RigPoses placed_poses;
  // When `cameras` is empty: why no camera could be tried (nothing posed or placed to register
  // against), in words for a camera's status.
  std::string why_none;

  bool AnyRegistered() const;
};

// Registers the cameras `placed` left without a full pose (not connected, rotation only) against
// the points of its placed cameras over its posed frames. `obs` are the observations `placed` was
// estimated from. Without cameras, and why_none says why, when nothing can be registered (no posed
// frame, no placed point).
TrackRegistration RegisterCamerasThroughTracks(const RigObservations& obs, const RigCalibrationResult& placed,
                                               const ViewPairMatcher& match, const TrackRegistrationOptions& options);

// The tracks of the cameras marked in `cameras` (one entry per camera): the inliers of the pairs
// between them that `placed` used, of their own motion, and of their view pairs across time.
std::vector<ViewTrack> TracksOfCameras(const RigObservations& obs, const RigCalibrationResult& placed,
                                       const std::vector<char>& cameras);

// `obs` with the registered cameras' inlier view pairs added as view pairs across time
// (cross_time): their tracks join the placed cameras' in the adjustment and in the next round.
RigObservations WithRegisteredViewPairs(const RigObservations& obs, const TrackRegistration& registration);

}  // namespace rigsim
