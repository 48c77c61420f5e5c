// A rig: named cameras with intrinsics and (when known) their pose in the rig frame.
//
// rig.json (written by render, read by calibrate; a real-photo user writes it without poses):
// {
//   "cameras": [
//     { "name": "cam0", "model": "OPENCV", "width": 1280, "height": 720,
//       "params": [fx, fy, cx, cy, k1, k2, p1, p2],          // camera_models.h orders
//       "cam_from_rig": { "rotation_wxyz": [w, x, y, z], "translation": [x, y, z] },  // optional
//       "time_offset_s": 0.0,                                  // optional, capture delay
//       "readout_s": 0.0, "readout_direction": "top-to-bottom", // optional, rolling shutter
//       "exposure_s": 0.0,                                     // optional, motion blur
//       "render_lens": { "model": "FULL_OPENCV", "params": [...] } }  // optional, see below
//   ]
// }
// The three timing fields are written only when they differ from their defaults, so a rig
// without them reads and writes as before they existed. "render_lens" likewise: the lens the
// images were rendered through when it is not the camera's model (the real lens beside a user's
// calibration of it); the renderer and the ground truth use it, the calibrator never reads it.
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
  // Rolling shutter: the time from the first row read out to the row after the last; row r (in
  // readout order) is captured time_offset_s + r * readout_s / height after the frame's
  // timestamp. 0 = global shutter.
  double readout_s = 0.0;
  bool readout_bottom_to_top = false;    // readout order: top row first (false) or bottom row first
  // Each row integrates light over [t - exposure_s / 2, t + exposure_s / 2] around its capture
  // time t (motion blur in the colour image; ground truth is at t). 0 = instantaneous.
  double exposure_s = 0.0;
  // The lens the images are rendered through when it differs from `camera`, the model a user has
  // of it (same image size); unset: `camera` itself. The calibrator is given `camera` only.
  std::optional<Camera> render_lens = std::nullopt;

  // The lens the images are rendered through: render_lens, or the model when there is none.
  const Camera& RenderedCamera() const { return render_lens ? *render_lens : camera; }
  // Whether the camera's capture is spread over time (rolling shutter or exposure).
  bool CaptureSpansTime() const { return readout_s > 0 || exposure_s > 0; }
  // Seconds after the frame's timestamp at which image row `row` is captured (mid exposure).
  double RowTime(int row) const {
    const int h = camera.height();
    const int r = readout_bottom_to_top ? h - 1 - row : row;
    return time_offset_s + (h > 0 ? r * readout_s / h : 0.0);
  }
};

struct Rig {
  std::vector<RigCamera> cameras;
  // The rig's own vehicle: a glTF file beside rig.json (a plain file name) whose meshes are in the
  // rig frame turned to glTF's axes (procedural/ego_vehicle.h); "" = none. rig.json's optional
  // "ego_vehicle".
  std::string ego_vehicle;

  // Index of the camera with this name, or -1.
  int FindCamera(const std::string& name) const;
  bool HasAllPoses() const;
  // The cameras that have a cam_from_rig, in order: what the exports can place.
  Rig PosedCameras() const;
  // The rig as it is rendered: each camera's model replaced by its render lens (the renderer's and
  // the ground truth's rig; render_lens unset in the copy).
  Rig AsRendered() const;
};

// Parse / serialise. Errors throw std::runtime_error whose message starts with `source`
// (a file name) and says what is wrong and where.
Rig RigFromJsonText(const std::string& text, const std::string& source);
std::string RigToJsonText(const Rig& rig);

Rig ReadRig(const std::filesystem::path& path);
// Writes atomically (temporary file, then rename).
void WriteRig(const Rig& rig, const std::filesystem::path& path);

}  // namespace rigsim
