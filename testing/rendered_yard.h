// A small scene ray-cast into real images for calibration tests: a walled yard (frame: x right, y
// down, z forward) with a floor (road) at y = 1.6, a back wall (building) at z = 9, a left wall
// (vegetation) at x = -4 and a right wall (building) at x = 5, walls ending at y = -3 with sky
// above, every surface textured with smooth value noise. Two cameras (cam0 pinhole, cam1 with
// barrel distortion, 0.6 m apart, turned 20 deg) over two frames of a short turning path: each
// view's photo, Cityscapes label ids (road 7, building 11, vegetation 21, sky 23) and range
// image (0 where there is no surface), 2x2 supersampled, as the calibrator sees a rendered dataset.
#pragma once

#include <vector>

#include "geometry/image.h"
#include "geometry/rig.h"
#include "geometry/rigid3.h"

namespace rigsim {

struct RenderedYard {
  Rig rig;                               // the truth: intrinsics and cam_from_rig
  std::vector<Rigid3d> rig_from_world;   // per frame
  // [camera][frame]
  std::vector<std::vector<ImageU8>> rgb, labels;
  std::vector<std::vector<ImageF>> range;
};

// Rendered once per process (a few seconds at -O1).
const RenderedYard& TwoCameraYard();

}  // namespace rigsim
