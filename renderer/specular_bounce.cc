#include "renderer/specular_bounce.h"

#include "renderer/camera_rays.h"

namespace rigsim {

void SpecularBounce::Trace(const std::vector<SampleRecord>& records, const MeshTable& meshes,
                           const EmbreeScene& embree, const ShadeParams& shade) {
  slot_.assign(records.size(), -1);
  source_.clear();
  cos_theta_.clear();
  rays_.clear();
  for (size_t i = 0; i < records.size(); ++i) {
    const SampleRecord& r = records[i];
    if (!r.hit.hit) continue;
    const MeshShading& m = meshes[r.hit.geom];
    if (!(m.gloss > 0.0f)) continue;
    Eigen::Vector3f ng, n;
    SurfaceNormals(m, r.hit, r.dir, &ng, &n);
    if (m.normal_layer.texture != nullptr) n = NormalMapped(m, r, ng, n);
    slot_[i] = int(rays_.size());
    source_.push_back(i);
    cos_theta_.push_back(-r.dir.dot(n));
    // Offset from the surface as a shadow ray is, so that the reflected ray does not meet it again.
    rays_.push_back(CameraRay(ShadowRayOriginAt(r.hit, r.shadow_origin, ng), MirrorDirection(r.dir, n, ng)));
    rays_.back().ray.time = r.time;
  }
  radiance_.resize(rays_.size());
  if (rays_.empty()) return;
  embree.Intersect(rays_);

  hits_.clear();
  for (size_t k = 0; k < rays_.size(); ++k) {
    const RTCRayHit& rh = rays_[k];
    const SampleRecord& from = records[source_[k]];
    SampleRecord& s = hits_.emplace_back();
    RecordHit(rh, &s);
    s.pixel = from.pixel;
    if (!s.hit.hit) continue;
    // A flat mirror's pixel covers the reflected surface as if the path were one straight ray.
    s.angle = s.hit.t > 0.0f ? from.angle * (from.hit.t + s.hit.t) / s.hit.t : from.angle;
    ShadeWithoutShadow(meshes[s.hit.geom], s, shade);
  }
  CollectShadowRays(hits_, shade, &shadow_);
  embree.Occlude(shadow_);
  size_t next_shadow = 0;
  for (size_t k = 0; k < hits_.size(); ++k) {
    SampleRecord& s = hits_[k];
    if (!s.hit.hit) {
      radiance_[k] = SkyRadiance(s.dir, shade);
      continue;
    }
    const bool sun_visible = !(shade.shadows && s.sun_ray) || !IsOccluded(shadow_[next_shadow++]);
    radiance_[k] = FinishShading(meshes[s.hit.geom], s, sun_visible);
  }
}

}  // namespace rigsim
