// COLMAP (3.12) rigs -> rig: rigs.txt with cameras.txt of a text model, or a rig_config.json
// beside such a model. The readers are exports/colmap.h's; the rig frame is the reference
// sensor's, which comes first.
#include <algorithm>
#include <map>
#include <optional>
#include <stdexcept>

#include "exports/colmap.h"
#include "geometry/json_io.h"
#include "rigs/rig_import.h"

namespace rigsim {

namespace fs = std::filesystem;

namespace {

// The camera of cameras.txt with this id as a rigsim camera; errors name `source` and `what`.
Camera CameraWithId(const std::vector<ColmapCamera>& cameras, int id, const fs::path& cameras_txt, const std::string& what) {
  const auto it = std::find_if(cameras.begin(), cameras.end(), [&](const ColmapCamera& c) { return c.camera_id == id; });
  if (it == cameras.end()) throw std::runtime_error(cameras_txt.string() + ": no camera " + std::to_string(id) + " (" + what + ")");
  try {
    return CameraFromColmap(*it);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(cameras_txt.string() + ": camera " + std::to_string(id) + " (" + what + "): " + e.what());
  }
}

// A camera name from an image folder ("rig1/cam2/" -> "rig1_cam2"): rigsim's camera names are
// folder names of a dataset.
std::string NameOfPrefix(std::string prefix) {
  while (!prefix.empty() && prefix.back() == '/') prefix.pop_back();
  std::replace(prefix.begin(), prefix.end(), '/', '_');
  return prefix;
}

// Per camera id, the folder all its images in images.txt share ("<folder>/<file>"), when there
// is one.
std::map<int, std::string> FolderPerCamera(const fs::path& images_txt) {
  std::map<int, std::optional<std::string>> folders;
  if (!fs::exists(images_txt)) return {};
  for (const ColmapImage& image : ReadColmapImages(images_txt)) {
    const size_t slash = image.name.rfind('/');
    const std::string folder = slash == std::string::npos ? "" : image.name.substr(0, slash);
    auto [it, added] = folders.emplace(image.camera_id, folder);
    if (!added && it->second != folder) it->second = "";
  }
  std::map<int, std::string> out;
  for (const auto& [id, folder] : folders) {
    if (folder && !folder->empty()) out[id] = NameOfPrefix(*folder);
  }
  return out;
}

}  // namespace

Rig RigFromColmapModel(const fs::path& path) {
  const fs::path dir = fs::is_directory(path) ? path : path.parent_path();
  const fs::path rigs_txt = dir / "rigs.txt", cameras_txt = dir / "cameras.txt";
  for (const fs::path& p : {rigs_txt, cameras_txt}) {
    if (!fs::exists(p)) {
      throw std::runtime_error(p.string() + ": missing: a COLMAP rig is rigs.txt with cameras.txt (COLMAP 3.12's text model)");
    }
  }
  // The rig of the most cameras: COLMAP gives every camera outside a rig a rig of its own.
  const std::vector<ColmapRig> rigs = ReadColmapRigs(rigs_txt);
  const auto cameras_of = [](const ColmapRig& r) {
    return std::count_if(r.sensors.begin(), r.sensors.end(), [](const ColmapRig::Sensor& s) { return s.type == "CAMERA"; });
  };
  const ColmapRig* best = nullptr;
  int ties = 0;
  for (const ColmapRig& r : rigs) {
    if (best == nullptr || cameras_of(r) > cameras_of(*best)) {
      best = &r;
      ties = 0;
    } else if (cameras_of(r) == cameras_of(*best)) {
      ++ties;
    }
  }
  if (best == nullptr || cameras_of(*best) == 0) throw std::runtime_error(rigs_txt.string() + ": no rig with a camera");
  if (ties > 0 && cameras_of(*best) > 1) {
    throw std::runtime_error(rigs_txt.string() + ": " + std::to_string(ties + 1) + " rigs have " +
                             std::to_string(cameras_of(*best)) + " cameras: cannot tell which is the rig; keep one in rigs.txt");
  }
  if (best->sensors[0].type != "CAMERA") {
    throw std::runtime_error(rigs_txt.string() + ": rig " + std::to_string(best->rig_id) + ": its reference sensor is " +
                             best->sensors[0].type + ": rigsim's rig frame is a camera's");
  }
  const std::vector<ColmapCamera> cameras = ReadColmapCameras(cameras_txt);
  const std::map<int, std::string> folders = FolderPerCamera(dir / "images.txt");
  Rig rig;
  for (const ColmapRig::Sensor& s : best->sensors) {
    if (s.type != "CAMERA") continue;  // an IMU has no image
    const std::string what = "rig " + std::to_string(best->rig_id);
    RigCamera rc;
    const auto folder = folders.find(s.sensor_id);
    rc.name = folder != folders.end() ? folder->second : "camera" + std::to_string(s.sensor_id);
    rc.camera = CameraWithId(cameras, s.sensor_id, cameras_txt, what);
    if (!s.sensor_from_rig) {
      throw std::runtime_error(rigs_txt.string() + ": " + what + ": camera " + std::to_string(s.sensor_id) +
                               " has no pose in the rig (HAS_POSE 0): a rig to move along a path needs every camera's");
    }
    rc.cam_from_rig = s.sensor_from_rig;
    if (rig.FindCamera(rc.name) >= 0) rc.name += "_" + std::to_string(s.sensor_id);
    rig.cameras.push_back(std::move(rc));
  }
  return rig;
}

Rig RigFromColmapRigConfig(const fs::path& path) {
  const std::string file = path.string();
  const json_io::Json config = json_io::ReadFile(path);
  // The rig of the most cameras.
  const json_io::Json* best = nullptr;
  for (const json_io::Json& r : config) {
    if (!r.is_object() || !r.contains("cameras") || !r["cameras"].is_array()) {
      throw std::runtime_error(file + ": every rig needs \"cameras\", a list");
    }
    if (best == nullptr || r["cameras"].size() > (*best)["cameras"].size()) best = &r;
  }
  const fs::path dir = path.parent_path();
  const fs::path cameras_txt = dir / "cameras.txt", images_txt = dir / "images.txt";
  if (!fs::exists(cameras_txt) || !fs::exists(images_txt)) {
    throw std::runtime_error(file + ": a rig_config.json records no image size: put it beside the cameras.txt and "
                             "images.txt of a COLMAP text model of its images (COLMAP's model_converter writes them)");
  }
  const std::vector<ColmapCamera> cameras = ReadColmapCameras(cameras_txt);
  const std::vector<ColmapImage> images = ReadColmapImages(images_txt);
  Rig rig;
  std::optional<size_t> ref;
  for (const json_io::Json& c : (*best)["cameras"]) {
    const std::string prefix = json_io::Get<std::string>(c, "image_prefix", file, "camera");
    const std::string where = "camera '" + prefix + "'";
    // The model's camera of the images under the prefix: one, or the rig is not what the model shows.
    std::optional<int> id;
    for (const ColmapImage& image : images) {
      if (image.name.rfind(prefix, 0) != 0) continue;
      if (id && *id != image.camera_id) {
        throw std::runtime_error(file + ": " + where + ": its images in " + images_txt.string() + " have cameras " +
                                 std::to_string(*id) + " and " + std::to_string(image.camera_id) + ": one camera per prefix");
      }
      id = image.camera_id;
    }
    if (!id) throw std::runtime_error(file + ": " + where + ": no image of " + images_txt.string() + " starts with it");
    RigCamera rc;
    rc.name = NameOfPrefix(prefix);
    rc.camera = CameraWithId(cameras, *id, cameras_txt, "the images of " + where);
    if (c.contains("camera_model_name") && c.contains("camera_params")) {
      ColmapCamera given{*id, json_io::Get<std::string>(c, "camera_model_name", file, where), rc.camera.width(),
                         rc.camera.height(), json_io::Get<std::vector<double>>(c, "camera_params", file, where)};
      try {
        rc.camera = CameraFromColmap(given);
      } catch (const std::invalid_argument& e) {
        throw std::runtime_error(file + ": " + where + ": " + e.what());
      }
    }
    const bool is_ref = c.value("ref_sensor", false);
    if (is_ref) {
      if (ref) throw std::runtime_error(file + ": " + where + ": a second ref_sensor (a rig has one)");
      ref = rig.cameras.size();
      rc.cam_from_rig = Rigid3d();
    } else {
      if (!c.contains("cam_from_rig_rotation") || !c.contains("cam_from_rig_translation")) {
        throw std::runtime_error(file + ": " + where + ": no cam_from_rig_rotation and cam_from_rig_translation (COLMAP "
                                 "would estimate them from a reconstruction; a rig to move along a path needs them given)");
      }
      const auto q = json_io::Get<std::vector<double>>(c, "cam_from_rig_rotation", file, where);
      const auto t = json_io::Get<std::vector<double>>(c, "cam_from_rig_translation", file, where);
      if (q.size() != 4 || t.size() != 3) {
        throw std::runtime_error(file + ": " + where + ": cam_from_rig_rotation is [w, x, y, z] and cam_from_rig_translation [x, y, z]");
      }
      const Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
      if (!(rotation.norm() > 0.5 && rotation.norm() < 2.0)) {
        throw std::runtime_error(file + ": " + where + ": cam_from_rig_rotation is not a unit quaternion");
      }
      rc.cam_from_rig = Rigid3d(rotation, Eigen::Vector3d(t[0], t[1], t[2]));
    }
    if (rig.FindCamera(rc.name) >= 0) throw std::runtime_error(file + ": " + where + ": listed twice");
    rig.cameras.push_back(std::move(rc));
  }
  if (!ref) throw std::runtime_error(file + ": no camera is the ref_sensor (COLMAP requires one per rig)");
  // The reference camera first: the rig frame is the first camera's.
  std::rotate(rig.cameras.begin(), rig.cameras.begin() + *ref, rig.cameras.begin() + *ref + 1);
  return rig;
}

}  // namespace rigsim
