// A real lens beside the model a user has of it. No calibration fits a lens exactly: the model
// (PINHOLE, OPENCV) leaves a residual that grows towards the image corners. make-rig's
// --lens-residual gives each camera a lens with the radial terms its model lacks, renders through
// that lens (RigCamera::render_lens) and writes, as the camera's model, the model's best fit to it:
// what a user's calibration of the real lens would give. The calibrator is given the model only.
//
// The lens is FULL_OPENCV: the model's own parameters plus, for a PINHOLE model, k1 and k2 in a
// seeded mix, and for an OPENCV model k3 (the r^6 term) of a seeded sign, scaled so that the fitted
// model misses the lens by the requested distance at the image corners.
#pragma once

#include <cstdint>

#include "geometry/camera.h"
#include "geometry/rig.h"

namespace rigsim {

struct LensResidualOptions {
  // The model's residual against the lens at the image's corner pixels (px, the largest of the
  // four); 0 = none: the rig is rendered through its models, as without this option.
  double corner_px = 0.0;
  uint64_t seed = 1;  // the mix (PINHOLE) or sign (OPENCV) of each camera's extra terms
  static constexpr double kMaxCornerPx = 20.0;
  bool Enabled() const { return corner_px > 0; }
  void Check() const;  // throws std::invalid_argument naming the option
};

// The largest distance, over the image's four corner pixels, between where `lens` images the
// corner pixel's ray and where `model` images it (px). Throws std::invalid_argument when either
// lens does not image a corner.
double CornerResidualPx(const Camera& model, const Camera& lens);

// `start`'s model with its parameters fitted to `lens` (same image size) by least squares on the
// pixel distance over a grid of pixels covering the image, from `start`'s parameters: the best
// that model can do for that lens.
Camera FitModelToLens(const Camera& start, const Camera& lens);

struct LensAndModel {
  Camera lens;   // what the images are rendered through
  Camera model;  // the model fitted to it: what the calibrator is given
};

// The lens of `camera` (PINHOLE or OPENCV) with its extra terms drawn from `seed`, and its model
// fitted to it, whose corner residual is `corner_px` to within 0.1%. Throws std::invalid_argument
// for other models, or when the lens stops imaging the corners before the residual is reached.
LensAndModel DrawLensResidual(const Camera& camera, double corner_px, uint64_t seed);

// Every camera of `rig`: `camera` becomes the fitted model and `render_lens` the lens; camera i
// draws from a seed mixed from options.seed and i. Nothing happens when it is not enabled.
// Throws std::invalid_argument naming the camera and the problem.
void ApplyLensResidual(Rig& rig, const LensResidualOptions& options);

}  // namespace rigsim
