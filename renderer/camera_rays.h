// Rays through the camera model: each pixel centre's bearing (computed once per camera and
// cached), the jittered colour samples within a pixel, and a batch's rays in the order Render
// traces and shades them.
//
// Conventions it relies on: the centre of pixel (x, y) has image coordinates (x, y) (OpenCV), and
// a bearing is camera.CamFromImg of its image point, so lens distortion is exact per ray. Sample
// positions are a hash of (seed, x, y, sample): the image does not depend on which thread renders
// which tile.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/camera.h"
#include "geometry/rigid3.h"
#include "renderer/embree_scene.h"
#include "renderer/renderer.h"
#include "renderer/shading.h"

namespace rigsim {

// Unit bearings of all pixel centres (invalid outside the lens) with each pixel's angular size
// (for texture filtering). They depend on the intrinsics only, so a dataset's frames reuse them
// (PixelCentreRayCache).
struct PixelCentreRays {
  int width = 0;
  std::vector<Eigen::Vector3f> bearings;  // float: half the memory traffic of the per-pixel read
  std::vector<float> angle;     // max angle to a valid neighbour's bearing (radians)
  std::vector<uint8_t> valid;
  bool interpolate_samples = false;  // SampleBearing interpolates (not for fisheyes)
};

// The unit bearing of a colour sample's image point: for PINHOLE, OPENCV and FULL_OPENCV
// interpolated between the four pixel centres around it (bilinear, normalised: an error of second
// order in the pixel size, below 0.005 px on the lenses of the tests), computed exactly at the
// image's border and for fisheyes (whose bearings change fast near the image circle's fold).
// Undistorting every sample exactly (Newton iterations for a distorted lens) would cost a quarter of
// the instructions of a 4-spp render of the demo rig. nullopt outside the lens.
std::optional<Eigen::Vector3f> SampleBearing(const Camera& camera, const PixelCentreRays& centres, const Eigen::Vector2d& point);

// The pixel-centre rays of the cameras rendered so far, keyed by model, size and parameters.
// Thread-safe.
class PixelCentreRayCache {
 public:
  // The camera's pixel-centre rays, computed on first use (outside the lock: another thread may
  // compute the same rays meanwhile; both results are identical).
  std::shared_ptr<const PixelCentreRays> For(const Camera& camera) const;

 private:
  static constexpr size_t kMaxCachedCameras = 8;  // ~27 MB each at 1280x720
  mutable std::mutex mutex_;
  mutable std::map<std::vector<double>, std::shared_ptr<const PixelCentreRays>> rays_;
};

// Where the camera is when it captures each image row: one pose for every row of a view taken at
// one instant, one per row for a rolling shutter, and with an exposure the ends of each row's
// exposure, between which the colour samples' poses are interpolated (centre linearly, rotation by
// normalised lerp: the motion within one exposure taken as linear).
struct RowPose {
  Eigen::Quaterniond world_from_cam;
  Eigen::Matrix3f world_from_cam_f;   // what rotates the rays' bearings
  Eigen::Vector3f origin;             // the camera centre, world
  float ray_time = 0.0f;              // Embree's time of the row's capture (0 without moving geometry)
  // The ends of the row's exposure.
  Eigen::Quaternionf begin_rotation, end_rotation;
  Eigen::Vector3f begin_origin, end_origin;
  float begin_ray_time = 0.0f, end_ray_time = 0.0f;
};

struct ViewPoses {
  std::vector<RowPose> rows;  // one: every row
  bool exposure = false;      // the colour samples spread over each row's exposure

  const RowPose& Row(int y) const { return rows.size() == 1 ? rows[0] : rows[size_t(y)]; }

  // A view taken at one instant from `cam_from_world`.
  static ViewPoses Still(const Rigid3d& cam_from_world);
};

// Where a camera ray of a batch belongs: its pixel in the tile, its angular footprint (texture
// filtering), and whether it is the pixel centre's ray or one of the colour samples.
struct CameraRayInfo {
  int pixel;
  float angle;
  bool centre;
};

// A view's camera rays, batch by batch (a run of pixels of one tile row), in the order Render
// traces them: for each pixel inside the lens its centre's ray (labels, instance, depth and, at
// 1 spp, the colour), then at spp > 1 the rays of its samples that fall inside the lens. One
// object per thread (it keeps a scratch permutation).
class CameraRays {
 public:
  CameraRays(const Camera& camera, const PixelCentreRays& centres, const ViewPoses& poses, const RenderOptions& options);

  // Pixels [x_begin, x_end) of image row y, in the tile whose top-left pixel is `tile_corner`.
  // With `bearings`, also each ray's unit bearing in the camera frame (for a scene attached to the
  // rig, which moves with the camera whatever the camera's motion).
  void Batch(const Eigen::Vector2i& tile_corner, int y, int x_begin, int x_end, std::vector<RTCRayHit>* rays,
             std::vector<CameraRayInfo>* info, std::vector<Eigen::Vector3f>* bearings = nullptr);

 private:
  const Camera& camera_;
  const PixelCentreRays& centres_;
  const ViewPoses& poses_;
  int spp_;
  int grid_ = 0;
  uint64_t seed_;
  std::vector<int> rooks_;
  std::vector<int> time_strata_;  // with an exposure: a per-pixel permutation of the samples' time strata
};

// A traced ray's hit, direction, hit point and time into a shading record (field by field: no
// wide copy over narrow stores); the pixel and footprint angle are the caller's.
inline void RecordHit(const RTCRayHit& rh, SampleRecord* r) {
  r->hit.hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  r->hit.geom = rh.hit.geomID;
  r->hit.prim = rh.hit.primID;
  r->hit.u = rh.hit.u;
  r->hit.v = rh.hit.v;
  r->hit.t = rh.ray.tfar;
  r->dir = Eigen::Vector3f(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
  r->shadow_origin = Eigen::Vector3f(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z) + r->hit.t * r->dir;  // the hit point
  r->time = rh.ray.time;
}

// A traced batch's colour samples as shading records, in pixel order; `on_centre(info, ray)`
// sees every pixel's centre ray (labels, instance and depth).
template <class OnCentre>
void CollectRecords(const std::vector<RTCRayHit>& rays, const std::vector<CameraRayInfo>& info,
                    std::vector<SampleRecord>* records, OnCentre&& on_centre) {
  records->clear();
  auto add = [&](size_t i) {
    SampleRecord& r = records->emplace_back();
    RecordHit(rays[i], &r);
    r.angle = info[i].angle;
    r.pixel = info[i].pixel;
  };
  for (size_t i = 0; i < rays.size();) {
    const size_t centre = i++;
    on_centre(info[centre], rays[centre]);
    const size_t first_sample = i;
    while (i < rays.size() && !info[i].centre) ++i;
    if (first_sample == i) add(centre);  // 1 spp, or every sample outside the lens
    for (size_t k = first_sample; k < i; ++k) add(k);
  }
}

}  // namespace rigsim
