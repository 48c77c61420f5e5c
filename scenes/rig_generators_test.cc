#include "scenes/rig_generators.h"

#include <gtest/gtest.h>

namespace rigsim {
namespace {

TEST(RingRig, CamerasFaceOutwardsFromLeftToRight) {
  RingRigOptions o;
  o.num_cameras = 4;
  o.yaw_spacing_deg = 60;
  const Rig rig = MakeRingRig(o);
  ASSERT_EQ(rig.cameras.size(), 4u);
  double previous_yaw = -1e9;
  for (const RigCamera& c : rig.cameras) {
    const Rigid3d rig_from_cam = c.cam_from_rig->Inverse();
    const Eigen::Vector3d axis = rig_from_cam.rotation * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d centre = rig_from_cam.translation;
    EXPECT_NEAR(centre.norm(), o.radius_m, 1e-12);
    EXPECT_NEAR(axis.y(), 0.0, 1e-12);                            // horizontal
    EXPECT_LT((axis - centre.normalized()).norm(), 1e-12);        // facing outwards
    const double yaw = RadToDeg(std::atan2(axis.x(), axis.z()));  // + = right
    EXPECT_GT(yaw, previous_yaw);
    if (previous_yaw > -1e9) {
      EXPECT_NEAR(yaw - previous_yaw, 60.0, 1e-9);
    }
    previous_yaw = yaw;
    // Image y stays down.
    EXPECT_LT((rig_from_cam.rotation * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  }
}

TEST(RingRig, DistortedCameraKeepsTheFieldOfView) {
  RingRigOptions o;
  const Rig rig = MakeRingRig(o);
  const Camera& barrel = rig.cameras[o.distorted_camera].camera;
  const Camera& pinhole = rig.cameras[0].camera;
  EXPECT_EQ(barrel.model(), CameraModelId::kOpenCV);
  const double half = DegToRad(o.hfov_deg / 2);
  const Eigen::Vector3d edge_ray(std::sin(half), 0.0, std::cos(half));
  EXPECT_NEAR(barrel.ImgFromCam(edge_ray)->x(), o.width - 0.5, 1e-9);
  EXPECT_NEAR(pinhole.ImgFromCam(edge_ray)->x(), o.width - 0.5, 1e-9);
  // The whole sensor is imaged.
  EXPECT_TRUE(barrel.CamFromImg(Eigen::Vector2d(-0.5, -0.5)).has_value());
}

TEST(RigPlacement, HeadingZeroLooksDownMinusZUpright) {
  const Rigid3d rig_from_world = RigFromWorldAt(Eigen::Vector3d(1, 1.6, 2), 0.0);
  EXPECT_LT((rig_from_world * Eigen::Vector3d(1, 1.6, -3) - Eigen::Vector3d(0, 0, 5)).norm(), 1e-12);
  EXPECT_LT((rig_from_world * Eigen::Vector3d(1, 2.6, 2)).y(), 0.0);  // world up = rig -y
  const Rigid3d right = RigFromWorldAt(Eigen::Vector3d::Zero(), 90.0);
  EXPECT_GT((right * Eigen::Vector3d(5, 0, 0)).z(), 4.99);
}

TEST(Trajectory, MovesForwardByTheStep) {
  const FramesFile f = MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 0), 0.0, 3, 2.0, 0.5);
  ASSERT_EQ(f.frames.size(), 3u);
  EXPECT_EQ(f.frames[2].name, "000002");
  EXPECT_DOUBLE_EQ(f.frames[2].timestamp_s, 1.0);
  const Eigen::Vector3d c2 = f.frames[2].rig_from_world->SourceOriginInTarget();
  EXPECT_LT((c2 - Eigen::Vector3d(0, 1.6, -4)).norm(), 1e-12);
}

}  // namespace
}  // namespace rigsim

namespace rigsim {
namespace {

Eigen::Vector3d Centre(const RigCamera& c) { return c.cam_from_rig->Inverse().translation; }
Eigen::Vector3d Axis(const RigCamera& c) { return c.cam_from_rig->Inverse().rotation * Eigen::Vector3d::UnitZ(); }

TEST(RingRig, TargetOverlapSetsTheSpacing) {
  for (double target : {0.1, 0.3, 0.5}) {
    RingRigOptions o;
    o.num_cameras = 3;
    o.distorted_camera = -1;
    const double spacing = RingSpacingForOverlap(o, target);
    // Independent check in normalised coordinates: a pinhole point (u, v) of camera a, rotated
    // about y by the spacing, is seen by b when |u_b| <= tan(h/2) and |v_b| <= tan(vfov/2).
    const double tu = std::tan(DegToRad(o.hfov_deg / 2)), tv = tu * o.height / o.width, s = DegToRad(spacing);
    int seen = 0, total = 0;
    for (int j = 0; j < 225; ++j) {
      for (int i = 0; i < 400; ++i, ++total) {
        const double u = tu * ((i + 0.5) / 200 - 1), v = tv * ((j + 0.5) / 112.5 - 1);
        const double z = u * std::sin(s) + std::cos(s);
        if (z > 0 && std::abs((u * std::cos(s) - std::sin(s)) / z) <= tu && std::abs(v / z) <= tv) ++seen;
      }
    }
    EXPECT_NEAR(double(seen) / total, target, 0.01) << "spacing " << spacing;
    o.target_overlap = target;
    const Rig rig = MakeRingRig(o);
    const double yaw0 = std::atan2(Axis(rig.cameras[0]).x(), Axis(rig.cameras[0]).z());
    const double yaw1 = std::atan2(Axis(rig.cameras[1]).x(), Axis(rig.cameras[1]).z());
    EXPECT_NEAR(RadToDeg(yaw1 - yaw0), spacing, 1e-6);
  }
  RingRigOptions o;
  o.target_overlap = 0.99;
  o.distorted_camera = -1;
  EXPECT_GT(AngularOverlap(MakeRingRig(o).cameras[0].camera, MakeRingRig(o).cameras[1].camera, Eigen::Matrix3d::Identity()), 0.99);
}

TEST(StereoRig, BaselineAndParallelAxes) {
  StereoRigOptions o;
  o.baseline_m = 0.3;
  const Rig rig = MakeStereoRig(o);
  ASSERT_EQ(rig.cameras.size(), 2u);
  EXPECT_EQ(rig.cameras[0].name, "left");
  EXPECT_NEAR((Centre(rig.cameras[1]) - Centre(rig.cameras[0])).norm(), 0.3, 1e-12);
  EXPECT_GT(Centre(rig.cameras[1]).x(), Centre(rig.cameras[0]).x());  // right is at +x
  EXPECT_LT((Axis(rig.cameras[0]) - Axis(rig.cameras[1])).norm(), 1e-12);
}

TEST(SurroundRig, MixedModelsAndFisheyeBeyond180) {
  SurroundRigOptions o;
  const Rig rig = MakeSurroundRig(o);
  ASSERT_EQ(rig.cameras.size(), 4u);
  EXPECT_EQ(rig.cameras[0].camera.model(), CameraModelId::kOpenCV);
  EXPECT_EQ(rig.cameras[1].camera.model(), CameraModelId::kOpenCVFisheye);
  EXPECT_EQ(rig.cameras[2].camera.model(), CameraModelId::kPinhole);
  EXPECT_EQ(rig.cameras[3].camera.model(), CameraModelId::kOpenCVFisheye);
  // The right fisheye images the ray 95 deg off its axis at its right image edge.
  const Camera& fish = rig.cameras[1].camera;
  const double theta = DegToRad(o.side_fov_deg / 2);
  const auto px = fish.ImgFromCam(Eigen::Vector3d(std::sin(theta), 0, std::cos(theta)));
  ASSERT_TRUE(px.has_value());
  EXPECT_NEAR(px->x(), fish.width() - 0.5, 1e-6);
  EXPECT_GT(RadToDeg(fish.max_valid_angle()), 95.0);
  // Directions: front +z, right +x, back -z, left -x in the rig frame.
  EXPECT_NEAR(Axis(rig.cameras[0]).z(), 1, 1e-12);
  EXPECT_NEAR(Axis(rig.cameras[1]).x(), 1, 1e-12);
  EXPECT_NEAR(Axis(rig.cameras[2]).z(), -1, 1e-12);
  EXPECT_NEAR(Axis(rig.cameras[3]).x(), -1, 1e-12);
  EXPECT_NEAR(Centre(rig.cameras[0]).z(), 2.0, 1e-12);
}

TEST(WideBaselineRig, BaselineAndConvergence) {
  WideBaselineRigOptions o;
  o.baseline_m = 3.0;
  o.convergence_deg = 40.0;
  const Rig rig = MakeWideBaselineRig(o);
  EXPECT_NEAR((Centre(rig.cameras[1]) - Centre(rig.cameras[0])).norm(), 3.0, 1e-12);
  EXPECT_NEAR(AngleBetweenDeg(Axis(rig.cameras[0]), Axis(rig.cameras[1])), 40.0, 1e-9);
  // Toed in: the axes meet in front of the rig.
  EXPECT_GT(Axis(rig.cameras[0]).x(), 0);
  EXPECT_LT(Axis(rig.cameras[1]).x(), 0);
}

TEST(RigPerturbation, SeededAndBounded) {
  Rig a = MakeStereoRig({}), b = MakeStereoRig({}), ref = MakeStereoRig({});
  PerturbRig(a, {2.0, 0.01, 7});
  PerturbRig(b, {2.0, 0.01, 7});
  for (size_t i = 0; i < a.cameras.size(); ++i) {
    EXPECT_EQ(a.cameras[i].cam_from_rig->translation, b.cameras[i].cam_from_rig->translation);
    const double rot = RotationDifferenceDeg(a.cameras[i].cam_from_rig->rotation, ref.cameras[i].cam_from_rig->rotation);
    EXPECT_GT(rot, 0.0);
    EXPECT_LE(rot, 2.0 + 1e-9);
  }
}

TEST(Trajectory, CircleKeepsRadiusAndTangentHeading) {
  TrajectoryOptions o;
  o.kind = TrajectoryKind::kCircle;
  o.circle_radius_m = 5.0;  // turning left
  o.num_frames = 9;
  o.step_m = 2 * 3.14159265358979 * 5.0 / 8;  // 8 steps = one lap
  o.start_world = Eigen::Vector3d(1, 1.6, 2);
  const FramesFile f = MakeTrajectory(o);
  const Eigen::Vector3d centre = o.start_world + Eigen::Vector3d(-5, 0, 0);  // left of heading 0 (-Z) is -X
  for (const Frame& fr : f.frames) {
    const Rigid3d world_from_rig = fr.rig_from_world->Inverse();
    const Eigen::Vector3d p = world_from_rig.translation;
    EXPECT_NEAR((p - centre).norm(), 5.0, 1e-9);
    const Eigen::Vector3d forward = world_from_rig.rotation * Eigen::Vector3d::UnitZ();
    EXPECT_NEAR(forward.dot(p - centre), 0.0, 1e-9);  // tangent
  }
  EXPECT_LT((f.frames[8].rig_from_world->Inverse().translation - o.start_world).norm(), 1e-9);
  EXPECT_LT((f.frames[2].rig_from_world->Inverse().translation - (centre + Eigen::Vector3d(0, 0, -5))).norm(), 1e-9);
}

TEST(Trajectory, PolylineFollowsWaypoints) {
  TrajectoryOptions o;
  o.kind = TrajectoryKind::kPolyline;
  o.start_world = Eigen::Vector3d(0, 1.6, 0);
  o.waypoints = {Eigen::Vector3d(0, 1.6, -4), Eigen::Vector3d(4, 1.6, -4)};
  o.num_frames = 6;
  o.step_m = 2.0;
  const FramesFile f = MakeTrajectory(o);
  auto pos = [&](int k) { return f.frames[k].rig_from_world->Inverse().translation; };
  EXPECT_LT((pos(2) - Eigen::Vector3d(0, 1.6, -4)).norm(), 1e-12);
  EXPECT_LT((pos(3) - Eigen::Vector3d(2, 1.6, -4)).norm(), 1e-12);
  EXPECT_LT((pos(5) - Eigen::Vector3d(4, 1.6, -4)).norm(), 1e-12);  // stops at the end
  const Eigen::Vector3d fwd = f.frames[3].rig_from_world->Inverse().rotation * Eigen::Vector3d::UnitZ();
  EXPECT_LT((fwd - Eigen::Vector3d::UnitX()).norm(), 1e-12);  // heading 90 along the second segment
}

// A 40 x 40 m ground with a closed box building and a long wall.
Scene PlacementScene() {
  Scene s;
  auto quad = [&](Eigen::Vector3f a, Eigen::Vector3f b, Eigen::Vector3f c, Eigen::Vector3f d) {
    SceneMesh m;
    m.positions = {a, b, c, d};
    m.indices = {0, 1, 2, 0, 2, 3};
    s.meshes.push_back(m);
  };
  quad({-20, 0, -20}, {20, 0, -20}, {20, 0, 20}, {-20, 0, 20});
  auto box = [&](Eigen::Vector3f lo, Eigen::Vector3f hi) {
    quad({lo.x(), lo.y(), lo.z()}, {hi.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), lo.z()}, {lo.x(), hi.y(), lo.z()});
    quad({lo.x(), lo.y(), hi.z()}, {hi.x(), lo.y(), hi.z()}, {hi.x(), hi.y(), hi.z()}, {lo.x(), hi.y(), hi.z()});
    quad({lo.x(), lo.y(), lo.z()}, {lo.x(), lo.y(), hi.z()}, {lo.x(), hi.y(), hi.z()}, {lo.x(), hi.y(), lo.z()});
    quad({hi.x(), lo.y(), lo.z()}, {hi.x(), lo.y(), hi.z()}, {hi.x(), hi.y(), hi.z()}, {hi.x(), hi.y(), lo.z()});
    quad({lo.x(), hi.y(), lo.z()}, {hi.x(), hi.y(), lo.z()}, {hi.x(), hi.y(), hi.z()}, {lo.x(), hi.y(), hi.z()});
  };
  box({-20, 0, -20}, {20, 8, -12});   // building along the north edge
  box({-5, 0, 0}, {5, 10, 10});       // a block in the middle
  box({-20, 0, 18}, {20, 3, 18.3f});  // a wall along the south edge
  return s;
}

TEST(RigPlacement, CastRayHitsTheNearestSurface) {
  const Scene s = PlacementScene();
  EXPECT_NEAR(*CastRay(s, Eigen::Vector3d(0, 1.6, -5), Eigen::Vector3d(0, 0, -1)), 7.0, 1e-9);
  EXPECT_NEAR(*CastRay(s, Eigen::Vector3d(0, 1.6, -5), Eigen::Vector3d(0, 0, 1)), 5.0, 1e-9);
  EXPECT_NEAR(*CastRay(s, Eigen::Vector3d(15, 1.6, -5), Eigen::Vector3d(0, -1, 0)), 1.6, 1e-9);
  EXPECT_NEAR(*CastRay(s, Eigen::Vector3d(-30, 1.6, 5), Eigen::Vector3d(1, 0, 0)), 25.0, 1e-9);  // from outside the grid
  EXPECT_FALSE(CastRay(s, Eigen::Vector3d(15, 1.6, -5), Eigen::Vector3d(0, 1, 0)).has_value());
}

TEST(RigPlacement, OnTheGroundOutsideGeometryAndClearOfWalls) {
  const Scene s = PlacementScene();
  RingRigOptions ring;
  ring.num_cameras = 3;
  const Rig rig = MakeRingRig(ring);
  PlacementOptions o;
  o.min_clearance_m = 2.0;
  const auto placement = PlaceRig(s, rig, o);
  ASSERT_TRUE(placement.has_value());
  const Eigen::Vector3d p = placement->position_world;
  EXPECT_NEAR(p.y(), 1.6, 1e-9);                                  // on the ground, not on a roof
  EXPECT_FALSE(p.z() < -12 || (std::abs(p.x()) < 5 && p.z() > 0 && p.z() < 10));  // not inside a building
  EXPECT_GT(placement->score, 0.5);
  const Rigid3d world_from_rig = RigFromWorldAt(p, placement->heading_deg).Inverse();
  for (const RigCamera& c : rig.cameras) {
    const Rigid3d world_from_cam = world_from_rig * c.cam_from_rig->Inverse();
    const auto d = CastRay(s, world_from_cam.translation, world_from_cam.rotation * Eigen::Vector3d::UnitZ());
    if (d) {
      EXPECT_GE(*d, 2.0) << c.name;
    }
  }
  // Same seed, same answer; an empty scene gives none.
  const auto again = PlaceRig(s, rig, o);
  EXPECT_EQ(again->position_world, p);
  EXPECT_FALSE(PlaceRig(Scene{}, rig, o).has_value());
}

}  // namespace
}  // namespace rigsim
