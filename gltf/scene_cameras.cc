#include "gltf/scene_cameras.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>
#include <stdexcept>

namespace rigsim {
namespace {

std::string Quote(const std::string& s) { return "'" + s + "'"; }

// Camera names become folder names in a dataset (render refuses separators, "." and ".."; a
// blank name makes a folder hard to see or type).
std::string FileSafeName(const SceneCamera& c) {
  std::string name = c.name;
  for (char& ch : name) {
    if (ch == '/' || ch == '\\') ch = '_';
  }
  const bool blank = name.find_first_not_of(" \t\n\v\f\r") == std::string::npos;
  if (blank || name == "." || name == "..") name = "camera" + std::to_string(c.node);
  return name;
}

// Names that differ only in letter case are one folder on case-insensitive file systems (macOS,
// Windows by default), so they count as repeats.
std::string FolderKey(std::string name) {
  for (char& ch : name) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  return name;
}

}  // namespace

SceneCameraRig RigFromSceneCameras(const Scene& scene, int width, int height) {
  if (width < 16 || height < 16) {
    throw std::invalid_argument("cameras from " + scene.source + ": image size " + std::to_string(width) + "x" +
                                std::to_string(height) + " is below 16x16");
  }
  SceneCameraRig out;
  std::vector<const SceneCamera*> perspective;
  std::string orthographic_names;
  for (const SceneCamera& c : scene.cameras) {
    if (c.orthographic) {
      out.warnings.push_back("camera " + Quote(c.name) + " (node " + std::to_string(c.node) +
                             ") is orthographic; only perspective cameras can be rig cameras, skipped");
      orthographic_names += (orthographic_names.empty() ? "" : ", ") + Quote(c.name);
    } else {
      perspective.push_back(&c);
    }
  }
  if (perspective.empty()) {
    std::string why;
    if (!orthographic_names.empty()) why = "orthographic cameras cannot be rig cameras: " + orthographic_names;
    if (scene.skipped_camera_nodes > 0) {
      why += (why.empty() ? "" : "; ") + std::to_string(scene.skipped_camera_nodes) +
             " camera node(s) skipped by the loader; its warnings say why";
    }
    throw std::runtime_error(scene.source + ": no perspective camera in the loaded scene (" +
                             (why.empty() ? "the file places no camera on its nodes" : why) + ")");
  }

  const Rigid3d rig_from_world = perspective.front()->cam_from_world;
  const Rigid3d world_from_rig = rig_from_world.Inverse();
  const double image_aspect = double(width) / height;
  std::set<std::string> used;  // FolderKey of the names given so far
  for (const SceneCamera* c : perspective) {
    const std::string wanted = FileSafeName(*c);
    std::string name = wanted;
    // A repeat gets "_<node>", and again if that name is taken too.
    while (!used.insert(FolderKey(name)).second) name.append("_").append(std::to_string(c->node));
    if (name != wanted) {
      out.warnings.push_back("camera name " + Quote(wanted) + " repeats (letter case aside, as folder names on macOS and "
                             "Windows); the camera on node " + std::to_string(c->node) + " is called " + Quote(name));
    }
    const double tan_half = std::tan(0.5 * c->yfov_rad);
    const double aspect = c->aspect_ratio > 0 ? c->aspect_ratio : image_aspect;
    if (c->aspect_ratio > 0 && std::abs(aspect / image_aspect - 1.0) > 1e-3) {
      out.warnings.push_back("camera " + Quote(name) + ": the file's aspectRatio " + std::to_string(aspect) +
                             " differs from the image's " + std::to_string(image_aspect) +
                             "; pixels are not square (fx != fy) so that the image shows the file's field of view "
                             "(for square pixels use an image size of that ratio, e.g. " + std::to_string(width) + "x" +
                             std::to_string(std::max(1L, std::lround(width / aspect))) + ")");
    }
    const double fy = 0.5 * height / tan_half;
    const double fx = 0.5 * width / (aspect * tan_half);
    const Camera camera(CameraModelId::kPinhole, width, height, {fx, fy, 0.5 * (width - 1), 0.5 * (height - 1)});
    out.rig.cameras.push_back(RigCamera{name, camera, c->cam_from_world * world_from_rig, 0.0});
  }
  out.frames.frames.push_back(Frame{"000000", rig_from_world, 0.0});
  out.frames.scene = std::filesystem::path(scene.source).filename().string();
  return out;
}

}  // namespace rigsim
