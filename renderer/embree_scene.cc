#include "renderer/embree_scene.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace rigsim {
namespace {

// Embree filter for MASK materials: rejecting a hit makes Embree continue the traversal beyond
// it, so the cut-out holds for camera rays and shadow rays alike.
void AlphaMaskFilter(const RTCFilterFunctionNArguments* args) {
  const MeshShading& m = *static_cast<const MeshShading*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    const float u = RTCHitN_u(args->hit, args->N, i);
    const float v = RTCHitN_v(args->hit, args->N, i);
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

bool FillVertices(RTCGeometry geom, unsigned slot, const std::vector<Eigen::Vector3f>& positions) {
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, slot, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size()));
  if (vertices == nullptr) return false;
  for (size_t v = 0; v < positions.size(); ++v) {
    vertices[3 * v] = positions[v].x();
    vertices[3 * v + 1] = positions[v].y();
    vertices[3 * v + 2] = positions[v].z();
  }
  return true;
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

  for (size_t i = 0; i < meshes.size(); ++i) {
    const SceneMesh& mesh = meshes[i];
    if (mesh.indices.empty()) continue;  // nothing to hit; geomIDs stay equal to mesh indices
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    bool allocated = true;
    if (Moves(steps, i)) {
      rtcSetGeometryTimeStepCount(geom, unsigned(steps->size()));
      for (size_t k = 0; k < steps->size(); ++k) allocated = allocated && FillVertices(geom, unsigned(k), (*steps)[k][i].positions);
    } else {
      allocated = FillVertices(geom, 0, mesh.positions);
    }
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), mesh.indices.size() / 3));
    if (!allocated || indices == nullptr) {
      rtcReleaseGeometry(geom);
      errors_.ThrowIfAny(source_ + ": mesh '" + mesh.name + "'");
      throw std::runtime_error(source_ + ": mesh '" + mesh.name + "': Embree could not allocate buffers");
    }
    std::copy(mesh.indices.begin(), mesh.indices.end(), indices);
    if (shading[i].alpha_tested) {
      // Embree takes a non-const user pointer; the filter only reads through it.
      rtcSetGeometryUserData(geom, const_cast<MeshShading*>(&shading[i]));
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
}

void EmbreeScene::Occlude(std::vector<RTCRay>& rays) const {
  if (rays.empty()) return;
  RTCIntersectContext context = CoherentContext();
  rtcOccluded1M(scene_, &context, rays.data(), unsigned(rays.size()), sizeof(RTCRay));
}

}  // namespace rigsim
