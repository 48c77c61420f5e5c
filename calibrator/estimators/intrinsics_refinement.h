// Refining the cameras' intrinsics in the rig's bundle adjustment (multi_frame_rig.h), from
// given values a few percent off (a datasheet's): the priors that keep each parameter near its
// given value, and the record of what the refinement made of each camera (its comparison with
// the true intrinsics is evaluation/intrinsics_errors.h's); and, for intrinsics held instead, how
// uncertain the given ones are.
//
// The refined parameters are the camera model's own (camera_models.h orders: fx fy cx cy, then
// the distortion), each with a Gaussian prior centred on its given value, and one more prior
// tying fx to fy (square pixels).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"

namespace rigsim {

// Standard deviations of the priors: how far a datasheet's values may be from a lens's own. Wide
// enough not to pull on what the images determine (thousands of observations fix a focal length
// to well under 0.1 %), narrow enough to hold what they do not (a camera with few observations,
// distortion terms beyond the images' reach).
struct IntrinsicsPriorOptions {
  // fx and fy, as a fraction of the given value: a lens's focal length is specified to 1-5 %.
  double focal_fraction = 0.05;
  // fx - fy, as a fraction of the given fx: sensors have square pixels to far better than 0.1 %,
  // and a free aspect ratio would soak up some of the distortion.
  double aspect_fraction = 0.001;
  // cx and cy (px), as a fraction of the image's larger side: sensor and lens are centred on each
  // other to about 1-2 % of the image (30 px on a 1920-pixel image at 2.5 %).
  double principal_point_fraction = 0.025;
  // The first radial term (OPENCV/FULL_OPENCV k1, OPENCV_FISHEYE k1): a datasheet without
  // distortion (0) must still reach a strong barrel lens's k1 of -0.3.
  double first_radial = 0.3;
  // Every further radial term (k2.., and FULL_OPENCV's denominator k4 k5 k6).
  double higher_radial = 0.1;
  // Tangential terms p1 p2: decentring of a lens is small.
  double tangential = 0.005;
  // The priors are weighed against the reprojection errors as if one image coordinate had this
  // much noise (px): a prior residual is pixel_noise_px * (value - given) / sigma.
  double pixel_noise_px = 0.5;
  // Per camera, the intrinsics the priors are centred on; empty: the cameras the bundle
  // adjustment starts from. Set when it starts from intrinsics refined before (rig_intrinsics.h).
  std::vector<Camera> centres;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
  bool operator==(const IntrinsicsPriorOptions&) const = default;
};

// The prior's standard deviation of each of `given`'s parameters (camera_models.h order).
std::vector<double> IntrinsicsPriorSigmas(const Camera& given, const IntrinsicsPriorOptions& options);

// How uncertain the given intrinsics are when they are held, not refined (a calibration report's
// standard deviations, OpenCV's stdDeviationsIntrinsics or Kalibr's): the poses are still
// adjusted with the intrinsics held at the given values, but the stated covariances add what that
// uncertainty moves them by, linearised at the solution (bundle_covariance.h
// HeldParameterCovariance). Each of fx, fy, cx, cy is off independently; distortion counts as
// exact.
struct GivenIntrinsicsDeviation {
  double focal_fraction = 0.0;      // of fx and of fy, as a fraction of each (0.002: 0.2 %)
  double principal_point_px = 0.0;  // of cx and of cy (px)
  // Empty, or per camera: the standard deviations (px) of its fx, fy, cx, cy, in place of the two
  // above.
  std::vector<Eigen::Vector4d> per_camera_px;

  // The standard deviations (px) of fx, fy, cx, cy of camera `c`, given as `camera`.
  Eigen::Vector4d OfCamera(int c, const Camera& camera) const;
  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
  bool operator==(const GivenIntrinsicsDeviation&) const = default;
};

// What the refinement made of one camera's intrinsics.
struct RefinedIntrinsics {
  std::vector<double> given;    // the parameters the calibration started from (the priors' centres)
  std::vector<double> refined;  // after the bundle adjustment
  // Standard deviation of each refined parameter, from the bundle adjustment's covariance; empty
  // when it could not be computed.
  std::vector<double> stddev;
};

}  // namespace rigsim
