// A CPU ray tracer (Embree) that renders a Scene as seen by a calibrated camera, producing the
// RGB image together with per-pixel ground truth: semantic label, instance and range.
//
// Conventions it relies on:
//   - Pixels are OpenCV's: the centre of pixel (x, y) has image coordinates (x, y), so the ray
//     of pixel (x, y) is camera.CamFromImg({x, y}). Lens distortion is applied exactly per ray
//     through geometry/camera.h (the calibrator's own model), never by warping an image.
//   - Label, instance and range come from the single ray through the pixel centre, so they are
//     exact; RGB averages samples_per_pixel jittered rays (anti-aliased).
//   - Range: distance in metres from the camera centre to the surface along the pixel's ray;
//     0 where no surface is hit (sky) or the pixel is outside the lens's valid region.
//   - Sky (no hit): label kSkyId (23), instance 0, range 0. Invalid pixels (outside the lens's
//     valid region): RGB black, label 0, instance 0, range 0.
//   - Every surface is seen from both sides (glTF double_sided is not needed for ground truth:
//     a culled back face would let rays see through walls). Alpha MASK cuts geometry out of every
//     output; BLEND is treated as MASK at its cutoff (a single-hit tracer cannot composite).
//   - Glossy materials (roughness below 0.3) also reflect the world by one specular bounce
//     (renderer/shading.h); the ground truth is that of the surface the pixel sees.
//   - A scene attached to the rig (SetAttached, e.g. the rig's own vehicle) is given in the rig
//     frame and moves with the cameras: every camera ray meets it where the camera sees it from
//     its place on the rig, whatever the rig's motion (rolling shutter and exposure included), and
//     the nearer of its hit and the scene's is the pixel's. It is lit by the sun and sky, shadowed
//     by the scene, and reflects the scene; it casts no shadow and is seen in no reflection.
//   - Results are byte-identical for a given seed whatever the thread count: every random
//     number is a hash of (seed, x, y, sample).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "geometry/image.h"
#include "geometry/rig.h"
#include "geometry/rigid3.h"
#include "scene/scene.h"

namespace rigsim {

struct PreparedScene;   // renderer/prepared_scene.h
struct ViewPoses;       // renderer/camera_rays.h
struct TraceOnlyStats;  // renderer/trace_only_benchmark.h

struct RenderOptions {
  // Rays averaged per pixel for the RGB image (>= 1). Square counts use a jittered
  // sqrt(n) x sqrt(n) grid, others n-rooks. With 1 the single ray goes through the pixel centre,
  // so RGB is noise-free and lines up exactly with the labels.
  int samples_per_pixel = 1;
  // Seed of the sample jitter; the same seed gives the same bytes.
  uint64_t seed = 0;
  // Direction from the scene TO the sun, world frame (+Y up); normalised internally.
  Eigen::Vector3d sun_direction_world = Eigen::Vector3d(0.4, 0.8, 0.3).normalized();
  // Irradiance of the sun on a surface facing it (linear units; albedo 1 -> radiance 1).
  double sun_intensity = 0.9;
  // Strength of the sky's ambient light on an upward-facing surface (downward-facing surfaces
  // get a darker ground bounce). Also scales the sky's own colour seen on a miss.
  double sky_intensity = 0.35;
  // Linear scale applied to radiance before sRGB encoding (values above 1 clip).
  double exposure = 1.0;
  // Cast hard sun shadows (one occlusion ray per shaded sample).
  bool shadows = true;
  // Worker threads; 0 = all cores. Does not change the output.
  int num_threads = 0;
  // Also output each pixel centre's surface normal in the camera frame (RenderedView::normal).
  bool normals = false;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

struct RenderedView {
  ImageU8 rgb;       // 3 channels, sRGB-encoded
  ImageU8 label;     // 1 channel, Cityscapes label ids (labels/cityscapes.h)
  ImageU16 instance; // 1 channel, SceneMesh::instance_id; 0 = none
  ImageF range;      // 1 channel, metres along the ray from the camera centre; 0 = no surface
  // With RenderOptions::normals: 3 channels, the unit normal (interpolated vertex normals, else the
  // face's; no normal map) of the surface at the pixel centre, camera frame (x right, y down,
  // z forward), turned towards the camera; 0 where there is no surface.
  ImageF normal;

  // The four images of a view, blank (no surface anywhere); no normals.
  static RenderedView Blank(int width, int height) {
    RenderedView v;
    v.rgb = ImageU8(width, height, 3, 0);
    v.label = ImageU8(width, height, 1, 0);
    v.instance = ImageU16(width, height, 1, 0);
    v.range = ImageF(width, height, 1, 0.0f);
    return v;
  }
};

// A camera on a moving rig capturing one view: when each row is captured (RigCamera's
// time_offset_s, readout_s, readout direction and exposure_s after the frame's timestamp) and
// where the camera is at any time.
struct MovingCameraView {
  const RigCamera* camera = nullptr;  // must outlive the Render call
  double frame_time_s = 0.0;          // the frame's timestamp (scene time, s)
  // cam_from_world at a scene time (e.g. cam_from_rig * RigTrajectory::RigFromWorldAt).
  std::function<Rigid3d(double time_s)> cam_from_world_at;

  // Scene time at which image row `row` is captured (mid exposure).
  double RowTime(int row) const { return frame_time_s + camera->RowTime(row); }
};

class Renderer {
 public:
  // Builds the acceleration structure and texture mip pyramids once. Throws
  // std::invalid_argument naming scene.source and the texture or mesh when the scene is
  // inconsistent (ValidateScene, scene/scene_validation.h: texture size, index out of range,
  // attribute counts, bad material/texture index) and std::runtime_error on an Embree failure.
  // `scene` must outlive the Renderer (meshes are referenced, not copied).
  explicit Renderer(const Scene& scene);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Replaces the geometry by `meshes` (same materials and textures as the scene; e.g.
  // PoseMeshesAt of an animated scene at another time, scene/scene_pose.h) and rebuilds the
  // Embree scene; textures are kept. Not to be called while a Render runs. `meshes` must outlive
  // the renderer or the next SetMeshes. Throws like the constructor (ValidateMeshes), and leaves
  // the renderer as it was when `meshes` are inconsistent.
  void SetMeshes(const std::vector<SceneMesh>& meshes);

  // Replaces the geometry by the scene posed at evenly spaced times: posed[k] at
  // t_begin + k (t_end - t_begin) / (K - 1), K = posed.size() >= 2, t_end > t_begin (e.g.
  // PoseMeshesAt at each). A mesh whose positions differ between the steps moves linearly from one
  // step to the next (Embree motion blur) and every ray meets it at the ray's own time (times
  // outside [t_begin, t_end] meet the first or last step); the others are static. Shading data
  // (normals, texel density) is the middle step's. `posed` must outlive the renderer or the next
  // SetMeshes*. Throws like SetMeshes.
  void SetMeshesOverTime(const std::vector<std::vector<SceneMesh>>& posed, double t_begin, double t_end);

  // Attaches `attached` (its meshes in the rig frame: x right, y down, z forward) to the rig;
  // views rendered with their camera's cam_from_rig show it. `attached` must outlive the renderer.
  // Throws like the constructor.
  void SetAttached(const Scene& attached);

  // Renders one view. Thread-safe (const): several views may render concurrently.
  RenderedView Render(const Camera& camera, const Rigid3d& cam_from_world, const RenderOptions& options) const;
  // The same for a camera at `cam_from_rig` on the rig, which shows the attached scene.
  RenderedView Render(const Camera& camera, const Rigid3d& cam_from_world, const RenderOptions& options,
                      const Rigid3d& cam_from_rig) const;

  // Renders one view of a camera on a moving rig (with the attached scene when the camera has a
  // cam_from_rig): each row's rays leave from where the camera is at
  // the row's capture time, and label, instance, range and normal are those of the pixel centre's
  // ray at that time; with exposure_s > 0 the colour samples are spread evenly (stratified,
  // jittered) over each row's exposure. Motion within one row's exposure is taken as linear
  // (centre and rotation interpolated between its ends). Without readout and exposure this is
  // Render(camera, cam_from_world_at(RowTime(0)), options).
  RenderedView Render(const MovingCameraView& view, const RenderOptions& options) const;

  // The unit bearings (camera frame) of the camera's pixel centres, row-major, zero outside the
  // lens: the rays Render traces through them, computed once per camera and kept. For work on
  // every pixel of a rendered view (the ground-truth overlap) without undistorting each again.
  std::shared_ptr<const std::vector<Eigen::Vector3f>> PixelCentreBearings(const Camera& camera) const;

 private:
  // Times Embree alone on the rays Render would trace (renderer/trace_only_benchmark.h).
  friend TraceOnlyStats TraceOnlyForBenchmark(const Renderer& renderer, const Camera& camera,
                                              const Rigid3d& cam_from_world, const RenderOptions& options);
  friend RenderedView MinimalFrameForBenchmark(const Renderer& renderer, const Camera& camera,
                                               const Rigid3d& cam_from_world, const RenderOptions& options);

  // Renders a view whose rows are captured from `poses`; with `cam_from_rig` and an attached scene,
  // that scene too.
  RenderedView RenderView(const Camera& camera, const ViewPoses& poses, const RenderOptions& options,
                          const Rigid3d* cam_from_rig = nullptr) const;

  std::unique_ptr<PreparedScene> prepared_;  // Embree handles and per-mesh data stay out of this header
  std::unique_ptr<PreparedScene> attached_;  // SetAttached's scene, in the rig frame; null: none
};

}  // namespace rigsim
