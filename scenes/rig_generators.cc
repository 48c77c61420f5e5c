#include "scenes/rig_generators.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace rigsim {
namespace {

void Fail(const std::string& what, const std::string& why) { throw std::invalid_argument(what + ": " + why); }

void CheckImage(const std::string& what, int width, int height) {
  if (width < 16 || height < 16) Fail(what, "image size must be at least 16x16");
}

// A perspective camera with the principal point at the centre whose side edges image the rays at
// +-hfov/2, with OPENCV radial distortion (k1, k2) or none.
Camera PerspectiveCamera(const std::string& what, int width, int height, double hfov_deg, double k1 = 0.0, double k2 = 0.0) {
  const double r = std::tan(DegToRad(0.5 * hfov_deg));  // normalised radius at the image's side edge
  const double half_w = 0.5 * width;
  const double cx = 0.5 * (width - 1), cy = 0.5 * (height - 1);
  if (k1 == 0.0 && k2 == 0.0) {
    const double f = half_w / r;
    return Camera(CameraModelId::kPinhole, width, height, {f, f, cx, cy});
  }
  const double rd = r * (1.0 + k1 * r * r + k2 * r * r * r * r);
  if (!(rd > 0)) Fail(what, "distortion folds inside the field of view");
  const double f = half_w / rd;
  return Camera(CameraModelId::kOpenCV, width, height, {f, f, cx, cy, k1, k2, 0.0, 0.0});
}

// Kannala-Brandt fisheye whose side edges image the rays at +-fov/2 (which may exceed 90 deg).
Camera FisheyeCamera(int width, int height, double fov_deg) {
  const std::vector<double> k = {0.02, -0.004, 0.0005, 0.0};  // mild, monotonic far beyond 100 deg
  const double theta = DegToRad(0.5 * fov_deg);
  const double t2 = theta * theta;
  const double theta_d = theta * (1 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
  const double f = 0.5 * width / theta_d;
  return Camera(CameraModelId::kOpenCVFisheye, width, height, {f, f, 0.5 * (width - 1), 0.5 * (height - 1), k[0], k[1], k[2], k[3]});
}

// rig_from_cam for a camera at `centre_in_rig`, turned right by `yaw_deg` and down by `pitch_deg`.
Rigid3d RigFromCam(const Eigen::Vector3d& centre_in_rig, double yaw_deg, double pitch_deg = 0.0) {
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(DegToRad(yaw_deg), Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(-DegToRad(pitch_deg), Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  return Rigid3d(r, centre_in_rig);
}

void AddCamera(Rig& rig, const std::string& name, const Camera& cam, const Rigid3d& rig_from_cam) {
  rig.cameras.push_back(RigCamera{name, cam, rig_from_cam.Inverse(), 0.0});
}

std::string FrameName(int k) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06d", k);
  return name;
}

Eigen::Vector3d Forward(double heading_deg) {
  const double h = DegToRad(heading_deg);
  return Eigen::Vector3d(std::sin(h), 0.0, -std::cos(h));
}

// splitmix64: our own generator, so results do not depend on the standard library.
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  uint64_t Next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double Uniform() { return double(Next() >> 11) * (1.0 / 9007199254740992.0); }
  double Uniform(double a, double b) { return a + (b - a) * Uniform(); }

 private:
  uint64_t state_;
};

// ---- Ray casting over a 2-D grid in the ground plane (x, z) --------------------------------------

class GridCaster {
 public:
  explicit GridCaster(const Scene& scene) {
    lo_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
    hi_ = -lo_;
    for (const SceneMesh& m : scene.meshes) {
      for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        Tri tri;
        for (int k = 0; k < 3; ++k) {
          const uint32_t idx = m.indices[t + k];
          if (idx >= m.positions.size()) continue;
          tri.v[k] = m.positions[idx].cast<double>();
          lo_ = lo_.cwiseMin(tri.v[k]);
          hi_ = hi_.cwiseMax(tri.v[k]);
        }
        tris_.push_back(tri);
      }
    }
    if (tris_.empty()) return;
    const double extent = std::max(hi_.x() - lo_.x(), hi_.z() - lo_.z());
    cell_ = std::max(0.5, extent / 200.0);
    nx_ = std::max(1, int(std::ceil((hi_.x() - lo_.x()) / cell_)) + 1);
    nz_ = std::max(1, int(std::ceil((hi_.z() - lo_.z()) / cell_)) + 1);
    cells_.assign(size_t(nx_) * nz_, {});
    for (uint32_t i = 0; i < tris_.size(); ++i) {
      const Tri& t = tris_[i];
      const double x0 = std::min({t.v[0].x(), t.v[1].x(), t.v[2].x()}), x1 = std::max({t.v[0].x(), t.v[1].x(), t.v[2].x()});
      const double z0 = std::min({t.v[0].z(), t.v[1].z(), t.v[2].z()}), z1 = std::max({t.v[0].z(), t.v[1].z(), t.v[2].z()});
      for (int cz = CellZ(z0); cz <= CellZ(z1); ++cz) {
        for (int cx = CellX(x0); cx <= CellX(x1); ++cx) cells_[size_t(cz) * nx_ + cx].push_back(i);
      }
    }
  }

  bool empty() const { return tris_.empty(); }
  const Eigen::Vector3d& lo() const { return lo_; }
  const Eigen::Vector3d& hi() const { return hi_; }

  struct Hit {
    double t;
    Eigen::Vector3d normal;  // unnormalised geometric normal (v1-v0) x (v2-v0)
  };

  // First hit along origin + t dir, t in (1e-6, max_t].
  std::optional<Hit> Cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double max_t = 1e9) const {
    if (tris_.empty()) return std::nullopt;
    std::optional<Hit> best;
    auto test_cell = [&](int cx, int cz) {
      if (cx < 0 || cz < 0 || cx >= nx_ || cz >= nz_) return;
      for (uint32_t i : cells_[size_t(cz) * nx_ + cx]) {
        double t;
        if (Intersect(tris_[i], o, d, &t) && t <= max_t && (!best || t < best->t)) {
          const Tri& tri = tris_[i];
          best = Hit{t, (tri.v[1] - tri.v[0]).cross(tri.v[2] - tri.v[0])};
        }
      }
    };
    const double dxz = std::hypot(d.x(), d.z());
    if (dxz < 1e-9) {  // vertical: one cell
      test_cell(CellX(o.x()), CellZ(o.z()));
      return best;
    }
    // 2-D DDA through the cells crossed by the ray's ground-plane projection.
    double px = (o.x() - lo_.x()) / cell_, pz = (o.z() - lo_.z()) / cell_;
    const double dx = d.x() / cell_, dz = d.z() / cell_;
    // Start inside the grid: advance to the grid's box if the origin is outside.
    double t0 = 0.0;
    auto clip = [&](double p, double dp, double n, double& tmin, double& tmax) {
      if (std::abs(dp) < 1e-15) {
        if (p < 0 || p > n) tmin = 1e300;
        return;
      }
      double a = (0 - p) / dp, b = (n - p) / dp;
      if (a > b) std::swap(a, b);
      tmin = std::max(tmin, a);
      tmax = std::min(tmax, b);
    };
    double tmin = 0.0, tmax = max_t;
    clip(px, dx, nx_, tmin, tmax);
    clip(pz, dz, nz_, tmin, tmax);
    if (tmin > tmax) return std::nullopt;
    t0 = tmin;
    int cx = std::clamp(int(std::floor(px + dx * t0)), 0, nx_ - 1), cz = std::clamp(int(std::floor(pz + dz * t0)), 0, nz_ - 1);
    const int sx = dx > 0 ? 1 : -1, sz = dz > 0 ? 1 : -1;
    auto next_boundary = [](double p, double dp, int c, int s) {
      if (std::abs(dp) < 1e-15) return 1e300;
      const double edge = s > 0 ? c + 1 : c;
      return (edge - p) / dp;
    };
    double tx = next_boundary(px, dx, cx, sx), tz = next_boundary(pz, dz, cz, sz);
    const double step_x = std::abs(dx) < 1e-15 ? 1e300 : std::abs(1.0 / dx), step_z = std::abs(dz) < 1e-15 ? 1e300 : std::abs(1.0 / dz);
    for (int guard = 0; guard < nx_ + nz_ + 4; ++guard) {
      test_cell(cx, cz);
      const double t_exit = std::min(tx, tz);
      if (best && best->t <= t_exit) return best;
      if (t_exit > tmax) break;
      if (tx < tz) {
        cx += sx;
        tx += step_x;
      } else {
        cz += sz;
        tz += step_z;
      }
      if (cx < 0 || cz < 0 || cx >= nx_ || cz >= nz_) break;
    }
    return best;
  }

 private:
  struct Tri {
    Eigen::Vector3d v[3];
  };
  int CellX(double x) const { return std::clamp(int((x - lo_.x()) / cell_), 0, nx_ - 1); }
  int CellZ(double z) const { return std::clamp(int((z - lo_.z()) / cell_), 0, nz_ - 1); }

  // Moeller-Trumbore, both sides.
  static bool Intersect(const Tri& tri, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t) {
    const Eigen::Vector3d e1 = tri.v[1] - tri.v[0], e2 = tri.v[2] - tri.v[0];
    const Eigen::Vector3d p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-14) return false;
    const double inv = 1.0 / det;
    const Eigen::Vector3d s = o - tri.v[0];
    const double u = s.dot(p) * inv;
    if (u < 0 || u > 1) return false;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = d.dot(q) * inv;
    if (v < 0 || u + v > 1) return false;
    *t = e2.dot(q) * inv;
    return *t > 1e-6;
  }

  std::vector<Tri> tris_;
  std::vector<std::vector<uint32_t>> cells_;
  Eigen::Vector3d lo_, hi_;
  double cell_ = 1.0;
  int nx_ = 0, nz_ = 0;
};

}  // namespace

// ---- Ring ---------------------------------------------------------------------------------------

void RingRigOptions::Check() const {
  const std::string w = "ring rig";
  if (num_cameras < 1) Fail(w, "needs at least one camera");
  if (!(hfov_deg > 1 && hfov_deg < 179)) Fail(w, "hfov_deg must be in (1, 179) for perspective cameras");
  if (!(radius_m >= 0)) Fail(w, "radius_m must be >= 0");
  CheckImage(w, width, height);
  if (distorted_camera >= num_cameras) Fail(w, "distorted_camera is not a camera index");
  if (!(target_overlap < 1)) Fail(w, "target_overlap must be < 1 (a fraction; <= 0 = use yaw_spacing_deg)");
  if (target_overlap > 0 && num_cameras < 2) Fail(w, "target_overlap needs at least two cameras");
}

Rig MakeRingRig(const RingRigOptions& o) {
  o.Check();
  const double spacing = o.target_overlap > 0 ? RingSpacingForOverlap(o, o.target_overlap) : o.yaw_spacing_deg;
  Rig rig;
  for (int i = 0; i < o.num_cameras; ++i) {
    const double yaw_deg = (i - 0.5 * (o.num_cameras - 1)) * spacing;
    const double yaw = DegToRad(yaw_deg);
    const Eigen::Vector3d centre_in_rig = o.radius_m * Eigen::Vector3d(std::sin(yaw), 0.0, std::cos(yaw));
    const Camera cam = i == o.distorted_camera ? PerspectiveCamera("ring rig", o.width, o.height, o.hfov_deg, o.k1, o.k2)
                                               : PerspectiveCamera("ring rig", o.width, o.height, o.hfov_deg);
    char name[32];
    std::snprintf(name, sizeof(name), "cam%d", i);
    AddCamera(rig, name, cam, RigFromCam(centre_in_rig, yaw_deg));
  }
  return rig;
}

double AngularOverlap(const Camera& a, const Camera& b, const Eigen::Matrix3d& b_from_a_rotation) {
  const int nx = 128, ny = std::max(8, int(std::lround(128.0 * a.height() / a.width())));
  int valid = 0, seen = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const Eigen::Vector2d px((i + 0.5) * a.width() / nx - 0.5, (j + 0.5) * a.height() / ny - 0.5);
      const std::optional<Eigen::Vector3d> ray = a.CamFromImg(px);
      if (!ray) continue;
      ++valid;
      const std::optional<Eigen::Vector2d> pb = b.ImgFromCam(b_from_a_rotation * *ray);
      if (pb && b.IsInImage(*pb)) ++seen;
    }
  }
  return valid ? double(seen) / valid : 0.0;
}

double RingSpacingForOverlap(const RingRigOptions& options, double overlap) {
  RingRigOptions o = options;
  o.target_overlap = 0.0;
  if (o.num_cameras < 2) Fail("ring rig", "target_overlap needs at least two cameras");
  auto mean_overlap = [&](double spacing) {
    o.yaw_spacing_deg = spacing;
    const Rig rig = MakeRingRig(o);
    double sum = 0;
    int n = 0;
    for (size_t i = 0; i + 1 < rig.cameras.size(); ++i) {
      const RigCamera& a = rig.cameras[i];
      const RigCamera& b = rig.cameras[i + 1];
      const Eigen::Matrix3d b_from_a = (*b.cam_from_rig * a.cam_from_rig->Inverse()).RotationMatrix();
      sum += AngularOverlap(a.camera, b.camera, b_from_a) + AngularOverlap(b.camera, a.camera, b_from_a.transpose());
      n += 2;
    }
    return sum / n;
  };
  double lo = 0.0, hi = std::min(179.0, o.hfov_deg * 1.5);
  if (mean_overlap(hi) > overlap) Fail("ring rig", "target overlap is below what a spacing of " + std::to_string(hi) + " deg gives");
  if (mean_overlap(lo) < overlap) Fail("ring rig", "target overlap is not reachable");
  for (int it = 0; it < 24; ++it) {
    const double mid = 0.5 * (lo + hi);
    (mean_overlap(mid) > overlap ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

namespace {

// Fraction of a's surface samples (rays that hit the scene) that b sees unoccluded.
double PredictedOverlapOneWay(const GridCaster& caster, const RigCamera& a, const RigCamera& b, const Rigid3d& rig_from_world) {
  const Rigid3d world_from_a = (*a.cam_from_rig * rig_from_world).Inverse();
  const Rigid3d b_from_world = *b.cam_from_rig * rig_from_world;
  const Eigen::Vector3d centre_b = b_from_world.Inverse().translation;
  const int nx = 48, ny = std::max(8, int(std::lround(48.0 * a.camera.height() / a.camera.width())));
  int surface = 0, seen = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const Eigen::Vector2d px((i + 0.5) * a.camera.width() / nx - 0.5, (j + 0.5) * a.camera.height() / ny - 0.5);
      const std::optional<Eigen::Vector3d> ray = a.camera.CamFromImg(px);
      if (!ray) continue;
      const Eigen::Vector3d dir = world_from_a.rotation * *ray;
      const auto hit = caster.Cast(world_from_a.translation, dir);
      if (!hit) continue;  // sky: not part of the ground-truth overlap
      ++surface;
      const Eigen::Vector3d x = world_from_a.translation + hit->t * dir;
      const auto pb = b.camera.ImgFromCam(b_from_world * x);
      if (!pb || !b.camera.IsInImage(*pb)) continue;
      const double dist = (x - centre_b).norm();
      const auto occluder = caster.Cast(centre_b, (x - centre_b) / dist, dist);
      if (!occluder || occluder->t >= dist - std::max(0.05, 0.02 * dist)) ++seen;
    }
  }
  return surface ? double(seen) / surface : 0.0;
}

double PredictedOverlapWith(const GridCaster& caster, const Rig& rig, int a, int b, const Rigid3d& rig_from_world) {
  return 0.5 * (PredictedOverlapOneWay(caster, rig.cameras[a], rig.cameras[b], rig_from_world) +
                PredictedOverlapOneWay(caster, rig.cameras[b], rig.cameras[a], rig_from_world));
}

}  // namespace

double PredictedOverlap(const Scene& scene, const Rig& rig, int a, int b, const Rigid3d& rig_from_world) {
  if (a < 0 || b < 0 || a >= int(rig.cameras.size()) || b >= int(rig.cameras.size()) || !rig.HasAllPoses()) {
    Fail("predicted overlap", "camera index out of range or camera without cam_from_rig");
  }
  return PredictedOverlapWith(GridCaster(scene), rig, a, b, rig_from_world);
}

Rig MakeRingRigInScene(const RingRigOptions& options, const Scene& scene, const Rigid3d& rig_from_world) {
  options.Check();
  if (!(options.target_overlap > 0)) Fail("ring rig", "MakeRingRigInScene needs target_overlap in (0, 1)");
  Rig rig = MakeRingRig(options);  // the angular solution: intrinsics, and cam0's yaw
  const GridCaster caster(scene);
  auto yaw_of = [&](int i) {
    const Eigen::Vector3d axis = rig.cameras[i].cam_from_rig->Inverse().rotation * Eigen::Vector3d::UnitZ();
    return RadToDeg(std::atan2(axis.x(), axis.z()));
  };
  auto place = [&](int i, double yaw_deg) {
    const double yaw = DegToRad(yaw_deg);
    const Eigen::Vector3d centre = options.radius_m * Eigen::Vector3d(std::sin(yaw), 0.0, std::cos(yaw));
    rig.cameras[i].cam_from_rig = RigFromCam(centre, yaw_deg).Inverse();
  };
  for (int i = 1; i < options.num_cameras; ++i) {
    const double base = yaw_of(i - 1);
    double lo = base, hi = base + std::min(179.0, 1.5 * options.hfov_deg);
    for (int it = 0; it < 14; ++it) {
      const double mid = 0.5 * (lo + hi);
      place(i, mid);
      (PredictedOverlapWith(caster, rig, i - 1, i, rig_from_world) > options.target_overlap ? lo : hi) = mid;
    }
    place(i, 0.5 * (lo + hi));
  }
  return rig;
}

// ---- Stereo, surround, wide baseline ---------------------------------------------------------------

void StereoRigOptions::Check() const {
  if (!(baseline_m > 0)) Fail("stereo rig", "baseline_m must be > 0");
  if (!(hfov_deg > 1 && hfov_deg < 179)) Fail("stereo rig", "hfov_deg must be in (1, 179)");
  CheckImage("stereo rig", width, height);
}

Rig MakeStereoRig(const StereoRigOptions& o) {
  o.Check();
  Rig rig;
  const Camera cam = PerspectiveCamera("stereo rig", o.width, o.height, o.hfov_deg);
  AddCamera(rig, "left", cam, RigFromCam(Eigen::Vector3d(-0.5 * o.baseline_m, 0, 0), 0.0));
  AddCamera(rig, "right", cam, RigFromCam(Eigen::Vector3d(0.5 * o.baseline_m, 0, 0), 0.0));
  return rig;
}

void SurroundRigOptions::Check() const {
  const std::string w = "surround rig";
  if (!(length_m >= 0) || !(width_m >= 0)) Fail(w, "length_m and width_m must be >= 0");
  if (!(front_hfov_deg > 1 && front_hfov_deg < 170)) Fail(w, "front_hfov_deg must be in (1, 170)");
  if (!(back_hfov_deg > 1 && back_hfov_deg < 170)) Fail(w, "back_hfov_deg must be in (1, 170)");
  if (!(side_fov_deg > 10 && side_fov_deg <= 220)) Fail(w, "side_fov_deg must be in (10, 220]");
  if (!(std::abs(side_pitch_deg) <= 60)) Fail(w, "side_pitch_deg must be within +-60");
  CheckImage(w, width, height);
}

Rig MakeSurroundRig(const SurroundRigOptions& o) {
  o.Check();
  Rig rig;
  const Camera fisheye = FisheyeCamera(o.width, o.height, o.side_fov_deg);
  if (fisheye.max_valid_angle() < DegToRad(0.5 * o.side_fov_deg) - 1e-9) {
    Fail("surround rig", "the fisheye lens cannot image " + std::to_string(o.side_fov_deg) + " deg");
  }
  AddCamera(rig, "front", PerspectiveCamera("surround rig", o.width, o.height, o.front_hfov_deg, -0.12, 0.02),
            RigFromCam(Eigen::Vector3d(0, 0, 0.5 * o.length_m), 0.0));
  AddCamera(rig, "right", fisheye, RigFromCam(Eigen::Vector3d(0.5 * o.width_m, 0, 0), 90.0, o.side_pitch_deg));
  AddCamera(rig, "back", PerspectiveCamera("surround rig", o.width, o.height, o.back_hfov_deg),
            RigFromCam(Eigen::Vector3d(0, 0, -0.5 * o.length_m), 180.0));
  AddCamera(rig, "left", fisheye, RigFromCam(Eigen::Vector3d(-0.5 * o.width_m, 0, 0), -90.0, o.side_pitch_deg));
  return rig;
}

void WideBaselineRigOptions::Check() const {
  if (!(baseline_m > 0)) Fail("wide-baseline rig", "baseline_m must be > 0");
  if (!(convergence_deg > -90 && convergence_deg < 170)) Fail("wide-baseline rig", "convergence_deg must be in (-90, 170)");
  if (!(hfov_deg > 1 && hfov_deg < 179)) Fail("wide-baseline rig", "hfov_deg must be in (1, 179)");
  CheckImage("wide-baseline rig", width, height);
}

Rig MakeWideBaselineRig(const WideBaselineRigOptions& o) {
  o.Check();
  Rig rig;
  const Camera cam = PerspectiveCamera("wide-baseline rig", o.width, o.height, o.hfov_deg);
  AddCamera(rig, "cam0", cam, RigFromCam(Eigen::Vector3d(-0.5 * o.baseline_m, 0, 0), 0.5 * o.convergence_deg));
  AddCamera(rig, "cam1", cam, RigFromCam(Eigen::Vector3d(0.5 * o.baseline_m, 0, 0), -0.5 * o.convergence_deg));
  return rig;
}

void PerturbRig(Rig& rig, const RigPerturbation& p) {
  if (!(p.rotation_deg >= 0) || !(p.translation_m >= 0)) Fail("rig perturbation", "amounts must be >= 0");
  Rng rng(p.seed);
  for (RigCamera& c : rig.cameras) {
    if (!c.cam_from_rig) continue;
    // Draws one by one, z first: as constructor arguments their order was the compiler's choice
    // (GCC's, last first, is the one kept: the same seed gives the rigs it gave).
    auto draw_vector = [&rng] {
      const double z = rng.Uniform(-1, 1), y = rng.Uniform(-1, 1), x = rng.Uniform(-1, 1);
      return Eigen::Vector3d(x, y, z);
    };
    Eigen::Vector3d axis = draw_vector();
    if (axis.norm() < 1e-9) axis = Eigen::Vector3d::UnitX();
    const double angle = DegToRad(p.rotation_deg) * rng.Uniform();
    Eigen::Vector3d dt = draw_vector();
    if (dt.norm() > 1) dt.normalize();
    const Rigid3d delta(Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized())), p.translation_m * dt);
    c.cam_from_rig = delta * *c.cam_from_rig;
  }
}

// ---- Poses and trajectories ---------------------------------------------------------------------

Rigid3d RigFromWorldAt(const Eigen::Vector3d& position_world, double heading_deg) {
  const double h = DegToRad(heading_deg);
  Eigen::Matrix3d world_from_rig;
  world_from_rig.col(0) = Eigen::Vector3d(std::cos(h), 0.0, std::sin(h));   // right
  world_from_rig.col(1) = Eigen::Vector3d(0.0, -1.0, 0.0);                  // down
  world_from_rig.col(2) = Eigen::Vector3d(std::sin(h), 0.0, -std::cos(h));  // forward
  return Rigid3d(world_from_rig, position_world).Inverse();
}

FramesFile MakeStraightTrajectory(const Eigen::Vector3d& start_world, double heading_deg, int num_frames,
                                  double step_m, double frame_interval_s) {
  TrajectoryOptions o;
  o.start_world = start_world;
  o.heading_deg = heading_deg;
  o.num_frames = num_frames;
  o.step_m = step_m;
  o.frame_interval_s = frame_interval_s;
  return MakeTrajectory(o);
}

FramesFile MakeDemoTrajectory(int num_frames) {
  TrajectoryOptions o;
  o.kind = TrajectoryKind::kCircle;
  o.start_world = Eigen::Vector3d(0.0, 1.6, 4.0);
  o.heading_deg = 0.0;
  o.num_frames = num_frames;
  o.step_m = 2.0;
  o.circle_radius_m = 12.0;
  return MakeTrajectory(o);
}

void TrajectoryOptions::Check() const {
  if (num_frames < 1) Fail("trajectory", "needs at least one frame");
  if (!std::isfinite(step_m)) Fail("trajectory", "step_m must be finite");
  if (!start_world.allFinite()) Fail("trajectory", "start_world must be finite");
  if (kind == TrajectoryKind::kCircle && !(std::abs(circle_radius_m) > 1e-6)) Fail("trajectory", "circle_radius_m must be non-zero");
  if (kind == TrajectoryKind::kPolyline && waypoints.empty()) Fail("trajectory", "a polyline needs at least one waypoint");
}

FramesFile MakeTrajectory(const TrajectoryOptions& o) {
  o.Check();
  FramesFile frames;
  const Eigen::Vector3d f0 = Forward(o.heading_deg);
  const Eigen::Vector3d right0 = Forward(o.heading_deg + 90.0);
  for (int k = 0; k < o.num_frames; ++k) {
    const double s = k * o.step_m;  // arc length travelled
    Eigen::Vector3d position = o.start_world;
    double heading = o.heading_deg;
    switch (o.kind) {
      case TrajectoryKind::kStraight:
        position = o.start_world + s * f0;
        break;
      case TrajectoryKind::kCircle: {
        const double r = std::abs(o.circle_radius_m), phi = s / r;
        const Eigen::Vector3d side = o.circle_radius_m > 0 ? Eigen::Vector3d(-right0) : right0;
        position = o.start_world + r * std::sin(phi) * f0 + r * (1.0 - std::cos(phi)) * side;
        heading = o.heading_deg + (o.circle_radius_m > 0 ? -1.0 : 1.0) * RadToDeg(phi);
        break;
      }
      case TrajectoryKind::kPolyline: {
        std::vector<Eigen::Vector3d> pts = {o.start_world};
        pts.insert(pts.end(), o.waypoints.begin(), o.waypoints.end());
        double left = s;
        size_t seg = 0;
        for (; seg + 1 < pts.size(); ++seg) {
          const double len = (pts[seg + 1] - pts[seg]).norm();
          if (left <= len || seg + 2 == pts.size()) break;
          left -= len;
        }
        const Eigen::Vector3d d = pts[seg + 1] - pts[seg];
        const double len = d.norm();
        position = len > 1e-12 ? pts[seg] + std::min(left, len) / len * d : pts[seg];
        if (std::hypot(d.x(), d.z()) > 1e-12) heading = RadToDeg(std::atan2(d.x(), -d.z()));
        break;
      }
    }
    frames.frames.push_back(Frame{FrameName(k), RigFromWorldAt(position, heading), k * o.frame_interval_s});
  }
  return frames;
}

// ---- Automatic placement --------------------------------------------------------------------

void PlacementOptions::Check() const {
  const std::string w = "rig placement";
  if (!(height_m > 0)) Fail(w, "height_m must be > 0");
  if (!(min_clearance_m >= 0)) Fail(w, "min_clearance_m must be >= 0");
  if (!(travel_m >= 0)) Fail(w, "travel_m must be >= 0");
  if (!(max_range_m > min_clearance_m)) Fail(w, "max_range_m must exceed min_clearance_m");
  if (num_candidates < 1 || num_headings < 1) Fail(w, "num_candidates and num_headings must be >= 1");
}

std::optional<RigPlacement> PlaceRig(const Scene& scene, const Rig& rig, const PlacementOptions& o) {
  o.Check();
  if (!rig.HasAllPoses()) Fail("rig placement", "every camera needs cam_from_rig");
  const GridCaster caster(scene);
  if (caster.empty()) return std::nullopt;
  const Eigen::Vector3d lo = caster.lo(), hi = caster.hi();
  // Probe rays per camera, in the camera frame: the optical axis and a small cross around it
  // ("central rays", which must be clear), plus a wider fan that scores structure.
  std::vector<Eigen::Vector3d> central, fan;
  for (double a : {0.0, -0.15, 0.15}) central.push_back(Eigen::Vector3d(std::sin(a), 0, std::cos(a)));
  central.push_back(Eigen::Vector3d(0, -0.1, 1).normalized());
  for (int i = -3; i <= 3; ++i) {
    for (int j = -1; j <= 1; ++j) fan.push_back(Eigen::Vector3d(0.25 * i, 0.2 * j, 1.0).normalized());
  }
  const double ground_tolerance = 0.5;  // the surface under the rig must be within this of the lowest level
  Rng rng(o.seed);
  std::optional<RigPlacement> best;
  const double margin_x = 0.05 * (hi.x() - lo.x()), margin_z = 0.05 * (hi.z() - lo.z());
  for (int c = 0; c < o.num_candidates; ++c) {
    const double x = rng.Uniform(lo.x() + margin_x, hi.x() - margin_x);
    const double z = rng.Uniform(lo.z() + margin_z, hi.z() - margin_z);
    // The ground: the first surface seen from above must be at the scene's lowest level.
    const auto down = caster.Cast(Eigen::Vector3d(x, hi.y() + 1.0, z), Eigen::Vector3d(0, -1, 0));
    if (!down) continue;
    const double ground_y = hi.y() + 1.0 - down->t;
    if (ground_y > lo.y() + ground_tolerance) continue;
    const Eigen::Vector3d position(x, ground_y + o.height_m, z);
    // Not inside anything: nothing just above the rig head, clear all around within 0.5 m.
    if (caster.Cast(position, Eigen::Vector3d(0, 1, 0), 0.5)) continue;
    bool boxed = false;
    for (int k = 0; k < 8 && !boxed; ++k) {
      const double a = k * 0.7853981633974483;  // 45 deg steps
      boxed = caster.Cast(position, Eigen::Vector3d(std::sin(a), 0, std::cos(a)), 0.6).has_value();
    }
    if (boxed) continue;
    for (int h = 0; h < o.num_headings; ++h) {
      const double heading = 360.0 * h / o.num_headings + rng.Uniform(0.0, 360.0 / o.num_headings);
      const Rigid3d world_from_rig = RigFromWorldAt(position, heading).Inverse();
      if (o.travel_m > 0) {
        const auto ahead = caster.Cast(position, Forward(heading), o.travel_m + o.min_clearance_m);
        if (ahead) continue;
      }
      bool clear = true;
      int hits = 0, probes = 0;
      for (const RigCamera& rc : rig.cameras) {
        const Rigid3d world_from_cam = world_from_rig * rc.cam_from_rig->Inverse();
        const Eigen::Vector3d centre = world_from_cam.translation;
        for (const Eigen::Vector3d& d : central) {
          if (caster.Cast(centre, world_from_cam.rotation * d, o.min_clearance_m)) {
            clear = false;
            break;
          }
        }
        if (!clear) break;
        for (const Eigen::Vector3d& d : fan) {
          ++probes;
          const auto hit = caster.Cast(centre, world_from_cam.rotation * d, o.max_range_m);
          if (hit && hit->t >= o.min_clearance_m) ++hits;
        }
      }
      if (!clear) continue;
      const double score = double(hits) / std::max(1, probes);
      if (!best || score > best->score) best = RigPlacement{position, heading, score};
    }
  }
  return best;
}

std::optional<double> CastRay(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  const GridCaster caster(scene);
  if (const auto hit = caster.Cast(origin, direction.normalized())) return hit->t;
  return std::nullopt;
}

}  // namespace rigsim
