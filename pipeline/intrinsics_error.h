// Intrinsics as a user has them: a calibration of the lenses, not the truth the images were
// rendered with. `calibrate --intrinsics-error E` and the sweep parameter `intrinsics_error` give
// the calibrator each camera's intrinsics with a seeded error of relative size E:
//   focal lengths   fx, fy (together, the aspect kept)  x exp(E z_0)     (a relative error of sd ~E)
//   principal point cx + E (width / 2) z_2,  cy + E (height / 2) z_3     (px)
//   distortion      each coefficient p_k, k >= 4        x (1 + E z_k)    (zero stays zero)
// with z_k standard normal draws that depend only on (seed, camera index, parameter index k in
// camera_models.h order; fy shares fx's draw): the same seed
// gives the same intrinsics on every machine. E = 0 gives the camera back unchanged, bit for bit.
// A focal error of E and a principal point moved by E (width / 2) displace a pixel at the image's
// edge by about the same E (width / 2) px.
#pragma once

#include <cstdint>
#include <string>

#include "geometry/camera.h"
#include "geometry/rig.h"

namespace rigsim {

struct IntrinsicsErrorOptions {
  // Relative size E of the error: 0.01 is 1 % of the focal length. 0: the intrinsics as given.
  double error = 0.0;
  // Seed of the draws (calibrate --intrinsics-error-seed; a sweep cell's seed).
  uint64_t seed = 1;
  // Largest error accepted: beyond it the given intrinsics are no calibration at all.
  static constexpr double kMaxError = 0.5;

  bool Enabled() const { return error > 0; }
  // Throws std::invalid_argument naming `option` when the error is negative, not finite or more
  // than kMaxError.
  void Check(const std::string& option = "intrinsics_error") const;
};

// The standard normal draw z of parameter `param` (camera_models.h order) of camera
// `camera_index` for `seed`.
double IntrinsicsErrorDraw(uint64_t seed, int camera_index, int param);

// `camera` with the error described above drawn for camera `camera_index`.
Camera WithIntrinsicsError(const Camera& camera, const IntrinsicsErrorOptions& options, int camera_index);

// Every camera of `rig` with its error (camera index = position in rig.cameras); `rig` itself when
// the error is 0.
Rig WithIntrinsicsError(const Rig& rig, const IntrinsicsErrorOptions& options);

// What the error means, in one sentence (--help, evaluation.json).
std::string IntrinsicsErrorMeaning();

}  // namespace rigsim
