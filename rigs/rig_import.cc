#include "rigs/rig_import.h"

#include <stdexcept>
#include <string>

#include "geometry/json_io.h"

namespace rigsim {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormatsRead =
    "rigsim reads a rig.json, a Kalibr camchain.yaml, a COLMAP text model with rigs.txt (its folder, rigs.txt or "
    "cameras.txt), a COLMAP rig_config.json, a DGP calibration JSON and nuScenes calibrated_sensor.json";

RigFileFormat FormatOfJson(const fs::path& path) {
  const json_io::Json j = json_io::ReadFile(path);
  if (j.is_object() && j.contains("cameras")) return RigFileFormat::kRigJson;
  if (j.is_object() && j.contains("names") && j.contains("intrinsics") && j.contains("extrinsics")) return RigFileFormat::kDgp;
  if (j.is_array() && !j.empty() && j[0].is_object()) {
    if (j[0].contains("cameras")) return RigFileFormat::kColmapRigConfig;
    if (j[0].contains("sensor_token") || j[0].contains("camera_intrinsic")) return RigFileFormat::kNuScenes;
  }
  throw std::runtime_error(path.string() + ": not a rig file: " + kFormatsRead);
}

}  // namespace

std::string_view RigFileFormatName(RigFileFormat format) {
  switch (format) {
    case RigFileFormat::kRigJson: return "rig.json";
    case RigFileFormat::kKalibr: return "Kalibr camchain";
    case RigFileFormat::kColmapModel: return "COLMAP model";
    case RigFileFormat::kColmapRigConfig: return "COLMAP rig_config.json";
    case RigFileFormat::kDgp: return "DGP calibration";
    case RigFileFormat::kNuScenes: return "nuScenes calibrated_sensor";
  }
  throw std::invalid_argument("RigFileFormatName: invalid format " + std::to_string(static_cast<int>(format)));
}

RigFileFormat DetectRigFileFormat(const fs::path& path) {
  if (fs::is_directory(path)) {
    if (fs::exists(path / "rigs.txt")) return RigFileFormat::kColmapModel;
    throw std::runtime_error(path.string() + ": a folder without rigs.txt: " + kFormatsRead);
  }
  if (!fs::is_regular_file(path)) throw std::runtime_error(path.string() + ": rig file not found");
  const std::string name = path.filename().string();
  const std::string ext = path.extension().string();
  if (name == "rigs.txt" || name == "cameras.txt") return RigFileFormat::kColmapModel;
  if (ext == ".yaml" || ext == ".yml") return RigFileFormat::kKalibr;
  if (ext == ".json") return FormatOfJson(path);
  throw std::runtime_error(path.string() + ": not a rig file (by its name): " + kFormatsRead);
}

namespace {

Rig ReadFormat(const fs::path& path, RigFileFormat format) {
  try {
    switch (format) {
      case RigFileFormat::kRigJson: return ReadRig(path);
      case RigFileFormat::kKalibr: return RigFromKalibrCamchain(path);
      case RigFileFormat::kColmapModel: return RigFromColmapModel(path);
      case RigFileFormat::kColmapRigConfig: return RigFromColmapRigConfig(path);
      case RigFileFormat::kDgp: return RigFromDgpCalibration(path);
      case RigFileFormat::kNuScenes: return RigFromNuScenesCalibratedSensors(path);
    }
  } catch (const nlohmann::json::exception& e) {
    // A value of a type the reader did not expect, where it reads without a check of its own.
    throw std::runtime_error(path.string() + ": " + std::string(RigFileFormatName(format)) + ": unexpected value: " + e.what());
  }
  throw std::logic_error("ImportRig: unhandled format");
}

}  // namespace

Rig ImportRig(const fs::path& path) {
  const RigFileFormat format = DetectRigFileFormat(path);
  Rig rig = ReadFormat(path, format);
  // JSON, YAML and text numbers may spell infinity (1e999, .inf, inf): a pose must be finite.
  for (const RigCamera& c : rig.cameras) {
    if (c.cam_from_rig && !(c.cam_from_rig->rotation.coeffs().allFinite() && c.cam_from_rig->translation.allFinite())) {
      throw std::runtime_error(path.string() + ": camera '" + c.name + "': its pose on the rig is not finite");
    }
  }
  if (format == RigFileFormat::kRigJson) return rig;
  // Another tool's rig obeys the rules of a rig.json (camera names usable as folder names, each
  // once; what make-rig writes must read back), so it goes through rig.json's reader.
  std::string text;
  try {
    text = RigToJsonText(rig);
  } catch (const nlohmann::json::exception&) {
    throw std::runtime_error(path.string() + ": a camera name is not UTF-8 text");
  }
  return RigFromJsonText(text, path.string());
}

}  // namespace rigsim
