// The rig's own vehicle, hidden from feature detection (`rigsim calibrate --mask DIR`): one mask
// image per camera, DIR/<camera>.png, applied to every frame of that camera. The hood and body
// move with the rig, so their features match across time and between frames with zero motion and
// pull the calibration towards it; hiding them is what a user of a car's rig needs first.
//
// Convention (COLMAP's ImageReader.mask_path too): a PNG of the camera's image size, black (0)
// where features must not be detected, anything else where they may. Grey, grey+alpha, RGB or
// RGBA: a pixel is black when its grey or R, G and B values are all 0; alpha is ignored. The mask
// is used as drawn (not eroded): draw it a few pixels past the body's edge.
//
// The pipeline reads the masks and passes them to detection as data (FeatureCache): the
// calibrator reads no file. Every semantic mode detects with them.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "geometry/image.h"
#include "geometry/rig.h"

namespace rigsim {

struct CameraMask {
  std::string camera;          // the rig camera's name
  std::filesystem::path file;  // DIR/<camera>.png
  ImageU8 keep;                // 1 channel, the camera's size: 255 where features may be, 0 where not
  double hidden_fraction = 0;  // share of the image's pixels the mask hides
};

struct RigMasks {
  std::filesystem::path folder;   // DIR as given
  std::vector<CameraMask> masks;  // the cameras that have one, in the rig's order
  std::vector<std::string> cameras_without;  // the rig's cameras with no DIR/<camera>.png

  // Camera `name`'s mask, or nullptr when it has none.
  const CameraMask* Of(const std::string& name) const;
};

// Reads DIR/<camera>.png for the cameras of `rig`, checking everything before the long run, in
// the command line's words (--mask; `rig_json` names the dataset's rig file): DIR must be a folder;
// every PNG in it must name a camera of the rig (a close name is suggested) and have that camera's
// image size; a mask must leave some of its image; a camera's mask in another format than PNG is
// refused; at least one camera must have a mask. A camera without one is allowed (its features are
// not masked): `warn` says so. Throws std::runtime_error naming the file.
RigMasks ReadRigMasks(const std::filesystem::path& dir, const Rig& rig, const std::filesystem::path& rig_json,
                      const std::function<void(const std::string&)>& warn);

// "DIR (2 of 3 cameras; CAM_C has none)" or "DIR (3 cameras)": for the terminal.
std::string DescribeRigMasks(const RigMasks& masks, size_t num_cameras);

}  // namespace rigsim
