// A rig: named cameras with intrinsics and (when known) their pose in the rig frame.
//
// rig.json (written by render, read by calibrate; a real-photo user writes it without poses):
// {
//   "cameras": [
//     { "name": "cam0", "model": "OPENCV", "width": 1280, "height": 720,
//       "params": [fx, fy, cx, cy, k1, k2, p1, p2],          // camera_models.h orders
//       "cam_from_rig": { "rotation_wxyz": [w, x, y, z], "translation": [x, y, z] },  // optional
//       "time_offset_s": 0.0 }                                 // optional, capture delay
//   ]
// }
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "geometry/camera.h"
#include "geometry/rigid3.h"

namespace rigsim {

struct RigCamera {
  std::string name;
  Camera camera;
  std::optional<Rigid3d> cam_from_rig;  // unknown for a rig that is yet to be calibrated
  double time_offset_s = 0.0;            // capture time relative to the frame's timestamp
};

struct Rig {
  std::vector<RigCamera> cameras;

  // Index of the camera with this name, or -1.
  int FindCamera(const std::string& name) const;
  bool HasAllPoses() const;
  // The cameras that have a cam_from_rig, in order: what the exports can place.
  Rig PosedCameras() const;
};

// Parse / serialise. Errors throw std::runtime_error whose message starts with `source`
// (a file name) and says what is wrong and where.
Rig RigFromJsonText(const std::string& text, const std::string& source);
std::string RigToJsonText(const Rig& rig);

Rig ReadRig(const std::filesystem::path& path);
// Writes atomically (temporary file, then rename).
void WriteRig(const Rig& rig, const std::filesystem::path& path);

}  // namespace rigsim
