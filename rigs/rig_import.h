// Rigs from other tools' calibration files, for `make-rig --type file --rig-file` (ReadRigFile):
// the cameras' intrinsics and their poses on the rig, whatever the tool that wrote them.
//
//   Kalibr camchain.yaml      cam0, cam1, ... with T_cn_cnm1 = cam_n_from_cam_{n-1}
//   COLMAP text model (3.12)  rigs.txt (sensor_from_rig, quaternion w first) with cameras.txt
//   COLMAP rig_config.json    cam_from_rig per image prefix, beside the cameras.txt and images.txt
//                             of a model of those images (the config records no image size)
//   DGP / DDAD calibration    calibration/<hash>.json: names, intrinsics, extrinsics =
//                             vehicle_from_sensor; image sizes from the scene_*.json beside calibration/
//   nuScenes calibrated_sensor  records with translation, rotation [w, x, y, z] = ego_from_sensor and
//                             camera_intrinsic; channels from sensor.json, image sizes from
//                             sample_data.json beside it (or "channel", "width", "height" in the records)
//
// Conventions of every import: the rig frame is the first camera's (cam_from_rig of the first
// camera is the identity), as in a rig.json make-rig writes and the calibrator's gauge: a vehicle
// rig's vehicle frame is not kept. Cameras keep the file's order (nuScenes: CAM_FRONT,
// CAM_FRONT_RIGHT, CAM_BACK_RIGHT, CAM_BACK, CAM_BACK_LEFT, CAM_FRONT_LEFT, then any other channel
// in the file's order). Pixels are rigsim's (the centre of the top-left pixel at (0, 0)): COLMAP's
// principal points lose 0.5. Every error is a std::runtime_error naming the file (and the camera)
// and why, in the user's words: a model rigsim cannot represent is refused, never approximated.
#pragma once

#include <filesystem>
#include <string_view>

#include "geometry/rig.h"

namespace rigsim {

enum class RigFileFormat { kRigJson, kKalibr, kColmapModel, kColmapRigConfig, kDgp, kNuScenes };

// "rig.json", "Kalibr camchain", "COLMAP model", "COLMAP rig_config.json", "DGP calibration",
// "nuScenes calibrated_sensor".
std::string_view RigFileFormatName(RigFileFormat format);

// The format of `path`, from its name and content. Throws std::runtime_error naming the file and
// the formats rigsim reads when it is none of them.
RigFileFormat DetectRigFileFormat(const std::filesystem::path& path);

// The rig of a file of any format above (a rig.json as ReadRig reads it). Another tool's rig then
// obeys a rig.json's rules too (finite poses, camera names usable as folder names, each once).
Rig ImportRig(const std::filesystem::path& path);

// One reader per format (ImportRig chooses).
Rig RigFromKalibrCamchain(const std::filesystem::path& path);
Rig RigFromColmapModel(const std::filesystem::path& path);  // a folder with rigs.txt, or rigs.txt itself
Rig RigFromColmapRigConfig(const std::filesystem::path& path);
Rig RigFromDgpCalibration(const std::filesystem::path& path);
Rig RigFromNuScenesCalibratedSensors(const std::filesystem::path& path);

}  // namespace rigsim
