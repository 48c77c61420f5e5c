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

EgoVehicleMeshes EgoVehicleInRig(const Rig& rig, double ground_below_rig_m) {
  if (rig.cameras.empty()) throw std::invalid_argument("the rig has no cameras");
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const RigCamera& c : rig.cameras) {
    if (!c.cam_from_rig) throw std::invalid_argument("camera '" + c.name + "' has no cam_from_rig");
    const Eigen::Vector3d centre = c.cam_from_rig->SourceOriginInTarget();
    lo = lo.cwiseMin(centre);
    hi = hi.cwiseMax(centre);
  }
  // The cabin's roof over the cameras' footprint and a margin, at least 1.3 m x 1.8 m. The front
  // and rear margins are small and the windshield and rear window shallow, so that a camera at the
  // roof's front edge sees the bonnet below the horizon as a camera behind a windshield does.
  const double x_mid = 0.5 * (lo.x() + hi.x()), z_mid = 0.5 * (lo.z() + hi.z());
  const double half_width = std::max(0.65, 0.5 * (hi.x() - lo.x()) + kRoofMargin);
  const double roof_front = std::max(hi.z() + kRoofEndMargin, z_mid + 0.9);
  const double roof_rear = std::min(lo.z() - kRoofEndMargin, z_mid - 0.9);
  // Heights (y down): the roof kRoofGap under the lowest camera, and lower where the roof reaches
  // further beyond a camera looking out, in the direction it looks, than kRoofMargin: there the
  // cameras stand on a mount, as cameras grouped on a roof rack do, so that each sees the roof's
  // edge no higher in its view than a camera at the roof's side edge. Without it, cameras grouped in
  // less than the roof's least size (a ring, a rig mounted at one height) look across a roof that
  // fills the lower half of every view. Then the beltline (bonnet and boot) below it, the sills
  // 0.2 m above the ground (or 0.3 m below the beltline when the rig stands lower than that).
  double roof = hi.y() + kRoofGap;
  for (const RigCamera& c : rig.cameras) {
    const Eigen::Vector3d centre = c.cam_from_rig->SourceOriginInTarget();
    const Eigen::Vector3d dir = c.cam_from_rig->rotation.conjugate() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector2d along(dir.x(), dir.z());
    // Only cameras looking out: one looking more up than out sees no roof, one looking more down
    // sees the car whatever its height (and is refused below when it looks into it).
    if (std::abs(dir.y()) >= along.norm()) continue;
    const Eigen::Vector2d d = along.normalized();
    // Where the camera's horizontal line of sight leaves the roof's rectangle.
    double to_edge = std::numeric_limits<double>::infinity();
    if (d.x() > 1e-9) to_edge = std::min(to_edge, (x_mid + half_width - centre.x()) / d.x());
    if (d.x() < -1e-9) to_edge = std::min(to_edge, (x_mid - half_width - centre.x()) / d.x());
    if (d.y() > 1e-9) to_edge = std::min(to_edge, (roof_front - centre.z()) / d.y());
    if (d.y() < -1e-9) to_edge = std::min(to_edge, (roof_rear - centre.z()) / d.y());
    roof = std::max(roof, centre.y() + to_edge * kRoofGap / kRoofMargin);
  }
  const double belt = roof + 0.4;
  const double bottom = std::max(belt + 0.3, ground_below_rig_m - 0.2);
  const double windshield_base = roof_front + 0.8, rear_window_base = roof_rear - 0.6;
  const double front = windshield_base + 1.1, rear = rear_window_base - 0.5;

  EgoVehicleMeshes body;
  // Cabin: windshield (edge 0), roof (1), rear window (2); its floor (3) lies on the lower body.
  const std::vector<Eigen::Vector2d> cabin = {{windshield_base, belt}, {roof_front, roof}, {roof_rear, roof}, {rear_window_base, belt}};
  AddPrism(cabin, x_mid - half_width, x_mid + half_width, &body.glass, [&](size_t edge) -> MeshData* {
    return edge == 1 ? &body.paint : edge == 3 ? nullptr : &body.glass;
  });
  // Lower body: the bonnet falls 0.12 m to the front, the boot 0.05 m to the rear.
  const std::vector<Eigen::Vector2d> lower = {{rear, bottom}, {front, bottom}, {front, belt + 0.12}, {windshield_base, belt},
                                              {rear_window_base, belt}, {rear, belt + 0.05}};
  AddPrism(lower, x_mid - half_width - 0.12, x_mid + half_width + 0.12, &body.paint, [&](size_t) { return &body.paint; });

  for (const RigCamera& c : rig.cameras) {
    const Eigen::Vector3d origin = c.cam_from_rig->SourceOriginInTarget();
    const Eigen::Vector3d dir = c.cam_from_rig->rotation.conjugate() * Eigen::Vector3d::UnitZ();
    const double t = std::min(NearestHit(body.paint, origin, dir), NearestHit(body.glass, origin, dir));
    if (t < kMinClearance) {
      char cm[32];
      std::snprintf(cm, sizeof(cm), "%.0f cm", 100 * t);
      throw std::invalid_argument("camera '" + c.name + "' looks into the car body " + cm +
                                  " from its lens (the roof is at least 5 cm below the lowest camera): turn it to "
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
