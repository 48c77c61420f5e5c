// OpenCV YAML export: a file cv::FileStorage reads (%YAML:1.0), one entry per camera in the
// sequence `cameras`:
//
//   %YAML:1.0
//   ---
//   num_cameras: 2
//   cameras:
//      -
//         name: "cam0"
//         model: "OPENCV"                 # rigsim/COLMAP model name
//         fisheye: 0                      # 1: use cv::fisheye with distortion_coefficients k1..k4
//         image_width: 1280
//         image_height: 720
//         camera_matrix: !!opencv-matrix  # 3x3 [fx 0 cx; 0 fy cy; 0 0 1]
//         distortion_coefficients: !!opencv-matrix  # 1xN, OpenCV's order
//         R: !!opencv-matrix              # 3x3 rotation of cam_from_rig (x_cam = R x_rig + T)
//         T: !!opencv-matrix              # 3x1 translation of cam_from_rig (metres)
//
// Distortion in OpenCV's order: PINHOLE (0 0 0 0), OPENCV (k1 k2 p1 p2), FULL_OPENCV
// (k1 k2 p1 p2 k3 k4 k5 k6, cv::CALIB_RATIONAL_MODEL), OPENCV_FISHEYE (k1 k2 k3 k4, cv::fisheye).
// Pixel coordinates are OpenCV's, exactly rigsim's (no shift). R and T are present only for
// cameras with a cam_from_rig. Written by our own small writer: OpenCV stays out of this module.
#pragma once

#include <filesystem>
#include <string>

#include <optional>

#include "geometry/estimate_gauge.h"
#include "geometry/rig.h"

namespace rigsim {

// An estimate's gauge goes into comments after the header (cv::FileStorage skips them).
std::string OpenCvRigYaml(const Rig& rig, const std::optional<EstimateGauge>& gauge = std::nullopt);
// Writes OpenCvRigYaml to `path` atomically.
void WriteOpenCvRigYaml(const Rig& rig, const std::filesystem::path& path,
                        const std::optional<EstimateGauge>& gauge = std::nullopt);

}  // namespace rigsim
