#include "geometry/rig.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "geometry/json_io.h"

namespace rigsim {

using json_io::Get;
using json_io::Json;

namespace {
// Image sides beyond this are certainly a corrupt file (no sensor has 1 million pixels per row).
constexpr int64_t kMaxImageSide = 1 << 20;
// The rolling shutter and exposure fields of one camera (absent = off).
void ReadTiming(const Json& c, const std::string& source, const std::string& where, RigCamera& rc) {
  auto non_negative = [&](const char* key, double* value) {
    if (!c.contains(key)) return;
    *value = Get<double>(c, key, source, where);
    if (!std::isfinite(*value) || *value < 0 || *value > 3600) {
      throw std::runtime_error(source + ": " + where + " ('" + rc.name + "'): " + key + " must be in [0, 3600] s, got " +
                               std::to_string(*value));
    }
  };
  non_negative("readout_s", &rc.readout_s);
  non_negative("exposure_s", &rc.exposure_s);
  if (!std::isfinite(rc.time_offset_s) || std::abs(rc.time_offset_s) > 3600) {
    throw std::runtime_error(source + ": " + where + " ('" + rc.name + "'): time_offset_s must be finite, within 3600 s");
  }
  if (c.contains("readout_direction")) {
    const std::string direction = Get<std::string>(c, "readout_direction", source, where);
    if (direction != "top-to-bottom" && direction != "bottom-to-top") {
      throw std::runtime_error(source + ": " + where + " ('" + rc.name + "'): readout_direction must be "
                               "\"top-to-bottom\" or \"bottom-to-top\", got \"" + direction + "\"");
    }
    rc.readout_bottom_to_top = direction == "bottom-to-top";
  }
}

// A camera's "render_lens": a model and its parameters at the camera's image size.
Camera ReadRenderLens(const Json& c, const std::string& source, const std::string& where, const RigCamera& rc) {
  const Json& lens = c["render_lens"];
  const std::string at = where + ".render_lens";
  if (!lens.is_object()) {
    throw std::runtime_error(source + ": " + at + " ('" + rc.name + "'): expected an object with \"model\" and \"params\"");
  }
  try {
    const CameraModelId model = CameraModelFromName(Get<std::string>(lens, "model", source, at));
    return Camera(model, rc.camera.width(), rc.camera.height(), Get<std::vector<double>>(lens, "params", source, at));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(source + ": " + at + " ('" + rc.name + "'): " + e.what());
  }
}

// A camera's "cam_from_rig". Its rotation is "rotation_wxyz"; "rotation" is read the same way, w
// first, as the real-rig folders' truth_rig.json (bench/real_rigs/rig_common.py) writes it. A pose
// with both is refused: which of the two holds is not known.
Rigid3d ReadCamFromRig(const Json& c, const std::string& source, const std::string& where, const RigCamera& rc) {
  const Json& pose = c["cam_from_rig"];
  const std::string at = where + ".cam_from_rig";
  if (pose.is_object() && pose.contains("rotation")) {
    if (pose.contains("rotation_wxyz")) {
      throw std::runtime_error(source + ": " + at + " ('" + rc.name + "'): has both \"rotation_wxyz\" and \"rotation\"; "
                               "give the rotation once, as \"rotation_wxyz\": [w, x, y, z]");
    }
    return json_io::PoseFromJson(pose, source, at, "rotation");
  }
  return json_io::PoseFromJson(pose, source, at);
}

}  // namespace

int Rig::FindCamera(const std::string& name) const {
  for (size_t i = 0; i < cameras.size(); ++i) {
    if (cameras[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

bool Rig::HasAllPoses() const {
  for (const RigCamera& c : cameras) {
    if (!c.cam_from_rig) return false;
  }
  return !cameras.empty();
}

Rig Rig::PosedCameras() const {
  Rig posed;
  for (const RigCamera& c : cameras) {
    if (c.cam_from_rig) posed.cameras.push_back(c);
  }
  return posed;
}

Rig Rig::AsRendered() const {
  Rig rendered = *this;
  for (RigCamera& c : rendered.cameras) {
    if (c.render_lens) c.camera = *c.render_lens;
    c.render_lens.reset();
  }
  return rendered;
}

Rig RigFromJsonText(const std::string& text, const std::string& source) {
  const Json root = json_io::Parse(text, source);
  if (!root.is_object() || !root.contains("cameras") || !root["cameras"].is_array()) {
    throw std::runtime_error(source + ": expected an object with a 'cameras' array");
  }
  Rig rig;
  const Json& cams = root["cameras"];
  if (cams.empty()) throw std::runtime_error(source + ": 'cameras' is empty");
  for (size_t i = 0; i < cams.size(); ++i) {
    const Json& c = cams[i];
    const std::string where = "cameras[" + std::to_string(i) + "]";
    RigCamera rc;
    rc.name = Get<std::string>(c, "name", source, where);
    if (rc.name.empty() || rc.name.find('/') != std::string::npos || rc.name == "." || rc.name == "..") {
      throw std::runtime_error(source + ": " + where + ": camera name '" + rc.name +
                               "' must be non-empty and usable as a folder name");
    }
    if (rig.FindCamera(rc.name) >= 0) {
      throw std::runtime_error(source + ": " + where + ": duplicate camera name '" + rc.name + "'");
    }
    try {
      const CameraModelId model = CameraModelFromName(Get<std::string>(c, "model", source, where));
      // Read as 64-bit so that a huge size is reported instead of being truncated to an int.
      const int64_t width = Get<int64_t>(c, "width", source, where);
      const int64_t height = Get<int64_t>(c, "height", source, where);
      if (width <= 0 || height <= 0 || width > kMaxImageSide || height > kMaxImageSide) {
        throw std::invalid_argument("image size " + std::to_string(width) + "x" + std::to_string(height) +
                                    " is outside 1.." + std::to_string(kMaxImageSide));
      }
      rc.camera = Camera(model, int(width), int(height), Get<std::vector<double>>(c, "params", source, where));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(source + ": " + where + " ('" + rc.name + "'): " + e.what());
    }
    if (c.contains("cam_from_rig") && !c["cam_from_rig"].is_null()) {
      rc.cam_from_rig = ReadCamFromRig(c, source, where, rc);
    }
    if (c.contains("render_lens")) rc.render_lens = ReadRenderLens(c, source, where, rc);
    if (c.contains("time_offset_s")) rc.time_offset_s = Get<double>(c, "time_offset_s", source, where);
    ReadTiming(c, source, where, rc);
    rig.cameras.push_back(std::move(rc));
  }
  if (root.contains("ego_vehicle")) {
    rig.ego_vehicle = Get<std::string>(root, "ego_vehicle", source, "the rig");
    const std::filesystem::path name(rig.ego_vehicle);
    if (rig.ego_vehicle.empty() || name != name.filename() || rig.ego_vehicle == "." || rig.ego_vehicle == "..") {
      throw std::runtime_error(source + ": ego_vehicle '" + rig.ego_vehicle +
                               "' must be the name of a file beside rig.json (no folder)");
    }
  }
  return rig;
}

std::string RigToJsonText(const Rig& rig) {
  Json cams = Json::array();
  for (const RigCamera& rc : rig.cameras) {
    Json c{{"name", rc.name},
           {"model", std::string(CameraModelName(rc.camera.model()))},
           {"width", rc.camera.width()},
           {"height", rc.camera.height()},
           {"params", rc.camera.params()},
           {"time_offset_s", rc.time_offset_s}};
    if (rc.cam_from_rig) c["cam_from_rig"] = json_io::PoseToJson(*rc.cam_from_rig);
    if (rc.readout_s > 0) {
      c["readout_s"] = rc.readout_s;
      c["readout_direction"] = rc.readout_bottom_to_top ? "bottom-to-top" : "top-to-bottom";
    }
    if (rc.exposure_s > 0) c["exposure_s"] = rc.exposure_s;
    if (rc.render_lens) {
      c["render_lens"] = Json{{"model", std::string(CameraModelName(rc.render_lens->model()))},
                              {"params", rc.render_lens->params()}};
    }
    cams.push_back(std::move(c));
  }
  Json root{{"cameras", cams}};
  if (!rig.ego_vehicle.empty()) root["ego_vehicle"] = rig.ego_vehicle;
  return root.dump(2) + "\n";
}

Rig ReadRig(const std::filesystem::path& path) {
  return RigFromJsonText(json_io::ReadText(path), path.string());
}

void WriteRig(const Rig& rig, const std::filesystem::path& path) {
  json_io::WriteTextAtomic(path, RigToJsonText(rig));
}

}  // namespace rigsim
