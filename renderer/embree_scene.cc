#include "renderer/embree_scene.h"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>

namespace rigsim {
namespace {

// Where a ray meets a triangle: its distance along the (unnormalised) direction and barycentrics.
struct TriangleHit {
  float t, u, v;
};

// Triangle `prim` of `g` at Embree's ray time `time` (in [0, 1] over the time steps; the vertices
// are interpolated linearly between the two steps around it, as Embree's motion blur does), met by
// the ray from `org` along `dir`: Moller-Trumbore in double precision with an exact division, so
// that the bits do not depend on the CPU (Embree's own come from RCPPS, which Intel's and AMD's
// CPUs compute otherwise). nullopt for a triangle the ray runs along.
std::optional<TriangleHit> ExactHit(const EmbreeScene::Geometry& g, unsigned prim, const Eigen::Vector3d& org,
                                    const Eigen::Vector3d& dir, float time) {
  const size_t segments = g.steps.size() - 1;
  size_t step = 0;
  double w = 0.0;
  if (segments > 0) {
    const double f = std::clamp(double(time), 0.0, 1.0) * double(segments);
    step = std::min(size_t(f), segments - 1);
    w = f - double(step);
  }
  Eigen::Vector3d p[3];
  for (int k = 0; k < 3; ++k) {
    const size_t vertex = g.indices[3 * size_t(prim) + k];
    const Eigen::Vector3d a(g.steps[step][3 * vertex], g.steps[step][3 * vertex + 1], g.steps[step][3 * vertex + 2]);
    if (segments == 0) {
      p[k] = a;
      continue;
    }
    const float* next = g.steps[step + 1];
    const Eigen::Vector3d b(next[3 * vertex], next[3 * vertex + 1], next[3 * vertex + 2]);
    p[k] = (1.0 - w) * a + w * b;
  }
  const Eigen::Vector3d e1 = p[1] - p[0], e2 = p[2] - p[0];
  const Eigen::Vector3d pvec = dir.cross(e2);
  const double det = e1.dot(pvec);
  if (det == 0.0) return std::nullopt;
  const Eigen::Vector3d tvec = org - p[0];
  const Eigen::Vector3d qvec = tvec.cross(e1);
  const double u = std::clamp(tvec.dot(pvec) / det, 0.0, 1.0);
  const double v = std::clamp(dir.dot(qvec) / det, 0.0, 1.0 - u);
  return TriangleHit{float(e2.dot(qvec) / det), float(u), float(v)};
}

// Embree filter for MASK materials: rejecting a hit makes Embree continue the traversal beyond
// it, so the cut-out holds for camera rays and shadow rays alike. The alpha is read at the exact
// barycentrics (ExactHit), so that a ray at the cut-out's edge is cut on every CPU alike.
void AlphaMaskFilter(const RTCFilterFunctionNArguments* args) {
  const EmbreeScene::Geometry& g = *static_cast<const EmbreeScene::Geometry*>(args->geometryUserPtr);
  const MeshShading& m = *g.shading;
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    float u = RTCHitN_u(args->hit, args->N, i);
    float v = RTCHitN_v(args->hit, args->N, i);
    const Eigen::Vector3d org(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                              RTCRayN_org_z(args->ray, args->N, i));
    const Eigen::Vector3d dir(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                              RTCRayN_dir_z(args->ray, args->N, i));
    if (const std::optional<TriangleHit> exact = ExactHit(g, prim, org, dir, RTCRayN_time(args->ray, args->N, i))) {
      u = exact->u;
      v = exact->v;
    }
    if (AlphaAt(m, prim, u, v) < m.alpha_cutoff) args->valid[i] = 0;
  }
}

RTCIntersectContext CoherentContext() {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  return context;
}

}  // namespace

void EmbreeErrors::Record(RTCError code, const char* message) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (first_.empty()) first_ = "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "");
}

void EmbreeErrors::ThrowIfAny(const std::string& during) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!first_.empty()) throw std::runtime_error(during + ": " + first_);
}

EmbreeScene::EmbreeScene(const std::string& source) : source_(source) {
  // Embree's SSE2 kernels on every node, the same code: left to choose by CPU, Embree traces with
  // its AVX2 kernels (fused multiply-adds) on one node and its SSE ones on another, which render
  // other depths and colours, and its 8-wide AVX ones meet a ray's ties between two surfaces in
  // another order than its 4-wide SSE ones (another instance id), so a render split over mixed
  // nodes would not merge into what one machine writes (BENCHMARKS.md has the cost).
  device_ = rtcNewDevice("max_isa=sse2");
  if (device_ == nullptr) {
    throw std::runtime_error(source_ + ": cannot create an Embree device (error " +
                             std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  }
  rtcSetDeviceErrorFunction(device_, &EmbreeErrors::Callback, &errors_);
}

EmbreeScene::~EmbreeScene() {
  Release();
  if (device_) rtcReleaseDevice(device_);
}

void EmbreeScene::Release() {
  if (scene_) {
    rtcReleaseScene(scene_);
    scene_ = nullptr;
  }
  geometries_.clear();
}

namespace {

// Whether mesh i moves between the steps.
bool Moves(const std::vector<std::vector<SceneMesh>>* steps, size_t i) {
  if (steps == nullptr) return false;
  for (const std::vector<SceneMesh>& step : *steps) {
    if (step[i].positions != steps->front()[i].positions) return true;
  }
  return false;
}

// The vertex buffer of time step `slot`, filled; nullptr when Embree could not allocate it.
const float* FillVertices(RTCGeometry geom, unsigned slot, const std::vector<Eigen::Vector3f>& positions) {
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, slot, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size()));
  if (vertices == nullptr) return nullptr;
  for (size_t v = 0; v < positions.size(); ++v) {
    vertices[3 * v] = positions[v].x();
    vertices[3 * v + 1] = positions[v].y();
    vertices[3 * v + 2] = positions[v].z();
  }
  return vertices;
}

}  // namespace

void EmbreeScene::Build(const std::vector<SceneMesh>& meshes, const std::vector<MeshShading>& shading,
                        const std::vector<std::vector<SceneMesh>>* steps) {
  Release();
  scene_ = rtcNewScene(device_);
  errors_.ThrowIfAny(source_ + ": creating the Embree scene");
  // Watertight traversal: without it a ray through the edge two triangles share can miss both
  // and see what lies behind, a wrong label and depth in the ground truth (seen: 13 pixels of six
  // split quads whose diagonals pass through pixel centres, and on a triangle strip).
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);

  geometries_.assign(meshes.size(), Geometry{});  // not resized again: the filters hold addresses
  for (size_t i = 0; i < meshes.size(); ++i) {
    const SceneMesh& mesh = meshes[i];
    if (mesh.indices.empty()) continue;  // nothing to hit; geomIDs stay equal to mesh indices
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    Geometry& g = geometries_[i];
    if (Moves(steps, i)) {
      rtcSetGeometryTimeStepCount(geom, unsigned(steps->size()));
      for (size_t k = 0; k < steps->size(); ++k) g.steps.push_back(FillVertices(geom, unsigned(k), (*steps)[k][i].positions));
    } else {
      g.steps.push_back(FillVertices(geom, 0, mesh.positions));
    }
    const bool allocated = std::find(g.steps.begin(), g.steps.end(), nullptr) == g.steps.end();
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), mesh.indices.size() / 3));
    g.indices = indices;
    g.shading = &shading[i];
    if (!allocated || indices == nullptr) {
      rtcReleaseGeometry(geom);
      errors_.ThrowIfAny(source_ + ": mesh '" + mesh.name + "'");
      throw std::runtime_error(source_ + ": mesh '" + mesh.name + "': Embree could not allocate buffers");
    }
    std::copy(mesh.indices.begin(), mesh.indices.end(), indices);
    if (shading[i].alpha_tested) {
      rtcSetGeometryUserData(geom, &g);
      rtcSetGeometryIntersectFilterFunction(geom, &AlphaMaskFilter);
      rtcSetGeometryOccludedFilterFunction(geom, &AlphaMaskFilter);
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(scene_, geom, unsigned(i));
    rtcReleaseGeometry(geom);  // the scene holds its own reference
  }
  rtcCommitScene(scene_);
  errors_.ThrowIfAny(source_ + ": building the Embree scene");
}

void EmbreeScene::Intersect(std::vector<RTCRayHit>& rays) const {
  if (rays.empty()) return;
  RTCIntersectContext context = CoherentContext();
  rtcIntersect1M(scene_, &context, rays.data(), unsigned(rays.size()), sizeof(RTCRayHit));
  for (RTCRayHit& rh : rays) {
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
    const Eigen::Vector3d org(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z), dir(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
    const std::optional<TriangleHit> exact = ExactHit(geometries_[rh.hit.geomID], rh.hit.primID, org, dir, rh.ray.time);
    if (!exact) continue;
    rh.ray.tfar = exact->t;
    rh.hit.u = exact->u;
    rh.hit.v = exact->v;
  }
}

void EmbreeScene::Occlude(std::vector<RTCRay>& rays) const {
  if (rays.empty()) return;
  RTCIntersectContext context = CoherentContext();
  rtcOccluded1M(scene_, &context, rays.data(), unsigned(rays.size()), sizeof(RTCRay));
}

}  // namespace rigsim
