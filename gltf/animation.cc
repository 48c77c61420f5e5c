#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gltf/loader.h"
#include "scene/morphing.h"
#include "scene/skinning.h"

namespace rigsim::gltf {

// Node animations: the node tree (rest transforms, parents) and every translation, rotation,
// scale and morph-weights channel. CUBICSPLINE keys are sampled at their values and interpolated
// linearly (warned).
void Loader::ParseAnimations() {
  if (model_.animations.empty()) return;
  for (size_t a = 0; a < model_.animations.size(); ++a) {
    const tinygltf::Animation& anim = model_.animations[a];
    const std::string aname = "animation " + std::to_string(a) + NameSuffix(anim.name);
    for (size_t c = 0; c < anim.channels.size(); ++c) {
      const tinygltf::AnimationChannel& ch = anim.channels[c];
      const std::string where = aname + " channel " + std::to_string(c);
      if (ch.target_node < 0) continue;  // glTF: no target node means the channel is ignored
      if (size_t(ch.target_node) >= model_.nodes.size()) Fail(where + ": target node " + std::to_string(ch.target_node) + " out of range");
      AnimationChannel out;
      out.node = ch.target_node;
      int ncomp = 3;  // values per key (the morph target count for weights)
      if (ch.target_path == "weights") {
        out.path = AnimationPath::kWeights;
        ncomp = int(MorphTargetCount(ch.target_node));
        if (ncomp == 0) {
          Warn(where + ": animates the morph weights of node " + std::to_string(ch.target_node) +
               ", whose mesh has no morph targets; ignored");
          continue;
        }
      } else if (ch.target_path == "translation") {
        out.path = AnimationPath::kTranslation;
      } else if (ch.target_path == "rotation") {
        out.path = AnimationPath::kRotation;
        ncomp = 4;
      } else if (ch.target_path == "scale") {
        out.path = AnimationPath::kScale;
      } else {
        Ignore("animation path " + ch.target_path);
        continue;
      }
      if (ch.sampler < 0 || size_t(ch.sampler) >= anim.samplers.size()) Fail(where + ": sampler " + std::to_string(ch.sampler) + " out of range");
      const tinygltf::AnimationSampler& sampler = anim.samplers[ch.sampler];
      bool cubic = false;
      if (sampler.interpolation == "STEP") {
        out.interpolation = AnimationInterpolation::kStep;
      } else if (sampler.interpolation == "CUBICSPLINE") {
        cubic = true;
        Warn(where + ": CUBICSPLINE interpolation is rendered as LINEAR between the keys");
      }
      size_t nkeys = 0, nvalues = 0;
      const std::vector<double> times = ReadAccessor(sampler.input, TINYGLTF_TYPE_SCALAR, where + " input", &nkeys);
      const bool weights = out.path == AnimationPath::kWeights;
      const int output_type = weights ? TINYGLTF_TYPE_SCALAR : ncomp == 4 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3;
      const std::vector<double> values = ReadAccessor(sampler.output, output_type, where + " output", &nvalues);
      if (nkeys == 0) Fail(where + ": no keyframes");
      // Weights: one scalar per morph target per key (glTF 2.0, "Animations").
      const size_t per_key = weights ? size_t(ncomp) : 1;
      if (nvalues != (cubic ? 3 : 1) * nkeys * per_key) {
        Fail(where + ": " + std::to_string(nvalues) + " output values for " + std::to_string(nkeys) + " keyframes" +
             (weights ? " of " + std::to_string(ncomp) + " morph target weights" : ""));
      }
      for (size_t k = 0; k < nkeys; ++k) {
        if (!std::isfinite(times[k]) || (k > 0 && !(times[k] > times[k - 1]))) {
          Fail(where + ": keyframe times must be finite and strictly increasing (key " + std::to_string(k) + ")");
        }
        const size_t v = cubic ? 3 * k + 1 : k;  // cubic: (in-tangent, value, out-tangent)
        out.times_s.push_back(times[k]);
        if (weights) {
          const Eigen::VectorXd w = Eigen::Map<const Eigen::VectorXd>(values.data() + ncomp * v, ncomp);
          if (!w.allFinite()) Fail(where + ": keyframe weights " + std::to_string(k) + " are not finite");
          out.weights.push_back(w);
          continue;
        }
        Eigen::Vector4d value(values[ncomp * v], values[ncomp * v + 1], values[ncomp * v + 2], ncomp == 4 ? values[ncomp * v + 3] : 0.0);
        if (!value.allFinite()) Fail(where + ": keyframe value " + std::to_string(k) + " is not finite");
        out.values.push_back(value);
      }
      // Morph weights move no node: the mesh alone is re-posed, not the node's subtree.
      (weights ? morph_animated_nodes_ : animated_nodes_).insert(out.node);
      scene_.animation_channels.push_back(std::move(out));
    }
  }
  if (scene_.animation_channels.empty()) return;
  scene_.nodes.resize(model_.nodes.size());
  for (size_t i = 0; i < model_.nodes.size(); ++i) {
    const tinygltf::Node& n = model_.nodes[i];
    SceneNode& out = scene_.nodes[i];
    out.name = n.name;
    if (n.matrix.size() == 16) {
      out.has_matrix = true;
      out.matrix = LocalTransform(n);
      if (animated_nodes_.count(int(i))) Warn("node " + std::to_string(i) + " has a matrix and an animation; glTF forbids this, the animation wins");
    }
    if (n.translation.size() == 3) out.translation = Eigen::Vector3d(n.translation[0], n.translation[1], n.translation[2]);
    if (n.rotation.size() == 4) out.rotation_xyzw = Eigen::Vector4d(n.rotation[0], n.rotation[1], n.rotation[2], n.rotation[3]);
    if (n.scale.size() == 3) out.scale = Eigen::Vector3d(n.scale[0], n.scale[1], n.scale[2]);
    for (int c : n.children) {
      if (c >= 0 && size_t(c) < model_.nodes.size()) scene_.nodes[c].parent = int(i);
    }
  }
}

// glTF skins: joints (nodes) and inverse bind matrices (identity when the file gives none).
void Loader::ParseSkins() {
  for (size_t k = 0; k < model_.skins.size(); ++k) {
    const tinygltf::Skin& in = model_.skins[k];
    const std::string where = "skin " + std::to_string(k) + NameSuffix(in.name);
    SceneSkin out;
    for (int joint : in.joints) {
      if (joint < 0 || size_t(joint) >= model_.nodes.size()) Fail(where + ": joint node " + std::to_string(joint) + " out of range");
      out.joints.push_back(joint);
    }
    out.inverse_bind.assign(out.joints.size(), Eigen::Matrix4d::Identity());
    if (in.inverseBindMatrices >= 0) {
      size_t count = 0;
      const std::vector<double> m = ReadAccessor(in.inverseBindMatrices, TINYGLTF_TYPE_MAT4, where + " inverseBindMatrices", &count);
      if (count < out.joints.size()) {
        Fail(where + ": " + std::to_string(count) + " inverse bind matrices for " + std::to_string(out.joints.size()) + " joints");
      }
      for (size_t j = 0; j < out.joints.size(); ++j) {
        for (int i = 0; i < 16; ++i) out.inverse_bind[j](i % 4, i / 4) = m[16 * j + i];  // column-major in glTF
        if (!out.inverse_bind[j].allFinite()) Fail(where + ": inverse bind matrix " + std::to_string(j) + " is not finite");
      }
    }
    scene_.skins.push_back(std::move(out));
  }
}

// Places the skinned meshes by their joints at the nodes' rest transforms, as Traverse found
// them (the mesh node's own transform does not apply, glTF 2.0 "Skins"; a skin's joints must be
// in the scene that uses it).
void Loader::SkinAtRestPose() {
  for (SceneMesh& m : scene_.meshes) {
    if (m.skin < 0) continue;
    for (int joint : scene_.skins[m.skin].joints) {
      if (!traversed_[joint]) {
        Fail("skin " + std::to_string(m.skin) + ": joint node " + std::to_string(joint) +
             " is not in the loaded scene (glTF requires a skin's joints to be)");
      }
    }
    try {
      SkinMesh(scene_.skins[m.skin], rest_world_, &m);
    } catch (const std::invalid_argument& e) {
      Fail(e.what());
    }
    for (const Eigen::Vector3f& p : m.positions) {
      if (!p.allFinite()) Fail("skinned mesh '" + m.name + "': a vertex is not finite at the rest pose");
    }
  }
}

// JOINTS_0 (unsigned byte or short) and WEIGHTS_0 (float, or normalized unsigned byte or
// short), weights rescaled to sum to 1.
void Loader::ReadSkinning(const tinygltf::Primitive& prim, int skin, size_t nverts, const std::string& where, SceneMesh* out) {
  if (size_t(skin) >= scene_.skins.size()) Fail(where + ": skin " + std::to_string(skin) + " out of range");
  const int joints_acc = prim.attributes.at("JOINTS_0"), weights_acc = prim.attributes.at("WEIGHTS_0");
  const std::string joints_label = "accessor " + std::to_string(joints_acc) + " (" + where + " JOINTS_0)";
  const std::string weights_label = "accessor " + std::to_string(weights_acc) + " (" + where + " WEIGHTS_0)";
  size_t nj = 0, nw = 0;
  const std::vector<double> joints = ReadAccessor(joints_acc, TINYGLTF_TYPE_VEC4, where + " JOINTS_0", &nj);
  const std::vector<double> weights = ReadAccessor(weights_acc, TINYGLTF_TYPE_VEC4, where + " WEIGHTS_0", &nw);
  const int joint_type = model_.accessors[joints_acc].componentType;  // in range: ReadAccessor checked
  if (joint_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && joint_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
    Fail(joints_label + ": componentType must be UNSIGNED_BYTE or UNSIGNED_SHORT");
  }
  if (nj != nverts) Fail(joints_label + ": count differs from POSITION");
  if (nw != nverts) Fail(weights_label + ": count differs from POSITION");
  const size_t num_joints = scene_.skins[skin].joints.size();
  out->skin = skin;
  out->joints.resize(nverts);
  out->weights.resize(nverts);
  for (size_t i = 0; i < nverts; ++i) {
    double sum = 0;
    for (int k = 0; k < 4; ++k) {
      const double w = weights[4 * i + k];
      if (!(w >= 0.0) || !std::isfinite(w)) Fail(weights_label + ": weight of vertex " + std::to_string(i) + " is negative or not finite");
      const double j = joints[4 * i + k];
      if (w > 0.0 && j >= double(num_joints)) {
        Fail(joints_label + ": vertex " + std::to_string(i) + " names joint " + std::to_string(int(j)) + " of a skin with " +
             std::to_string(num_joints));
      }
      out->joints[i][k] = uint16_t(j);
      sum += w;
    }
    if (!(sum > 0.0)) Fail(weights_label + ": vertex " + std::to_string(i) + " has no joint weight");
    for (int k = 0; k < 4; ++k) out->weights[i][k] = float(weights[4 * i + k] / sum);
  }
}

// How many morph targets the mesh on `node` has (its first primitive's: all must have as many);
// 0 without a mesh.
size_t Loader::MorphTargetCount(int node) const {
  const int mesh = model_.nodes[node].mesh;
  if (mesh < 0 || size_t(mesh) >= model_.meshes.size() || model_.meshes[mesh].primitives.empty()) return 0;
  return model_.meshes[mesh].primitives[0].targets.size();
}

// The morph weights of the mesh on `node` at rest: node.weights, else mesh.weights, else zeros;
// one per morph target, which every primitive of the mesh must have as many of.
std::vector<double> Loader::RestMorphWeights(int node_index) {
  const tinygltf::Node& node = model_.nodes[node_index];
  const tinygltf::Mesh& mesh = model_.meshes[node.mesh];
  const size_t count = MorphTargetCount(node_index);
  for (size_t p = 1; p < mesh.primitives.size(); ++p) {
    if (mesh.primitives[p].targets.size() != count) {
      Fail(MeshLabel(model_, node.mesh, int(p)) + ": " + std::to_string(mesh.primitives[p].targets.size()) +
           " morph targets, primitive 0 has " + std::to_string(count) + " (glTF requires the same number)");
    }
  }
  const bool from_node = !node.weights.empty();
  const std::vector<double>& weights = from_node ? node.weights : mesh.weights;
  const std::string owner = from_node ? "node " + std::to_string(node_index) + NameSuffix(node.name)
                                      : "mesh " + std::to_string(node.mesh) + NameSuffix(mesh.name);
  if (weights.empty()) return std::vector<double>(count, 0.0);
  if (count == 0) {  // invalid glTF, but nothing to morph: exporters write such weights
    Warn(owner + ": " + std::to_string(weights.size()) + " morph weights but no morph targets; weights ignored");
    return {};
  }
  if (weights.size() != count) {
    Fail(owner + ": " + std::to_string(weights.size()) + " morph weights for " + std::to_string(count) + " morph targets");
  }
  for (size_t i = 0; i < weights.size(); ++i) {
    if (!std::isfinite(weights[i])) Fail(owner + ": morph weight " + std::to_string(i) + " is not finite");
  }
  return weights;
}

// The primitive's morph targets: POSITION and (when the primitive has normals) NORMAL
// displacements, VEC3 of float or, under KHR_mesh_quantization, of (normalized) byte or short.
// TANGENT, which rigsim does not use, and other attributes are ignored.
std::vector<MorphTarget> Loader::ReadMorphTargets(const tinygltf::Primitive& prim, size_t nverts, const std::string& where) {
  std::vector<MorphTarget> targets(prim.targets.size());
  for (size_t t = 0; t < prim.targets.size(); ++t) {
    for (const auto& [name, accessor] : prim.targets[t]) {
      const bool normal = name == "NORMAL" && prim.attributes.count("NORMAL");
      if (name != "POSITION" && !normal) {
        Ignore("morph target attribute " + name);
        continue;
      }
      const std::string use = where + " target " + std::to_string(t) + " " + name;
      const std::string label = "accessor " + std::to_string(accessor) + " (" + use + ")";
      size_t n = 0;
      const std::vector<double> d = ReadAccessor(accessor, TINYGLTF_TYPE_VEC3, use, &n);
      const int type = model_.accessors[accessor].componentType;  // in range: ReadAccessor checked
      if (type != TINYGLTF_COMPONENT_TYPE_FLOAT && type != TINYGLTF_COMPONENT_TYPE_BYTE && type != TINYGLTF_COMPONENT_TYPE_SHORT) {
        Fail(label + ": componentType must be FLOAT, BYTE or SHORT");
      }
      if (n != nverts) Fail(label + ": count " + std::to_string(n) + " differs from POSITION's " + std::to_string(nverts));
      std::vector<Eigen::Vector3f>& out = normal ? targets[t].normals : targets[t].positions;
      out.resize(n);
      for (size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d v(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
        if (!v.allFinite()) Fail(label + ": vertex " + std::to_string(i) + " is not finite");
        out[i] = v.cast<float>();
      }
    }
  }
  return targets;
}

// Applies the rest morph weights to the primitive's node-frame positions and normals (xyz
// triples). A mesh whose weights are animated keeps its base vertices and targets for posing.
void Loader::Morph(const tinygltf::Primitive& prim, size_t nverts, const std::vector<double>& weights, bool keep, const std::string& where,
                   std::vector<double>* pos, std::vector<double>* nrm, SceneMesh* out) {
  auto to_vectors = [](const std::vector<double>& xyz) {
    std::vector<Eigen::Vector3f> v(xyz.size() / 3);
    for (size_t i = 0; i < v.size(); ++i) v[i] = Eigen::Vector3d(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]).normalized().cast<float>();
    return v;
  };
  SceneMesh& m = *out;
  m.morph_targets = ReadMorphTargets(prim, nverts, where);
  m.morph_base_positions.resize(nverts);
  for (size_t i = 0; i < nverts; ++i) m.morph_base_positions[i] = Eigen::Vector3d((*pos)[3 * i], (*pos)[3 * i + 1], (*pos)[3 * i + 2]).cast<float>();
  m.morph_base_normals = to_vectors(*nrm);
  try {
    MorphMesh(weights, &m);  // the one implementation, which PoseSceneAt uses too
  } catch (const std::invalid_argument& e) {
    Fail(where + ": " + e.what());
  }
  for (size_t i = 0; i < nverts; ++i) {
    for (int c = 0; c < 3; ++c) (*pos)[3 * i + c] = m.local_positions[i][c];
  }
  for (size_t i = 0; i < m.local_normals.size(); ++i) {
    for (int c = 0; c < 3; ++c) (*nrm)[3 * i + c] = m.local_normals[i][c];
  }
  m.local_positions.clear();
  m.local_normals.clear();
  if (!keep) {
    m.morph_base_positions.clear();
    m.morph_base_normals.clear();
    m.morph_targets.clear();
  }
}

}  // namespace rigsim::gltf
