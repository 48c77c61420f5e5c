#include "renderer/trace_only_benchmark.h"

#include <atomic>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "labels/cityscapes.h"
#include "renderer/camera_rays.h"
#include "renderer/embree_scene.h"
#include "renderer/prepared_scene.h"
#include "renderer/shading.h"
#include "renderer/srgb.h"
#include "renderer/tiles.h"

namespace rigsim {
namespace {

// A batch's camera ray directions and shadow ray origins, found as Render finds them.
struct TracedBatch {
  std::vector<Eigen::Vector3f> camera_dirs;
  std::vector<Eigen::Vector3f> shadow_origins;
};

// Every tile's batches of the view, in Render's order (untimed: this is Render's own ray
// generation and shading).
std::vector<std::vector<TracedBatch>> GenerateRays(const PreparedScene& prepared, const Camera& camera,
                                                   const Rigid3d& cam_from_world, const RenderOptions& options,
                                                   const ShadeParams& shade, tbb::task_arena& arena) {
  const int width = camera.width(), height = camera.height();
  const int num_tiles = NumTiles(width, height);
  std::vector<std::vector<TracedBatch>> batches(num_tiles);
  const ViewPoses poses = ViewPoses::Still(cam_from_world);
  arena.execute([&] {
    const std::shared_ptr<const PixelCentreRays> centres_ptr = prepared.centre_rays.For(camera);
    tbb::parallel_for(0, num_tiles, [&](int tile) {
      CameraRays camera_rays(camera, *centres_ptr, poses, options);
      std::vector<RTCRayHit> rays;
      std::vector<CameraRayInfo> info;
      std::vector<SampleRecord> records;
      std::vector<RTCRay> shadow;
      const Eigen::Vector2i corner = TileCorner(tile, width);
      ForEachBatch(corner, width, height, options.samples_per_pixel, [&](int y, int x_begin, int x_end) {
        TracedBatch& batch = batches[tile].emplace_back();
        camera_rays.Batch(corner, y, x_begin, x_end, &rays, &info);
        for (const RTCRayHit& rh : rays) batch.camera_dirs.emplace_back(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
        prepared.embree.Intersect(rays);
        CollectRecords(rays, info, &records, [](const CameraRayInfo&, const RTCRayHit&) {});
        if (options.samples_per_pixel > 1) ShareShadingWithinPixels(records);
        for (SampleRecord& r : records) {
          if (r.hit.hit && r.lit_by < 0) ShadeWithoutShadow(prepared.meshes[r.hit.geom], r, shade);
        }
        CollectShadowRays(records, shade, &shadow);
        for (const RTCRay& ray : shadow) batch.shadow_origins.emplace_back(ray.org_x, ray.org_y, ray.org_z);
      });
    });
  });
  return batches;
}

}  // namespace

TraceOnlyStats TraceOnlyForBenchmark(const Renderer& renderer, const Camera& camera, const Rigid3d& cam_from_world,
                                     const RenderOptions& options) {
  options.Check();
  const PreparedScene& prepared = *renderer.prepared_;
  const ShadeParams shade = ShadeParamsOf(options);
  tbb::task_arena arena(options.num_threads > 0 ? options.num_threads : tbb::task_arena::automatic);
  const std::vector<std::vector<TracedBatch>> batches =
      GenerateRays(prepared, camera, cam_from_world, options, shade, arena);

  TraceOnlyStats stats;
  for (const std::vector<TracedBatch>& tile_batches : batches) {
    for (const TracedBatch& batch : tile_batches) {
      stats.primary_rays += batch.camera_dirs.size();
      stats.shadow_rays += batch.shadow_origins.size();
    }
  }
  const Eigen::Vector3f origin = cam_from_world.SourceOriginInTarget().cast<float>();
  std::atomic<size_t> sink{0};  // keeps the results observable so nothing is optimised away
  const auto start = std::chrono::steady_clock::now();
  arena.execute([&] {
    tbb::parallel_for(0, int(batches.size()), [&](int tile) {
      size_t hits = 0;
      std::vector<RTCRayHit> rays;
      std::vector<RTCRay> shadow;
      for (const TracedBatch& batch : batches[tile]) {
        rays.clear();
        for (const Eigen::Vector3f& dir : batch.camera_dirs) rays.push_back(CameraRay(origin, dir));
        prepared.embree.Intersect(rays);
        for (const RTCRayHit& rh : rays) hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        shadow.clear();
        for (const Eigen::Vector3f& o : batch.shadow_origins) shadow.push_back(ShadowRay(o, shade.sun_dir));
        prepared.embree.Occlude(shadow);
        for (const RTCRay& ray : shadow) hits += IsOccluded(ray);
      }
      sink += hits;
    });
  });
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  prepared.embree.ThrowIfAny("tracing");
  return stats;
}

RenderedView MinimalFrameForBenchmark(const Renderer& renderer, const Camera& camera, const Rigid3d& cam_from_world,
                                      const RenderOptions& options) {
  options.Check();
  if (options.samples_per_pixel != 1) throw std::invalid_argument("MinimalFrameForBenchmark: 1 spp only");
  const PreparedScene& prepared = *renderer.prepared_;
  const ShadeParams shade = ShadeParamsOf(options);
  const int width = camera.width(), height = camera.height();
  RenderedView view = RenderedView::Blank(width, height);
  const SrgbEncodeTables& srgb = SrgbEncodeTables::Get();
  const Eigen::Matrix3f world_from_cam = cam_from_world.rotation.conjugate().toRotationMatrix().cast<float>();
  const Eigen::Vector3f origin = cam_from_world.SourceOriginInTarget().cast<float>();
  tbb::task_arena arena(options.num_threads > 0 ? options.num_threads : tbb::task_arena::automatic);
  arena.execute([&] {
    const std::shared_ptr<const PixelCentreRays> centres_ptr = prepared.centre_rays.For(camera);
    const PixelCentreRays& centres = *centres_ptr;
    tbb::parallel_for(0, NumTiles(width, height), [&](int tile) {
      std::vector<RTCRayHit> rays;
      std::vector<int> xs;
      std::vector<RTCRay> shadow;
      std::vector<float> lambert;
      const Eigen::Vector2i corner = TileCorner(tile, width);
      ForEachBatch(corner, width, height, 1, [&](int y, int x_begin, int x_end) {
        rays.clear();
        xs.clear();
        for (int x = x_begin; x < x_end; ++x) {
          const size_t idx = size_t(y) * width + x;
          if (!centres.valid[idx]) continue;
          rays.push_back(CameraRay(origin, world_from_cam * centres.bearings[idx]));
          xs.push_back(x);
        }
        prepared.embree.Intersect(rays);
        shadow.clear();
        lambert.assign(rays.size(), 0.0f);
        for (size_t i = 0; i < rays.size(); ++i) {
          const RTCRayHit& rh = rays[i];
          const int x = xs[i];
          if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            view.label.at(x, y) = kSkyId;
            continue;
          }
          const MeshShading& m = prepared.meshes[rh.hit.geomID];
          view.label.at(x, y) = m.class_id;
          view.instance.at(x, y) = m.instance_id;
          view.range.at(x, y) = rh.ray.tfar;
          const Eigen::Vector3f dir(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
          Eigen::Vector3f n = m.triangles[rh.hit.primID].face_normal;
          if (n.dot(dir) > 0) n = -n;
          lambert[i] = n.dot(shade.sun_dir);
          if (lambert[i] > 0) {
            Hit hit;
            hit.t = rh.ray.tfar;
            shadow.push_back(ShadowRay(ShadowRayOrigin(hit, origin, dir, n), shade.sun_dir));
          }
        }
        prepared.embree.Occlude(shadow);
        size_t next_shadow = 0;
        for (size_t i = 0; i < rays.size(); ++i) {
          const int x = xs[i];
          float light = shade.sky_intensity;
          if (rays[i].hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            light *= kSkyViewGain;
          } else if (lambert[i] > 0 && !IsOccluded(shadow[next_shadow++])) {
            light += shade.sun_intensity * lambert[i];
          }
          const uint8_t code = SrgbCodeFromLinear(0.5f * light, srgb);
          for (int c = 0; c < 3; ++c) view.rgb.at(x, y, c) = code;
        }
      });
    });
  });
  prepared.embree.ThrowIfAny("tracing");
  return view;
}

}  // namespace rigsim
