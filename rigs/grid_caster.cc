#include "rigs/grid_caster.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Geometry>

namespace rigsim {

GridCaster::GridCaster(const Scene& scene) {
  lo_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
  hi_ = -lo_;
  for (const SceneMesh& m : scene.meshes) {
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
      Tri tri;
      tri.class_id = m.class_id;
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

std::optional<GridCaster::Hit> GridCaster::Cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double max_t) const {
  if (tris_.empty()) return std::nullopt;
  std::optional<Hit> best;
  auto test_cell = [&](int cx, int cz) {
    if (cx < 0 || cz < 0 || cx >= nx_ || cz >= nz_) return;
    for (uint32_t i : cells_[size_t(cz) * nx_ + cx]) {
      double t;
      if (Intersect(tris_[i], o, d, &t) && t <= max_t && (!best || t < best->t)) {
        const Tri& tri = tris_[i];
        best = Hit{t, (tri.v[1] - tri.v[0]).cross(tri.v[2] - tri.v[0]), tri.class_id};
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

int GridCaster::CellX(double x) const { return std::clamp(int((x - lo_.x()) / cell_), 0, nx_ - 1); }
int GridCaster::CellZ(double z) const { return std::clamp(int((z - lo_.z()) / cell_), 0, nz_ - 1); }

// Moeller-Trumbore, both sides.
bool GridCaster::Intersect(const Tri& tri, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t) {
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

}  // namespace rigsim
