#include "rigs/rig_params.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "common/did_you_mean.h"

namespace rigsim {

using Json = nlohmann::ordered_json;

namespace {

std::string G(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

ParamSpec Number(const char* name, Json def, double min, double max, std::string help) {
  return {name, ParamSpec::Kind::kNumber, std::move(def), {}, min, max, std::move(help)};
}
ParamSpec Int(const char* name, Json def, double min, double max, std::string help) {
  return {name, ParamSpec::Kind::kInt, std::move(def), {}, min, max, std::move(help)};
}
ParamSpec Text(const char* name, Json def, std::string help) {
  return {name, ParamSpec::Kind::kText, std::move(def), {}, 0, 0, std::move(help)};
}
ParamSpec Choice(const char* name, Json def, std::vector<std::string> choices, std::string help) {
  return {name, ParamSpec::Kind::kChoice, std::move(def), std::move(choices), 0, 0, std::move(help)};
}

std::vector<RigParam> MakeRigParams() {
  using G_ = RigParamGroup;
  const std::string hfov_defaults = "ring " + G(RingRigOptions{}.hfov_deg) + ", stereo " + G(StereoRigOptions{}.hfov_deg) +
                                    ", wide-baseline " + G(WideBaselineRigOptions{}.hfov_deg) + ", surround front " +
                                    G(SurroundRigOptions{}.front_hfov_deg);
  const std::string baseline_defaults = G(StereoRigOptions{}.baseline_m) + " and " + G(WideBaselineRigOptions{}.baseline_m);
  return {
      // The rig: its type, the options of each type, its lenses.
      {Choice("rig", "ring", NamesOf(kAllRigTypes, RigTypeName),
              "rig type (as rigsim make-rig builds it); file: the cameras of rig_file"),
       G_::kRig, "type,--type", true, {}, [](const Json& v, RigSpec& s) { s.type = RigTypeFromName(v.get<std::string>()); }},
      {Text("rig_file", nullptr,
            "rig file: a rig.json (as make-rig writes it) whose cameras, intrinsics and cam_from_rig, make the rig, "
            "or another tool's calibration (Kalibr camchain.yaml, COLMAP rigs.txt or rig_config.json, DGP calibration, "
            "nuScenes calibrated_sensor.json); the options of the preset types, image size and lens do not apply to it"),
       G_::kRig, "", true, {}, [](const Json& v, RigSpec& s) { s.rig_file = v.get<std::string>(); }},
      {Int("cameras", 4, 1, 64, "ring: number of cameras"), G_::kRig, "", true, {},
       [](const Json& v, RigSpec& s) { s.ring.num_cameras = v.get<int>(); }},
      {Number("overlap", nullptr, 0, 99,
              "ring: overlap of neighbours (percent, the smaller of the two directions): the ground truth where the "
              "rig stands in a scene, else at infinity; 0: none at any depth; unset: spacing"),
       G_::kRig, "", true, {}, [](const Json& v, RigSpec& s) { s.overlap_percent = v.get<double>(); }},
      {Number("spacing", 60.0, 1, 180, "ring: yaw between neighbours (deg), when overlap is unset"), G_::kRig, "", true, {},
       [](const Json& v, RigSpec& s) { s.ring.yaw_spacing_deg = v.get<double>(); }},
      {Number("radius", 0.5, 0, 100, "ring: radius (m)"), G_::kRig, "", true, {},
       [](const Json& v, RigSpec& s) { s.ring.radius_m = v.get<double>(); }},
      {Number("baseline", nullptr, 0.01, 100,
              "stereo, wide-baseline: distance between the cameras (m); unset: " + baseline_defaults),
       G_::kRig, "", true, {}, [](const Json& v, RigSpec& s) { s.baseline_m = v.get<double>(); }},
      {Number("convergence", 30.0, -89, 169, "wide-baseline: angle between the optical axes (deg)"), G_::kRig, "", true, {},
       [](const Json& v, RigSpec& s) { s.wide.convergence_deg = v.get<double>(); }},
      {Number("hfov", nullptr, 10, 170,
              "horizontal field of view of the perspective lenses (deg); unset: the type's own (" + hfov_defaults + ")"),
       G_::kRig, "", true, {}, [](const Json& v, RigSpec& s) { s.hfov_deg = v.get<double>(); }},
      {Choice("lens", "preset", NamesOf(kAllLensKinds, LensKindName),
              "preset: the rig type's own lenses (ring: cam1 barrel-distorted); pinhole, opencv (k1 = distortion, "
              "k2 = -0.24 k1) or fisheye (Kannala-Brandt over fisheye_fov): every camera"),
       G_::kRig, "", true, {}, [](const Json& v, RigSpec& s) { s.lens.kind = LensKindFromName(v.get<std::string>()); }},
      {Number("distortion", -0.25, -1, 1, "opencv lens: k1 (negative: barrel)"), G_::kRig, "--distortion,--lens-k1", true, {},
       [](const Json& v, RigSpec& s) { s.lens.k1 = v.get<double>(); }},
      {Number("fisheye_fov", 190.0, 60, 240,
              "fisheye lens, and the surround rig's side cameras: horizontal field of view (deg)"),
       G_::kRig, "--fisheye-fov,--side-fov", true, {}, [](const Json& v, RigSpec& s) {
         s.lens.fisheye_fov_deg = v.get<double>();
         s.surround.side_fov_deg = v.get<double>();
       }},
      {Number("lens_residual", 0.0, 0, LensResidualOptions::kMaxCornerPx,
              "render each camera through a richer lens than its model: the lens has the radial terms the model "
              "lacks (PINHOLE: k1, k2; OPENCV: k3; drawn from the seed), sized so that the model fitted to it, which "
              "rig.json keeps and the calibrator is given, misses it by this much at the image corners (px); 0 = none"),
       G_::kRig, "", true, {}, [](const Json& v, RigSpec& s) { s.lens_residual.corner_px = v.get<double>(); }},
      {Int("distorted", nullptr, -1, 63,
           "ring: index of the camera with barrel distortion (k1, k2; -1 = none); unset: cam1 from two cameras on"),
       G_::kRig, "", false, {}, [](const Json& v, RigSpec& s) { s.distorted_camera = v.get<int>(); }},
      {Number("k1", -0.25, -1, 1, "ring: the distorted camera's OPENCV k1"), G_::kRig, "", false, {},
       [](const Json& v, RigSpec& s) { s.ring.k1 = v.get<double>(); }},
      {Number("k2", 0.06, -1, 1, "ring: the distorted camera's OPENCV k2"), G_::kRig, "", false, {},
       [](const Json& v, RigSpec& s) { s.ring.k2 = v.get<double>(); }},
      {Number("vehicle", 4.0, 0, 100, "surround: distance between the front and back cameras (m)"), G_::kRig, "", false, {},
       [](const Json& v, RigSpec& s) { s.surround.length_m = v.get<double>(); }},
      // How it renders.
      {Int("width", 1280, 16, 16384, "image width (px)"), G_::kImage, "", true, 640,
       [](const Json& v, RigSpec& s) { s.width = v.get<int>(); }},
      {Int("height", 720, 16, 16384, "image height (px)"), G_::kImage, "", true, 360,
       [](const Json& v, RigSpec& s) { s.height = v.get<int>(); }},
      // Mounting errors.
      {Number("jitter_deg", 0.0, 0, 180, "random mounting error: rotation up to this (deg)"), G_::kMounting, "", false, {},
       [](const Json& v, RigSpec& s) { s.perturbation.rotation_deg = v.get<double>(); }},
      {Number("jitter_m", 0.0, 0, 100, "random mounting error: translation up to this (m)"), G_::kMounting, "", false, {},
       [](const Json& v, RigSpec& s) { s.perturbation.translation_m = v.get<double>(); }},
      // Its path over the frames, and where it stands.
      {Int("frames", 1, 1, 100000, "frames along the trajectory"), G_::kPath, "", true, 3,
       [](const Json& v, RigSpec& s) { s.trajectory.num_frames = v.get<int>(); }},
      {Choice("trajectory", "straight", NamesOf(kNamedTrajectoryKinds, TrajectoryKindName),
              "path of the rig over the frames: straight; circle (an arc, step apart); loop (one whole lap of the "
              "circle, back to the start); figure-eight (a lap turning left, then one turning right, for radius > 0); "
              "handheld (the arc, pitching and rolling by tilt: rotations about three axes, which fix every camera's "
              "place by hand-eye)"),
       G_::kPath, "", true, "circle",
       [](const Json& v, RigSpec& s) { s.trajectory.kind = TrajectoryKindFromName(v.get<std::string>()); }},
      {Number("step", 2.0, -100, 100,
              "distance travelled between frames (m); loop and figure-eight spread their frames over the whole path"),
       G_::kPath, "", true, {},
       [](const Json& v, RigSpec& s) { s.trajectory.step_m = v.get<double>(); }},
      {Number("frame_interval", 0.1, 0.001, 3600,
              "time between frames (s); with step it sets the rig's speed (2 m per 0.1 s: 20 m/s, 72 km/h)"),
       G_::kPath, "", true, {}, [](const Json& v, RigSpec& s) { s.trajectory.frame_interval_s = v.get<double>(); }},
      {Number("circle_radius", 10.0, -10000, 10000,
              "circle, loop, figure-eight, handheld: radius of the path (m; > 0 turns left first, < 0 right)"),
       G_::kPath, "", true, 12.0, [](const Json& v, RigSpec& s) { s.trajectory.circle_radius_m = v.get<double>(); }},
      {Number("tilt", 10.0, 0, 45,
              "handheld: amplitude of the pitch and roll (deg), swinging over " + G(kHandheldPitchWavelengthM) + " and " +
                  G(kHandheldRollWavelengthM) + " m of the path"),
       G_::kPath, "", true, {}, [](const Json& v, RigSpec& s) { s.trajectory.tilt_deg = v.get<double>(); }},
      {Number("heading", 0.0, -360, 360, "rig heading at frame 0 without a scene (deg; 0 = world -Z, 90 = world +X)"),
       G_::kPath, "", false, {}, [](const Json& v, RigSpec& s) { s.trajectory.heading_deg = v.get<double>(); }},
      {Number("clearance", 2.0, 0, 50,
              "placement in a scene: no surface closer along a camera axis (m); road: along the lane ahead of the path"),
       G_::kPath, "", false, {}, [](const Json& v, RigSpec& s) { s.placement.min_clearance_m = v.get<double>(); }},
      {Choice("placement", "structure", NamesOf(kAllPlacementModes, PlacementModeName),
              "how the rig is placed in a scene: structure (a free spot on the ground where every camera sees "
              "structure) or road (a vehicle in its lane: on the surface labelled road, heading along the road, right "
              "of its centre line where it is wide enough for two lanes; the whole path stays on the road)"),
       G_::kPath, "", true, {},
       [](const Json& v, RigSpec& s) { s.placement.mode = PlacementModeFromName(v.get<std::string>()); }},
      {Number("rig_height", PlacementOptions{}.height_m, 0.05, 100,
              "placement in a scene: height of the rig's origin above the ground (m); a rig whose frame is its first "
              "camera's (an imported rig) has that camera at this height"),
       G_::kPath, "", false, {}, [](const Json& v, RigSpec& s) { s.placement.height_m = v.get<double>(); }},
  };
}

}  // namespace

std::string RigParam::Flags() const {
  if (!flags.empty()) return flags;
  std::string f = "--" + spec.name;
  for (char& c : f) c = c == '_' ? '-' : c;
  return f;
}

ParamSpec RigParam::SweepSpec() const {
  ParamSpec s = spec;
  if (sweep_default) s.default_value = *sweep_default;
  return s;
}

const std::vector<RigParam>& RigParams() {
  static const std::vector<RigParam> params = MakeRigParams();
  return params;
}

RigSpec RigSpecFromParams(const Json& values) {
  if (!values.is_object()) throw std::invalid_argument("rig parameters: expected an object of names and values");
  std::vector<std::string> names;
  for (const RigParam& p : RigParams()) names.push_back(p.spec.name);
  for (const auto& [name, value] : values.items()) {
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      throw std::invalid_argument("unknown rig parameter '" + name + "'" + DidYouMean(name, names));
    }
  }
  RigSpec spec;
  for (const RigParam& p : RigParams()) {
    Json v;
    try {
      v = CheckParamValue(p.spec, values.contains(p.spec.name) ? values[p.spec.name] : p.spec.default_value);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(p.spec.name + ": " + e.what());
    }
    if (!v.is_null()) p.apply(v, spec);
  }
  if (!spec.rig_file.empty() && spec.type != RigType::kFile) {
    throw std::invalid_argument("rig_file: applies to rig file only (the rig is " + std::string(RigTypeName(spec.type)) +
                                ")");
  }
  return spec;
}

}  // namespace rigsim
