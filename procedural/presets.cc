#include "procedural/presets.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "common/param_spec.h"
#include "gltf/scene_builder.h"
#include "procedural/glass_and_water.h"
#include "procedural/motion.h"
#include "procedural/objects.h"
#include "procedural/street_scene.h"
#include "procedural/textures.h"

namespace rigsim {
namespace {

using namespace procedural;  // NOLINT: the painters and builders are this file's vocabulary

// Texels per metre by distance from the origin, where rigs stand: dense near, sparse far.
float GroundPpm(float distance, float near_ppm = 48.f, float mid_ppm = 20.f, float far_ppm = 10.f) {
  return distance < 12.f ? near_ppm : distance < 25.f ? mid_ppm : far_ppm;
}

// Distance from the origin to the nearest point of the rectangle [x0, x1] x [z0, z1].
float RectDistance(float x0, float z0, float x1, float z1) {
  const float dx = std::max({x0, 0.f, -x1}), dz = std::max({z0, 0.f, -z1});
  return std::hypot(dx, dz);
}

// What every preset generator shares: the builder, the random stream, materials from canvases,
// ground tiles, buildings, trees with foliage cards, people, lamps and animations.
class PresetGenerator {
 protected:
  struct Placed {  // a node and where it stands
    int node;
    Eigen::Matrix4d place;
    float yaw;
  };

  // The motion and the puddles draw from their own streams, so that the rest of the scene is the
  // same with and without them; the glass draws nothing (it lies on the painted windows).
  PresetGenerator(const ScenePresetOptions& o)
      : rng_(o.seed),
        motion_rng_(o.seed ^ 0x9e3779b97f4a7c15ull),
        wet_rng_(o.seed ^ 0xc2b2ae3d27d4eb4full),
        animated_(o.animated),
        traffic_(o.traffic),
        glass_(o.glass),
        wet_(o.wet) {}

  // A material showing `c`; `texture` receives the texture's index, for the glossy parts over it.
  int Material(const std::string& name, const Canvas& c, int* texture = nullptr) {
    const int tex = b_.AddTexture(name, c.w, c.h, 3, c.ToRgb8());
    if (texture != nullptr) *texture = tex;
    return b_.AddMaterial(name, Eigen::Vector4f::Ones(), tex);
  }

  // A horizontal ground tile [x0, x1] x [z0, z1] at height y, u along +x, v along +z. With a
  // `texture` (the material's) and a wet world, puddles lie on it, parts of its node.
  void GroundTile(const std::string& name, const std::string& cls, float x0, float z0, float x1, float z1, float y, int material,
                  int texture = -1) {
    MeshData m;
    AddQuad(m, Vector3f(x0, y, z0), Vector3f(x1 - x0, 0, 0), Vector3f(0, 0, z1 - z0));
    MeshData puddles = texture >= 0 ? Puddles(wet_rng_, x0, z0, x1, z1, y, float(wet_)) : MeshData{};
    if (puddles.indices.empty()) {
      b_.AddNode(name, cls, std::move(m), material);
      return;
    }
    std::vector<MeshPart> parts;
    parts.push_back({std::move(m), material});
    parts.push_back({std::move(puddles), PuddleMaterial(b_, name + "_puddles", texture)});
    b_.AddNode(name, cls, std::move(parts));
  }

  // A building box whose facade faces the origin side: `facing` = direction of the facade normal
  // in the ground plane (one of +-x, +-z). The facade spans `along` = [a0, a1] at `front`.
  void Building(const std::string& name, char axis, int facing, float front, float a0, float a1, float height, float depth,
                float ppm) {
    const float width = a1 - a0;
    std::vector<Pane> panes;
    const Canvas painted = PaintFacade(rng_.Fork(), width, height, ppm, glass_ ? &panes : nullptr);
    int facade_tex = -1;
    const int facade = Material(name + "_facade", painted, &facade_tex);
    const uint64_t sides_seed = rng_.Fork();
    const Vector3f sides_color = RandomColor(rng_, 0.4f, 0.8f);
    const int sides = Material(name + "_sides", PaintPlain(sides_seed, 128, 128, sides_color, 0.08f, 20));
    MeshData front_quad, rest;
    const float back = front - facing * depth;
    // The facade quad (top-left corner, right and down edges, as AddQuad takes them).
    Vector3f tl, right;
    const Vector3f down(0, -height, 0);
    if (axis == 'x') {  // facade plane x = front, normal (facing, 0, 0)
      tl = facing < 0 ? Vector3f(front, height, a0) : Vector3f(front, height, a1);
      right = Vector3f(0, 0, facing < 0 ? width : -width);
      AddQuad(front_quad, tl, right, down);
      AddBox(rest, Vector3f(std::min(front, back) + (facing < 0 ? 0.001f : 0.f), 0, a0),
             Vector3f(std::max(front, back) - (facing > 0 ? 0.001f : 0.f), height, a1));
    } else {  // facade plane z = front, normal (0, 0, facing)
      tl = facing < 0 ? Vector3f(a1, height, front) : Vector3f(a0, height, front);
      right = Vector3f(facing < 0 ? -width : width, 0, 0);
      AddQuad(front_quad, tl, right, down);
      AddBox(rest, Vector3f(a0, 0, std::min(front, back) + (facing < 0 ? 0.001f : 0.f)),
             Vector3f(a1, height, std::max(front, back) - (facing > 0 ? 0.001f : 0.f)));
    }
    // One node (one instance): the facade, the plain body behind it, and the windows' glass when
    // the world has it.
    std::vector<MeshPart> parts;
    parts.push_back({std::move(front_quad), facade});
    parts.push_back({std::move(rest), sides});
    MeshData glass = GlassPanes(tl, right, down, painted.w, painted.h, panes);
    if (!glass.indices.empty()) parts.push_back({std::move(glass), GlassMaterial(b_, name + "_glass", facade_tex)});
    b_.AddNode(name, "building", std::move(parts));
  }

  // Buildings in slots of random width along one side of a square.
  void BuildingRow(const std::string& prefix, char axis, int facing, float front, float from, float to, float h0, float h1,
                   float ppm) {
    int k = 0;
    for (float a = from; a < to - 0.5f; ++k) {
      float w = rng_.Uniform(10.f, 20.f);
      if (to - (a + w) < 6.f) w = to - a;
      const float h = rng_.Uniform(h0, h1);
      Building(prefix + std::to_string(k), axis, facing, front, a, a + w, h, 10.f, ppm);
      a += w;
    }
  }

  // Foliage materials: alpha-masked RGBA cards, shared by the trees.
  void MakeFoliage(int variants) {
    for (int i = 0; i < variants; ++i) {
      std::vector<float> alpha;
      const Canvas c = PaintFoliage(rng_.Fork(), 256, &alpha);
      const std::string name = "foliage_" + std::to_string(i);
      const int tex = b_.AddTexture(name, c.w, c.h, 4, ToRgba8(c, alpha));
      const int mat = b_.AddMaterial(name, Eigen::Vector4f::Ones(), tex, /*double_sided=*/true);
      b_.SetAlphaMask(mat, 0.5f);
      foliage_.push_back(mat);
    }
    bark_ = Material("bark", PaintPlain(rng_.Fork(), 64, 256, Vector3f(0.32f, 0.24f, 0.16f), 0.12f, 30));
  }

  // A tree: trunk and crossed foliage cards in clusters (one instance, two materials).
  void Tree(const std::string& name, float x, float z, float y0 = 0.f) {
    Rng rng(rng_.Fork());
    MeshData trunk, crown;
    const float trunk_h = rng.Uniform(2.5f, 3.5f);
    AddCylinder(trunk, Vector3f(0, 0, 0), 0.15f, trunk_h + 1.f, 8);
    for (int k = 0, n = rng.Int(4, 7); k < n; ++k) {
      const float cx = rng.Uniform(-0.9f, 0.9f), cy = trunk_h + rng.Uniform(0.5f, 2.5f), cz = rng.Uniform(-0.9f, 0.9f);
      const float size = rng.Uniform(1.6f, 2.6f), angle = rng.Uniform(0, kPi);
      AddCrossedCards(crown, Vector3f(cx, cy, cz), size, 3, angle);
    }
    const int leaves = foliage_[size_t(rng.Int(0, int(foliage_.size()) - 1))];
    std::vector<MeshPart> parts;
    parts.push_back({std::move(trunk), bark_});
    parts.push_back({std::move(crown), leaves});
    const float yaw = rng.Uniform(0, 2 * kPi);
    Eigen::Matrix4d place = Placement(x, z, yaw);
    place(1, 3) = y0;
    trees_.push_back({b_.AddNode(name, "vegetation", std::move(parts), place), place, yaw});
    obstacles_.push_back({x, z, 1.f});
  }

  void Person(const std::string& name, float x, float z, float y0 = 0.f) {
    Rng rng(rng_.Fork());
    const int mat = Material(name, PaintPersonAtlas(rng.Fork()));
    const float yaw = rng.Uniform(0, 2 * kPi), scale = rng.Uniform(0.9f, 1.08f);
    Eigen::Matrix4d place = Placement(x, z, yaw);
    place(1, 3) = y0;
    people_.push_back({b_.AddNode(name, "person", PersonMesh(scale, rng.Fork()), mat, place), place, yaw});
  }

  void Lamp(const std::string& name, float x, float z, float height) {
    if (lamp_material_ < 0) lamp_material_ = Material("lamp_metal", PaintPlain(rng_.Fork(), 64, 512, Vector3f(0.3f, 0.32f, 0.3f), 0.08f, 40));
    MeshData m;
    AddCylinder(m, Vector3f(0, 0, 0), 0.1f, height, 10);
    AddBox(m, Vector3f(-0.6f, height - 0.2f, -0.2f), Vector3f(0.6f, height, 0.2f));
    b_.AddNode(name, "pole", std::move(m), lamp_material_, Placement(x, z, rng_.Uniform(0, kPi)));
    obstacles_.push_back({x, z, 0.3f});
  }

  // A free-standing advertising wall carrying `poster` on both faces (class wall).
  void PosterWall(const std::string& name, float x, float z, float yaw, float width, float height, int poster) {
    MeshData face, frame;
    AddQuad(face, Vector3f(-width / 2, height, 0.11f), Vector3f(width, 0, 0), Vector3f(0, -(height - 0.4f), 0));
    AddQuad(face, Vector3f(width / 2, height, -0.11f), Vector3f(-width, 0, 0), Vector3f(0, -(height - 0.4f), 0));
    AddBox(frame, Vector3f(-width / 2 - 0.1f, 0, -0.1f), Vector3f(width / 2 + 0.1f, height + 0.1f, 0.1f));
    const int concrete = Material(name + "_frame", PaintPlain(rng_.Fork(), 128, 64, Vector3f(0.6f, 0.6f, 0.58f), 0.1f, 20));
    std::vector<MeshPart> parts;
    parts.push_back({std::move(face), poster});
    parts.push_back({std::move(frame), concrete});
    b_.AddNode(name, "wall", std::move(parts), Placement(x, z, yaw));
    for (float a = -width / 2; a <= width / 2 + 0.01f; a += 1.f) obstacles_.push_back({x + a * std::cos(yaw), z - a * std::sin(yaw), 0.5f});
  }

  void Bus(const std::string& name, float x, float z, float yaw, int poster) {
    const Vector3f colour = RandomColor(rng_, 0.5f, 0.95f);  // before the fork, as GCC ordered the arguments
    const int paint = Material(name + "_paint", PaintPlain(rng_.Fork(), 128, 128, colour, 0.05f, 10));
    const Eigen::Matrix4d place = Placement(x, z, yaw);
    buses_.push_back({b_.AddNode(name, "bus", BusParts(11.f, 2.5f, 3.1f, paint, poster), place), place, yaw});
  }

  // Cars in the scene share a few atlases and one body shape: identical models.
  int CarMaterial(int variant) {
    while (int(car_materials_.size()) <= variant) {
      const Vector3f paint = RandomColor(rng_, 0.05f, 0.9f);
      car_materials_.push_back(Material("car_paint_" + std::to_string(car_materials_.size()), PaintCarAtlas(rng_.Fork(), paint)));
    }
    return car_materials_[variant];
  }

  // A car; `in_lane` ones drive first when the world moves (the rest stay parked).
  void Car(const std::string& name, float x, float z, float yaw, int variant, bool in_lane) {
    const int node = b_.AddNode(name, "car", CarMesh(4.3f, 1.8f, 1.55f), CarMaterial(variant), Placement(x, z, yaw));
    if (in_lane) lane_cars_.push_back(node);
  }

  // Trees sway in one wind.
  void SwayTrees() {
    const Eigen::Vector3f wind = RandomWind(motion_rng_);
    for (const Placed& t : trees_) AddMotion(&b_, t.node, SwayKeys(RandomSway(t.yaw, wind, motion_rng_)));
  }

  // A person paces along `yaw` from `start` as far as the obstacles and the box |x| <= half_x,
  // |z| <= half_z let it (at most 10 m), or the other way when that is longer; one hemmed in on
  // both sides (under 1 m) stands still.
  void WalkFrom(const Placed& person, const Eigen::Vector3f& start, float yaw, float half_x, float half_z) {
    const Eigen::Vector2f at(start.x(), start.z());
    const float ahead = ClearLength(at, {std::sin(yaw), std::cos(yaw)}, 10.f, 0.4f, obstacles_, half_x, half_z);
    const float behind = ClearLength(at, {-std::sin(yaw), -std::cos(yaw)}, 10.f, 0.4f, obstacles_, half_x, half_z);
    Walk w;
    w.start = start;
    w.yaw = ahead >= behind ? yaw : yaw + kPi;
    w.leg_m = std::max(ahead, behind);
    w.speed_mps = motion_rng_.Uniform(1.2f, 1.5f);
    w.phase = motion_rng_.Uniform();
    if (w.leg_m >= 1.f) AddMotion(&b_, person.node, WalkKeys(w));
  }

  // Vehicles on `lanes` at the traffic density (`lane_length_m` of lane in view): the lane cars
  // first, then new cars of the scene's models.
  void DriveLanes(const std::vector<LaneDrive>& lanes, float lane_length_m) {
    std::vector<LaneDrive> spread_lanes = lanes;
    for (LaneDrive& lane : spread_lanes) lane.offset_m = motion_rng_.Uniform(0, (lane.to - lane.from).norm());
    const std::vector<LaneDrive> drives = SpreadOnLanes(VehiclesOnLanes(traffic_, lane_length_m), spread_lanes);
    for (size_t k = 0; k < drives.size(); ++k) {
      const int node = k < lane_cars_.size() ? lane_cars_[k]
                                             : b_.AddNode("car_traffic_" + std::to_string(k), "car", CarMesh(4.3f, 1.8f, 1.55f),
                                                          CarMaterial(int(k % 3)), Placement(drives[k].from.x(), drives[k].from.z(), 0));
      AddMotion(&b_, node, LaneDriveKeys(drives[k]));
    }
  }

  // Buses drive `distance_m` ahead at 6 m/s to their stop when there is traffic.
  void DriveBuses(float distance_m) {
    if (traffic_ <= 0) return;
    for (const Placed& bus : buses_) {
      const Eigen::Vector3f start = bus.place.topRightCorner<3, 1>().cast<float>();
      AddMotion(&b_, bus.node, DriveToStopKeys(start, bus.yaw, distance_m, 6.f));
    }
  }

  // Keeps walkers off a bus and the `distance_m` it drives: discs along it.
  void BusRouteObstacles(float distance_m) {
    for (const Placed& bus : buses_) {
      for (float d = -6.f; d <= distance_m + 6.f; d += 2.f) {
        obstacles_.push_back({float(bus.place(0, 3)) + d * std::sin(bus.yaw), float(bus.place(2, 3)) + d * std::cos(bus.yaw), 1.6f});
      }
    }
  }

  Rng rng_, motion_rng_, wet_rng_;
  bool animated_;
  double traffic_;
  bool glass_;  // glass in the windows
  double wet_;  // the share of the ground's asphalt the puddles cover
  SceneBuilder b_;
  std::vector<int> foliage_, car_materials_, lane_cars_;
  std::vector<Placed> trees_, people_, buses_;
  std::vector<Obstacle> obstacles_;
  int bark_ = -1, lamp_material_ = -1;
};

// An open square, 100 x 100 m: paving and lawns, buildings 40-50 m away on all sides, many trees,
// people, lamps, a poster wall and a bus with the same poster.
class PlazaGenerator : public PresetGenerator {
 public:
  explicit PlazaGenerator(const ScenePresetOptions& o) : PresetGenerator(o) {}

  SceneBuilder Build() {
    Ground();
    BuildingRow("building_north_", 'z', 1, -45.f, -55.f, 55.f, 10.f, 22.f, 20.f);
    BuildingRow("building_south_", 'z', -1, 45.f, -55.f, 55.f, 10.f, 22.f, 20.f);
    BuildingRow("building_west_", 'x', 1, -45.f, -45.f, 45.f, 8.f, 18.f, 20.f);
    BuildingRow("building_east_", 'x', -1, 45.f, -45.f, 45.f, 8.f, 18.f, 20.f);
    MakeFoliage(3);
    const float trees[][2] = {{-12, -8}, {-8, 14}, {10, -14}, {15, 9}, {-20, -20}, {22, -22}, {-24, 18}, {20, 24},
                              {-32, -5}, {33, 4}, {3, -30}, {-4, 31}, {-16, 30}, {28, -33}, {-30, -32}, {34, 30}};
    for (size_t i = 0; i < std::size(trees); ++i) Tree("tree_" + std::to_string(i), trees[i][0], trees[i][1]);
    for (int i = 0; i < 22; ++i) {
      float x = 0, z = 0;
      do {
        x = rng_.Uniform(-35.f, 35.f);
        z = rng_.Uniform(-35.f, 35.f);
      } while (std::hypot(x, z) < 4.f);
      Person("person_" + std::to_string(i), x, z);
    }
    for (int i = 0; i < 8; ++i) {
      const float a = 2 * kPi * i / 8 + 0.3f;
      Lamp("lamp_" + std::to_string(i), 18.f * std::cos(a), 18.f * std::sin(a), 5.f);
    }
    Monument();
    const int poster = Material("poster", PaintPoster(rng_.Fork(), 512, 192));
    PosterWall("poster_wall", -9.f, -17.f, 0.3f, 6.f, 2.6f, poster);
    Bus("bus", 26.f, -6.f, 0.f, poster);
    if (animated_) Animate();  // after everything else: the static scene is the same either way
    return std::move(b_);
  }

 private:
  // The bus crosses the square to z = 30, people walk in the directions they face, trees sway.
  void Animate() {
    constexpr float kBusRoute = 36.f;
    SwayTrees();
    obstacles_.push_back({2.f, -12.f, 2.2f});  // the monument
    BusRouteObstacles(traffic_ > 0 ? kBusRoute : 0.f);
    for (const Placed& p : people_) WalkFrom(p, p.place.topRightCorner<3, 1>().cast<float>(), p.yaw, 40.f, 40.f);
    DriveBuses(kBusRoute);
  }

  void Ground() {
    for (float z0 = -50.f; z0 < 50.f; z0 += 10.f) {
      for (float x0 = -50.f; x0 < 50.f; x0 += 10.f) {
        const float d = RectDistance(x0, z0, x0 + 10.f, z0 + 10.f);
        const std::string tag = std::to_string(int(x0)) + "_" + std::to_string(int(z0));
        // Lawns in two diagonal quarters away from the centre.
        const bool lawn = d > 8.f && d < 32.f && ((x0 < 0) == (z0 < 0)) && std::abs(x0 + 5) > 10.f;
        if (lawn) {
          GroundTile("lawn_" + tag, "terrain", x0, z0, x0 + 10.f, z0 + 10.f, 0.f, Material("lawn_" + tag, PaintGrass(rng_.Fork(), 10, 10, GroundPpm(d))));
        } else {
          GroundTile("paving_" + tag, "sidewalk", x0, z0, x0 + 10.f, z0 + 10.f, 0.f,
                     Material("paving_" + tag, PaintPaving(rng_.Fork(), 10, 10, GroundPpm(d))));
        }
      }
    }
  }

  // A plinth with a figure, 12 m in front of the origin (looking down -Z).
  void Monument() {
    const int stone = Material("plinth", PaintPlain(rng_.Fork(), 256, 256, Vector3f(0.7f, 0.68f, 0.62f), 0.1f, 60));
    MeshData plinth;
    AddBox(plinth, Vector3f(-1.5f, 0, -1.5f), Vector3f(1.5f, 2.f, 1.5f));
    b_.AddNode("monument_plinth", "wall", std::move(plinth), stone, Placement(2.f, -12.f, 0.4f));
    const int bronze = Material("statue", PaintPlain(rng_.Fork(), 128, 128, Vector3f(0.35f, 0.3f, 0.2f), 0.15f, 30));
    MeshData statue;
    AddBlob(statue, Vector3f(0, 3.2f, 0), Vector3f(0.6f, 1.2f, 0.5f), 0.4f, rng_.Fork());
    b_.AddNode("monument_statue", "pole", std::move(statue), bronze, Placement(2.f, -12.f, 0.4f));
  }
};

// A parking lot, 60 x 80 m: asphalt with painted bays in rows, mostly filled with identical car
// models, light poles, fences, a supermarket with a poster and a bus with the same poster.
class ParkingGenerator : public PresetGenerator {
 public:
  explicit ParkingGenerator(const ScenePresetOptions& o) : PresetGenerator(o) {}

  SceneBuilder Build() {
    Ground();
    // Rows of bays: 2.5 m wide along x, 5 m deep, facing driving lanes at z = 0 and z = +-24.
    int car = 0;
    for (float row_z : {-18.5f, -7.5f, 7.5f, 18.5f}) {
      for (float x = -27.5f; x < 27.5f; x += 2.5f) {
        if (!rng_.Chance(0.7f)) continue;
        const float yaw = (row_z > 0 ? 0.f : kPi) + rng_.Uniform(-0.04f, 0.04f) + (rng_.Chance(0.3f) ? kPi : 0.f);
        const float jx = rng_.Uniform(-0.15f, 0.15f), jz = rng_.Uniform(-0.2f, 0.2f);
        Car("car_" + std::to_string(car), x + 1.25f + jx, row_z + jz, yaw, rng_.Int(0, 2), false);
        ++car;
      }
    }
    // Cars in the driving lane: the first to drive when the world moves.
    Car("car_lane_0", -12.f, -1.6f, 0.5f * kPi, 0, true);
    Car("car_lane_1", 14.f, 1.6f, -0.5f * kPi, 1, true);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 4; ++j) Lamp("lamp_" + std::to_string(i) + "_" + std::to_string(j), -24.f + 16.f * j, -13.f + 13.f * i, 8.f);
    }
    Fences();
    const int poster = Material("poster", PaintPoster(rng_.Fork(), 512, 192));
    Supermarket(poster);
    Bus("bus", -33.5f, 5.f, 0.f, poster);
    BuildingRow("building_south_", 'z', -1, 46.f, -40.f, 40.f, 8.f, 16.f, 20.f);
    BuildingRow("building_east_", 'x', -1, 40.f, -40.f, 46.f, 6.f, 12.f, 20.f);
    BuildingRow("building_west_", 'x', 1, -46.f, -40.f, 46.f, 6.f, 14.f, 20.f);
    MakeFoliage(2);
    const float trees[][2] = {{-35, -30}, {-36, 25}, {35, -28}, {34, 20}, {-10, 36}, {12, 37}};
    for (size_t i = 0; i < std::size(trees); ++i) Tree("tree_" + std::to_string(i), trees[i][0], trees[i][1]);
    for (int i = 0; i < 8; ++i) {
      const float x = rng_.Uniform(4.f, 28.f) * (i % 2 ? 1.f : -1.f);  // not next to the origin
      const float z = rng_.Chance(0.5f) ? rng_.Uniform(-2.5f, -1.f) : rng_.Uniform(12.5f, 13.5f);
      Person("person_" + std::to_string(i), x, z);
    }
    if (animated_) Animate();  // after everything else: the static scene is the same either way
    return std::move(b_);
  }

 private:
  // Cars drive the middle lane (z = -1.6 towards +x, z = +1.6 towards -x; the lane's ends inside the
  // buildings east and west), the bus drives up the west road to z = 36, people walk along the
  // bays (z = -3.8) and the aisle (z = 12) beside them, trees sway.
  void Animate() {
    SwayTrees();
    LaneDrive east, west;
    east.from = Eigen::Vector3f(-50.f, 0, -1.6f);
    east.to = Eigen::Vector3f(44.f, 0, -1.6f);
    west.from = Eigen::Vector3f(44.f, 0, 1.6f);
    west.to = Eigen::Vector3f(-50.f, 0, 1.6f);
    DriveLanes({east, west}, 2 * 60.f);
    DriveBuses(31.f);
    for (const Placed& p : people_) {
      const float x = float(p.place(0, 3)), z = float(p.place(2, 3));
      WalkFrom(p, Eigen::Vector3f(x, 0, z < 0 ? -3.8f : 12.f), std::sin(p.yaw) >= 0 ? 0.5f * kPi : -0.5f * kPi, 28.f, 40.f);
    }
  }

  void Ground() {
    for (float z0 = -40.f; z0 < 40.f; z0 += 10.f) {
      for (float x0 = -30.f; x0 < 30.f; x0 += 10.f) {
        const float d = RectDistance(x0, z0, x0 + 10.f, z0 + 10.f);
        const float ppm = GroundPpm(d, 64.f, 32.f, 16.f);  // views are mostly ground here: denser everywhere
        Canvas c = PaintAsphalt(rng_.Fork(), 10.f, 10.f, ppm);
        // Bay lines in world coordinates (white, 0.12 m), so they continue across tiles.
        auto paint = [&](float wx0, float wz0, float wx1, float wz1) {
          FillRect(c, (wx0 - x0) * ppm, (wz0 - z0) * ppm, (wx1 - x0) * ppm, (wz1 - z0) * ppm, Vector3f(0.88f, 0.88f, 0.84f), 0.9f);
        };
        for (float row_z : {-18.5f, -7.5f, 7.5f, 18.5f}) {
          for (float x = -27.5f; x <= 27.5f; x += 2.5f) paint(x - 0.06f, row_z - 2.5f, x + 0.06f, row_z + 2.5f);
        }
        for (float lane_z : {0.f, -24.f, 24.f}) paint(-30.f, lane_z - 0.06f, 30.f, lane_z + 0.06f);
        // Bay numbers at the lane end of every bay, direction arrows on the lanes and oil stains
        // under the cars: texture the detectors find on an otherwise uniform lot.
        Rng marks(rng_.Fork());
        for (float row_z : {-18.5f, -7.5f, 7.5f, 18.5f}) {
          const float end_z = row_z + (std::abs(row_z) < 10.f ? (row_z < 0 ? 2.0f : -2.6f) : (row_z < 0 ? 2.0f : -2.6f));
          for (float x = -27.5f; x < 27.5f; x += 2.5f) {
            Glyphs(c, marks, (x + 0.55f - x0) * ppm, (end_z - z0) * ppm, 0.5f * ppm, 2, Vector3f(0.9f, 0.9f, 0.86f));
            const float sx = (x + 1.25f + marks.Uniform(-0.5f, 0.5f) - x0) * ppm, sz = (row_z + marks.Uniform(-1.f, 1.f) - z0) * ppm;
            // Drawn one by one: two draws as arguments of one call come in an order the compiler
            // picks (GCC's last argument first, which the shipped assets keep; clang's first).
            const float ry = marks.Uniform(0.2f, 0.6f) * ppm, rx = marks.Uniform(0.2f, 0.5f) * ppm;
            FillEllipse(c, sx, sz, rx, ry, Vector3f(0.08f, 0.08f, 0.08f), 0.4f);
          }
        }
        for (float x = -25.f; x < 30.f; x += 10.f) {
          for (float lane_z : {-1.5f, 1.5f}) {
            const float ax = (x - x0) * ppm, az = (lane_z - z0) * ppm, len = 2.5f * ppm, dir = lane_z < 0 ? 1.f : -1.f;
            Stroke(c, ax - dir * len * 0.5f, az, ax + dir * len * 0.5f, az, 0.15f * ppm, Vector3f(0.9f, 0.9f, 0.86f), 0.9f);
            Stroke(c, ax + dir * len * 0.5f, az, ax + dir * len * 0.2f, az - 0.35f * ppm, 0.15f * ppm, Vector3f(0.9f, 0.9f, 0.86f), 0.9f);
            Stroke(c, ax + dir * len * 0.5f, az, ax + dir * len * 0.2f, az + 0.35f * ppm, 0.15f * ppm, Vector3f(0.9f, 0.9f, 0.86f), 0.9f);
          }
        }
        const std::string tag = std::to_string(int(x0)) + "_" + std::to_string(int(z0));
        int tex = -1;
        const int mat = Material("parking_" + tag, c, &tex);
        GroundTile("parking_" + tag, "parking", x0, z0, x0 + 10.f, z0 + 10.f, 0.f, mat, tex);
      }
    }
    // Sidewalks around the lot, and a road along its west side.
    const int walk = Material("sidewalk", PaintPaving(rng_.Fork(), 8.f, 40.f, 12.f));
    GroundTile("sidewalk_north", "sidewalk", -30.f, -46.f, 30.f, -40.f, 0.f, walk);
    GroundTile("sidewalk_south", "sidewalk", -30.f, 40.f, 30.f, 46.f, 0.f, walk);
    GroundTile("sidewalk_east", "sidewalk", 30.f, -46.f, 40.f, 46.f, 0.f, walk);
    int road_tex = -1;
    const int road = Material("road", PaintAsphalt(rng_.Fork(), 8.f, 46.f, 10.f), &road_tex);
    GroundTile("road_west", "road", -40.f, -46.f, -30.f, 46.f, 0.f, road, road_tex);
  }

  void Fences() {
    const int metal = Material("fence", PaintPlain(rng_.Fork(), 64, 64, Vector3f(0.25f, 0.35f, 0.3f), 0.1f, 8));
    for (int side = -1; side <= 1; side += 2) {
      MeshData m;
      for (float z = -38.f; z <= 38.01f; z += 2.f) AddBox(m, Vector3f(-0.04f, 0, z - 0.04f), Vector3f(0.04f, 1.2f, z + 0.04f));
      AddBox(m, Vector3f(-0.03f, 1.15f, -38.f), Vector3f(0.03f, 1.2f, 38.f));
      AddBox(m, Vector3f(-0.03f, 0.6f, -38.f), Vector3f(0.03f, 0.64f, 38.f));
      b_.AddNode(side < 0 ? "fence_west" : "fence_east", "fence", std::move(m), metal, Placement(side * 30.5f, 0.f, 0.f));
    }
  }

  // The supermarket closing the lot at z = -46, facing +z, with the poster beside its entrance.
  void Supermarket(int poster) {
    Building("supermarket", 'z', 1, -46.f, -30.f, 30.f, 9.f, 25.f, 40.f);
    PosterWall("supermarket_poster", 12.f, -45.5f, 0.f, 6.f, 2.6f, poster);
  }
};

}  // namespace

std::string_view ScenePresetName(ScenePreset preset) {
  switch (preset) {
    case ScenePreset::kStreet: return "street";
    case ScenePreset::kPlaza: return "plaza";
    case ScenePreset::kParking: return "parking";
  }
  return "?";
}

ScenePreset ScenePresetFromName(std::string_view name) {
  for (ScenePreset p : AllScenePresets()) {
    if (ScenePresetName(p) == name) return p;
  }
  throw std::invalid_argument("unknown scene preset '" + std::string(name) + "' (expected " +
                              JoinNames(NamesOf(AllScenePresets(), ScenePresetName)) + ")");
}

std::vector<ScenePreset> AllScenePresets() { return {ScenePreset::kStreet, ScenePreset::kPlaza, ScenePreset::kParking}; }

void ScenePresetOptions::Check() const {
  if (preset != ScenePreset::kStreet && preset != ScenePreset::kPlaza && preset != ScenePreset::kParking) {
    throw std::invalid_argument("scene preset: unknown preset");
  }
  if (!(wet >= 0 && wet <= kMaxWet)) {
    char range[128];
    std::snprintf(range, sizeof range, "scene preset: wet must be between 0 and %g (the share of the road under puddles)",
                  kMaxWet);
    throw std::invalid_argument(range);
  }
  if (!(traffic >= 0 && traffic <= kMaxTraffic)) {
    throw std::invalid_argument("scene preset: traffic must be between 0 and " + std::to_string(int(kMaxTraffic)) +
                                " vehicles per 100 m of lane");
  }
}

std::vector<uint8_t> ScenePresetGlb(const ScenePresetOptions& o) {
  o.Check();
  switch (o.preset) {
    case ScenePreset::kStreet: return StreetSceneGlb(o.seed, o.animated, o.traffic, o.glass, o.wet);
    case ScenePreset::kPlaza: return PlazaGenerator(o).Build().ToGlb();
    case ScenePreset::kParking: return ParkingGenerator(o).Build().ToGlb();
  }
  return {};
}

void WriteScenePreset(const ScenePresetOptions& options, const std::filesystem::path& path) {
  const std::vector<uint8_t> glb = ScenePresetGlb(options);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error(path.string() + ": cannot open for writing");
  const bool ok = std::fwrite(glb.data(), 1, glb.size(), f) == glb.size();
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error(path.string() + ": write failed");
}

}  // namespace rigsim
