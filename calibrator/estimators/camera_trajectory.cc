#include "calibrator/estimators/camera_trajectory.h"

#include <stdexcept>

#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/model/rig_state.h"

namespace rigsim {

CameraTrajectory EstimateCameraTrajectory(const Camera& camera, int camera_index, const FrameKeypoints& keypoints,
                                          const std::vector<TemporalPairEstimate>& temporal,
                                          const PerFrame<Eigen::Quaterniond>& steps,
                                          const RigPositionOptions& options) {
  const int num_frames = static_cast<int>(keypoints.size());
  // The camera's temporal pairs, as pairs of a one-camera rig.
  std::vector<TemporalPairEstimate> own;
  for (const TemporalPairEstimate& t : temporal) {
    if (t.camera != camera_index || !t.two_view.success) continue;
    if (t.frame < 0 || t.frame + 1 >= num_frames) throw std::invalid_argument("EstimateCameraTrajectory: temporal pair out of range");
    own.push_back(t);
    own.back().camera = 0;
  }
  PerFrame<Eigen::Quaterniond> rotations(num_frames);
  if (num_frames > 0) rotations[0] = Eigen::Quaterniond::Identity();
  for (int k = 0; k + 1 < num_frames && k < static_cast<int>(steps.size()) && rotations[k] && steps[k]; ++k) {
    rotations[k + 1] = (*steps[k] * *rotations[k]).normalized();
  }
  std::vector<std::vector<Eigen::Vector2d>> own_keypoints(num_frames);
  for (int k = 0; k < num_frames; ++k) own_keypoints[k] = keypoints.at(k).at(camera_index);
  const std::vector<ViewTrack> tracks = BuildViewTracks(1, num_frames, {}, own);
  const auto centres = EstimateTrajectoryCentres(camera, own_keypoints, tracks, rotations, options);
  CameraTrajectory trajectory(num_frames);
  for (int k = 0; k < num_frames; ++k) {
    if (rotations[k] && centres[k]) trajectory[k] = Rigid3d(*rotations[k], -(*rotations[k] * *centres[k]));
  }
  return trajectory;
}

}  // namespace rigsim
