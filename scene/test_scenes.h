// Small scenes the tests of scene posing (scene/scene_pose_test.cc) and of rendering animated
// scenes (renderer/animated_render_test.cc) share. Header-only, for tests.
#pragma once

#include <Eigen/Core>

#include "scene/scene.h"

namespace rigsim {

// A unit cube (node frame, centred on the origin) carried by node 0, which moves along x from
// (-1, 0, 6) at t = 0 to (1, 0, 6) at t = 1 (LINEAR). World = the camera frame of an identity pose.
inline Scene AnimatedBoxScene(AnimationInterpolation interpolation = AnimationInterpolation::kLinear) {
  Scene scene;
  scene.source = "animated box";
  SceneNode node;
  node.name = "carrier";
  node.translation = Eigen::Vector3d(-1, 0, 6);
  scene.nodes.push_back(node);
  AnimationChannel ch;
  ch.node = 0;
  ch.path = AnimationPath::kTranslation;
  ch.interpolation = interpolation;
  ch.times_s = {0.0, 1.0};
  ch.values = {Eigen::Vector4d(-1, 0, 6, 0), Eigen::Vector4d(1, 0, 6, 0)};
  scene.animation_channels.push_back(ch);
  SceneMesh box;
  box.name = "box";
  box.class_id = 26;  // car
  box.instance_id = 5;
  box.node = 0;
  for (int c = 0; c < 8; ++c) box.local_positions.emplace_back(c & 1 ? 0.5f : -0.5f, c & 2 ? 0.5f : -0.5f, c & 4 ? 0.5f : -0.5f);
  box.indices = {0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1, 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3};
  for (const Eigen::Vector3f& p : box.local_positions) box.positions.push_back(p + Eigen::Vector3f(-1, 0, 6));  // rest pose
  scene.meshes.push_back(box);
  return scene;
}

}  // namespace rigsim
