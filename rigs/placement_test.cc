#include "rigs/placement.h"

#include <cmath>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "rigs/trajectories.h"

namespace rigsim {
namespace {

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
