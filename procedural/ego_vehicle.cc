#include "procedural/ego_vehicle.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace rigsim {
namespace {

// Linear colours and factors of the body: a dark blue clear-coated paint (a dielectric, glossy
// enough to mirror the street at grazing angles) and tinted glass.
const Eigen::Vector4f kPaintColour(0.05f, 0.08f, 0.16f, 1.0f);
constexpr float kPaintRoughness = 0.08f;
const Eigen::Vector4f kGlassColour(0.02f, 0.025f, 0.03f, 1.0f);
constexpr float kGlassRoughness = 0.02f;

// Adds the planar convex polygon `corners` to `mesh` as a fan, wound counter-clockwise seen from
// outside the solid whose inner point is `inside`.
void AddFace(const std::vector<Eigen::Vector3d>& corners, const Eigen::Vector3d& inside, MeshData* mesh) {
  const Eigen::Vector3d normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
  const bool flip = normal.dot(corners[0] - inside) < 0;
  const uint32_t first = uint32_t(mesh->positions.size());
  for (const Eigen::Vector3d& c : corners) mesh->positions.push_back(c.cast<float>());
  for (size_t k = 1; k + 1 < corners.size(); ++k) {
    const uint32_t a = first, b = first + uint32_t(k), c = first + uint32_t(k + 1);
    for (uint32_t i : flip ? std::array<uint32_t, 3>{a, c, b} : std::array<uint32_t, 3>{a, b, c}) mesh->indices.push_back(i);
  }
}

// The convex side profile `profile` ((z, y) corners in order) extruded over x in [x0, x1]: its two
// end caps, and a side face per profile edge. `part(edge)` says where each goes (edge k runs from
// corner k to k + 1; `cap` for the end caps); nullptr leaves a face out.
template <class Part>
void AddPrism(const std::vector<Eigen::Vector2d>& profile, double x0, double x1, MeshData* cap, Part&& part) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : profile) mean += p / double(profile.size());
  const Eigen::Vector3d inside(0.5 * (x0 + x1), mean.y(), mean.x());
  auto at = [](double x, const Eigen::Vector2d& zy) { return Eigen::Vector3d(x, zy.y(), zy.x()); };
  for (const double x : {x0, x1}) {
    std::vector<Eigen::Vector3d> corners;
    for (const Eigen::Vector2d& p : profile) corners.push_back(at(x, p));
    AddFace(corners, inside, cap);
  }
  for (size_t k = 0; k < profile.size(); ++k) {
    MeshData* mesh = part(k);
    if (mesh == nullptr) continue;
    const Eigen::Vector2d& a = profile[k];
    const Eigen::Vector2d& b = profile[(k + 1) % profile.size()];
    AddFace({at(x0, a), at(x0, b), at(x1, b), at(x1, a)}, inside, mesh);
  }
}

// Distance along the ray (origin, unit dir) to triangle (a, b, c) (Moller-Trumbore), if it meets it.
std::optional<double> RayTriangle(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, p = dir.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-12) return std::nullopt;
  const Eigen::Vector3d s = origin - a;
  const double u = s.dot(p) / det;
  if (u < 0 || u > 1) return std::nullopt;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = dir.dot(q) / det;
  if (v < 0 || u + v > 1) return std::nullopt;
  const double t = e2.dot(q) / det;
  if (t < 0) return std::nullopt;
  return t;
}

// Where the central ray of a camera at `origin` looking along `dir` first meets `mesh`.
double NearestHit(const MeshData& mesh, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) {
  double nearest = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const auto p = [&](size_t k) { return mesh.positions[mesh.indices[i + k]].cast<double>().eval(); };
    if (const auto t = RayTriangle(origin, dir, p(0), p(1), p(2))) nearest = std::min(nearest, *t);
  }
  return nearest;
}

}  // namespace

Eigen::Matrix3d RigFromCar(const std::vector<Eigen::Vector3d>& centres) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& c : centres) mean += c / double(centres.size());
  Eigen::Matrix2d normal_eq = Eigen::Matrix2d::Identity() * (double(centres.size()) * 0.1 * 0.1);
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (const Eigen::Vector3d& c : centres) {
    const Eigen::Vector2d xz(c.x() - mean.x(), c.z() - mean.z());
    normal_eq += xz * xz.transpose();
    rhs += xz * (c.y() - mean.y());
  }
  const Eigen::Vector2d slope = normal_eq.ldlt().solve(rhs);  // y = mean.y + slope . (x, z)
  bool level = std::atan(slope.norm()) <= kMaxLevelTilt;
  for (const Eigen::Vector3d& c : centres) {
    const double off = c.y() - mean.y() - slope.dot(Eigen::Vector2d(c.x() - mean.x(), c.z() - mean.z()));
    level = level && std::abs(off) <= kRoofGap;
  }
  if (!level) return Eigen::Matrix3d::Identity();
  const Eigen::Vector3d down = Eigen::Vector3d(-slope.x(), 1, -slope.y()).normalized();
  const Eigen::Vector3d forward = (Eigen::Vector3d::UnitZ() - down * down.z()).normalized();
  Eigen::Matrix3d rig_from_car;
  rig_from_car << down.cross(forward), down, forward;
  return rig_from_car;
}

EgoVehicleMeshes EgoVehicleInRig(const Rig& rig, double ground_below_rig_m) {
  if (rig.cameras.empty()) throw std::invalid_argument("the rig has no cameras");
  std::vector<Eigen::Vector3d> centres, dirs;  // rig frame, then the car's
  for (const RigCamera& c : rig.cameras) {
    if (!c.cam_from_rig) throw std::invalid_argument("camera '" + c.name + "' has no cam_from_rig");
    centres.push_back(c.cam_from_rig->SourceOriginInTarget());
    dirs.push_back(c.cam_from_rig->rotation.conjugate() * Eigen::Vector3d::UnitZ());
  }
  // The body is built in the car's frame (RigFromCar: x right, y down, z forward) and turned into
  // the rig's at the end.
  const Eigen::Matrix3d rig_from_car = RigFromCar(centres);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (size_t i = 0; i < centres.size(); ++i) {
    centres[i] = rig_from_car.transpose() * centres[i];
    dirs[i] = rig_from_car.transpose() * dirs[i];
    lo = lo.cwiseMin(centres[i]);
    hi = hi.cwiseMax(centres[i]);
  }
  // The cabin's roof: the cameras' footprint and a margin, kRoofGap under the lowest camera. Every
  // camera so sits at the roof's edge it looks out over, as cameras on a car's roof, mirrors and
  // bumpers sit just above its skin: each sees that edge a few centimetres out and below it (kRoofGap
  // down over kRoofMargin out, 27 degrees below its horizon, for a camera at a side edge), and beyond
  // it the windshield, bonnet or side falling away, in the bottom of a view that looks out level.
  // The roof is not widened or lengthened to a car's size: a camera would then look across it (a
  // front camera beside side cameras across 0.9 m of roof), and lowering the roof out of that
  // camera's view takes it out of every other's. The car's size is the lower body's.
  const double x_mid = 0.5 * (lo.x() + hi.x());
  const double half_width = 0.5 * (hi.x() - lo.x()) + kRoofMargin;
  const double roof_front = hi.z() + kRoofMargin, roof_rear = lo.z() - kRoofMargin;
  const double roof = hi.y() + kRoofGap;  // y down
  // Then the beltline (bonnet and boot) 0.4 m below the roof, the sills 0.2 m above the ground (or
  // 0.3 m below the beltline when the rig stands lower than that).
  const double belt = roof + 0.4;
  const double bottom = std::max(belt + 0.3, ground_below_rig_m - 0.2);
  const double windshield_base = roof_front + 0.8, rear_window_base = roof_rear - 0.6;
  double front = windshield_base + 1.1, rear = rear_window_base - 0.5;
  // A car's size at least, below the beltline: kMinBodyWidth wide, and kMinBodyLength long by a
  // longer boot, or bonnet, at the end no camera looks out over (half each when cameras look out
  // over both or neither), so that no camera sees more of its car than its place on the roof gives.
  const double lower_half_width = std::max(half_width + 0.12, 0.5 * kMinBodyWidth);
  if (const double short_by = kMinBodyLength - (front - rear); short_by > 0) {
    bool over_front = false, over_rear = false;
    for (size_t i = 0; i < centres.size(); ++i) {
      const Eigen::Vector3d& centre = centres[i];
      const Eigen::Vector2d along(dirs[i].x(), dirs[i].z());
      // Only cameras looking out: one looking more up or down than out sees no end of the car.
      if (std::abs(dirs[i].y()) >= along.norm()) continue;
      const Eigen::Vector2d d = along.normalized();
      // The roof edge its horizontal line of sight leaves through: a side, the front or the rear.
      const double to_side = std::abs(d.x()) > 1e-9 ? ((d.x() > 0 ? x_mid + half_width : x_mid - half_width) - centre.x()) / d.x()
                                                    : std::numeric_limits<double>::infinity();
      const double to_end = std::abs(d.y()) > 1e-9 ? ((d.y() > 0 ? roof_front : roof_rear) - centre.z()) / d.y()
                                                   : std::numeric_limits<double>::infinity();
      if (to_end < to_side) (d.y() > 0 ? over_front : over_rear) = true;
    }
    const double to_front = over_front == over_rear ? 0.5 * short_by : over_front ? 0.0 : short_by;
    front += to_front;
    rear -= short_by - to_front;
  }

  EgoVehicleMeshes body;
  // Cabin: windshield (edge 0), roof (1), rear window (2); its floor (3) lies on the lower body.
  const std::vector<Eigen::Vector2d> cabin = {{windshield_base, belt}, {roof_front, roof}, {roof_rear, roof}, {rear_window_base, belt}};
  AddPrism(cabin, x_mid - half_width, x_mid + half_width, &body.glass, [&](size_t edge) -> MeshData* {
    return edge == 1 ? &body.paint : edge == 3 ? nullptr : &body.glass;
  });
  // Lower body: the bonnet falls 0.2 m to the front (its front edge 0.6 m under the roof, as on a
  // car), the boot 0.05 m to the rear.
  const std::vector<Eigen::Vector2d> lower = {{rear, bottom}, {front, bottom}, {front, belt + 0.2}, {windshield_base, belt},
                                              {rear_window_base, belt}, {rear, belt + 0.05}};
  AddPrism(lower, x_mid - lower_half_width, x_mid + lower_half_width, &body.paint, [&](size_t) { return &body.paint; });
  for (MeshData* mesh : {&body.paint, &body.glass}) {
    for (Eigen::Vector3f& p : mesh->positions) p = (rig_from_car * p.cast<double>()).cast<float>();
  }

  for (const RigCamera& c : rig.cameras) {
    const Eigen::Vector3d origin = c.cam_from_rig->SourceOriginInTarget();
    const Eigen::Vector3d dir = c.cam_from_rig->rotation.conjugate() * Eigen::Vector3d::UnitZ();
    const double t = std::min(NearestHit(body.paint, origin, dir), NearestHit(body.glass, origin, dir));
    if (t < kMinClearance) {
      char cm[32];
      std::snprintf(cm, sizeof(cm), "%.0f cm", 100 * t);
      throw std::invalid_argument("camera '" + c.name + "' looks into the car body " + cm +
                                  " from its lens (the roof is 5 cm below the lowest camera): turn it to "
                                  "look out, or go without the car body");
    }
  }
  return body;
}

std::vector<uint8_t> EgoVehicleGlb(const Rig& rig, double ground_below_rig_m) {
  EgoVehicleMeshes body = EgoVehicleInRig(rig, ground_below_rig_m);
  for (MeshData* mesh : {&body.paint, &body.glass}) {
    for (Eigen::Vector3f& p : mesh->positions) p = Eigen::Vector3f(-p.x(), -p.y(), p.z());  // rig -> glTF axes
  }
  SceneBuilder builder;
  const int paint = builder.AddMaterial("ego vehicle paint", kPaintColour);
  builder.SetMetallicRoughness(paint, 0.0f, kPaintRoughness);
  const int glass = builder.AddMaterial("ego vehicle glass", kGlassColour);
  builder.SetMetallicRoughness(glass, 0.0f, kGlassRoughness);
  std::vector<MeshPart> parts;
  parts.push_back({std::move(body.paint), paint});
  parts.push_back({std::move(body.glass), glass});
  builder.AddNode("ego vehicle", "ego vehicle", std::move(parts));
  return builder.ToGlb();
}

void EgoVehicleToRigFrame(Scene& scene) {
  const auto turn = [](Eigen::Vector3f& v) { v = Eigen::Vector3f(-v.x(), -v.y(), v.z()); };
  for (SceneMesh& mesh : scene.meshes) {
    for (Eigen::Vector3f& p : mesh.positions) turn(p);
    for (Eigen::Vector3f& n : mesh.normals) turn(n);
  }
}

}  // namespace rigsim
