// The reflected rays of a batch's glossy hits (renderer/shading.h, "One specular bounce"): traced
// together after the batch's camera rays, at each camera ray's own time (the scene posed as the
// camera ray saw it), shaded as a camera ray's hit is, and mixed into their samples' colour.
// Labels, instances, depth and normals stay those of the camera ray's hit. Reflected rays meet
// the scene only, not a scene attached to the rig (a car's paint shows the world, not itself),
// and a glossy hit on the attached scene reflects the world like any other. Internal to the
// renderer (it holds Embree rays); a scene without glossy materials never runs it.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "renderer/embree_scene.h"
#include "renderer/shading.h"

namespace rigsim {

class SpecularBounce {
 public:
  // Traces and shades the reflected ray of every record that hit a mesh with gloss > 0. `records`
  // as CollectRecords leaves them (shadow_origin is the hit point): before ShadeWithoutShadow.
  void Trace(const std::vector<SampleRecord>& records, const MeshTable& meshes, const EmbreeScene& embree,
             const ShadeParams& shade);

  // Whether record `i` of the last Trace has a reflection to mix in.
  bool Reflects(size_t i) const { return slot_[i] >= 0; }

  // Record `i`'s radiance: `surface` (its own shading, albedo known) mixed with its reflection.
  Eigen::Vector3f Mix(size_t i, const SampleRecord& r, const MeshShading& m, const Eigen::Vector3f& surface) const {
    const int k = slot_[i];
    const SpecularMix mix = SpecularMixOf(m.gloss, m.metallic, r.albedo, cos_theta_[size_t(k)]);
    return mix.keep * surface + mix.reflect.cwiseProduct(radiance_[size_t(k)]);
  }

 private:
  std::vector<int> slot_;                // per record: its reflected ray's index, or -1
  std::vector<size_t> source_;           // per reflected ray: its record
  std::vector<float> cos_theta_;         // per reflected ray: cos of the incidence angle
  std::vector<Eigen::Vector3f> radiance_;  // per reflected ray: what it sees
  std::vector<RTCRayHit> rays_;
  std::vector<SampleRecord> hits_;
  std::vector<RTCRay> shadow_;
};

}  // namespace rigsim
