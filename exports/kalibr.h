// Kalibr camchain.yaml export (https://github.com/ethz-asl/kalibr/wiki/yaml-formats).
//
//   cam0:
//     camera_model: pinhole
//     intrinsics: [fu, fv, pu, pv]
//     distortion_model: radtan | equidistant
//     distortion_coeffs: [k1, k2, r1, r2] | [k1, k2, k3, k4]
//     resolution: [width, height]
//     rostopic: /cam0/image_raw
//   cam1:
//     T_cn_cnm1:            # cam1_from_cam0 = cam_from_rig[1] * cam_from_rig[0]^-1, 4x4 row-major
//     - [r11, r12, r13, t1]
//     ...
//
// Model mapping: PINHOLE -> pinhole/radtan with zero coefficients; OPENCV -> pinhole/radtan
// (k1 k2 p1 p2, the same order as Kalibr's k1 k2 r1 r2); FULL_OPENCV -> pinhole/radtan only when
// k3..k6 are zero (Kalibr has no rational model; otherwise an error); OPENCV_FISHEYE ->
// pinhole/equidistant (k1..k4, Kalibr's equidistant is the same Kannala-Brandt polynomial).
// Pixel coordinates are OpenCV's (no +0.5 shift, unlike COLMAP).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "geometry/estimate_gauge.h"
#include "geometry/rig.h"

namespace rigsim {

// Throws std::invalid_argument when a camera has no cam_from_rig or a model Kalibr cannot express.
// An estimate's gauge goes into the header comments (Kalibr reads every top-level key as a camera).
std::string KalibrCamchainYaml(const Rig& rig, const std::optional<EstimateGauge>& gauge = std::nullopt);
// Writes KalibrCamchainYaml to `path` atomically.
void WriteKalibrCamchain(const Rig& rig, const std::filesystem::path& path,
                         const std::optional<EstimateGauge>& gauge = std::nullopt);

// One camera of a camchain.yaml as read back: its key (cam0, cam1, ...), its name (from
// `rostopic` /<name>/image_raw, else empty), its resolution, cam_from_cam0 (the chain of
// T_cn_cnm1 multiplied out; cam0 is the identity), and its intrinsics as the file states them
// (empty where it states none; KalibrIntrinsics turns them into a rigsim camera).
struct KalibrCamera {
  std::string key;
  std::string name;
  int width = 0, height = 0;
  Rigid3d cam_from_cam0;
  std::string camera_model, distortion_model;
  std::vector<double> intrinsics, distortion_coeffs;
};

// Reads the cameras of a camchain.yaml in order cam0, cam1, ... Throws std::runtime_error naming
// the file and the key when the chain is broken (a camera without T_cn_cnm1, a matrix that is not
// 4x4 with a rotation in its top-left 3x3).
std::vector<KalibrCamera> ReadKalibrCamchain(const std::filesystem::path& path);

// The rigsim camera of a camchain's camera, the inverse of the export's mapping: pinhole with
// radtan -> OPENCV (PINHOLE when every coefficient is 0), with equidistant -> OPENCV_FISHEYE, with
// none -> PINHOLE. Throws std::invalid_argument saying why for what rigsim has no model of (omni,
// ds, eucm, the fov distortion), a missing resolution or a wrong number of values.
Camera KalibrIntrinsics(const KalibrCamera& camera);

}  // namespace rigsim
