// Ray casting against a Scene's triangles for rig placement, without the renderer: the triangles
// are binned into a 2-D grid over the ground plane (x, z), and a ray walks the cells its
// ground-plane projection crosses (2-D DDA), testing each cell's triangles (Moeller-Trumbore,
// both sides). Coarse but enough to probe clearances and overlaps with a few thousand rays.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "scene/scene.h"

namespace rigsim {

class GridCaster {
 public:
  explicit GridCaster(const Scene& scene);

  bool empty() const { return tris_.empty(); }
  // The scene's bounding box.
  const Eigen::Vector3d& lo() const { return lo_; }
  const Eigen::Vector3d& hi() const { return hi_; }

  struct Hit {
    double t;
    Eigen::Vector3d normal;  // unnormalised geometric normal (v1-v0) x (v2-v0)
    uint8_t class_id = 0;    // the hit mesh's Cityscapes label id (SceneMesh::class_id)
  };

  // First hit along origin + t dir, t in (1e-6, max_t].
  std::optional<Hit> Cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double max_t = 1e9) const;

 private:
  struct Tri {
    Eigen::Vector3d v[3];
    uint8_t class_id = 0;
  };
  int CellX(double x) const;
  int CellZ(double z) const;
  static bool Intersect(const Tri& tri, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t);

  std::vector<Tri> tris_;
  std::vector<std::vector<uint32_t>> cells_;
  Eigen::Vector3d lo_, hi_;
  double cell_ = 1.0;
  int nx_ = 0, nz_ = 0;
};

}  // namespace rigsim
