// The Embree scene the renderer traces: the device, the scene built from a set of meshes (alpha-
// tested materials cut out by an intersection filter), the coherent ray streams it traces, and
// rays in Embree's format. Internal to the renderer: no header outside renderer/ includes this
// one, so no Embree type leaves the module.
#pragma once

#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <embree3/rtcore.h>

#include "renderer/shading.h"
#include "scene/scene.h"

namespace rigsim {

// Collects Embree errors; Embree calls back from C code, so we record and throw later.
class EmbreeErrors {
 public:
  static void Callback(void* user, RTCError code, const char* message) {
    static_cast<EmbreeErrors*>(user)->Record(code, message);
  }
  void Record(RTCError code, const char* message);
  // Throws std::runtime_error "<during>: Embree error <code>: <message>" for the first error recorded.
  void ThrowIfAny(const std::string& during);

 private:
  std::mutex mutex_;
  std::string first_;
};

class EmbreeScene {
 public:
  // Creates the Embree device; `source` names the scene in messages. Throws std::runtime_error
  // when Embree cannot.
  explicit EmbreeScene(const std::string& source);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Frees the scene (before a rebuild, so that two acceleration structures are not held at once).
  void Release();

  // Builds the scene from `meshes` (checked by scene/scene_validation.h): mesh i is geometry i.
  // `shading[i]` is mesh i's shading data, read by the alpha test of MASK and BLEND materials; it
  // must outlive the scene. With `steps` (the same meshes posed at evenly spaced times), a mesh
  // whose positions differ between the steps gets one vertex buffer per step (Embree motion blur:
  // rays meet it at their `time`). Throws std::runtime_error on an Embree failure.
  void Build(const std::vector<SceneMesh>& meshes, const std::vector<MeshShading>& shading,
             const std::vector<std::vector<SceneMesh>>* steps = nullptr);

  // Rays go to Embree in streams, a batch's camera rays in one call and their shadow rays in
  // another, marked coherent: Embree then traverses neighbouring rays together in SIMD packets,
  // much faster than a call per ray and hitting the same triangles at the same points
  // (BENCHMARKS.md, "Ray streams"). Embree decides which triangle a ray hits; the hit's distance
  // and barycentrics are computed again from that triangle (ExactHit), because Embree's come from
  // approximate reciprocals whose last bits differ between Intel's and AMD's CPUs. Thread-safe.
  void Intersect(std::vector<RTCRayHit>& rays) const;
  void Occlude(std::vector<RTCRay>& rays) const;

  // Whether Embree traces with its 8-wide (AVX or wider) kernels on this device: never, as the
  // device is held to SSE2 (embree_scene.cc), whatever the CPU.
  bool UsesWideKernels() const {
    return rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) != 0;
  }

  // Throws std::runtime_error "<during>: <first Embree error>" when Embree reported one.
  void ThrowIfAny(const std::string& during) const { errors_.ThrowIfAny(during); }

  // A geometry's triangles as Embree holds them: its vertex buffer per time step (one for a mesh
  // that does not move) and its index buffer; with its shading, for the alpha test.
  struct Geometry {
    std::vector<const float*> steps;  // xyz per vertex
    const unsigned* indices = nullptr;
    const MeshShading* shading = nullptr;
  };

 private:
  mutable EmbreeErrors errors_;  // written from Embree callbacks during const traces
  std::string source_;           // for messages
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<Geometry> geometries_;  // by geomID; empty entries for meshes without triangles
};

// A camera ray as Embree takes it, and a shadow ray (no hit record: only whether it is blocked).
inline RTCRayHit CameraRay(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir) {
  RTCRayHit rh;
  rh.ray.org_x = origin.x();
  rh.ray.org_y = origin.y();
  rh.ray.org_z = origin.z();
  rh.ray.tnear = 0.0f;
  rh.ray.dir_x = dir.x();
  rh.ray.dir_y = dir.y();
  rh.ray.dir_z = dir.z();
  rh.ray.time = 0.0f;
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.mask = ~0u;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

inline RTCRay ShadowRay(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir) { return CameraRay(origin, dir).ray; }

inline bool IsOccluded(const RTCRay& ray) { return ray.tfar == -std::numeric_limits<float>::infinity(); }

// The shadow rays of a batch's records lit by their own shading, in record order.
inline void CollectShadowRays(const std::vector<SampleRecord>& records, const ShadeParams& p, std::vector<RTCRay>* shadow) {
  shadow->clear();
  if (!p.shadows) return;
  for (const SampleRecord& r : records) {
    if (r.hit.hit && r.lit_by < 0 && r.sun_ray) {
      shadow->push_back(ShadowRay(r.shadow_origin, p.sun_dir));
      shadow->back().time = r.time;
    }
  }
}

}  // namespace rigsim
