// nuScenes calibrated_sensor records -> rig. A record (nuScenes' schema, calibrated_sensor.json):
// token, sensor_token, translation [x, y, z] and rotation [w, x, y, z] of the sensor in the ego
// vehicle's frame (x_ego = rotation * x_sensor + translation), camera_intrinsic (3x3, [] for a
// sensor that is not a camera). nuScenes' images are undistorted: every camera is PINHOLE. The
// channel (CAM_FRONT, ...) is sensor.json's, the image size sample_data.json's (both tables beside
// the file); a record may carry "channel", "width" and "height" itself instead.
#include <algorithm>
#include <map>
#include <tuple>
#include <stdexcept>

#include "geometry/json_io.h"
#include "rigs/rig_import.h"

namespace rigsim {

namespace fs = std::filesystem;

namespace {

// nuScenes' camera ring, the front camera first (the rig frame).
constexpr const char* kRingOrder[] = {"CAM_FRONT", "CAM_FRONT_RIGHT", "CAM_BACK_RIGHT", "CAM_BACK", "CAM_BACK_LEFT", "CAM_FRONT_LEFT"};

// Calls f on each record of a nuScenes table (a JSON list), when the file exists.
template <typename F>
void ForEachRecord(const fs::path& table, F&& f) {
  if (!fs::exists(table)) return;
  const json_io::Json records = json_io::ReadFile(table);
  if (!records.is_array()) throw std::runtime_error(table.string() + ": not a nuScenes table (a list of records)");
  for (const json_io::Json& r : records) {
    if (r.is_object()) f(r);
  }
}

std::string TextOf(const json_io::Json& r, const char* key) { return r.contains(key) && r[key].is_string() ? r[key].get<std::string>() : ""; }
int IntOf(const json_io::Json& r, const char* key) { return r.contains(key) && r[key].is_number_integer() ? r[key].get<int>() : 0; }

struct CameraRecord {
  std::string channel;
  Rigid3d ego_from_cam;
  Camera camera;
};

}  // namespace

Rig RigFromNuScenesCalibratedSensors(const fs::path& path) {
  const std::string file = path.string();
  const fs::path dir = path.parent_path();
  const json_io::Json records = json_io::ReadFile(path);
  if (!records.is_array()) throw std::runtime_error(file + ": not nuScenes calibrated_sensor records (a list)");
  std::map<std::string, std::string> channel_of_sensor;
  ForEachRecord(dir / "sensor.json", [&](const json_io::Json& r) { channel_of_sensor[TextOf(r, "token")] = TextOf(r, "channel"); });
  std::map<std::string, std::pair<int, int>> size_of_calibration;
  ForEachRecord(dir / "sample_data.json", [&](const json_io::Json& r) {
    if (IntOf(r, "width") > 0 && IntOf(r, "height") > 0) {
      size_of_calibration.emplace(TextOf(r, "calibrated_sensor_token"), std::make_pair(IntOf(r, "width"), IntOf(r, "height")));
    }
  });
  std::vector<CameraRecord> cameras;
  for (size_t k = 0; k < records.size(); ++k) {
    const json_io::Json& r = records[k];
    const std::string where = "record " + std::to_string(k);
    const json_io::Json intrinsic = json_io::Get<json_io::Json>(r, "camera_intrinsic", file, where);
    if (!intrinsic.is_array() || intrinsic.empty()) continue;  // a lidar or radar
    const std::string token = TextOf(r, "token");
    std::string channel = TextOf(r, "channel");
    if (channel.empty()) {
      const auto it = channel_of_sensor.find(json_io::Get<std::string>(r, "sensor_token", file, where));
      if (it == channel_of_sensor.end()) {
        throw std::runtime_error(file + ": " + where + ": its sensor_token is not in " + (dir / "sensor.json").string() +
                                 " (the camera's channel comes from there, or from a \"channel\" in the record)");
      }
      channel = it->second;
    }
    const std::string cam = "camera '" + channel + "'";
    const auto fail = [&](const std::string& why) { return std::runtime_error(file + ": " + cam + ": " + why); };
    int width = IntOf(r, "width"), height = IntOf(r, "height");
    if (const auto it = size_of_calibration.find(token); (width <= 0 || height <= 0) && it != size_of_calibration.end()) {
      std::tie(width, height) = it->second;
    }
    if (width <= 0 || height <= 0) {
      throw fail("calibrated_sensor records no image size, and no record of " + (dir / "sample_data.json").string() +
                 " has this calibrated_sensor_token; put nuScenes' sample_data.json beside it or add \"width\" and "
                 "\"height\" to the record");
    }
    std::vector<std::vector<double>> k3;
    try {
      k3 = intrinsic.get<std::vector<std::vector<double>>>();
    } catch (const nlohmann::json::exception&) {
      throw fail("camera_intrinsic is not a 3x3 matrix of numbers");
    }
    if (k3.size() != 3 || k3[0].size() != 3 || k3[1].size() != 3 || k3[2].size() != 3) throw fail("camera_intrinsic is not 3x3");
    if (k3[0][1] != 0.0 || k3[1][0] != 0.0 || k3[2][0] != 0.0 || k3[2][1] != 0.0 || k3[2][2] != 1.0) {
      throw fail("camera_intrinsic is not a pinhole K [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (skew or a projective row)");
    }
    const auto t = json_io::Get<std::vector<double>>(r, "translation", file, cam);
    const auto q = json_io::Get<std::vector<double>>(r, "rotation", file, cam);
    if (t.size() != 3 || q.size() != 4) throw fail("translation is [x, y, z] and rotation [w, x, y, z]");
    const Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
    if (!(rotation.norm() > 0.5 && rotation.norm() < 2.0)) throw fail("rotation is not a unit quaternion");
    CameraRecord c;
    c.channel = channel;
    c.ego_from_cam = Rigid3d(rotation, Eigen::Vector3d(t[0], t[1], t[2]));
    try {
      c.camera = Camera(CameraModelId::kPinhole, width, height, {k3[0][0], k3[1][1], k3[0][2], k3[1][2]});
    } catch (const std::invalid_argument& e) {
      throw fail(e.what());
    }
    for (const CameraRecord& other : cameras) {
      if (other.channel == channel) {
        throw fail("calibrated twice: the records hold more than one rig (nuScenes' table has a calibration per log); "
                   "give the records of one log");
      }
    }
    cameras.push_back(std::move(c));
  }
  if (cameras.empty()) throw std::runtime_error(file + ": no camera (no record with a camera_intrinsic)");
  const auto rank = [](const std::string& channel) {
    const auto it = std::find(std::begin(kRingOrder), std::end(kRingOrder), channel);
    return it - std::begin(kRingOrder);
  };
  std::stable_sort(cameras.begin(), cameras.end(), [&](const CameraRecord& a, const CameraRecord& b) { return rank(a.channel) < rank(b.channel); });
  Rig rig;
  for (const CameraRecord& c : cameras) {
    RigCamera rc;
    rc.name = c.channel;
    rc.camera = c.camera;
    // The rig frame is the first camera's: cam_from_rig = inv(ego_from_cam) * ego_from_cam0.
    rc.cam_from_rig = c.ego_from_cam.Inverse() * cameras[0].ego_from_cam;
    rig.cameras.push_back(std::move(rc));
  }
  return rig;
}

}  // namespace rigsim
