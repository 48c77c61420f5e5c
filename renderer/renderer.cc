#include "renderer/renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "labels/cityscapes.h"
#include "renderer/camera_rays.h"
#include "renderer/embree_scene.h"
#include "renderer/prepared_scene.h"
#include "renderer/shading.h"
#include "renderer/specular_bounce.h"
#include "renderer/srgb.h"
#include "renderer/tiles.h"
#include "scene/scene_validation.h"

namespace rigsim {
namespace {

// One tile's outputs, written pixel by pixel in cache and copied to the images row by row at the
// end. Written in place, every tile row would start new cache lines in four images, a whole image
// row apart, one miss at a time.
struct TileOutputs {
  static constexpr int kPixels = kTileSize * kTileSize;
  std::array<uint8_t, 3 * kPixels> rgb;
  std::array<uint8_t, kPixels> label;
  std::array<uint16_t, kPixels> instance;
  std::array<float, kPixels> range;

  // A pixel outside the lens: black, label 0, instance 0, range 0.
  void SetInvalid(int pixel) {
    std::fill_n(&rgb[3 * pixel], 3, 0);
    label[pixel] = 0;
    instance[pixel] = 0;
    range[pixel] = 0.0f;
  }

  void CopyTo(RenderedView& view, int x_begin, int y_begin, int tile_width, int tile_height) const {
    if (tile_width == kTileSize) {  // constant sizes: inlined copies, not memmove calls
      CopyRows(view, x_begin, y_begin, kTileSize, tile_height);
    } else {
      CopyRows(view, x_begin, y_begin, tile_width, tile_height);
    }
  }

  [[gnu::always_inline]] void CopyRows(RenderedView& view, int x_begin, int y_begin, int tile_width,
                                       int tile_height) const {
    for (int row = 0; row < tile_height; ++row) {
      const int y = y_begin + row;
      const int first = row * kTileSize;
      std::copy_n(&rgb[3 * first], 3 * tile_width, &view.rgb.at(x_begin, y, 0));
      std::copy_n(&label[first], tile_width, &view.label.at(x_begin, y));
      std::copy_n(&instance[first], tile_width, &view.instance.at(x_begin, y));
      std::copy_n(&range[first], tile_width, &view.range.at(x_begin, y));
    }
  }
};

// Traces `rays` (world) again through the attached scene, as rays of the rig frame from the
// camera's place on the rig along their `bearings`, and takes its hit where it is nearer than the
// scene's (geom offset by kAttachedGeom). The rays' directions are unit vectors in both frames, so
// their distances compare.
void NearerAttachedHits(const PreparedScene& attached, const Eigen::Matrix3f& rig_from_cam, const Eigen::Vector3f& camera_in_rig,
                        const std::vector<Eigen::Vector3f>& bearings, std::vector<RTCRayHit>* attached_rays,
                        std::vector<RTCRayHit>* rays) {
  attached_rays->clear();
  for (size_t i = 0; i < rays->size(); ++i) {
    RTCRayHit& rh = attached_rays->emplace_back(CameraRay(camera_in_rig, rig_from_cam * bearings[i]));
    rh.ray.tfar = (*rays)[i].ray.tfar;  // only what lies before the scene's hit
  }
  attached.embree.Intersect(*attached_rays);
  for (size_t i = 0; i < rays->size(); ++i) {
    const RTCRayHit& a = (*attached_rays)[i];
    if (a.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
    RTCRayHit& rh = (*rays)[i];
    rh.hit.geomID = kAttachedGeom + a.hit.geomID;
    rh.hit.primID = a.hit.primID;
    rh.hit.u = a.hit.u;
    rh.hit.v = a.hit.v;
    rh.ray.tfar = a.ray.tfar;
  }
}

// The unit normal (world) of the surface a pixel centre's ray hit, turned towards the ray.
Eigen::Vector3f CentreNormal(const MeshShading& mesh, const RTCRayHit& rh) {
  Hit hit;
  hit.prim = rh.hit.primID;
  hit.u = rh.hit.u;
  hit.v = rh.hit.v;
  Eigen::Vector3f ng, n;
  SurfaceNormals(mesh, hit, Eigen::Vector3f(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z), &ng, &n);
  return n;
}

}  // namespace

void RenderOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("invalid render options: " + why); };
  if (samples_per_pixel < 1 || samples_per_pixel > 65536) {
    fail("samples_per_pixel must be in 1..65536, got " + std::to_string(samples_per_pixel));
  }
  if (!sun_direction_world.allFinite() || sun_direction_world.norm() < 1e-12) {
    fail("sun_direction_world must be a finite non-zero vector");
  }
  if (!std::isfinite(sun_intensity) || sun_intensity < 0) fail("sun_intensity must be finite and >= 0");
  if (!std::isfinite(sky_intensity) || sky_intensity < 0) fail("sky_intensity must be finite and >= 0");
  if (!std::isfinite(exposure) || exposure <= 0) fail("exposure must be finite and > 0");
  if (num_threads < 0) fail("num_threads must be >= 0 (0 = all cores), got " + std::to_string(num_threads));
}

Renderer::Renderer(const Scene& scene) {
  ValidateScene(scene);
  prepared_ = std::make_unique<PreparedScene>(scene);
}

Renderer::~Renderer() = default;

void Renderer::SetMeshes(const std::vector<SceneMesh>& meshes) {
  ValidateMeshes(prepared_->scene, meshes);
  prepared_->SetMeshes(meshes);
}

void Renderer::SetMeshesOverTime(const std::vector<std::vector<SceneMesh>>& posed, double t_begin, double t_end) {
  if (posed.size() < 2 || !(t_end > t_begin)) {
    throw std::invalid_argument("SetMeshesOverTime: needs at least 2 steps over a time span of positive length");
  }
  for (const std::vector<SceneMesh>& step : posed) ValidateMeshes(prepared_->scene, step);
  prepared_->SetMeshesOverTime(posed, t_begin, t_end);
}

void Renderer::SetAttached(const Scene& attached) {
  ValidateScene(attached);
  attached_ = std::make_unique<PreparedScene>(attached);
}

RenderedView Renderer::Render(const Camera& camera, const Rigid3d& cam_from_world, const RenderOptions& options) const {
  return RenderView(camera, ViewPoses::Still(cam_from_world), options);
}

RenderedView Renderer::Render(const Camera& camera, const Rigid3d& cam_from_world, const RenderOptions& options,
                              const Rigid3d& cam_from_rig) const {
  return RenderView(camera, ViewPoses::Still(cam_from_world), options, &cam_from_rig);
}

namespace {

// The pose of the camera at `time_s` as a RowPose; `ray_time` maps scene time to Embree's.
RowPose RowPoseAt(const MovingCameraView& view, double time_s, double exposure_s,
                  const std::function<float(double)>& ray_time) {
  const Rigid3d cam_from_world = view.cam_from_world_at(time_s);
  RowPose row = ViewPoses::Still(cam_from_world).rows[0];
  row.ray_time = ray_time(time_s);
  if (exposure_s > 0) {
    const Rigid3d begin = view.cam_from_world_at(time_s - exposure_s / 2);
    const Rigid3d end = view.cam_from_world_at(time_s + exposure_s / 2);
    row.begin_rotation = begin.rotation.conjugate().cast<float>();
    row.end_rotation = end.rotation.conjugate().cast<float>();
    if (row.begin_rotation.dot(row.end_rotation) < 0) row.end_rotation.coeffs() *= -1;  // interpolate the short way
    row.begin_origin = begin.SourceOriginInTarget().cast<float>();
    row.end_origin = end.SourceOriginInTarget().cast<float>();
    row.begin_ray_time = ray_time(time_s - exposure_s / 2);
    row.end_ray_time = ray_time(time_s + exposure_s / 2);
  }
  return row;
}

}  // namespace

RenderedView Renderer::Render(const MovingCameraView& view, const RenderOptions& options) const {
  if (view.camera == nullptr || !view.cam_from_world_at) throw std::invalid_argument("Render: the moving view has no camera or pose");
  const RigCamera& cam = *view.camera;
  const PreparedScene& prepared = *prepared_;
  auto ray_time = [&](double t) { return prepared.RayTime(t); };
  ViewPoses poses;
  poses.exposure = cam.exposure_s > 0 && options.samples_per_pixel > 1;
  const int rows = cam.readout_s > 0 ? cam.camera.height() : 1;
  poses.rows.resize(size_t(rows));
  tbb::parallel_for(0, rows, [&](int y) { poses.rows[size_t(y)] = RowPoseAt(view, view.RowTime(y), cam.exposure_s, ray_time); });
  return RenderView(cam.camera, poses, options, cam.cam_from_rig ? &*cam.cam_from_rig : nullptr);
}

RenderedView Renderer::RenderView(const Camera& camera, const ViewPoses& poses, const RenderOptions& options,
                                  const Rigid3d* cam_from_rig) const {
  options.Check();
  const PreparedScene& prepared = *prepared_;
  const int width = camera.width(), height = camera.height();
  // The attached scene: camera rays go into the rig frame by their bearing (the camera does not
  // move on the rig), and its shading data into the world frame by the rig's rotation at the
  // view's middle row (within one view's readout the rig turns little; only shading uses it).
  const PreparedScene* attached = attached_ != nullptr && cam_from_rig != nullptr ? attached_.get() : nullptr;
  std::vector<MeshShading> attached_world;
  Eigen::Matrix3f rig_from_cam_rotation = Eigen::Matrix3f::Identity();
  Eigen::Vector3f camera_in_rig = Eigen::Vector3f::Zero();
  if (attached != nullptr) {
    rig_from_cam_rotation = cam_from_rig->rotation.conjugate().toRotationMatrix().cast<float>();
    camera_in_rig = cam_from_rig->SourceOriginInTarget().cast<float>();
    const Eigen::Matrix3f world_from_rig = poses.Row(height / 2).world_from_cam_f * rig_from_cam_rotation.transpose();
    for (const MeshShading& m : attached->meshes) attached_world.push_back(RotatedShading(m, world_from_rig));
  }
  const MeshTable meshes{&prepared.meshes, attached != nullptr ? &attached_world : nullptr};

  RenderedView view = RenderedView::Blank(width, height);
  if (options.normals) view.normal = ImageF(width, height, 3, 0.0f);

  const ShadeParams shade = ShadeParamsOf(options);
  const bool glossy = prepared.glossy || (attached != nullptr && attached->glossy);
  const float exposure = float(options.exposure);
  const SrgbEncodeTables& srgb = SrgbEncodeTables::Get();

  tbb::task_arena arena(options.num_threads > 0 ? options.num_threads : tbb::task_arena::automatic);
  arena.execute([&] {
    const std::shared_ptr<const PixelCentreRays> centres_ptr = prepared.centre_rays.For(camera);
    const PixelCentreRays& centres = *centres_ptr;
    tbb::parallel_for(tbb::blocked_range<int>(0, NumTiles(width, height)), [&](const tbb::blocked_range<int>& tiles) {
      CameraRays camera_rays(camera, centres, poses, options);
      std::vector<RTCRayHit> rays;
      std::vector<CameraRayInfo> info;
      std::vector<SampleRecord> records;
      std::vector<RTCRay> shadow;
      std::vector<Eigen::Vector3f> bearings;
      std::vector<RTCRayHit> attached_rays;
      SpecularBounce bounce;
      TileOutputs out;
      for (int tile = tiles.begin(); tile < tiles.end(); ++tile) {
        const Eigen::Vector2i corner = TileCorner(tile, width);
        ForEachBatch(corner, width, height, options.samples_per_pixel, [&](int y, int x_begin, int x_end) {
          for (int x = x_begin; x < x_end; ++x) {
            if (!centres.valid[size_t(y) * width + x]) out.SetInvalid((y - corner.y()) * kTileSize + (x - corner.x()));
          }
          // 1. Camera rays, traced together: label, instance and depth from each pixel centre's ray.
          camera_rays.Batch(corner, y, x_begin, x_end, &rays, &info, attached != nullptr ? &bearings : nullptr);
          prepared.embree.Intersect(rays);
          if (attached != nullptr) NearerAttachedHits(*attached, rig_from_cam_rotation, camera_in_rig, bearings, &attached_rays, &rays);
          CollectRecords(rays, info, &records, [&](const CameraRayInfo& centre, const RTCRayHit& rh) {
            const bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            out.label[centre.pixel] = hit ? meshes[rh.hit.geomID].class_id : kSkyId;
            out.instance[centre.pixel] = hit ? meshes[rh.hit.geomID].instance_id : 0;
            out.range[centre.pixel] = hit ? rh.ray.tfar : 0.0f;
            if (options.normals && hit) {
              const int x = corner.x() + centre.pixel % kTileSize;
              const Eigen::Vector3f n = poses.Row(y).world_from_cam_f.transpose() * CentreNormal(meshes[rh.hit.geomID], rh);
              for (int c = 0; c < 3; ++c) view.normal.at(x, y, c) = n[c];
            }
          });
          // 1b. Glossy hits' reflected rays, traced and shaded together (only in scenes that have
          // glossy materials).
          if (glossy) bounce.Trace(records, meshes, prepared.embree, shade);
          // 2. Shading without the sun: no rays traced, so the hits' work can overlap. A pixel's
          // samples on one triangle share one lighting.
          if (options.samples_per_pixel > 1) ShareShadingWithinPixels(records);
          for (SampleRecord& r : records) {
            if (!r.hit.hit) continue;
            if (r.lit_by < 0) {
              ShadeWithoutShadow(meshes[r.hit.geom], r, shade);
            } else {
              AlbedoOnly(meshes[r.hit.geom], r);
            }
          }
          // 3. Shadow rays, traced together, then each pixel's colour: the mean of its samples.
          CollectShadowRays(records, shade, &shadow);
          prepared.embree.Occlude(shadow);
          size_t next_shadow = 0;
          for (size_t i = 0; i < records.size();) {
            const int pixel = records[i].pixel;
            Eigen::Vector3f radiance = Eigen::Vector3f::Zero();
            int num_samples = 0;
            for (; i < records.size() && records[i].pixel == pixel; ++i, ++num_samples) {
              SampleRecord& r = records[i];
              if (!r.hit.hit) {
                radiance += SkyRadiance(r.dir, shade);
                continue;
              }
              const MeshShading& m = meshes[r.hit.geom];
              Eigen::Vector3f sample;
              if (r.lit_by >= 0) {  // lit as an earlier sample on the same triangle, finished before it
                sample = LitAs(m, r, records[size_t(r.lit_by)]);
              } else {
                const bool sun_visible = !(shade.shadows && r.sun_ray) || !IsOccluded(shadow[next_shadow++]);
                sample = FinishShading(m, r, sun_visible);
              }
              radiance += glossy && bounce.Reflects(i) ? bounce.Mix(i, r, m, sample) : sample;
            }
            radiance *= exposure / float(num_samples);
            for (int c = 0; c < 3; ++c) out.rgb[3 * pixel + c] = SrgbCodeFromLinear(radiance[c], srgb);
          }
        });
        out.CopyTo(view, corner.x(), corner.y(), std::min(width - corner.x(), kTileSize),
                   std::min(height - corner.y(), kTileSize));
      }
    });
  });
  prepared.embree.ThrowIfAny("rendering");
  if (attached != nullptr) attached->embree.ThrowIfAny("rendering the attached scene");
  return view;
}

std::shared_ptr<const std::vector<Eigen::Vector3f>> Renderer::PixelCentreBearings(const Camera& camera) const {
  const std::shared_ptr<const PixelCentreRays> rays = prepared_->centre_rays.For(camera);
  return std::shared_ptr<const std::vector<Eigen::Vector3f>>(rays, &rays->bearings);  // keeps `rays` alive
}

}  // namespace rigsim
