#include "rigs/rig_presets.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/param_spec.h"
#include "geometry/camera_models.h"
#include "rigs/rng.h"

namespace rigsim {
namespace {

[[noreturn]] void Fail(const std::string& what, const std::string& why) { throw std::invalid_argument(what + ": " + why); }

void CheckImage(const std::string& what, int width, int height) {
  if (width < 16 || height < 16) Fail(what, "image size must be at least 16x16");
}

// A perspective camera with the principal point at the centre whose side edges image the rays at
// +-hfov/2, with OPENCV radial distortion (k1, k2) or none.
Camera PerspectiveCamera(const std::string& what, int width, int height, double hfov_deg, double k1 = 0.0, double k2 = 0.0) {
  if (k1 == 0.0 && k2 == 0.0) return Camera::PinholeFromHorizontalFov(width, height, hfov_deg);
  const double r = std::tan(DegToRad(0.5 * hfov_deg));  // normalised radius at the image's side edge
  // Where the OPENCV model puts that radius (no tangential terms): the focal length maps it to the edge.
  const double distortion[4] = {k1, k2, 0.0, 0.0};
  double rd = 0.0, unused = 0.0;
  DistortNormalized(CameraModelId::kOpenCV, distortion, r, 0.0, &rd, &unused);
  if (!(rd > 0)) Fail(what, "distortion folds inside the field of view");
  const double f = 0.5 * width / rd;
  return Camera(CameraModelId::kOpenCV, width, height, {f, f, 0.5 * (width - 1), 0.5 * (height - 1), k1, k2, 0.0, 0.0});
}

// Kannala-Brandt fisheye whose side edges image the rays at +-fov/2 (which may exceed 90 deg).
Camera FisheyeCamera(int width, int height, double fov_deg) {
  const double k[4] = {0.02, -0.004, 0.0005, 0.0};  // mild, monotonic far beyond 100 deg
  const double theta_d = FisheyeDistortedTheta(k, DegToRad(0.5 * fov_deg));
  const double f = 0.5 * width / theta_d;
  return Camera(CameraModelId::kOpenCVFisheye, width, height, {f, f, 0.5 * (width - 1), 0.5 * (height - 1), k[0], k[1], k[2], k[3]});
}

// rig_from_cam for a camera at `centre_in_rig`, turned right by `yaw_deg` and down by `pitch_deg`.
Rigid3d RigFromCam(const Eigen::Vector3d& centre_in_rig, double yaw_deg, double pitch_deg = 0.0) {
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(DegToRad(yaw_deg), Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(-DegToRad(pitch_deg), Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  return Rigid3d(r, centre_in_rig);
}

void AddCamera(Rig& rig, const std::string& name, const Camera& cam, const Rigid3d& cam_from_rig) {
  rig.cameras.push_back(RigCamera{name, cam, cam_from_rig, 0.0});
}

}  // namespace

// ---- Lenses --------------------------------------------------------------------------------------

void LensOptions::Check() const {
  if (!(k1 > -1 && k1 < 1)) Fail("lens", "k1 must be in (-1, 1)");
  if (!(fisheye_fov_deg > 10 && fisheye_fov_deg <= 240)) Fail("lens", "fisheye_fov_deg must be in (10, 240]");
}

std::string_view LensKindName(LensOptions::Kind kind) {
  switch (kind) {
    case LensOptions::Kind::kPreset: return "preset";
    case LensOptions::Kind::kPinhole: return "pinhole";
    case LensOptions::Kind::kOpenCV: return "opencv";
    case LensOptions::Kind::kFisheye: return "fisheye";
  }
  return "preset";
}

LensOptions::Kind LensKindFromName(std::string_view name) {
  for (LensOptions::Kind k : kAllLensKinds) {
    if (LensKindName(k) == name) return k;
  }
  throw std::invalid_argument("unknown lens '" + std::string(name) + "': give " + JoinNames(NamesOf(kAllLensKinds, LensKindName)));
}

Camera LensCamera(const LensOptions& lens, int width, int height, double hfov_deg) {
  lens.Check();
  switch (lens.kind) {
    case LensOptions::Kind::kPinhole: return PerspectiveCamera("lens", width, height, hfov_deg);
    case LensOptions::Kind::kOpenCV: return PerspectiveCamera("lens", width, height, hfov_deg, lens.k1, -0.24 * lens.k1);
    case LensOptions::Kind::kFisheye: {
      const Camera cam = FisheyeCamera(width, height, lens.fisheye_fov_deg);
      if (cam.max_valid_angle() < DegToRad(0.5 * lens.fisheye_fov_deg) - 1e-9) {
        Fail("lens", "the fisheye lens cannot image " + std::to_string(lens.fisheye_fov_deg) + " deg");
      }
      return cam;
    }
    case LensOptions::Kind::kPreset: break;
  }
  Fail("lens", "the preset lens is the rig type's own: no single camera");
}

// ---- Ring ---------------------------------------------------------------------------------------

void RingRigOptions::Check() const {
  const std::string w = "ring rig";
  if (num_cameras < 1) Fail(w, "needs at least one camera");
  if (!(hfov_deg > 1 && hfov_deg < 179)) Fail(w, "hfov_deg must be in (1, 179) for perspective cameras");
  if (!(radius_m >= 0)) Fail(w, "radius_m must be >= 0");
  CheckImage(w, width, height);
  if (distorted_camera >= num_cameras) Fail(w, "distorted_camera is not a camera index");
  if (!(target_overlap < 1)) Fail(w, "target_overlap must be < 1 (a fraction; <= 0 = use yaw_spacing_deg)");
  if (target_overlap > 0 && num_cameras < 2) Fail(w, "target_overlap needs at least two cameras");
}

Rigid3d RingCamFromRig(double radius_m, double yaw_deg) {
  const double yaw = DegToRad(yaw_deg);
  const Eigen::Vector3d centre_in_rig = radius_m * Eigen::Vector3d(std::sin(yaw), 0.0, std::cos(yaw));
  return RigFromCam(centre_in_rig, yaw_deg).Inverse();
}

Rig MakeRingRig(const RingRigOptions& o) {
  o.Check();
  const double spacing = o.target_overlap > 0 ? RingSpacingForOverlap(o, o.target_overlap) : o.yaw_spacing_deg;
  Rig rig;
  for (int i = 0; i < o.num_cameras; ++i) {
    const double yaw_deg = (i - 0.5 * (o.num_cameras - 1)) * spacing;
    const Camera cam = o.lens.kind != LensOptions::Kind::kPreset ? LensCamera(o.lens, o.width, o.height, o.hfov_deg)
                       : i == o.distorted_camera ? PerspectiveCamera("ring rig", o.width, o.height, o.hfov_deg, o.k1, o.k2)
                                                 : PerspectiveCamera("ring rig", o.width, o.height, o.hfov_deg);
    char name[32];
    std::snprintf(name, sizeof(name), "cam%d", i);
    AddCamera(rig, name, cam, RingCamFromRig(o.radius_m, yaw_deg));
  }
  return rig;
}

double AngularOverlap(const Camera& a, const Camera& b, const Eigen::Matrix3d& b_from_a_rotation) {
  const int nx = 128, ny = std::max(8, int(std::lround(128.0 * a.height() / a.width())));
  int valid = 0, seen = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const Eigen::Vector2d px((i + 0.5) * a.width() / nx - 0.5, (j + 0.5) * a.height() / ny - 0.5);
      const std::optional<Eigen::Vector3d> ray = a.CamFromImg(px);
      if (!ray) continue;
      ++valid;
      const std::optional<Eigen::Vector2d> pb = b.ImgFromCam(b_from_a_rotation * *ray);
      if (pb && b.IsInImage(*pb)) ++seen;
    }
  }
  return valid ? double(seen) / valid : 0.0;
}

double RingSpacingForOverlap(const RingRigOptions& options, double overlap) {
  RingRigOptions o = options;
  o.target_overlap = 0.0;
  if (o.num_cameras < 2) Fail("ring rig", "target_overlap needs at least two cameras");
  auto mean_overlap = [&](double spacing) {
    o.yaw_spacing_deg = spacing;
    const Rig rig = MakeRingRig(o);
    double sum = 0;
    int n = 0;
    for (size_t i = 0; i + 1 < rig.cameras.size(); ++i) {
      const RigCamera& a = rig.cameras[i];
      const RigCamera& b = rig.cameras[i + 1];
      const Eigen::Matrix3d b_from_a = (*b.cam_from_rig * a.cam_from_rig->Inverse()).RotationMatrix();
      // The smaller of the two directions, the figure render and calibrate report; for none at all,
      // neither direction may share anything.
      const double ab = AngularOverlap(a.camera, b.camera, b_from_a);
      const double ba = AngularOverlap(b.camera, a.camera, b_from_a.transpose());
      sum += overlap > 0 ? std::min(ab, ba) : std::max(ab, ba);
      ++n;
    }
    return sum / n;
  };
  const double fov = o.lens.kind == LensOptions::Kind::kFisheye ? o.lens.fisheye_fov_deg : o.hfov_deg;
  double lo = 0.0, hi = std::min(179.0, fov * 1.5);
  if (mean_overlap(hi) > overlap) Fail("ring rig", "target overlap is below what a spacing of " + std::to_string(hi) + " deg gives");
  if (mean_overlap(lo) < overlap) Fail("ring rig", "target overlap is not reachable");
  for (int it = 0; it < 24; ++it) {
    const double mid = 0.5 * (lo + hi);
    (mean_overlap(mid) > overlap ? lo : hi) = mid;
  }
  // None at all: the side of the bracket where neighbours share nothing.
  return overlap > 0 ? 0.5 * (lo + hi) : hi;
}

// ---- Stereo, surround, wide baseline ---------------------------------------------------------------

void StereoRigOptions::Check() const {
  if (!(baseline_m > 0)) Fail("stereo rig", "baseline_m must be > 0");
  if (!(hfov_deg > 1 && hfov_deg < 179)) Fail("stereo rig", "hfov_deg must be in (1, 179)");
  CheckImage("stereo rig", width, height);
}

Rig MakeStereoRig(const StereoRigOptions& o) {
  o.Check();
  Rig rig;
  const Camera cam = o.lens.kind != LensOptions::Kind::kPreset ? LensCamera(o.lens, o.width, o.height, o.hfov_deg)
                                                                : PerspectiveCamera("stereo rig", o.width, o.height, o.hfov_deg);
  AddCamera(rig, "left", cam, RigFromCam(Eigen::Vector3d(-0.5 * o.baseline_m, 0, 0), 0.0).Inverse());
  AddCamera(rig, "right", cam, RigFromCam(Eigen::Vector3d(0.5 * o.baseline_m, 0, 0), 0.0).Inverse());
  return rig;
}

void SurroundRigOptions::Check() const {
  const std::string w = "surround rig";
  if (!(length_m >= 0) || !(width_m >= 0)) Fail(w, "length_m and width_m must be >= 0");
  if (!(front_hfov_deg > 1 && front_hfov_deg < 170)) Fail(w, "front_hfov_deg must be in (1, 170)");
  if (!(back_hfov_deg > 1 && back_hfov_deg < 170)) Fail(w, "back_hfov_deg must be in (1, 170)");
  if (!(side_fov_deg > 10 && side_fov_deg <= 220)) Fail(w, "side_fov_deg must be in (10, 220]");
  if (!(std::abs(side_pitch_deg) <= 60)) Fail(w, "side_pitch_deg must be within +-60");
  CheckImage(w, width, height);
}

Rig MakeSurroundRig(const SurroundRigOptions& o) {
  o.Check();
  Rig rig;
  if (o.lens.kind != LensOptions::Kind::kPreset) {
    const Camera cam = LensCamera(o.lens, o.width, o.height, o.front_hfov_deg);
    AddCamera(rig, "front", cam, RigFromCam(Eigen::Vector3d(0, 0, 0.5 * o.length_m), 0.0).Inverse());
    AddCamera(rig, "right", cam, RigFromCam(Eigen::Vector3d(0.5 * o.width_m, 0, 0), 90.0, o.side_pitch_deg).Inverse());
    AddCamera(rig, "back", cam, RigFromCam(Eigen::Vector3d(0, 0, -0.5 * o.length_m), 180.0).Inverse());
    AddCamera(rig, "left", cam, RigFromCam(Eigen::Vector3d(-0.5 * o.width_m, 0, 0), -90.0, o.side_pitch_deg).Inverse());
    return rig;
  }
  const Camera fisheye = FisheyeCamera(o.width, o.height, o.side_fov_deg);
  if (fisheye.max_valid_angle() < DegToRad(0.5 * o.side_fov_deg) - 1e-9) {
    Fail("surround rig", "the fisheye lens cannot image " + std::to_string(o.side_fov_deg) + " deg");
  }
  AddCamera(rig, "front", PerspectiveCamera("surround rig", o.width, o.height, o.front_hfov_deg, -0.12, 0.02),
            RigFromCam(Eigen::Vector3d(0, 0, 0.5 * o.length_m), 0.0).Inverse());
  AddCamera(rig, "right", fisheye, RigFromCam(Eigen::Vector3d(0.5 * o.width_m, 0, 0), 90.0, o.side_pitch_deg).Inverse());
  AddCamera(rig, "back", PerspectiveCamera("surround rig", o.width, o.height, o.back_hfov_deg),
            RigFromCam(Eigen::Vector3d(0, 0, -0.5 * o.length_m), 180.0).Inverse());
  AddCamera(rig, "left", fisheye, RigFromCam(Eigen::Vector3d(-0.5 * o.width_m, 0, 0), -90.0, o.side_pitch_deg).Inverse());
  return rig;
}

void WideBaselineRigOptions::Check() const {
  if (!(baseline_m > 0)) Fail("wide-baseline rig", "baseline_m must be > 0");
  if (!(convergence_deg > -90 && convergence_deg < 170)) Fail("wide-baseline rig", "convergence_deg must be in (-90, 170)");
  if (!(hfov_deg > 1 && hfov_deg < 179)) Fail("wide-baseline rig", "hfov_deg must be in (1, 179)");
  CheckImage("wide-baseline rig", width, height);
}

Rig MakeWideBaselineRig(const WideBaselineRigOptions& o) {
  o.Check();
  Rig rig;
  const Camera cam = o.lens.kind != LensOptions::Kind::kPreset
                         ? LensCamera(o.lens, o.width, o.height, o.hfov_deg)
                         : PerspectiveCamera("wide-baseline rig", o.width, o.height, o.hfov_deg);
  AddCamera(rig, "cam0", cam, RigFromCam(Eigen::Vector3d(-0.5 * o.baseline_m, 0, 0), 0.5 * o.convergence_deg).Inverse());
  AddCamera(rig, "cam1", cam, RigFromCam(Eigen::Vector3d(0.5 * o.baseline_m, 0, 0), -0.5 * o.convergence_deg).Inverse());
  return rig;
}

void PerturbRig(Rig& rig, const RigPerturbation& p) {
  if (!(p.rotation_deg >= 0) || !(p.translation_m >= 0)) Fail("rig perturbation", "amounts must be >= 0");
  Rng rng(p.seed);
  for (RigCamera& c : rig.cameras) {
    if (!c.cam_from_rig) continue;
    // Draws one by one, z first (GCC's order for constructor arguments, last first): as arguments
    // their order would be the compiler's choice, and a seed must give the same rig everywhere.
    auto draw_vector = [&rng] {
      const double z = rng.Uniform(-1, 1), y = rng.Uniform(-1, 1), x = rng.Uniform(-1, 1);
      return Eigen::Vector3d(x, y, z);
    };
    Eigen::Vector3d axis = draw_vector();
    if (axis.norm() < 1e-9) axis = Eigen::Vector3d::UnitX();
    const double angle = DegToRad(p.rotation_deg) * rng.Uniform();
    Eigen::Vector3d dt = draw_vector();
    if (dt.norm() > 1) dt.normalize();
    const Rigid3d delta(Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized())), p.translation_m * dt);
    c.cam_from_rig = delta * *c.cam_from_rig;
  }
}

}  // namespace rigsim
