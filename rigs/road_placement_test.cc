// Road placement (PlaceRig with PlacementMode::kRoad) on a small street: a road strip with
// sidewalks and buildings beside it, turned so that the road runs along no world axis.

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "labels/cityscapes.h"
#include "rigs/placement.h"
#include "rigs/trajectories.h"
#include "testing/expect_error.h"

namespace rigsim {
namespace {

// The street's frame: u across the road (to the right looking along -v), v along it; the world
// is the street turned by `yaw_deg` about +Y.
struct Street {
  double yaw_deg = 30.0;
  double road_half_width = 4.0;  // 8 m: two lanes
  double half_length = 60.0;
  Eigen::Vector3f World(double u, double y, double v) const {
    const Eigen::Vector3d p = Eigen::AngleAxisd(DegToRad(yaw_deg), Eigen::Vector3d::UnitY()) * Eigen::Vector3d(u, y, v);
    return p.cast<float>();
  }
  // (across, along) of a world point.
  Eigen::Vector2d Local(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d q = Eigen::AngleAxisd(-DegToRad(yaw_deg), Eigen::Vector3d::UnitY()) * p;
    return Eigen::Vector2d(q.x(), q.z());
  }
  // The road's axis as a heading (rigs/trajectories.h): along -v.
  double AxisHeadingDeg() const {
    const Eigen::Vector3f d = World(0, 0, -1);
    return RadToDeg(std::atan2(d.x(), -d.z()));
  }
};

uint8_t Id(const char* name) { return FindClassByName(name)->id; }

// The road (labelled `road_class`), sidewalks 4 m wide at curb height and a row of buildings on
// each side with gaps between them, and a building closing each end of the street.
Scene StreetScene(const Street& st, const char* road_class = "road") {
  Scene s;
  auto quad = [&](uint8_t cls, Eigen::Vector3f a, Eigen::Vector3f b, Eigen::Vector3f c, Eigen::Vector3f d) {
    SceneMesh m;
    m.class_id = cls;
    m.positions = {a, b, c, d};
    m.indices = {0, 1, 2, 0, 2, 3};
    s.meshes.push_back(m);
  };
  auto flat = [&](uint8_t cls, double u0, double u1, double v0, double v1, double y) {
    quad(cls, st.World(u0, y, v0), st.World(u1, y, v0), st.World(u1, y, v1), st.World(u0, y, v1));
  };
  auto box = [&](double u0, double u1, double v0, double v1, double h) {
    const uint8_t b = Id("building");
    quad(b, st.World(u0, 0, v0), st.World(u1, 0, v0), st.World(u1, h, v0), st.World(u0, h, v0));
    quad(b, st.World(u0, 0, v1), st.World(u1, 0, v1), st.World(u1, h, v1), st.World(u0, h, v1));
    quad(b, st.World(u0, 0, v0), st.World(u0, 0, v1), st.World(u0, h, v1), st.World(u0, h, v0));
    quad(b, st.World(u1, 0, v0), st.World(u1, 0, v1), st.World(u1, h, v1), st.World(u1, h, v0));
    flat(b, u0, u1, v0, v1, h);
  };
  const double w = st.road_half_width, L = st.half_length;
  flat(Id(road_class), -w, w, -L, L, 0.0);
  flat(Id("sidewalk"), w, w + 4, -L, L, 0.15);
  flat(Id("sidewalk"), -w - 4, -w, -L, L, 0.15);
  for (double v = -L; v < L; v += 20) {
    box(w + 4, w + 14, v, v + 16, 12);
    box(-w - 14, -w - 4, v + 4, v + 20, 15);
  }
  box(-w - 14, w + 14, L, L + 5, 20);
  box(-w - 14, w + 14, -L - 5, -L, 20);
  return s;
}

// A car's rig in its own frame: a front camera at the origin, two side cameras and a rear camera
// 1.3 m behind, all at the front camera's height.
Rig CarRig() {
  Rig rig;
  const Camera cam(CameraModelId::kPinhole, 640, 400, {400, 400, 319.5, 199.5});
  auto add = [&](const char* name, double yaw_deg, const Eigen::Vector3d& centre_in_rig) {
    // Camera z along the rig's z turned by yaw about the rig's y (down): positive yaw looks right.
    const Eigen::Matrix3d rig_from_cam = Eigen::AngleAxisd(DegToRad(yaw_deg), Eigen::Vector3d::UnitY()).toRotationMatrix();
    rig.cameras.push_back({name, cam, Rigid3d(rig_from_cam, centre_in_rig).Inverse(), 0.0});
  };
  add("front", 0, {0, 0, 0});
  add("right", 90, {0.7, 0, -0.4});
  add("left", -90, {-0.2, 0, -0.4});
  add("rear", 180, {0.1, 0, -1.3});
  return rig;
}

PlacementOptions RoadOptions(uint64_t seed = 1) {
  PlacementOptions o;
  o.mode = PlacementMode::kRoad;
  o.seed = seed;
  o.num_candidates = 60;
  return o;
}

// The heading's difference from the road's axis, either way along it (deg, 0..90).
double OffAxisDeg(double heading_deg, double axis_deg) {
  const double d = std::fmod(std::abs(heading_deg - axis_deg), 180.0);
  return std::min(d, 180.0 - d);
}

// Whether every point of the path, every 0.25 m, keeps the rig's centre and 1 m to each side on the
// road (the scene's geometry, not the placement's raster).
bool OnTheRoadAllAlong(const Street& st, const TrajectoryOptions& path) {
  const double closed = ClosedPathLength(path);
  const double total = closed > 0 ? closed : (path.num_frames - 1) * path.step_m;
  const int n = std::max(1, int(std::ceil(std::abs(total) / 0.25)));
  for (int k = 0; k <= n; ++k) {
    const Rigid3d world_from_rig = RigFromWorldAlongPath(path, total * k / n).Inverse();
    const Eigen::Vector3d right = world_from_rig.rotation * Eigen::Vector3d::UnitX();
    for (double side : {-1.0, 0.0, 1.0}) {
      const Eigen::Vector2d p = st.Local(world_from_rig.translation + side * right);
      if (std::abs(p.x()) > st.road_half_width || std::abs(p.y()) > st.half_length) return false;
    }
  }
  return true;
}

TEST(RoadPlacement, InTheRightHandLaneHeadingAlongTheRoadAtItsHeight) {
  const Street st;
  const Scene s = StreetScene(st);
  const Rig rig = CarRig();
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const auto placed = PlaceRig(s, rig, RoadOptions(seed));
    ASSERT_TRUE(placed.has_value()) << "seed " << seed;
    ASSERT_TRUE(placed->road.has_value());
    EXPECT_LT(OffAxisDeg(placed->heading_deg, st.AxisHeadingDeg()), 1.0) << "heading " << placed->heading_deg;
    EXPECT_NEAR(placed->position_world.y(), 1.6, 1e-6);  // the rig's origin, its front camera, 1.6 m above the road
    // In a lane: a quarter of the 8 m road to the right of the centre line, looking along the heading.
    const Eigen::Vector3d right = HeadingDirection(placed->heading_deg + 90.0);
    const Eigen::Vector3d centre_line_point = st.World(0, 1.6, st.Local(placed->position_world).y()).cast<double>();
    EXPECT_NEAR((placed->position_world - centre_line_point).dot(right), 2.0, 0.3);
    EXPECT_NEAR(placed->road->width_m, 8.0, 0.5);
    EXPECT_NEAR(placed->road->lane_offset_m, 2.0, 0.15);
    // The middle of the street, where the road runs far both ways.
    EXPECT_GT(std::min(placed->road->clear_ahead_m, placed->road->clear_behind_m), 40.0);
    const auto again = PlaceRig(s, rig, RoadOptions(seed));
    EXPECT_EQ(again->position_world, placed->position_world);
    EXPECT_EQ(again->heading_deg, placed->heading_deg);
  }
}

TEST(RoadPlacement, ANarrowRoadIsDrivenOnItsCentreLine) {
  Street st;
  st.road_half_width = 2.0;  // 4 m: one lane
  st.yaw_deg = -70.0;
  const auto placed = PlaceRig(StreetScene(st), CarRig(), RoadOptions());
  ASSERT_TRUE(placed.has_value());
  EXPECT_LT(OffAxisDeg(placed->heading_deg, st.AxisHeadingDeg()), 1.0);
  EXPECT_NEAR(st.Local(placed->position_world).x(), 0.0, 0.3);
  EXPECT_EQ(placed->road->lane_offset_m, 0.0);
}

TEST(RoadPlacement, EveryPathStaysOnTheRoadOrIsRefused) {
  const Street st;
  const Scene s = StreetScene(st);
  const Rig rig = CarRig();
  TrajectoryOptions straight;
  straight.num_frames = 20;
  straight.step_m = 2.0;  // 38 m along the lane
  TrajectoryOptions circle;
  circle.kind = TrajectoryKind::kCircle;
  circle.num_frames = 8;
  circle.step_m = 2.0;
  circle.circle_radius_m = 40.0;  // a bend: 14 m of a wide arc
  TrajectoryOptions small_loop = circle;
  small_loop.kind = TrajectoryKind::kLoop;
  small_loop.circle_radius_m = 2.0;  // 4 m across: within the 8 m road
  TrajectoryOptions handheld = circle;
  handheld.kind = TrajectoryKind::kHandheld;
  TrajectoryOptions eight = small_loop;
  eight.kind = TrajectoryKind::kFigureEight;
  // Laps on both sides of the start: from the lane, 2 m right of the centre line, 4 radii across.
  eight.circle_radius_m = 0.4;
  for (const TrajectoryOptions& path : {straight, circle, small_loop, handheld, eight}) {
    const auto placed = PlaceRig(s, rig, RoadOptions(), &path);
    ASSERT_TRUE(placed.has_value()) << DescribePath(path);
    EXPECT_LT(OffAxisDeg(placed->heading_deg, st.AxisHeadingDeg()), 1.0) << DescribePath(path);
    TrajectoryOptions along = path;
    along.start_world = placed->position_world;
    along.heading_deg = placed->heading_deg;
    EXPECT_TRUE(OnTheRoadAllAlong(st, along)) << DescribePath(path);
  }
  // A straight drive goes along the lane: 38 m on, still a quarter of the road right of the centre.
  const auto placed = PlaceRig(s, rig, RoadOptions(), &straight);
  const Eigen::Vector3d end = placed->position_world + 38.0 * HeadingDirection(placed->heading_deg);
  EXPECT_NEAR(std::abs(st.Local(end).x()), 2.0, 0.3);
  // Turning circles wider than the road, and paths longer than the street, fit nowhere.
  TrajectoryOptions loop = small_loop;
  loop.circle_radius_m = 12.0;
  EXPECT_FALSE(PlaceRig(s, rig, RoadOptions(), &loop).has_value());
  TrajectoryOptions tight = circle;
  tight.circle_radius_m = 6.0;  // 14 m of arc: 130 deg, across the road
  EXPECT_FALSE(PlaceRig(s, rig, RoadOptions(), &tight).has_value());
  TrajectoryOptions wide_eight = eight;
  wide_eight.circle_radius_m = 1.5;  // its right lap would leave the road
  EXPECT_FALSE(PlaceRig(s, rig, RoadOptions(), &wide_eight).has_value());
  TrajectoryOptions too_long = straight;
  too_long.num_frames = 70;  // 138 m on a 120 m street
  EXPECT_FALSE(PlaceRig(s, rig, RoadOptions(), &too_long).has_value());
}

TEST(RoadPlacement, AWithoutRoadSceneIsRefusedNamingItsGround) {
  const Scene s = StreetScene(Street{}, "parking");
  EXPECT_THAT([&] { PlaceRig(s, CarRig(), RoadOptions()); },
              ThrowsWith<NoRoadError>("no surface labelled road (Cityscapes 'road', id 7)", "parking", "sidewalk", "building"));
  // The same scene with its road labelled road places the rig (structure mode needs no labels).
  EXPECT_TRUE(PlaceRig(StreetScene(Street{}), CarRig(), RoadOptions()).has_value());
  EXPECT_TRUE(PlaceRig(s, CarRig(), PlacementOptions{}).has_value());
}

TEST(RoadPlacement, ModeNamesRoundTrip) {
  for (PlacementMode m : kAllPlacementModes) EXPECT_EQ(PlacementModeFromName(PlacementModeName(m)), m);
  EXPECT_THAT([] { PlacementModeFromName("lane"); }, ThrowsWith<std::invalid_argument>("give structure or road"));
}

}  // namespace
}  // namespace rigsim
