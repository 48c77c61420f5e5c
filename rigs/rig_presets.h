// Rig presets: ring, stereo, surround and wide-baseline rigs, and mounting errors.
//
// Rig frame: x right, y down, z forward (like a camera). Yaw turns a camera to the right
// (from +z towards +x) about the rig's y axis. Angles are degrees in options (user-facing),
// radians inside. Everything random takes an explicit seed.
#pragma once

#include <cstdint>
#include <string_view>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "geometry/rig.h"
#include "geometry/rigid3.h"

namespace rigsim {

// A lens for every camera of a rig, in place of its type's own (ring: pinhole with one camera
// barrel-distorted; surround: OPENCV front, fisheye sides, pinhole back). Perspective lenses take
// the rig's horizontal field of view; the fisheye its own.
struct LensOptions {
  enum class Kind { kPreset, kPinhole, kOpenCV, kFisheye };
  Kind kind = Kind::kPreset;
  double k1 = -0.25;               // kOpenCV: k1, and k2 = -0.24 k1 (the ring's distorted camera's shape)
  double fisheye_fov_deg = 190.0;  // kFisheye: horizontal field of view (Kannala-Brandt, > 180 ok)
  void Check() const;              // throws std::invalid_argument
};
inline constexpr LensOptions::Kind kAllLensKinds[] = {LensOptions::Kind::kPreset, LensOptions::Kind::kPinhole,
                                                     LensOptions::Kind::kOpenCV, LensOptions::Kind::kFisheye};
// "preset", "pinhole", "opencv", "fisheye".
std::string_view LensKindName(LensOptions::Kind kind);
// Throws std::invalid_argument naming the kinds when `name` is none of them.
LensOptions::Kind LensKindFromName(std::string_view name);
// The camera of `lens` (not kPreset) at this image size; perspective lenses see `hfov_deg`
// between the image's side edges, the fisheye `lens.fisheye_fov_deg`.
Camera LensCamera(const LensOptions& lens, int width, int height, double hfov_deg);

struct RingRigOptions {
  int num_cameras = 4;           // cameras on the ring, named cam0..cam{N-1} from left to right
  double yaw_spacing_deg = 60.0; // yaw between neighbours: at hfov 95, neighbours share about a third of their view
  double hfov_deg = 95.0;        // horizontal field of view of every camera (distorted ones too)
  double radius_m = 0.5;         // camera centres lie on this circle around the rig origin
  int width = 1280;
  int height = 720;
  int distorted_camera = 1;      // index of the camera with barrel distortion; -1 = none
  double k1 = -0.25;             // its OPENCV radial distortion
  double k2 = 0.06;
  // When in (0, 1): choose the yaw spacing so that neighbours share this fraction of their image
  // (overrides yaw_spacing_deg; see RingSpacingForOverlap). <= 0: use yaw_spacing_deg.
  double target_overlap = 0.0;
  LensOptions lens;              // every camera's, instead of pinhole and distorted_camera
  void Check() const;            // throws std::invalid_argument
};

// N cameras on a horizontal circle, facing outwards, centred on the rig's forward direction.
Rig MakeRingRig(const RingRigOptions& options);

// cam_from_rig of a ring camera on the circle of `radius_m`, facing outwards at `yaw_deg`.
Rigid3d RingCamFromRig(double radius_m, double yaw_deg);

// Fraction of camera a's pixels whose rays, seen from b (pure rotation, points at infinity),
// land inside b's image. The exact ground-truth overlap also depends on depth (parallax from the
// ring radius) and on how much sky a view sees; the renderer measures it (overlap.json).
double AngularOverlap(const Camera& a, const Camera& b, const Eigen::Matrix3d& b_from_a_rotation);

// Yaw spacing (deg) at which neighbouring ring cameras overlap by `overlap` (AngularOverlap, the
// smaller of the two directions, averaged over the neighbour pairs). 0: the smallest spacing at
// which neither direction of any neighbour pair shares a pixel. Throws when unreachable.
double RingSpacingForOverlap(const RingRigOptions& options, double overlap);

struct StereoRigOptions {
  double baseline_m = 0.12;  // distance between the two camera centres along the rig's x axis
  double hfov_deg = 80.0;    // horizontal field of view (pinhole)
  int width = 1280;
  int height = 720;
  LensOptions lens;          // both cameras', instead of pinhole
  void Check() const;
};
// "left" and "right", parallel optical axes along the rig's +z, centres at x = -+baseline/2.
Rig MakeStereoRig(const StereoRigOptions& options);

struct SurroundRigOptions {
  double length_m = 4.0;         // front and back cameras at z = +-length/2 (vehicle-like)
  double width_m = 1.8;          // side cameras at x = +-width/2
  double front_hfov_deg = 100.0; // front camera: OPENCV with mild barrel distortion
  double back_hfov_deg = 90.0;   // back camera: PINHOLE
  double side_fov_deg = 190.0;   // side cameras: OPENCV_FISHEYE, horizontal field of view (> 180 ok)
  double side_pitch_deg = 0.0;   // side cameras look down by this much (positive = down)
  int width = 1280;
  int height = 720;
  LensOptions lens;              // every camera's (perspective ones at front_hfov_deg), instead of the mix
  void Check() const;
};
// "front" (OPENCV), "right" (OPENCV_FISHEYE), "back" (PINHOLE), "left" (OPENCV_FISHEYE).
Rig MakeSurroundRig(const SurroundRigOptions& options);

struct WideBaselineRigOptions {
  double baseline_m = 2.0;       // distance between the two camera centres
  double convergence_deg = 30.0; // angle between the optical axes; each camera toes in by half
  double hfov_deg = 70.0;        // horizontal field of view (pinhole)
  int width = 1280;
  int height = 720;
  LensOptions lens;              // both cameras', instead of pinhole
  void Check() const;
};
// "cam0" at x = -baseline/2 and "cam1" at +baseline/2, both turned towards the rig's +z axis.
Rig MakeWideBaselineRig(const WideBaselineRigOptions& options);

// Mounting errors: every camera's cam_from_rig is perturbed by a random rotation of up to
// `rotation_deg` and a translation of up to `translation_m` (uniform, seeded).
struct RigPerturbation {
  double rotation_deg = 0.0;
  double translation_m = 0.0;
  uint64_t seed = 1;
};
void PerturbRig(Rig& rig, const RigPerturbation& perturbation);

}  // namespace rigsim
