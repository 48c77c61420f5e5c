// COLMAP text model export (cameras.txt, images.txt, points3D.txt), one image per camera x frame,
// named "<cam>/<frame><ext>" relative to DATASET/images, so COLMAP runs on the dataset as it is
// (--image_path DATASET/images).
//
//   cameras.txt: CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]   (ids 1..N in rig order)
//   images.txt:  IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME, then an empty POINTS2D line;
//                the pose is cam_from_world = cam_from_rig * rig_from_world.
//   points3D.txt: header only.
//
// Model names and parameter orders are COLMAP's (PINHOLE, OPENCV, FULL_OPENCV, OPENCV_FISHEYE are
// identical in rigsim). COLMAP puts the centre of the top-left pixel at (0.5, 0.5), rigsim at
// (0, 0): cx and cy get +0.5 here, and nowhere else.
#pragma once

#include <filesystem>
#include <string>

#include "dataset/dataset.h"
#include "exports/image_name.h"
#include "geometry/rig.h"

namespace rigsim {

struct ColmapExportOptions {
  // Name in images.txt of camera `cam`'s image of frame `frame`, relative to the images folder;
  // by default "<cam>/<frame>.png" (what render writes). DatasetLayout::ImageName gives the
  // files a dataset has, whatever their extension.
  ImageNameFn image_name = DefaultImageName;
};

struct ColmapModelText {
  std::string cameras, images, points3d;
};

// Throws std::invalid_argument when a camera has no cam_from_rig or a frame no rig_from_world.
ColmapModelText ColmapModel(const Rig& rig, const FramesFile& frames, const ColmapExportOptions& options = {});
// Writes cameras.txt, images.txt and points3D.txt into `dir` (created if needed).
void WriteColmapModel(const Rig& rig, const FramesFile& frames, const std::filesystem::path& dir,
                      const ColmapExportOptions& options = {});

}  // namespace rigsim
