#include "rigs/lens_residual.h"

#include <cmath>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "rigs/rig_params.h"
#include "rigs/rig_spec.h"
#include "testing/expect_error.h"

namespace rigsim {
namespace {

Camera Pinhole() { return Camera::PinholeFromHorizontalFov(640, 360, 95.0); }
Camera Distorted() {
  const Camera p = Pinhole();
  return Camera(CameraModelId::kOpenCV, 640, 360, {p.fx(), p.fy(), p.cx(), p.cy(), -0.25, 0.06, 0.0, 0.0});
}

TEST(LensResidual, TheFittedModelMissesTheLensByTheRequestedAmountAtTheCorners) {
  for (const Camera& camera : {Pinhole(), Distorted()}) {
    for (double px : {0.5, 1.0, 2.0, 8.0}) {
      const LensAndModel drawn = DrawLensResidual(camera, px, 7);
      EXPECT_EQ(drawn.lens.model(), CameraModelId::kFullOpenCV);
      EXPECT_EQ(drawn.model.model(), camera.model());
      EXPECT_NEAR(CornerResidualPx(drawn.model, drawn.lens), px, 1e-3 * px) << CameraModelName(camera.model());
      // The lens is a real departure from the model: the model it started from misses it too.
      EXPECT_GT(CornerResidualPx(camera, drawn.lens), 0.5 * px);
    }
  }
}

TEST(LensResidual, TheModelIsTheBestFitOfItsKind) {
  const LensAndModel drawn = DrawLensResidual(Distorted(), 2.0, 3);
  // Refitting from the fit changes nothing, and moving any parameter of the fit makes the corner
  // residual or the fit over the image worse: it is a least-squares optimum over the image.
  const Camera again = FitModelToLens(drawn.model, drawn.lens);
  for (size_t k = 0; k < again.params().size(); ++k) {
    EXPECT_NEAR(again.params()[k], drawn.model.params()[k], 1e-6 * std::max(1.0, std::abs(drawn.model.params()[k]))) << k;
  }
  // The lens's own model part (its first eight parameters) is not the best fit: the fit moved it.
  const std::vector<double>& l = drawn.lens.params();
  const Camera unfitted(CameraModelId::kOpenCV, 640, 360, std::vector<double>(l.begin(), l.begin() + 8));
  EXPECT_GT(CornerResidualPx(unfitted, drawn.lens), CornerResidualPx(drawn.model, drawn.lens));
}

TEST(LensResidual, TheSeedDrawsTheLensAndTheSameSeedTheSameLens) {
  const LensAndModel a = DrawLensResidual(Pinhole(), 1.0, 11);
  const LensAndModel b = DrawLensResidual(Pinhole(), 1.0, 11);
  const LensAndModel c = DrawLensResidual(Pinhole(), 1.0, 12);
  EXPECT_EQ(a.lens.params(), b.lens.params());
  EXPECT_EQ(a.model.params(), b.model.params());
  EXPECT_NE(a.lens.params(), c.lens.params());
}

TEST(LensResidual, AppliedToARigEveryCameraGetsItsLensAndItsFit) {
  RigSpec spec;
  spec.width = 640;
  spec.height = 360;
  Rig rig = BuildPresetRig(spec);  // the ring: pinholes and one OPENCV camera
  const Rig before = rig;
  ApplyLensResidual(rig, {0.0, 1});
  EXPECT_EQ(RigToJsonText(rig), RigToJsonText(before));  // off: nothing changes
  ApplyLensResidual(rig, {1.5, 1});
  for (size_t c = 0; c < rig.cameras.size(); ++c) {
    ASSERT_TRUE(rig.cameras[c].render_lens.has_value());
    EXPECT_EQ(rig.cameras[c].camera.model(), before.cameras[c].camera.model());
    EXPECT_NEAR(CornerResidualPx(rig.cameras[c].camera, *rig.cameras[c].render_lens), 1.5, 1.5e-3);
  }
  EXPECT_NE(rig.cameras[0].render_lens->params(), rig.cameras[2].render_lens->params());  // drawn per camera
  // The rig parameter reaches the spec, and make-rig's and a sweep's rigs through it.
  const RigSpec from_params = RigSpecFromParams(nlohmann::ordered_json{{"lens_residual", 0.5}});
  EXPECT_EQ(from_params.lens_residual.corner_px, 0.5);
  EXPECT_EQ(RigSpecFromParams(nlohmann::ordered_json::object()).lens_residual.corner_px, 0.0);
}

TEST(LensResidual, BadValuesAndModelsAreRefusedInTheUsersWords) {
  using E = std::invalid_argument;
  EXPECT_THAT([] { RigSpecFromParams(nlohmann::ordered_json{{"lens_residual", -1}}); },
              ThrowsWith<E>("lens_residual", "-1"));
  EXPECT_THAT([] { RigSpecFromParams(nlohmann::ordered_json{{"lens_residual", 50}}); },
              ThrowsWith<E>("lens_residual", "50"));
  EXPECT_THAT([] { LensResidualOptions o; o.corner_px = std::nan(""); o.Check(); }, ThrowsWith<E>("lens residual", "px"));
  Rig fisheye;
  fisheye.cameras.push_back({"side", Camera(CameraModelId::kOpenCVFisheye, 64, 48, {20, 20, 31.5, 23.5, 0, 0, 0, 0}),
                             Rigid3d(), 0.0});
  EXPECT_THAT([&] { ApplyLensResidual(fisheye, {1.0, 1}); },
              ThrowsWith<E>("lens residual", "'side'", "PINHOLE and OPENCV", "OPENCV_FISHEYE"));
  // A model that does not image its own corners has no fit to miss them by.
  EXPECT_THAT([] { DrawLensResidual(Camera(CameraModelId::kOpenCV, 640, 360, {200, 200, 319.5, 179.5, -0.5, 0, 0, 0}), 1.0, 1); },
              ThrowsWith<E>("folds over", "(0, 0)"));
  // A residual the lens cannot reach before it folds over at the corners is refused, not clipped.
  EXPECT_THAT([] { DrawLensResidual(Camera::PinholeFromHorizontalFov(32, 24, 60.0), 20.0, 1); },
              ThrowsWith<E>("20 px", "smaller residual"));
}

}  // namespace
}  // namespace rigsim
