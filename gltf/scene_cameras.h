// glTF cameras as rig cameras: the perspective cameras a scene file places on its nodes become a
// rig (PINHOLE cameras) plus the rig's pose in the world (one frame), so that rendering the rig
// reproduces the views the file's cameras define.
//
// Conventions:
//  - Rig frame = the first perspective camera's frame (file order = node index, as
//    Scene::cameras is sorted): its cam_from_rig is the identity and frame 0's rig_from_world is
//    its cam_from_world; every other camera's cam_from_rig = cam_from_world * world_from_rig.
//    Poses come from SceneCamera::cam_from_world, converted from glTF's -Z-forward, +Y-up frame
//    once, by CamFromWorldFromGltfCameraNode (geometry/rigid3.h).
//  - Intrinsics for the requested width x height: the principal point at the image centre
//    ((w-1)/2, (h-1)/2 in OpenCV pixels), fy = (h/2) / tan(yfov/2) and fx = (w/2) / (a * tan(yfov/2))
//    with a = the file's aspectRatio, or w/h when the file gives none. So the image spans glTF's
//    view volume exactly; when the file's aspect ratio differs from w/h the pixels are not square
//    (fx != fy), which a warning says.
#pragma once

#include <string>
#include <vector>

#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "scene/scene.h"

namespace rigsim {

struct SceneCameraRig {
  Rig rig;                            // one PINHOLE camera per perspective camera, named after its node
  FramesFile frames;                  // one frame "000000" at time 0 with the rig's rig_from_world
  std::vector<std::string> warnings;  // orthographic cameras skipped, non-square pixels, renamed cameras
};

// Throws std::invalid_argument for an image size below 16x16 and std::runtime_error starting with
// scene.source when the scene has no perspective camera (naming any orthographic ones and counting
// the camera nodes the loader skipped).
SceneCameraRig RigFromSceneCameras(const Scene& scene, int width, int height);

}  // namespace rigsim
