// DGP (DDAD, Parallel Domain) calibration JSON -> rig. A SampleCalibration (dgp/proto/sample.proto):
// "names", "intrinsics" (CameraIntrinsics of dgp/proto/geometry.proto) and "extrinsics" (Pose: the
// sensor's pose in the vehicle frame, x_vehicle = rotation * x_sensor + translation) per sensor;
// the cameras are the sensors whose focal lengths are set (the lidar's are 0). Image sizes are not
// in it: they are the datums' of the scene_*.json that the DGP layout puts beside calibration/.
#include <algorithm>
#include <map>
#include <optional>
#include <stdexcept>

#include "geometry/json_io.h"
#include "rigs/rig_import.h"

namespace rigsim {

namespace fs = std::filesystem;

namespace {

// A field of a DGP message, 0 when it is left out: proto3's JSON leaves out the fields that are 0.
double NumberOr0(const json_io::Json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : 0.0;
}

Rigid3d DgpPose(const json_io::Json& pose, const std::string& file, const std::string& where) {
  if (!pose.is_object()) throw std::runtime_error(file + ": " + where + ": not a pose (rotation and translation)");
  const json_io::Json r = pose.value("rotation", json_io::Json::object());
  const json_io::Json t = pose.value("translation", json_io::Json::object());
  const Eigen::Quaterniond q(NumberOr0(r, "qw"), NumberOr0(r, "qx"), NumberOr0(r, "qy"), NumberOr0(r, "qz"));
  if (!(q.norm() > 0.5 && q.norm() < 2.0)) throw std::runtime_error(file + ": " + where + ": the rotation is not a unit quaternion");
  return Rigid3d(q, Eigen::Vector3d(NumberOr0(t, "x"), NumberOr0(t, "y"), NumberOr0(t, "z")));
}

// The rigsim camera of a DGP CameraIntrinsics: PINHOLE without distortion, OPENCV with k1 k2 p1 p2,
// FULL_OPENCV with k3..k6 (DGP's are OpenCV's: dgp/utils/camera.py projects with
// cv2.projectPoints). What rigsim cannot draw is refused, naming the field.
Camera DgpCamera(const json_io::Json& in, int width, int height, const std::string& file, const std::string& where) {
  const auto fail = [&](const std::string& why) { return std::runtime_error(file + ": " + where + ": " + why); };
  if (NumberOr0(in, "skew") != 0.0) throw fail("skew is not 0: rigsim's cameras have square pixel axes");
  if (NumberOr0(in, "fisheye") != 0.0) {
    throw fail("fisheye " + in["fisheye"].dump() + ": rigsim reads DGP's Brown-Conrady (OpenCV) cameras only");
  }
  if (NumberOr0(in, "equirectangular") != 0.0) throw fail("an equirectangular camera has no rigsim model");
  for (const char* key : {"s1", "s2", "s3", "s4", "taux", "tauy", "alpha", "beta", "w", "xi"}) {
    if (NumberOr0(in, key) != 0.0) throw fail(std::string(key) + " is not 0: rigsim has no thin-prism, tilted, UCM, FOV or double-sphere model");
  }
  std::vector<double> params = {NumberOr0(in, "fx"), NumberOr0(in, "fy"), NumberOr0(in, "cx"), NumberOr0(in, "cy")};
  const std::vector<double> brown = {NumberOr0(in, "k1"), NumberOr0(in, "k2"), NumberOr0(in, "p1"), NumberOr0(in, "p2")};
  const std::vector<double> rational = {NumberOr0(in, "k3"), NumberOr0(in, "k4"), NumberOr0(in, "k5"), NumberOr0(in, "k6")};
  const auto zero = [](const std::vector<double>& v) { return std::all_of(v.begin(), v.end(), [](double x) { return x == 0.0; }); };
  CameraModelId model = CameraModelId::kPinhole;
  if (!zero(rational)) {
    model = CameraModelId::kFullOpenCV;
    params.insert(params.end(), brown.begin(), brown.end());
    params.insert(params.end(), rational.begin(), rational.end());
  } else if (!zero(brown)) {
    model = CameraModelId::kOpenCV;
    params.insert(params.end(), brown.begin(), brown.end());
  }
  try {
    return Camera(model, width, height, params);
  } catch (const std::invalid_argument& e) {
    throw fail(e.what());
  }
}

// Per camera name, the image size of its datums in the scene_*.json beside calibration/ (DGP's
// scene layout: SCENE/scene_<hash>.json, SCENE/calibration/<hash>.json).
std::map<std::string, std::pair<int, int>> ImageSizes(const fs::path& calibration, std::string* looked_in) {
  std::map<std::string, std::pair<int, int>> sizes;
  const fs::path scene_dir = fs::absolute(calibration).parent_path().parent_path();
  *looked_in = scene_dir.string();
  if (!fs::is_directory(scene_dir)) return sizes;
  std::vector<fs::path> scenes;
  for (const auto& e : fs::directory_iterator(scene_dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("scene", 0) == 0 && e.path().extension() == ".json") scenes.push_back(e.path());
  }
  std::sort(scenes.begin(), scenes.end());
  for (const fs::path& scene_path : scenes) {
    const json_io::Json scene = json_io::ReadFile(scene_path);
    for (const json_io::Json& d : scene.value("data", json_io::Json::array())) {
      if (!d.is_object() || !d.contains("datum") || !d["datum"].is_object() || !d["datum"].contains("image")) continue;
      const json_io::Json& image = d["datum"]["image"];
      const std::string name = d.value("id", json_io::Json::object()).value("name", "");
      if (!name.empty() && image.value("width", json_io::Json()).is_number_integer() &&
          image.value("height", json_io::Json()).is_number_integer() && !sizes.count(name)) {
        sizes[name] = {image["width"].get<int>(), image["height"].get<int>()};
      }
    }
  }
  return sizes;
}

}  // namespace

Rig RigFromDgpCalibration(const fs::path& path) {
  const std::string file = path.string();
  const json_io::Json calibration = json_io::ReadFile(path);
  const auto names = json_io::Get<std::vector<std::string>>(calibration, "names", file, "calibration");
  const json_io::Json intrinsics = json_io::Get<json_io::Json>(calibration, "intrinsics", file, "calibration");
  const json_io::Json extrinsics = json_io::Get<json_io::Json>(calibration, "extrinsics", file, "calibration");
  if (!intrinsics.is_array() || !extrinsics.is_array() || intrinsics.size() != names.size() ||
      extrinsics.size() != names.size()) {
    throw std::runtime_error(file + ": \"names\", \"intrinsics\" and \"extrinsics\" must be lists of the same length");
  }
  std::string looked_in;
  const std::map<std::string, std::pair<int, int>> sizes = ImageSizes(path, &looked_in);
  Rig rig;
  std::vector<Rigid3d> vehicle_from_cam;
  for (size_t i = 0; i < names.size(); ++i) {
    if (NumberOr0(intrinsics[i], "fx") == 0.0 && NumberOr0(intrinsics[i], "fy") == 0.0) continue;  // not a camera
    const std::string where = "camera '" + names[i] + "'";
    const auto size = sizes.find(names[i]);
    if (size == sizes.end()) {
      throw std::runtime_error(file + ": " + where + ": a DGP calibration records no image size, and no scene_*.json in " +
                               looked_in + " (the folder above calibration/) has an image of this camera");
    }
    RigCamera rc;
    rc.name = names[i];
    rc.camera = DgpCamera(intrinsics[i], size->second.first, size->second.second, file, where);
    vehicle_from_cam.push_back(DgpPose(extrinsics[i], file, where + " extrinsics"));
    rig.cameras.push_back(std::move(rc));
  }
  if (rig.cameras.empty()) throw std::runtime_error(file + ": no camera (every sensor's fx and fy are 0)");
  // The rig frame is the first camera's: cam_from_rig = inv(vehicle_from_cam) * vehicle_from_cam0.
  for (size_t i = 0; i < rig.cameras.size(); ++i) rig.cameras[i].cam_from_rig = vehicle_from_cam[i].Inverse() * vehicle_from_cam[0];
  return rig;
}

}  // namespace rigsim
