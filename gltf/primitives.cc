#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/LU>

#include "gltf/loader.h"
#include "labels/cityscapes.h"

namespace rigsim::gltf {

// Decodes the primitive once and adds one SceneMesh per placement (one, or one per
// EXT_mesh_gpu_instancing instance), each at world * node_from_instance.
void Loader::AddPrimitive(int node_index, int mesh_index, int prim_index, const Eigen::Matrix4d& world, ClassTag cls,
                          const std::vector<Placement>& placements, const std::vector<double>& morph_weights) {
  const tinygltf::Node& node = model_.nodes[node_index];
  const tinygltf::Mesh& mesh = model_.meshes[mesh_index];
  const tinygltf::Primitive& prim = mesh.primitives[prim_index];
  const std::string where = MeshLabel(model_, mesh_index, prim_index);
  if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP && prim.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    const char* kind = prim.mode == TINYGLTF_MODE_POINTS ? "points" : "lines";
    Warn(where + ": " + kind + " primitive (mode " + std::to_string(prim.mode) + ") skipped; only triangles are rendered");
    return;
  }
  for (const auto& [name, value] : prim.extensions) Ignore("primitive extension " + name);
  // The texture coordinates the material's textures sample (TEXCOORD_0 without a texture).
  const MaterialUvs uvs =
      prim.material >= 0 && size_t(prim.material) < material_uv_.size() ? material_uv_[prim.material] : MaterialUvs{};
  const bool skinned = node.skin >= 0 && prim.attributes.count("JOINTS_0") && prim.attributes.count("WEIGHTS_0");
  if (node.skin >= 0 && !skinned) {
    Warn(where + ": on a skinned node but without JOINTS_0 and WEIGHTS_0; placed by its node");
  }
  IgnoreUnreadAttributes(prim, uvs, skinned);
  if (!prim.attributes.count("POSITION")) {
    Warn(where + ": no POSITION attribute; skipped");
    return;
  }
  SceneMesh out;  // what every placement shares; positions, normals and winding are per placement
  out.name = !node.name.empty() ? node.name : mesh.name;
  cls = PrimitiveClass(node_index, mesh_index, prim, cls, where, &out);
  const PrimitiveVertices vertices = DecodeVertices(node_index, prim, skinned, morph_weights, where, &out);
  ReadTexcoordSets(prim, uvs, vertices.count, where, &out);
  if (auto it = prim.attributes.find("COLOR_0"); it != prim.attributes.end()) ReadVertexColors(it->second, where, vertices.count, &out);
  AssembleTriangles(prim.mode, VertexSequence(prim, vertices.count, where), where, &out.indices);
  if (out.indices.empty()) {
    Warn(where + ": no triangles; skipped");
    return;
  }
  AddPlacedCopies(std::move(out), placements, world, vertices, cls.has_value(), where);
}

// Counts (Ignore) the vertex attributes nothing reads: all but POSITION, NORMAL, COLOR_0, the
// texture coordinates the material samples and, when skinned, JOINTS_0 and WEIGHTS_0.
void Loader::IgnoreUnreadAttributes(const tinygltf::Primitive& prim, const MaterialUvs& uvs, bool skinned) {
  const std::string texcoord_name = "TEXCOORD_" + std::to_string(uvs.base_color.set);
  const std::string emissive_texcoord_name = uvs.emissive ? "TEXCOORD_" + std::to_string(uvs.emissive->set) : "";
  const std::string normal_texcoord_name = uvs.normal ? "TEXCOORD_" + std::to_string(uvs.normal->set) : "";
  const std::string occlusion_texcoord_name = uvs.occlusion ? "TEXCOORD_" + std::to_string(uvs.occlusion->set) : "";
  for (const auto& [name, acc] : prim.attributes) {
    if (name != "POSITION" && name != "NORMAL" && name != texcoord_name && name != emissive_texcoord_name &&
        name != normal_texcoord_name && name != occlusion_texcoord_name && name != "COLOR_0" &&
        !(skinned && (name == "JOINTS_0" || name == "WEIGHTS_0"))) {
      Ignore("vertex attribute " + name);
    }
  }
}

// The primitive's class: its material's, else `cls` (the mesh's or the node's), else the label
// rules'; nullopt when none gives one (out->class_id is then unlabeled). Sets out->material.
ClassTag Loader::PrimitiveClass(int node_index, int mesh_index, const tinygltf::Primitive& prim, ClassTag cls,
                                const std::string& where, SceneMesh* out) {
  if (prim.material >= 0) {
    if (size_t(prim.material) >= model_.materials.size()) Fail(where + ": material " + std::to_string(prim.material) + " out of range");
    out->material = prim.material;
    if (material_class_[prim.material]) cls = material_class_[prim.material];
  }
  if (!cls && options_.label_rules) cls = ClassFromLabelRules(node_index, mesh_index, prim.material);
  if (cls) {
    out->class_id = *cls;
  } else {
    out->class_id = kUnlabeledId;
  }
  return cls;
}

// POSITION and NORMAL, morphed at the rest weights; the skinning attributes; and, for a mesh
// PoseSceneAt re-poses, its node and node-frame positions in *out.
Loader::PrimitiveVertices Loader::DecodeVertices(int node_index, const tinygltf::Primitive& prim, bool skinned,
                                                 const std::vector<double>& morph_weights, const std::string& where, SceneMesh* out) {
  PrimitiveVertices v;
  v.position_accessor = prim.attributes.at("POSITION");
  size_t& nverts = v.count;
  std::vector<double>& pos = v.positions;
  std::vector<double>& nrm = v.normals;
  pos = ReadAccessor(v.position_accessor, TINYGLTF_TYPE_VEC3, where + " POSITION", &nverts);
  if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
    size_t n = 0;
    nrm = ReadAccessor(it->second, TINYGLTF_TYPE_VEC3, where + " NORMAL", &n);
    if (n != nverts) Fail("accessor " + std::to_string(it->second) + " (" + where + " NORMAL): count differs from POSITION");
  }
  out->num_morph_targets = int(prim.targets.size());
  const bool morph_animated = !prim.targets.empty() && morph_animated_nodes_.count(node_index) > 0;
  if (!prim.targets.empty()) Morph(prim, nverts, morph_weights, morph_animated, where, &pos, &nrm, out);
  for (size_t i = 0; i < nverts; ++i) {
    if (!Eigen::Vector3d(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]).allFinite()) {
      Fail("accessor " + std::to_string(v.position_accessor) + " (" + where + " POSITION): vertex " + std::to_string(i) +
           " is not finite");
    }
  }
  if (skinned) ReadSkinning(prim, model_.nodes[node_index].skin, nverts, where, out);
  v.posed_later = current_mesh_animated_ || skinned || morph_animated;
  if (v.posed_later) {
    // PoseSceneAt re-poses this mesh from its node-frame vertices (SkinAtRestPose places a
    // skinned one); local_normals are set per placement, as a placement may drop its normals.
    out->node = node_index;
    out->local_positions.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) out->local_positions[i] = Eigen::Vector3d(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]).cast<float>();
  }
  return v;
}

// The texture coordinates of the material's base colour, emissive, normal and occlusion textures.
// A primitive without the set a texture samples is drawn without that texture (counted by Ignore).
void Loader::ReadTexcoordSets(const tinygltf::Primitive& prim, const MaterialUvs& uvs, size_t nverts, const std::string& where,
                              SceneMesh* out) {
  out->texcoords = ReadTexcoords(prim, uvs.base_color, nverts, where);
  if (out->texcoords.empty() && out->material >= 0 && scene_.materials[out->material].base_color_texture >= 0) {
    Ignore("textured primitives without their texture's TEXCOORD_" + std::to_string(uvs.base_color.set) + " (rendered untextured)");
  }
  if (uvs.emissive) {
    out->emissive_texcoords = ReadTexcoords(prim, *uvs.emissive, nverts, where);
    if (out->emissive_texcoords.empty()) {
      Ignore("emissive primitives without their texture's TEXCOORD_" + std::to_string(uvs.emissive->set) +
             " (emissive texture not shown)");
    }
  }
  if (uvs.normal) {
    out->normal_texcoords = ReadTexcoords(prim, *uvs.normal, nverts, where);
    if (out->normal_texcoords.empty()) {
      Ignore("normal-mapped primitives without their texture's TEXCOORD_" + std::to_string(uvs.normal->set) + " (normal map not used)");
    }
  }
  if (uvs.occlusion) {
    out->occlusion_texcoords = ReadTexcoords(prim, *uvs.occlusion, nverts, where);
    if (out->occlusion_texcoords.empty()) {
      Ignore("occluded primitives without their texture's TEXCOORD_" + std::to_string(uvs.occlusion->set) + " (occlusion not used)");
    }
  }
}

// The vertex sequence the primitive's mode is applied to: its indices, or 0..n-1 when non-indexed.
std::vector<uint32_t> Loader::VertexSequence(const tinygltf::Primitive& prim, size_t nverts, const std::string& where) {
  std::vector<uint32_t> seq;
  if (prim.indices >= 0) {
    if (size_t(prim.indices) >= model_.accessors.size()) Fail(where + ": indices accessor " + std::to_string(prim.indices) + " out of range");
    const tinygltf::Accessor& ia = model_.accessors[prim.indices];
    if (ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
      Fail("accessor " + std::to_string(prim.indices) + " (" + where + " indices): componentType must be an unsigned integer");
    }
    size_t n = 0;
    const std::vector<double> idx = ReadAccessor(prim.indices, TINYGLTF_TYPE_SCALAR, where + " indices", &n);
    seq.resize(n);
    for (size_t i = 0; i < n; ++i) {
      if (idx[i] >= double(nverts)) {
        Fail("accessor " + std::to_string(prim.indices) + " (" + where + " indices): index " + std::to_string(uint64_t(idx[i])) +
             " at position " + std::to_string(i) + " is >= vertex count " + std::to_string(nverts));
      }
      seq[i] = uint32_t(idx[i]);
    }
  } else {
    seq.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) seq[i] = uint32_t(i);
  }
  return seq;
}

// Triangles (three indices each, in the file's winding; PlacePrimitive turns it for a mirroring
// placement) from the vertex sequence of a TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN primitive.
void Loader::AssembleTriangles(int mode, const std::vector<uint32_t>& seq, const std::string& where, std::vector<uint32_t>* indices) {
  auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
    indices->push_back(a);
    indices->push_back(b);
    indices->push_back(c);
  };
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    if (seq.size() % 3 != 0) Warn(where + ": vertex/index count " + std::to_string(seq.size()) + " is not a multiple of 3; the remainder is ignored");
    indices->reserve(seq.size());
    for (size_t i = 0; i + 2 < seq.size(); i += 3) emit(seq[i], seq[i + 1], seq[i + 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    // glTF spec: triangle i = (v_i, v_{i+1+i%2}, v_{i+2-i%2}); degenerate joiners are dropped.
    for (size_t i = 0; i + 2 < seq.size(); ++i) {
      const uint32_t a = seq[i], b = seq[i + 1 + i % 2], c = seq[i + 2 - i % 2];
      if (a != b && b != c && a != c) emit(a, b, c);
    }
  } else {  // fan: triangle i = (v_{i+1}, v_{i+2}, v_0)
    for (size_t i = 0; i + 2 < seq.size(); ++i) {
      const uint32_t a = seq[i + 1], b = seq[i + 2], c = seq[0];
      if (a != b && b != c && a != c) emit(a, b, c);
    }
  }
}

// One SceneMesh per placement, `out` placed at world * node_from_instance with the placement's
// instance id; a placement whose normals cannot be transformed is warned about once for all.
void Loader::AddPlacedCopies(SceneMesh out, const std::vector<Placement>& placements, const Eigen::Matrix4d& world,
                             const PrimitiveVertices& vertices, bool labeled, const std::string& where) {
  size_t singular = 0, bad_normals = 0;  // placements whose normals were dropped, warned once below
  for (size_t k = 0; k < placements.size(); ++k) {
    const Placement& place = placements[k];
    const bool last = k + 1 == placements.size();
    SceneMesh copy = last ? std::move(out) : out;
    copy.instance_id = place.instance_id;
    copy.gpu_instance = place.gpu_instance;
    copy.node_from_instance = place.node_from_instance;
    const std::string instance_where = place.gpu_instance < 0 ? where : where + " instance " + std::to_string(place.gpu_instance);
    PlacePrimitive(world * place.node_from_instance, vertices.positions, vertices.normals, vertices.posed_later,
                   vertices.position_accessor, instance_where, &singular, &bad_normals, &copy);
    if (!labeled) {
      unlabeled_triangles_ += copy.indices.size() / 3;
      ++unlabeled_meshes_;
    }
    scene_.meshes.push_back(std::move(copy));
  }
  const bool instanced = placements.front().gpu_instance >= 0;
  if (singular) {
    Warn(where + ": singular node transform" + (instanced ? " for " + std::to_string(singular) + " instance(s)" : "") +
         "; normals dropped (face normals used)");
  }
  if (bad_normals) {
    Warn(where + ": zero or non-finite normals" + (instanced ? " in " + std::to_string(bad_normals) + " instance(s)" : "") +
         "; normals dropped (face normals used)");
  }
}

// The primitive's TEXCOORD_<uv.set> mapped by uv's transform; empty when it has no such attribute.
std::vector<Eigen::Vector2f> Loader::ReadTexcoords(const tinygltf::Primitive& prim, const TextureUv& uv, size_t nverts,
                                                   const std::string& where) {
  const std::string name = "TEXCOORD_" + std::to_string(uv.set);
  const auto it = prim.attributes.find(name);
  if (it == prim.attributes.end()) return {};
  size_t n = 0;
  const std::vector<double> raw = ReadAccessor(it->second, TINYGLTF_TYPE_VEC2, where + " " + name, &n);
  if (n != nverts) Fail("accessor " + std::to_string(it->second) + " (" + where + " " + name + "): count differs from POSITION");
  std::vector<Eigen::Vector2f> out(n);
  for (size_t i = 0; i < n; ++i) {
    out[i] = (uv.uv_from_texcoord * Eigen::Vector3d(raw[2 * i], raw[2 * i + 1], 1.0)).cast<float>();
  }
  return out;
}

// Places one copy of a decoded primitive (node-frame positions `pos` and normals `nrm`, xyz
// triples) at `world`: world positions, normals by the inverse transpose, the winding turned
// when `world` mirrors, and local_normals for a mesh PoseSceneAt re-poses. A placement whose
// normals cannot be transformed counts in *singular or *bad_normals and uses face normals.
void Loader::PlacePrimitive(const Eigen::Matrix4d& world, const std::vector<double>& pos, const std::vector<double>& nrm, bool posed_later,
                            int pos_accessor, const std::string& where, size_t* singular, size_t* bad_normals, SceneMesh* out) {
  const size_t nverts = pos.size() / 3;
  const Eigen::Matrix3d linear = world.topLeftCorner<3, 3>();
  const Eigen::Vector3d offset = world.topRightCorner<3, 1>();
  out->positions.resize(nverts);
  for (size_t i = 0; i < nverts; ++i) {
    const Eigen::Vector3d w = linear * Eigen::Vector3d(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]) + offset;
    if (!w.allFinite()) {
      Fail("accessor " + std::to_string(pos_accessor) + " (" + where + " POSITION): vertex " + std::to_string(i) +
           " is not finite once transformed");
    }
    out->positions[i] = w.cast<float>();
  }
  if (!nrm.empty()) {
    if (std::abs(linear.determinant()) < 1e-300) {
      ++*singular;
    } else {
      const Eigen::Matrix3d normal_matrix = linear.inverse().transpose();
      out->normals.resize(nverts);
      bool bad = false;
      for (size_t i = 0; i < nverts && !bad; ++i) {
        const Eigen::Vector3d v = normal_matrix * Eigen::Vector3d(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
        const double len = v.norm();
        if (!std::isfinite(len) || len < 1e-12) bad = true;
        else out->normals[i] = (v / len).cast<float>();
      }
      if (bad) {
        ++*bad_normals;
        out->normals.clear();
      }
    }
  }
  if (posed_later && !out->normals.empty()) {
    out->local_normals.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) out->local_normals[i] = Eigen::Vector3d(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]).normalized().cast<float>();
  }
  if (out->normals.empty()) out->morph_base_normals.clear();  // as local_normals: face normals are used
  // A mirroring transform turns counter-clockwise faces clockwise: swap two corners to undo it.
  if (linear.determinant() < 0) {
    for (size_t t = 0; t + 2 < out->indices.size(); t += 3) std::swap(out->indices[t + 1], out->indices[t + 2]);
  }
}

// COLOR_0 (glTF 2.0: VEC3 or VEC4 of float, or of normalized unsigned byte or short), linear
// RGBA with alpha 1 when it is VEC3.
void Loader::ReadVertexColors(int accessor, const std::string& where, size_t nverts, SceneMesh* out) {
  const std::string label = "accessor " + std::to_string(accessor) + " (" + where + " COLOR_0)";
  if (accessor < 0 || size_t(accessor) >= model_.accessors.size()) Fail(label + ": index out of range");
  const tinygltf::Accessor& a = model_.accessors[accessor];
  if (a.type != TINYGLTF_TYPE_VEC3 && a.type != TINYGLTF_TYPE_VEC4) Fail(label + ": type must be VEC3 or VEC4");
  const bool normalized_integer = a.normalized && (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                                   a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  if (a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !normalized_integer) {
    Fail(label + ": componentType must be FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT");
  }
  size_t n = 0;
  const std::vector<double> rgba = ReadAccessor(accessor, a.type, where + " COLOR_0", &n);
  if (n != nverts) Fail(label + ": count differs from POSITION");
  const int ncomp = a.type == TINYGLTF_TYPE_VEC4 ? 4 : 3;
  out->colors.resize(n);
  for (size_t i = 0; i < n; ++i) {
    Eigen::Vector4d c(rgba[ncomp * i], rgba[ncomp * i + 1], rgba[ncomp * i + 2], ncomp == 4 ? rgba[ncomp * i + 3] : 1.0);
    if (!c.allFinite()) Fail(label + ": vertex " + std::to_string(i) + " is not finite");
    out->colors[i] = c.cwiseMax(0.0).cwiseMin(1.0).cast<float>();  // the spec's range
  }
}

}  // namespace rigsim::gltf
