#include "calibrator/estimators/rig_positions.h"

#include <gtest/gtest.h>

#include "calibrator/estimators/multi_frame_rig.h"
#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

// A ring whose cameras share nothing, on a planar path that turns both ways: each camera's own
// tracks across frames, every rotation known.
struct IsolatedRing {
  SyntheticRig s;
  std::vector<ViewTrack> tracks;
  std::vector<std::optional<Eigen::Quaterniond>> cam_from_rig, rig_from_world;

  explicit IsolatedRing(uint32_t seed) {
    SyntheticRigOptions o;
    o.cameras.assign(4, Camera::PinholeFromHorizontalFov(640, 360, 90.0));
    o.ring_radius_m = 0.5;
    o.max_tilt_deg = 4.0;
    o.max_offset_m = 0.2;
    o.isolated_cameras = {0, 1, 2, 3};
    o.num_frames = 8;
    o.path = TurningPath(8, 1.5, 10.0, 2.0, 0.0, 0.0);
    o.noise_px = 0.2;
    o.seed = seed;
    s = SynthesizeRig(o);
    std::vector<TemporalPairEstimate> temporal;
    for (int c = 0; c < 4; ++c) {
      for (int k = 0; k + 1 < 8; ++k) {
        TemporalPairEstimate t;
        t.camera = c;
        t.frame = k;
        t.two_view.success = true;
        t.inliers = s.TrueMatches({k, c}, {k + 1, c});
        temporal.push_back(t);
      }
    }
    tracks = BuildViewTracks(4, 8, {}, temporal);
    for (const RigCamera& rc : s.rig.cameras) cam_from_rig.push_back(rc.cam_from_rig->rotation);
    for (const Rigid3d& p : s.rig_from_world) rig_from_world.push_back(p.rotation);
  }
  std::vector<Camera> Cameras() const {
    std::vector<Camera> out;
    for (const RigCamera& rc : s.rig.cameras) out.push_back(rc.camera);
    return out;
  }
};

// The motion fixes each centre across the turn axis; along it (the rig's y) nothing does. Held
// there, the centres come out right across the axis and at camera 0's height.
TEST(RigPositions, APlanarMotionPlacesCentresAcrossItsAxisWithTheHeightHeld) {
  IsolatedRing ring(TestSeed());
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitY();
  std::vector<std::optional<Eigen::Vector3d>> held(4, axis);
  held[0].reset();
  const RigPositions p = EstimateRigPositions(ring.Cameras(), ring.s.keypoints, ring.tracks, ring.cam_from_rig,
                                              ring.rig_from_world, {}, false, held);
  ASSERT_TRUE(p.solved) << p.reason;
  // Compare in the plane across the axis, up to the common scale.
  double scale = 0.0, count = 0.0;
  for (int c = 1; c < 4; ++c) {
    ASSERT_TRUE(p.centre_in_rig[c]) << c;
    EXPECT_NEAR(p.centre_in_rig[c]->dot(axis), 0.0, 1e-9) << c;
    Eigen::Vector3d truth = ring.s.rig.cameras[c].cam_from_rig->SourceOriginInTarget();
    truth -= axis * axis.dot(truth);
    EXPECT_LT(AngleBetweenDeg(*p.centre_in_rig[c], truth), 3.0) << c;
    scale += p.centre_in_rig[c]->norm() / truth.norm();
    count += 1;
  }
  // One scale for every camera: the rig's motion links them.
  for (int c = 1; c < 4; ++c) {
    Eigen::Vector3d truth = ring.s.rig.cameras[c].cam_from_rig->SourceOriginInTarget();
    truth -= axis * axis.dot(truth);
    EXPECT_NEAR(p.centre_in_rig[c]->norm(), scale / count * truth.norm(), 0.05 * scale / count * truth.norm()) << c;
  }
}

TEST(RigPositions, HeldAxesNeedOneEntryPerCamera) {
  IsolatedRing ring(TestSeed());
  EXPECT_THROW(EstimateRigPositions(ring.Cameras(), ring.s.keypoints, ring.tracks,
                                    ring.cam_from_rig, ring.rig_from_world, {}, false,
                                    {Eigen::Vector3d::UnitY()}),
               std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
