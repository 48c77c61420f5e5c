#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "geometry/rigid3.h"
#include "gltf/loader.h"

namespace rigsim::gltf {

Eigen::Matrix4d LocalTransform(const tinygltf::Node& node) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (node.matrix.size() == 16) {
    for (int i = 0; i < 16; ++i) m(i % 4, i / 4) = node.matrix[i];  // column-major in glTF
    return m;
  }
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (node.translation.size() == 3) t.translate(Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4) {
    // glTF stores quaternions as (x, y, z, w); Eigen's constructor takes (w, x, y, z).
    t.rotate(Eigen::Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]).normalized());
  }
  if (node.scale.size() == 3) t.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
  return t.matrix();
}

std::vector<int> Loader::RootNodes() {
  int scene = options_.scene >= 0 ? options_.scene : std::max(model_.defaultScene, 0);
  if (model_.scenes.empty()) {
    // No scene at all: treat every node that is nobody's child as a root.
    std::vector<bool> is_child(model_.nodes.size(), false);
    for (const tinygltf::Node& n : model_.nodes) {
      for (int c : n.children) {
        if (c >= 0 && size_t(c) < is_child.size()) is_child[c] = true;
      }
    }
    std::vector<int> roots;
    for (size_t i = 0; i < model_.nodes.size(); ++i) {
      if (!is_child[i]) roots.push_back(int(i));
    }
    if (!model_.nodes.empty()) Warn("file defines no scene; loading all " + std::to_string(roots.size()) + " root node(s)");
    return roots;
  }
  if (size_t(scene) >= model_.scenes.size()) Fail("scene " + std::to_string(scene) + " out of range");
  if (model_.scenes.size() > 1) {
    Warn("file has " + std::to_string(model_.scenes.size()) + " scenes; only scene " + std::to_string(scene) + " is loaded");
  }
  return model_.scenes[scene].nodes;
}

// glTF: a node's matrix has 16 numbers, translation and scale 3, rotation 4 and not zero (a unit
// quaternion; LocalTransform normalises it, as exporters round). tinygltf takes any count, and
// LocalTransform would read a wrong one, or a zero quaternion, as identity.
void Loader::CheckNodeTransforms() const {
  for (size_t i = 0; i < model_.nodes.size(); ++i) {
    const tinygltf::Node& node = model_.nodes[i];
    const std::tuple<const char*, const std::vector<double>&, size_t> properties[] = {
        {"matrix", node.matrix, 16}, {"translation", node.translation, 3}, {"rotation", node.rotation, 4}, {"scale", node.scale, 3}};
    for (const auto& [name, values, size] : properties) {
      if (!values.empty() && values.size() != size) {
        Fail(NodeLabel(int(i)) + ": " + name + " has " + std::to_string(values.size()) + " numbers, glTF requires " +
             std::to_string(size));
      }
    }
    if (node.rotation.size() == 4 && IsZeroQuaternion(Eigen::Map<const Eigen::Vector4d>(node.rotation.data()))) {
      Fail(NodeLabel(int(i)) + ": rotation is a zero quaternion, which is no rotation");
    }
  }
}

void Loader::Traverse() {
  struct Item {
    int node;
    Eigen::Matrix4d world_from_parent;  // the parent's world transform (identity for a root)
    ClassTag inherited;
    bool animated = false;  // an ancestor is animated
  };
  std::vector<bool>& visited = traversed_;
  visited.assign(model_.nodes.size(), false);
  rest_world_.assign(model_.nodes.size(), Eigen::Matrix4d::Identity());
  std::vector<Item> stack;
  const std::vector<int> roots = RootNodes();
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, Eigen::Matrix4d::Identity(), std::nullopt});
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    if (item.node < 0 || size_t(item.node) >= model_.nodes.size()) Fail("node " + std::to_string(item.node) + " out of range");
    if (visited[item.node]) {
      Fail("node " + std::to_string(item.node) + " is reached twice: the node graph is recursive or shares a node (glTF requires a tree)");
    }
    visited[item.node] = true;
    const tinygltf::Node& node = model_.nodes[item.node];
    const Eigen::Matrix4d world = item.world_from_parent * LocalTransform(node);
    if (!world.allFinite()) Fail("node " + std::to_string(item.node) + ": transform is not finite");
    rest_world_[item.node] = world;
    const ClassTag cls = node_class_[item.node] ? node_class_[item.node] : item.inherited;
    for (const auto& [name, value] : node.extensions) {
      if (name != kGpuInstancing) Ignore("node extension " + name);
    }
    const bool animated = item.animated || animated_nodes_.count(item.node) > 0;
    current_mesh_animated_ = animated;
    if (node.camera >= 0) AddCamera(item.node, world, animated);
    if (node.mesh >= 0) {
      AddMeshInstance(item.node, world, cls);
    } else if (node.extensions.count(kGpuInstancing)) {
      Warn(NodeLabel(item.node) + ": " + kGpuInstancing + " on a node without a mesh, where it means nothing; ignored");
    }
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.push_back({*c, world, cls, animated});
  }
  size_t unreached_meshes = 0, unreached_cameras = 0;
  for (size_t i = 0; i < model_.nodes.size(); ++i) {
    if (!visited[i] && model_.nodes[i].mesh >= 0) ++unreached_meshes;
    if (!visited[i] && model_.nodes[i].camera >= 0) ++unreached_cameras;
  }
  if (unreached_meshes > 0) {
    Warn(std::to_string(unreached_meshes) + " node(s) with a mesh are not part of the loaded scene and are ignored");
  }
  scene_.skipped_camera_nodes += unreached_cameras;
  if (unreached_cameras > 0) {
    Warn(std::to_string(unreached_cameras) + " node(s) with a camera are not part of the loaded scene and are ignored");
  }
  // File order (node index), whatever the traversal order: the first camera is a rig's reference.
  std::stable_sort(scene_.cameras.begin(), scene_.cameras.end(),
                   [](const SceneCamera& a, const SceneCamera& b) { return a.node < b.node; });
}

// A glTF camera on a node: its rest pose in the OpenCV frame and its perspective parameters.
// A camera that cannot be a rig camera (bad parameters, mirrored or singular transform, unknown
// type) is skipped with a warning rather than failing the load: rendering does not need it.
void Loader::AddCamera(int node_index, const Eigen::Matrix4d& world, bool animated) {
  const tinygltf::Node& node = model_.nodes[node_index];
  if (size_t(node.camera) >= model_.cameras.size()) {
    Fail("node " + std::to_string(node_index) + ": camera " + std::to_string(node.camera) + " out of range");
  }
  const tinygltf::Camera& cam = model_.cameras[node.camera];
  const std::string where = "node " + std::to_string(node_index) + NameSuffix(node.name) +
                            " (camera " + std::to_string(node.camera) + NameSuffix(cam.name) + ")";
  auto skip = [&](const std::string& why) {
    Warn(where + ": " + why + "; camera skipped");
    ++scene_.skipped_camera_nodes;
  };
  SceneCamera out;
  out.node = node_index;
  out.camera = node.camera;
  out.name = !node.name.empty() ? node.name : !cam.name.empty() ? cam.name : "camera" + std::to_string(node_index);
  if (cam.type == "perspective") {
    const tinygltf::PerspectiveCamera& p = cam.perspective;
    if (!(p.yfov > 0.0 && p.yfov < std::numbers::pi)) {
      skip("yfov " + std::to_string(p.yfov) + " is not in (0, pi) radians");
      return;
    }
    if (!(p.aspectRatio >= 0.0 && std::isfinite(p.aspectRatio))) {
      skip("aspectRatio " + std::to_string(p.aspectRatio) + " is not a positive number");
      return;
    }
    out.yfov_rad = p.yfov;
    out.aspect_ratio = p.aspectRatio;
    out.znear_m = p.znear;
    out.zfar_m = p.zfar;
  } else if (cam.type == "orthographic") {
    out.orthographic = true;
    out.znear_m = cam.orthographic.znear;
    out.zfar_m = cam.orthographic.zfar;
  } else {
    skip("camera type " + Quote(cam.type) + " is neither perspective nor orthographic");
    return;
  }
  const Eigen::Matrix3d linear = world.topLeftCorner<3, 3>();
  if (!(linear.determinant() > 1e-12)) {
    skip("the node's transform mirrors or collapses space, which no camera pose can");
    return;
  }
  Eigen::Matrix3d r = linear;
  for (int c = 0; c < 3; ++c) r.col(c).normalize();
  if (!(r.transpose() * r).isIdentity(1e-6)) {
    Warn(where + ": the node's transform shears (non-uniform scale under a rotation); its orientation is approximated");
  }
  if (animated) Warn(where + ": is animated; cameras are loaded at their rest pose");
  out.cam_from_world = CamFromWorldFromGltfCameraNode(world);
  scene_.cameras.push_back(std::move(out));
}

std::string Loader::NodeLabel(int node_index) const {
  const std::string& name = model_.nodes[node_index].name;
  return "node " + std::to_string(node_index) + NameSuffix(name);
}

// 1, 2, ... for each instance (a mesh node, or one instance of an instanced node); 0 after 65535.
uint16_t Loader::NextInstanceId() {
  if (next_instance_ <= 65535) return uint16_t(next_instance_++);
  if (!instance_overflow_warned_) {
    instance_overflow_warned_ = true;
    Warn("more than 65535 mesh nodes or instances: further ones get instance id 0");
  }
  return 0;
}

void Loader::AddMeshInstance(int node_index, const Eigen::Matrix4d& world, ClassTag node_cls) {
  const tinygltf::Node& node = model_.nodes[node_index];
  if (size_t(node.mesh) >= model_.meshes.size()) Fail("node " + std::to_string(node_index) + ": mesh " + std::to_string(node.mesh) + " out of range");
  std::vector<Placement> placements = GpuInstances(node_index);
  if (placements.empty()) placements.push_back({});
  for (Placement& p : placements) p.instance_id = NextInstanceId();
  const tinygltf::Mesh& mesh = model_.meshes[node.mesh];
  const ClassTag mesh_cls = mesh_class_[node.mesh] ? mesh_class_[node.mesh] : node_cls;
  const std::vector<double> morph_weights = RestMorphWeights(node_index);
  for (size_t p = 0; p < mesh.primitives.size(); ++p) {
    AddPrimitive(node_index, node.mesh, int(p), world, mesh_cls, placements, morph_weights);
  }
}

}  // namespace rigsim::gltf
