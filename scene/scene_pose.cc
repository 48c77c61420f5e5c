#include "scene/scene_pose.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "scene/morphing.h"
#include "scene/skinning.h"

namespace rigsim {
namespace {

struct Trs {
  Eigen::Vector3d translation;
  Eigen::Quaterniond rotation;
  Eigen::Vector3d scale;
};

Eigen::Quaterniond FromXyzw(const Eigen::Vector4d& q) { return Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized(); }

// Where `t` falls among a channel's keys: key k, and the fraction a of the way to key k + 1 (0
// before the first key, at or after the last, and under STEP, which holds key k).
struct KeyBracket {
  size_t k = 0;
  double a = 0.0;
};

KeyBracket BracketOf(const AnimationChannel& ch, double t) {
  const auto& times = ch.times_s;
  if (t <= times.front()) return {0, 0.0};
  if (t >= times.back()) return {times.size() - 1, 0.0};
  const size_t k = size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;  // times[k] <= t < times[k+1]
  if (ch.interpolation == AnimationInterpolation::kStep) return {k, 0.0};
  return {k, (t - times[k]) / (times[k + 1] - times[k])};
}

// The channel's value at `t` (clamped to its key range).
Eigen::Vector4d Sample(const AnimationChannel& ch, double t) {
  const auto [k, a] = BracketOf(ch, t);
  if (a == 0.0) return ch.values[k];
  if (ch.path == AnimationPath::kRotation) {
    const Eigen::Quaterniond q = FromXyzw(ch.values[k]).slerp(a, FromXyzw(ch.values[k + 1]));
    return Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
  }
  return (1 - a) * ch.values[k] + a * ch.values[k + 1];
}

// A weights channel's morph weights at `t` (clamped; LINEAR blends each weight, STEP holds).
Eigen::VectorXd SampleWeights(const AnimationChannel& ch, double t) {
  const auto [k, a] = BracketOf(ch, t);
  if (a == 0.0) return ch.weights[k];
  return (1 - a) * ch.weights[k] + a * ch.weights[k + 1];
}

[[noreturn]] void ThrowInconsistent(const Scene& scene, const AnimationChannel& ch) {
  throw std::invalid_argument(scene.source + ": animation channel of node " + std::to_string(ch.node) +
                              " is inconsistent (node out of range or keys without values)");
}

}  // namespace

std::vector<Eigen::Matrix4d> NodeWorldTransformsAt(const Scene& scene, double time_s) {
  const size_t n = scene.nodes.size();
  std::vector<Trs> trs(n);
  std::vector<bool> animated(n, false);
  for (size_t i = 0; i < n; ++i) {
    trs[i] = {scene.nodes[i].translation, FromXyzw(scene.nodes[i].rotation_xyzw), scene.nodes[i].scale};
  }
  for (const AnimationChannel& ch : scene.animation_channels) {
    if (ch.path == AnimationPath::kWeights) continue;  // moves a mesh's vertices, not its node
    if (ch.node < 0 || size_t(ch.node) >= n || ch.times_s.empty() || ch.values.size() != ch.times_s.size()) {
      ThrowInconsistent(scene, ch);
    }
    const Eigen::Vector4d v = Sample(ch, time_s);
    animated[ch.node] = true;
    switch (ch.path) {
      case AnimationPath::kTranslation: trs[ch.node].translation = v.head<3>(); break;
      case AnimationPath::kRotation: trs[ch.node].rotation = FromXyzw(v); break;
      case AnimationPath::kScale: trs[ch.node].scale = v.head<3>(); break;
      case AnimationPath::kWeights: break;
    }
  }
  auto local = [&](size_t i) -> Eigen::Matrix4d {
    if (scene.nodes[i].has_matrix && !animated[i]) return scene.nodes[i].matrix;
    Eigen::Affine3d t = Eigen::Affine3d::Identity();
    t.translate(trs[i].translation);
    t.rotate(trs[i].rotation);
    t.scale(trs[i].scale);
    return t.matrix();
  };
  // Without recursion, as the loader traverses: a valid file may nest nodes 100,000 deep.
  std::vector<Eigen::Matrix4d> world(n);
  std::vector<int> state(n, 0);  // 0 = todo, 1 = on the path being resolved, 2 = done
  std::vector<size_t> path;      // from a node up to the first ancestor that is done (or a root)
  for (size_t start = 0; start < n; ++start) {
    for (size_t i = start; state[i] != 2;) {
      if (state[i] == 1) throw std::invalid_argument(scene.source + ": node " + std::to_string(i) + " is its own ancestor");
      state[i] = 1;
      path.push_back(i);
      const int parent = scene.nodes[i].parent;
      if (parent < 0 || size_t(parent) >= n) break;
      i = size_t(parent);
    }
    for (; !path.empty(); path.pop_back()) {  // parents first
      const size_t i = path.back();
      const int parent = scene.nodes[i].parent;
      world[i] = parent >= 0 && size_t(parent) < n ? Eigen::Matrix4d(world[parent] * local(i)) : local(i);
      state[i] = 2;
    }
  }
  return world;
}

std::vector<std::vector<double>> MorphWeightsAt(const Scene& scene, double time_s) {
  std::vector<std::vector<double>> weights(scene.nodes.size());
  for (const AnimationChannel& ch : scene.animation_channels) {
    if (ch.path != AnimationPath::kWeights) continue;
    if (ch.node < 0 || size_t(ch.node) >= weights.size() || ch.times_s.empty() || ch.weights.size() != ch.times_s.size()) {
      ThrowInconsistent(scene, ch);
    }
    for (const Eigen::VectorXd& w : ch.weights) {
      if (w.size() != ch.weights.front().size()) {
        throw std::invalid_argument(scene.source + ": morph weights channel of node " + std::to_string(ch.node) +
                                    " has keys of different lengths");
      }
    }
    const Eigen::VectorXd w = SampleWeights(ch, time_s);
    weights[ch.node].assign(w.data(), w.data() + w.size());
  }
  return weights;
}

std::vector<SceneMesh> PoseMeshesAt(const Scene& scene, double time_s) {
  std::vector<SceneMesh> meshes = scene.meshes;
  if (!scene.IsAnimated()) return meshes;
  const std::vector<Eigen::Matrix4d> world = NodeWorldTransformsAt(scene, time_s);
  const std::vector<std::vector<double>> morph_weights = MorphWeightsAt(scene, time_s);
  for (size_t m = 0; m < meshes.size(); ++m) {
    SceneMesh& mesh = meshes[m];
    if (mesh.node < 0) continue;
    if (!mesh.morph_targets.empty()) {
      // Morphing comes first, in the mesh's own frame; placing or skinning follows (glTF 2.0).
      if (size_t(mesh.node) >= morph_weights.size() || morph_weights[mesh.node].empty()) {
        throw std::invalid_argument(scene.source + ": mesh " + std::to_string(m) + " '" + mesh.name +
                                    "' has morph targets to pose but no weights channel on its node");
      }
      MorphMesh(morph_weights[mesh.node], &mesh);
    }
    if (size_t(mesh.node) >= world.size() || mesh.local_positions.size() != mesh.positions.size() ||
        (!mesh.local_normals.empty() && mesh.local_normals.size() != mesh.positions.size())) {
      throw std::invalid_argument(scene.source + ": animated mesh " + std::to_string(m) + " '" + mesh.name +
                                  "' has an invalid node or local vertex count");
    }
    if (mesh.skin >= 0) {
      if (size_t(mesh.skin) >= scene.skins.size()) {
        throw std::invalid_argument(scene.source + ": mesh " + std::to_string(m) + " '" + mesh.name + "': skin out of range");
      }
      SkinMesh(scene.skins[mesh.skin], world, &mesh);
      continue;
    }
    // Identity but for an EXT_mesh_gpu_instancing instance, whose transform comes before its node's.
    const Eigen::Matrix4d world_from_mesh = world[mesh.node] * mesh.node_from_instance;
    const Eigen::Matrix3d linear = world_from_mesh.topLeftCorner<3, 3>();
    const Eigen::Vector3d offset = world_from_mesh.topRightCorner<3, 1>();
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
      mesh.positions[i] = (linear * mesh.local_positions[i].cast<double>() + offset).cast<float>();
    }
    if (!mesh.local_normals.empty()) {
      const double det = linear.determinant();
      if (std::abs(det) < 1e-300) {
        mesh.normals.clear();  // a collapsed node: face normals (zero area) are used
      } else {
        const Eigen::Matrix3d normal_matrix = linear.inverse().transpose();
        mesh.normals.resize(mesh.local_normals.size());
        for (size_t i = 0; i < mesh.local_normals.size(); ++i) {
          mesh.normals[i] = (normal_matrix * mesh.local_normals[i].cast<double>()).normalized().cast<float>();
        }
      }
    }
  }
  return meshes;
}

Scene PoseSceneAt(const Scene& scene, double time_s) {
  Scene posed;
  posed.source = scene.source;
  posed.meshes = PoseMeshesAt(scene, time_s);
  posed.materials = scene.materials;
  posed.textures = scene.textures;
  posed.warnings = scene.warnings;
  posed.skins = scene.skins;
  posed.nodes = scene.nodes;
  posed.animation_channels = scene.animation_channels;
  return posed;
}

}  // namespace rigsim
