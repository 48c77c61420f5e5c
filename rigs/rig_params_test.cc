#include "rigs/rig_params.h"

#include <cmath>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

using Json = nlohmann::ordered_json;

// Every field of a spec that a rig parameter can reach, as text: two specs print alike exactly
// when they build the same rig on the same path.
std::string Describe(const RigSpec& s) {
  std::ostringstream o;
  o << RigTypeName(s.type) << " ring " << s.ring.num_cameras << " " << s.ring.yaw_spacing_deg << " " << s.ring.radius_m
    << " " << s.ring.k1 << " " << s.ring.k2 << " distorted " << s.distorted_camera.value_or(-99) << " stereo "
    << s.stereo.baseline_m << " surround " << s.surround.length_m << " " << s.surround.side_fov_deg << " wide "
    << s.wide.convergence_deg << " " << s.wide.baseline_m << " image " << s.width << "x" << s.height << " hfov "
    << s.hfov_deg.value_or(-1) << " baseline " << s.baseline_m.value_or(-1) << " lens " << LensKindName(s.lens.kind) << " "
    << s.lens.k1 << " " << s.lens.fisheye_fov_deg << " overlap " << s.overlap_percent.value_or(-1) << " jitter "
    << s.perturbation.rotation_deg << " " << s.perturbation.translation_m << " lens residual " << s.lens_residual.corner_px
    << " path "
    << TrajectoryKindName(s.trajectory.kind) << " " << s.trajectory.num_frames << " " << s.trajectory.step_m << " "
    << s.trajectory.circle_radius_m << " " << s.trajectory.heading_deg << " " << s.trajectory.tilt_deg << " every " << s.trajectory.frame_interval_s << " s clearance "
    << s.placement.min_clearance_m << " placement " << PlacementModeName(s.placement.mode) << " at "
    << s.placement.height_m << " m file " << s.rig_file;
  return o.str();
}

// A valid value other than the default, in the parameter's range.
Json OtherValue(const ParamSpec& p) {
  switch (p.kind) {
    case ParamSpec::Kind::kChoice:
      return p.choices.at(p.default_value == p.choices.at(0) ? 1 : 0);
    case ParamSpec::Kind::kText:
      return "elsewhere/rig.json";
    case ParamSpec::Kind::kInt:
      return p.default_value.is_null() ? Json(int64_t(p.min + 1)) : Json(p.default_value.get<int64_t>() + 1);
    default:
      return p.default_value.is_null() ? Json(0.5 * (p.min + p.max)) : Json(0.5 * (p.default_value.get<double>() + p.max));
  }
}

TEST(RigParams, TheirDefaultsAreRigSpecsDefaults) {
  EXPECT_EQ(Describe(RigSpecFromParams(Json::object())), Describe(RigSpec{}));
}

TEST(RigParams, NamesAndOptionsAreUniqueAndDefaultsPassTheirOwnCheck) {
  std::set<std::string> names, flags;
  for (const RigParam& p : RigParams()) {
    EXPECT_TRUE(names.insert(p.spec.name).second) << p.spec.name;
    EXPECT_TRUE(flags.insert(p.Flags()).second) << p.Flags();
    EXPECT_FALSE(p.spec.help.empty()) << p.spec.name;
    EXPECT_NO_THROW(CheckParamValue(p.spec, p.spec.default_value)) << p.spec.name;
    EXPECT_NO_THROW(CheckParamValue(p.SweepSpec(), p.SweepSpec().default_value)) << p.spec.name;
    ASSERT_NE(p.apply, nullptr) << p.spec.name;
  }
}

// A parameter whose value does not reach the spec would be an option that does nothing.
TEST(RigParams, EveryParameterReachesTheSpec) {
  const std::string defaults = Describe(RigSpecFromParams(Json::object()));
  for (const RigParam& p : RigParams()) {
    const Json value = OtherValue(p.spec);
    Json values = {{p.spec.name, value}};
    if (p.spec.name == "rig_file") values["rig"] = "file";  // it applies to that type only
    EXPECT_NE(Describe(RigSpecFromParams(values)), defaults) << p.spec.name << " = " << value;
  }
}

TEST(RigParams, TheSweepsDefaultsAreAnExplicitFewOfThem) {
  std::set<std::string> different;
  for (const RigParam& p : RigParams()) {
    if (p.sweep_default) different.insert(p.spec.name);
  }
  EXPECT_EQ(different, (std::set<std::string>{"width", "height", "frames", "trajectory", "circle_radius"}));
}

TEST(RigParams, RefuseUnknownNamesAndBadValuesNamingTheParameter) {
  try {
    RigSpecFromParams(Json{{"camreas", 3}});
    ADD_FAILURE() << "an unknown parameter passed";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "unknown rig parameter 'camreas' (did you mean 'cameras'?)");
  }
  try {
    RigSpecFromParams(Json{{"cameras", 0}});
    ADD_FAILURE() << "a value outside the range passed";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "cameras: 0 is outside 1 to 64");
  }
}

TEST(RigParams, TheDistortedCameraIsCam1FromTwoCamerasOnUnlessGiven) {
  const Rig four = BuildPresetRig(RigSpecFromParams(Json::object()));
  EXPECT_EQ(four.cameras[1].camera.model(), CameraModelId::kOpenCV);
  const Rig one = BuildPresetRig(RigSpecFromParams(Json{{"cameras", 1}}));
  EXPECT_EQ(one.cameras[0].camera.model(), CameraModelId::kPinhole);
  const Rig first = BuildPresetRig(RigSpecFromParams(Json{{"cameras", 1}, {"distorted", 0}}));
  EXPECT_EQ(first.cameras[0].camera.model(), CameraModelId::kOpenCV);
  const Rig none = BuildPresetRig(RigSpecFromParams(Json{{"distorted", -1}}));
  for (const RigCamera& c : none.cameras) EXPECT_EQ(c.camera.model(), CameraModelId::kPinhole);
}

TEST(RigParams, TheFisheyeFieldOfViewIsTheSurroundRigsSideCamerasToo) {
  const Rig rig = BuildPresetRig(RigSpecFromParams(Json{{"rig", "surround"}, {"fisheye_fov", 150.0}}));
  const RigCamera& right = rig.cameras[1];
  ASSERT_EQ(right.camera.model(), CameraModelId::kOpenCVFisheye);
  const auto edge = right.camera.CamFromImg(Eigen::Vector2d(-0.5, 0.5 * (right.camera.height() - 1)));
  ASSERT_TRUE(edge.has_value());
  EXPECT_NEAR(RadToDeg(std::atan2(std::abs(edge->x()), edge->z())), 75.0, 0.01);
}

}  // namespace
}  // namespace rigsim
