#include "calibrator/stages/rig_adjustment_cache.h"

#include <cstddef>
#include <utility>

namespace rigsim {
namespace {

template <typename T>
void AppendBits(const T& value, std::string* bits) {
  bits->append(reinterpret_cast<const char*>(&value), sizeof value);
}

void AppendPose(const std::optional<Rigid3d>& pose, std::string* bits) {
  AppendBits(pose.has_value(), bits);
  if (!pose) return;
  for (int i = 0; i < 4; ++i) AppendBits(pose->rotation.coeffs()[i], bits);
  for (int i = 0; i < 3; ++i) AppendBits(pose->translation[i], bits);
}

// Every observation of every track with the keypoint it observes: the solver reads the keypoints
// through the tracks only, and the number of frames from their size. False when an observation
// names a view or keypoint that is not there.
bool AppendTracks(const std::vector<ViewTrack>& tracks, const FrameKeypoints& keypoints, std::string* bits) {
  AppendBits(keypoints.size(), bits);
  for (const auto& frame : keypoints) AppendBits(frame.size(), bits);
  AppendBits(tracks.size(), bits);
  for (const ViewTrack& t : tracks) {
    AppendBits(t.observations.size(), bits);
    for (const ViewObservation& o : t.observations) {
      if (o.frame < 0 || o.frame >= static_cast<int>(keypoints.size()) || o.camera < 0 ||
          o.camera >= static_cast<int>(keypoints[o.frame].size()) || o.keypoint < 0 ||
          o.keypoint >= static_cast<int>(keypoints[o.frame][o.camera].size())) {
        return false;
      }
      const Eigen::Vector2d& x = keypoints[o.frame][o.camera][o.keypoint];
      AppendBits(o.camera, bits);
      AppendBits(o.frame, bits);
      AppendBits(o.keypoint, bits);
      AppendBits(x.x(), bits);
      AppendBits(x.y(), bits);
    }
  }
  return true;
}

}  // namespace

AdjustedStart AdjustStart(const StartAdjustmentInputs& in) {
  AdjustedStart out;
  out.ba = MultiFrameRigBundleAdjust(in.cameras, in.keypoints, in.tracks, in.start, in.scale_camera, in.options,
                                     in.hold_frames, in.timing);
  out.cost = TruncatedReprojectionCost(out.ba.cameras, in.keypoints, in.tracks, out.ba.poses,
                                       in.options.max_reprojection_error_px, in.options.min_triangulation_angle_deg,
                                       &out.cost_observations);
  return out;
}

std::optional<RigAdjustmentCache::Key> RigAdjustmentCache::KeyOf(const StartAdjustmentInputs& in) {
  Key key{in.cameras, in.options, std::nullopt, {}};
  if (in.timing) key.timing = *in.timing;
  if (!AppendTracks(in.tracks, in.keypoints, &key.bits)) return std::nullopt;
  AppendBits(in.scale_camera, &key.bits);
  AppendBits(in.hold_frames, &key.bits);
  AppendBits(in.start.cam_from_rig.size(), &key.bits);
  for (const auto& pose : in.start.cam_from_rig) AppendPose(pose, &key.bits);
  AppendBits(in.start.rig_from_world.size(), &key.bits);
  for (const auto& pose : in.start.rig_from_world) AppendPose(pose, &key.bits);
  return key;
}

AdjustedStart RigAdjustmentCache::Adjust(const StartAdjustmentInputs& in) {
  std::optional<Key> key = KeyOf(in);
  if (!key) return AdjustStart(in);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const Entry& e : entries_) {
      if (!(e.key == *key)) continue;
      AdjustedStart copy = e.adjusted;
      copy.reused = true;
      return copy;
    }
  }
  // Solved outside the lock: the other starts of the round solve at the same time.
  AdjustedStart adjusted = AdjustStart(in);
  std::lock_guard<std::mutex> lock(mutex_);
  entries_.push_back({*std::move(key), adjusted});
  return adjusted;
}

}  // namespace rigsim
