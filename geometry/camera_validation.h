// Is a camera usable over its whole image? Camera's constructor rejects parameters that are
// impossible in themselves (non-positive focal length, wrong count, non-finite values); this
// module rejects cameras whose lens cannot be inverted (Camera::CamFromImg has no ray) where the
// image needs it, which depends on the image size and the model:
//
//  - Perspective models (PINHOLE, OPENCV, FULL_OPENCV) image a field of view below 180 degrees
//    onto the whole sensor, so every pixel must have a ray. A pixel without one means the
//    distortion polynomial folds back inside the image: the rendered image would have holes and
//    calibration would use a lens that does not exist. Rejected.
//  - A fisheye (OPENCV_FISHEYE) may legitimately draw its image circle inside the sensor, so only
//    the image centre must have a ray; pixels without one are counted in a warning.
//
// The check samples the image border densely (every pixel up to a cap per side) and the interior
// on a grid; the valid region of a radial lens is star-shaped around the principal point, so a
// fold shows on the border first. Also rejected: images larger than kMaxCameraPixels, which no
// real camera has and which would exhaust memory when rendered.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "geometry/camera.h"
#include "geometry/rig.h"

namespace rigsim {

// Largest image (width x height) rigsim accepts: 100 megapixels.
inline constexpr int64_t kMaxCameraPixels = 100'000'000;

struct CameraCoverage {
  int64_t samples = 0;          // pixels checked
  int64_t invalid_samples = 0;  // of those, pixels without a ray
  bool centre_valid = false;    // the pixel at the image centre has a ray
  double first_invalid_x = 0, first_invalid_y = 0;  // an example, when invalid_samples > 0
};

// Samples which pixels of `camera` have a ray (CamFromImg). Bounded work whatever the image size.
CameraCoverage MeasureCameraCoverage(const Camera& camera);

// Throws std::runtime_error("<source>: camera '<name>': ...") when the camera is unusable by the
// rule above; returns the warnings (fisheye pixels outside the image circle) otherwise.
std::vector<std::string> CheckCameraCoversImage(const Camera& camera, const std::string& name, const std::string& source);

// The same for every camera of a rig and its render lens, if any; warnings are concatenated.
std::vector<std::string> CheckRigCoversImages(const Rig& rig, const std::string& source);

}  // namespace rigsim
