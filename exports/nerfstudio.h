// nerfstudio transforms.json export: one entry per frame x camera with its own intrinsics.
//
//   { "camera_model": "OPENCV" | "OPENCV_FISHEYE",
//     "frames": [ { "file_path": "<prefix>/<cam>/<frame>.png" (the extension of the file),
//                   "transform_matrix": 4x4 world_from_cam in OpenGL camera axes,
//                   "fl_x", "fl_y", "cx", "cy", "w", "h",
//                   "k1", "k2", "p1", "p2" (OPENCV; "k3" for FULL_OPENCV) |
//                   "k1", "k2", "k3", "k4" (OPENCV_FISHEYE) } ] }
//
// Conventions:
//  - transform_matrix = world_from_cam * diag(1, -1, -1, 1): nerfstudio's camera axes are
//    OpenGL's (x right, y up, z back), rigsim's OpenCV's (x right, y down, z forward). Its
//    column 2 is the camera's backward direction in the world.
//  - nerfstudio samples pixel centres at (i + 0.5, j + 0.5) (like COLMAP, whose cameras.txt its
//    ns-process-data copies unchanged): cx and cy get +0.5.
//  - camera_model is one value for the whole file (nerfstudio reads it only at the top level), so
//    a rig mixing perspective and fisheye cameras gives two files: transforms_perspective.json and
//    transforms_fisheye.json. FULL_OPENCV is exported only when k4..k6 (rational terms) are zero.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dataset/dataset.h"
#include "exports/image_name.h"
#include "geometry/estimate_gauge.h"
#include "geometry/rig.h"

namespace rigsim {

struct NerfstudioExportOptions {
  // Folder of the images relative to the folder holding transforms.json (e.g. "../DATASET/images").
  std::string image_prefix = "images";
  // Name of camera `cam`'s image of frame `frame` under image_prefix (exports/image_name.h).
  ImageNameFn image_name = DefaultImageName;
  // An estimate's gauge, said in the top-level key "rigsim_estimate" (nerfstudio reads only the
  // keys it knows).
  std::optional<EstimateGauge> gauge;
};

struct NerfstudioFile {
  std::string filename;  // "transforms.json", or per model group for mixed rigs
  std::string text;
};

// Throws std::invalid_argument when poses are missing or a model has no nerfstudio equivalent.
std::vector<NerfstudioFile> NerfstudioTransforms(const Rig& rig, const FramesFile& frames,
                                                 const NerfstudioExportOptions& options = {});
// Writes the files into `dir` (created if needed).
void WriteNerfstudioTransforms(const Rig& rig, const FramesFile& frames, const std::filesystem::path& dir,
                               const NerfstudioExportOptions& options = {});

}  // namespace rigsim
