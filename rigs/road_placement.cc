#include "rigs/road_placement.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "labels/cityscapes.h"
#include "rigs/path_clearance.h"
#include "rigs/rng.h"

namespace rigsim {
namespace {

// The scene seen from above on a raster over its ground plane (x, z): per cell, the height of the
// highest surface labelled road, cast against the road's triangles alone (so a road under trees,
// a bridge or a parked car, or touching a tyre, is still road: what stands on it is the clearance
// checks' business), and the class of the lowest surface of the whole scene, the ground.
class RoadRaster {
 public:
  RoadRaster(const Scene& scene, const GridCaster& caster) : lo_(caster.lo()) {
    const Eigen::Vector3d hi = caster.hi();
    res_ = std::max(0.25, std::max(hi.x() - lo_.x(), hi.z() - lo_.z()) / 800.0);
    nx_ = std::max(1, int(std::ceil((hi.x() - lo_.x()) / res_)));
    nz_ = std::max(1, int(std::ceil((hi.z() - lo_.z()) / res_)));
    road_y_.assign(size_t(nx_) * nz_, std::numeric_limits<double>::quiet_NaN());
    ground_.assign(size_t(nx_) * nz_, kNothing);
    Scene road_only;
    const uint8_t road = FindClassByName("road")->id;
    for (const SceneMesh& m : scene.meshes) {
      if (m.class_id != road) continue;
      road_only.meshes.emplace_back();
      road_only.meshes.back().positions = m.positions;
      road_only.meshes.back().indices = m.indices;
    }
    const GridCaster road_caster(road_only);
    for (int iz = 0; iz < nz_; ++iz) {
      for (int ix = 0; ix < nx_; ++ix) {
        const size_t cell = size_t(iz) * nx_ + ix;
        const Eigen::Vector3d top(lo_.x() + (ix + 0.5) * res_, hi.y() + 1.0, lo_.z() + (iz + 0.5) * res_);
        if (const auto hit = road_caster.Cast(top, Eigen::Vector3d(0, -1, 0))) {
          road_y_[cell] = top.y() - hit->t;
          ++num_road_;
        }
        Eigen::Vector3d o = top;
        for (int layer = 0; layer < 64; ++layer) {  // down through the column's surfaces to the lowest
          const auto hit = caster.Cast(o, Eigen::Vector3d(0, -1, 0));
          if (!hit) break;
          ground_[cell] = hit->class_id;
          o.y() -= hit->t + 1e-4;
        }
      }
    }
  }

  double resolution() const { return res_; }
  int num_road_cells() const { return num_road_; }

  // The road's height at (x, z), or NaN off the road.
  double RoadY(const Eigen::Vector2d& p) const {
    const int ix = int(std::floor((p.x() - lo_.x()) / res_)), iz = int(std::floor((p.y() - lo_.z()) / res_));
    if (ix < 0 || iz < 0 || ix >= nx_ || iz >= nz_) return std::numeric_limits<double>::quiet_NaN();
    return road_y_[size_t(iz) * nx_ + ix];
  }
  bool OnRoad(const Eigen::Vector2d& p) const { return !std::isnan(RoadY(p)); }

  // The centre (x, z) of the road cell of rank `k` (0 <= k < num_road_cells, in raster order).
  Eigen::Vector2d RoadCell(int k) const {
    if (road_index_.empty()) {
      for (size_t c = 0; c < road_y_.size(); ++c) {
        if (!std::isnan(road_y_[c])) road_index_.push_back(c);
      }
    }
    const size_t c = road_index_[size_t(k)];
    return Eigen::Vector2d(lo_.x() + (double(c % nx_) + 0.5) * res_, lo_.z() + (double(c / nx_) + 0.5) * res_);
  }

  // How far from p along the unit direction d the road continues (up to max_m).
  double Run(const Eigen::Vector2d& p, const Eigen::Vector2d& d, double max_m) const {
    const double step = 0.5 * res_;
    for (double s = step; s <= max_m; s += step) {
      if (!OnRoad(p + s * d)) return s - step;
    }
    return max_m;
  }

  // "sidewalk 62%, terrain 30%, unlabeled 8%": the ground's classes by their share of the columns
  // that have one, largest first, down to 0.5%.
  std::string GroundClasses() const {
    std::map<uint8_t, int> count;
    int total = 0;
    for (uint8_t g : ground_) {
      if (g == kNothing) continue;
      ++count[g];
      ++total;
    }
    std::vector<std::pair<int, uint8_t>> shares;
    for (const auto& [id, n] : count) shares.push_back({-n, id});
    std::sort(shares.begin(), shares.end());
    std::string text;
    for (const auto& [minus_n, id] : shares) {
      if (-minus_n < 0.005 * total) break;  // the ground's main classes, not every speck
      const LabelClass* c = FindClassById(id);
      char part[64];
      std::snprintf(part, sizeof part, "%s%s %.0f%%", text.empty() ? "" : ", ", c ? std::string(c->name).c_str() : "?",
                    100.0 * -minus_n / total);
      text += part;
    }
    return text.empty() ? "nothing" : text;
  }

 private:
  static constexpr uint8_t kNothing = 255;  // no surface in the column (ids are 0..33)
  Eigen::Vector3d lo_;
  double res_ = 1.0;
  int nx_ = 0, nz_ = 0, num_road_ = 0;
  std::vector<double> road_y_;
  std::vector<uint8_t> ground_;
  mutable std::vector<size_t> road_index_;
};

// The horizontal unit direction of a heading as (x, z).
Eigen::Vector2d FlatHeading(double heading_deg) {
  const Eigen::Vector3d d = HeadingDirection(heading_deg);
  return Eigen::Vector2d(d.x(), d.z());
}

// The road's long direction at p: the heading in [0, 180) along which the road continues furthest
// both ways from p. Where several headings reach as far (to the road's ends), the middle of their
// range: on a straight strip that is the strip's axis, from anywhere across it.
double RoadAxisAt(const RoadRaster& road, const Eigen::Vector2d& p, double max_m) {
  constexpr int kHeadings = 180;  // 1 deg apart
  std::vector<double> run(kHeadings);
  int best = 0;
  for (int k = 0; k < kHeadings; ++k) {
    const Eigen::Vector2d d = FlatHeading(k);
    run[k] = road.Run(p, d, max_m) + road.Run(p, -d, max_m);
    if (run[k] > run[best]) best = k;
  }
  const double tolerance = 2.0 * road.resolution();
  int left = 0, right = 0;  // the contiguous range around `best` within the tolerance (headings wrap at 180)
  while (left < kHeadings / 2 && run[(best - left - 1 + kHeadings) % kHeadings] >= run[best] - tolerance) ++left;
  while (right < kHeadings / 2 && run[(best + right + 1) % kHeadings] >= run[best] - tolerance) ++right;
  const double axis = best + 0.5 * (right - left);
  return axis - 180.0 * std::floor(axis / 180.0);
}

// The road's cross-section through p perpendicular to `axis_deg`: its centre and width.
struct CrossSection {
  Eigen::Vector2d centre;
  double width_m;
};
CrossSection RoadCrossSection(const RoadRaster& road, const Eigen::Vector2d& p, double axis_deg, double max_m) {
  const Eigen::Vector2d right = FlatHeading(axis_deg + 90.0);
  const double to_right = road.Run(p, right, max_m), to_left = road.Run(p, -right, max_m);
  // The runs end half a step inside each edge on average.
  return {p + 0.5 * (to_right - to_left) * right, to_right + to_left + 0.5 * road.resolution()};
}

// The axis refined on the road's centre line: the centres of cross-sections up to 10 m either way
// along `axis_deg` from `centre`, where the road is as wide as at the centre (not at a junction),
// fitted by a line through `centre` (least squares of their offsets across the axis). Removes the
// coarse axis's degree steps on a straight road and follows a gentle bend.
double CentreLineAxis(const RoadRaster& road, const CrossSection& at, double axis_deg, double max_m) {
  const Eigen::Vector2d along = FlatHeading(axis_deg), right = FlatHeading(axis_deg + 90.0);
  double ss = 0.0, sl = 0.0;
  for (int k = -4; k <= 4; ++k) {
    const double s = 2.5 * k;
    if (k == 0 || !road.OnRoad(at.centre + s * along)) continue;
    const CrossSection section = RoadCrossSection(road, at.centre + s * along, axis_deg, max_m);
    if (std::abs(section.width_m - at.width_m) > 0.1 * at.width_m + road.resolution()) continue;
    ss += s * s;
    sl += s * (section.centre - at.centre).dot(right);
  }
  // A centre line drifting right (+l) as s grows turns the axis clockwise, to a larger heading.
  const double axis = ss > 0 ? axis_deg + RadToDeg(std::atan(sl / ss)) : axis_deg;
  return axis - 180.0 * std::floor(axis / 180.0);
}

// Whether the rig's footprint (its centre and half_width_m to each side) stays on the road along
// the whole path, sampled every 0.5 m at most (closed paths all round).
bool PathStaysOnRoad(const RoadRaster& road, const TrajectoryOptions& path, double half_width_m) {
  const double closed = ClosedPathLength(path);
  const double total = closed > 0 ? closed : (path.num_frames - 1) * path.step_m;
  const int samples = std::max(1, int(std::ceil(std::abs(total) / std::min(0.5, road.resolution()))));
  for (int k = 0; k <= samples; ++k) {
    const Rigid3d world_from_rig = RigFromWorldAlongPath(path, total * k / samples).Inverse();
    const Eigen::Vector2d centre(world_from_rig.translation.x(), world_from_rig.translation.z());
    const Eigen::Vector3d right3 = world_from_rig.rotation * Eigen::Vector3d::UnitX();
    Eigen::Vector2d right(right3.x(), right3.z());
    right = right.norm() > 1e-6 ? right.normalized() : Eigen::Vector2d::Zero();
    for (double side : {0.0, -1.0, 1.0}) {
      if (!road.OnRoad(centre + side * half_width_m * right)) return false;
    }
  }
  return true;
}

// How far the lane runs clear from the rig along `heading_deg`: over the road and free of geometry
// for its whole footprint (its centre and half_width_m to each side), both at the rig's height and
// 0.5 m above the road, where a parked car's body is (up to max_m).
double ClearLane(const GridCaster& caster, const RoadRaster& road, const Eigen::Vector3d& position, double ground_y,
                 double heading_deg, double half_width_m, double max_m) {
  const Eigen::Vector3d along = HeadingDirection(heading_deg), right = HeadingDirection(heading_deg + 90.0);
  double clear = max_m;
  for (double side : {0.0, -1.0, 1.0}) {
    const Eigen::Vector3d p = position + side * half_width_m * right;
    clear = std::min(clear, road.Run(Eigen::Vector2d(p.x(), p.z()), FlatHeading(heading_deg), clear));
    for (const double y : {p.y(), ground_y + 0.5}) {
      if (const auto hit = caster.Cast(Eigen::Vector3d(p.x(), y, p.z()), along, clear)) clear = hit->t;
    }
  }
  return clear;
}

struct LaneCandidate {
  RigPlacement placement;
  int order;  // for a stable, seed-determined order among equal scores
};

}  // namespace

std::optional<RigPlacement> PlaceRigOnRoad(const Scene& scene, const GridCaster& caster, const Rig& rig,
                                           const PlacementOptions& o, const TrajectoryOptions* path) {
  const RoadRaster road(scene, caster);
  if (road.num_road_cells() == 0) {
    throw NoRoadError("no surface labelled road (Cityscapes 'road', id " + std::to_string(FindClassByName("road")->id) +
                      ") to drive on; its ground, the lowest surface seen from above, is " + road.GroundClasses());
  }
  const double reach = (caster.hi() - caster.lo()).norm();  // runs are measured to the road's ends
  Rng rng(o.seed);
  std::vector<LaneCandidate> candidates;
  for (int c = 0; c < o.num_candidates; ++c) {
    const int k = std::min(road.num_road_cells() - 1, int(rng.Uniform() * road.num_road_cells()));
    // The axis from the spot, then from the centre of the road there, which sees the road's ends
    // symmetrically.
    const Eigen::Vector2d spot = road.RoadCell(k);
    const CrossSection first = RoadCrossSection(road, spot, RoadAxisAt(road, spot, reach), reach);
    const double coarse_axis = RoadAxisAt(road, first.centre, reach);
    const CrossSection coarse = RoadCrossSection(road, first.centre, coarse_axis, reach);
    const double axis = CentreLineAxis(road, coarse, coarse_axis, reach);
    const CrossSection section = RoadCrossSection(road, coarse.centre, axis, reach);
    for (const double heading : {axis, axis + 180.0}) {
      const double lane_offset = section.width_m >= o.two_lane_width_m ? 0.25 * section.width_m : 0.0;
      const Eigen::Vector2d lane = section.centre + lane_offset * FlatHeading(heading + 90.0);
      const double road_y = road.RoadY(lane);
      if (std::isnan(road_y)) continue;
      const Eigen::Vector3d position(lane.x(), road_y + o.height_m, lane.y());
      if (Boxed(caster, position)) continue;
      if (o.travel_m > 0 && caster.Cast(position, HeadingDirection(heading), o.travel_m + o.min_clearance_m)) continue;
      const RoadSpot spot_info{section.width_m, lane_offset,
                               ClearLane(caster, road, position, road_y, heading, o.half_width_m, o.max_range_m),
                               ClearLane(caster, road, position, road_y, heading + 180.0, o.half_width_m, o.max_range_m)};
      const double score = std::min(spot_info.clear_ahead_m, spot_info.clear_behind_m) / o.max_range_m;
      candidates.push_back({RigPlacement{position, heading, score, spot_info}, int(candidates.size())});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const LaneCandidate& a, const LaneCandidate& b) {
    return a.placement.score != b.placement.score ? a.placement.score > b.placement.score : a.order < b.order;
  });
  for (const LaneCandidate& c : candidates) {
    TrajectoryOptions from_here = path ? *path : TrajectoryOptions{};  // without a path: one frame, standing
    from_here.start_world = c.placement.position_world;
    from_here.heading_deg = c.placement.heading_deg;
    if (!PathStaysOnRoad(road, from_here, o.half_width_m)) continue;
    if (!PathIsClear(caster, rig, MakeTrajectory(from_here), o.height_m)) continue;
    return c.placement;
  }
  return std::nullopt;
}

}  // namespace rigsim
