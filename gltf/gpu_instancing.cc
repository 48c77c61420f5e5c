#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "gltf/loader.h"

namespace rigsim::gltf {

// EXT_mesh_gpu_instancing on a mesh node: each instance's T * R * S (node_from_instance) and
// index, in accessor order, without instance ids yet; empty when the node has no such extension (or is skinned, which the extension
// leaves undefined: drawn once, by its joints, with a warning). TRANSLATION and SCALE are VEC3
// float, ROTATION VEC4 float or normalized byte/short (x, y, z, w), all of one count; a missing
// one is identity. The geometry all instances make is bounded before anything is decoded.
std::vector<Loader::Placement> Loader::GpuInstances(int node_index) {
  const tinygltf::Node& node = model_.nodes[node_index];
  const auto ext_it = node.extensions.find(kGpuInstancing);
  if (ext_it == node.extensions.end()) return {};
  const std::string where = NodeLabel(node_index) + " " + kGpuInstancing;
  if (node.skin >= 0) {
    Warn(where + ": on a skinned node, which the extension leaves undefined; the mesh is drawn once, placed by its joints");
    return {};
  }
  const tinygltf::Value& ext = ext_it->second;
  if (!ext.IsObject() || !ext.Has("attributes") || !ext.Get("attributes").IsObject()) Fail(where + ": has no attributes object");
  const tinygltf::Value& attributes = ext.Get("attributes");
  struct Attribute {
    const char* name;
    int type;
    int accessor = -1;
  };
  Attribute trs[3] = {{"TRANSLATION", TINYGLTF_TYPE_VEC3}, {"ROTATION", TINYGLTF_TYPE_VEC4}, {"SCALE", TINYGLTF_TYPE_VEC3}};
  for (const std::string& key : attributes.Keys()) {
    Attribute* known = nullptr;
    for (Attribute& a : trs) known = key == a.name ? &a : known;
    if (!known) {
      Ignore(std::string(kGpuInstancing) + " attribute " + key);  // custom (_ID, ...): nothing rigsim draws
      continue;
    }
    const tinygltf::Value& v = attributes.Get(key);
    if (!v.IsInt()) Fail(where + ": attribute " + key + " is not an accessor index");
    known->accessor = v.GetNumberAsInt();
  }
  // Metadata first (types, counts), so that the size bound holds before anything is read.
  size_t count = 0;
  const Attribute* first = nullptr;
  for (const Attribute& a : trs) {
    if (a.accessor < 0 && attributes.Has(a.name)) Fail(where + ": " + a.name + " accessor " + std::to_string(a.accessor) + " out of range");
    if (a.accessor < 0) continue;
    const std::string label = "accessor " + std::to_string(a.accessor) + " (" + where + " " + a.name + ")";
    if (size_t(a.accessor) >= model_.accessors.size()) Fail(label + ": index out of range");
    const tinygltf::Accessor& acc = model_.accessors[a.accessor];
    const bool rotation = a.type == TINYGLTF_TYPE_VEC4;
    if (acc.type != a.type) Fail(label + ": type must be " + (rotation ? "VEC4" : "VEC3"));
    const bool normalized_signed =
        acc.normalized && (acc.componentType == TINYGLTF_COMPONENT_TYPE_BYTE || acc.componentType == TINYGLTF_COMPONENT_TYPE_SHORT);
    if (acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !(rotation && normalized_signed)) {
      Fail(label + ": componentType must be FLOAT" + (rotation ? ", or normalized BYTE or SHORT" : ""));
    }
    if (acc.count == 0) Fail(label + ": count is 0 (an instanced node needs at least one instance)");
    if (first && acc.count != count) {
      Fail(label + ": count " + std::to_string(acc.count) + " differs from " + first->name + "'s " + std::to_string(count) +
           " (all instance attributes must have the same count)");
    }
    first = &a;
    count = acc.count;
  }
  if (!first) {
    Warn(where + ": no TRANSLATION, ROTATION or SCALE attribute; the mesh is drawn once");
    return {};
  }
  CheckInstancedSize(node_index, count, where);
  std::vector<double> values[3];  // per attribute: count x (3 or 4), empty when not given
  for (int k = 0; k < 3; ++k) {
    const Attribute& a = trs[k];
    if (a.accessor < 0) continue;
    const std::string label = "accessor " + std::to_string(a.accessor) + " (" + where + " " + a.name + ")";
    size_t n = 0;
    values[k] = ReadAccessor(a.accessor, a.type, where + " " + a.name, &n);
    const size_t ncomp = size_t(NumComponents(a.type));
    for (size_t i = 0; i < values[k].size(); ++i) {
      if (!std::isfinite(values[k][i])) Fail(label + ": instance " + std::to_string(i / ncomp) + " is not finite");
    }
    for (size_t i = 0; k == 1 && i < n; ++i) {
      if (IsZeroQuaternion(Eigen::Map<const Eigen::Vector4d>(&values[k][4 * i]))) {
        Fail(label + ": instance " + std::to_string(i) + " has a zero quaternion, which is no rotation");
      }
    }
  }
  std::vector<Placement> out(count);  // count is bounded now: ReadAccessor checked it
  for (size_t i = 0; i < count; ++i) {
    Eigen::Affine3d t = Eigen::Affine3d::Identity();
    if (!values[0].empty()) t.translate(Eigen::Map<const Eigen::Vector3d>(&values[0][3 * i]));
    if (!values[1].empty()) {
      const double* q = &values[1][4 * i];  // glTF (x, y, z, w); quantized (and float) ones are unit only nearly
      t.rotate(Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized());
    }
    if (!values[2].empty()) t.scale(Eigen::Map<const Eigen::Vector3d>(&values[2][3 * i]));
    out[i].node_from_instance = t.matrix();
    out[i].gpu_instance = int(i);
  }
  return out;
}

// Instances copy their mesh's geometry, which is decoded once per node: this bounds the copies
// (vertices and indices of every instance, summed over the file) by max_accessor_count, as
// ReadAccessor bounds what is decoded, so that a small file cannot ask for billions of vertices.
void Loader::CheckInstancedSize(int node_index, size_t count, const std::string& where) {
  const tinygltf::Mesh& mesh = model_.meshes[model_.nodes[node_index].mesh];
  auto accessor_count = [&](int a) -> size_t { return a >= 0 && size_t(a) < model_.accessors.size() ? model_.accessors[a].count : 0; };
  size_t per_instance = 0;  // accessor metadata only: AddPrimitive checks the accessors themselves
  for (const tinygltf::Primitive& prim : mesh.primitives) {
    const auto pos = prim.attributes.find("POSITION");
    if (pos == prim.attributes.end()) continue;
    per_instance += std::min(accessor_count(pos->second), options_.max_accessor_count);
    per_instance += std::min(accessor_count(prim.indices), options_.max_accessor_count);
  }
  const size_t limit = options_.max_accessor_count;
  const size_t room = limit - std::min(limit, instanced_elements_);
  if (per_instance > 0 && count > room / per_instance) {
    Fail(where + ": " + std::to_string(count) + " instances of a mesh of " + std::to_string(per_instance) +
         " vertices and indices each exceed the limit of " + std::to_string(limit) +
         " on all instanced geometry (GltfLoadOptions::max_accessor_count; instanced nodes before this one made " +
         std::to_string(instanced_elements_) + ")");
  }
  instanced_elements_ += count * per_instance;
}

}  // namespace rigsim::gltf
