#include "exports/kalibr.h"

#include <algorithm>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "exports/export_common.h"
#include "geometry/json_io.h"

namespace rigsim {

using exports_internal::Num;
using exports_internal::NumList;

std::string KalibrCamchainYaml(const Rig& rig, const std::optional<EstimateGauge>& gauge) {
  exports_internal::RequireAllPoses(rig, "kalibr");
  std::string out = "# Kalibr camchain written by rigsim. T_cn_cnm1 = cam_n_from_cam_{n-1}.\n";
  if (gauge) out += EstimateGaugeComment(*gauge);
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const RigCamera& rc = rig.cameras[i];
    const std::vector<double>& p = rc.camera.params();
    std::string distortion_model = "radtan";
    std::vector<double> coeffs = {0.0, 0.0, 0.0, 0.0};
    switch (rc.camera.model()) {
      case CameraModelId::kPinhole: break;
      case CameraModelId::kOpenCV: coeffs.assign(p.begin() + 4, p.begin() + 8); break;
      case CameraModelId::kFullOpenCV:
        for (int k = 8; k < 12; ++k) {
          if (p[k] != 0.0) {
            throw std::invalid_argument("kalibr export: camera '" + rc.name +
                                        "' is FULL_OPENCV with non-zero k3..k6; Kalibr's radtan has only k1 k2 r1 r2");
          }
        }
        coeffs.assign(p.begin() + 4, p.begin() + 8);
        break;
      case CameraModelId::kOpenCVFisheye:
        distortion_model = "equidistant";
        coeffs.assign(p.begin() + 4, p.begin() + 8);
        break;
    }
    out += "cam" + std::to_string(i) + ":\n";
    if (i > 0) {
      const Rigid3d cn_from_cnm1 = *rc.cam_from_rig * rig.cameras[i - 1].cam_from_rig->Inverse();
      const Eigen::Matrix<double, 3, 4> m = cn_from_cnm1.ToMatrix();
      out += "  T_cn_cnm1:\n";
      for (int r = 0; r < 3; ++r) out += "  - " + NumList({m(r, 0), m(r, 1), m(r, 2), m(r, 3)}) + "\n";
      out += "  - [0, 0, 0, 1]\n";
    }
    out += "  camera_model: pinhole\n";
    out += "  intrinsics: " + NumList({p[0], p[1], p[2], p[3]}) + "\n";
    out += "  distortion_model: " + distortion_model + "\n";
    out += "  distortion_coeffs: " + NumList(coeffs) + "\n";
    out += "  resolution: [" + std::to_string(rc.camera.width()) + ", " + std::to_string(rc.camera.height()) + "]\n";
    out += "  rostopic: /" + rc.name + "/image_raw\n";
  }
  return out;
}

void WriteKalibrCamchain(const Rig& rig, const std::filesystem::path& path, const std::optional<EstimateGauge>& gauge) {
  json_io::WriteTextAtomic(path, KalibrCamchainYaml(rig, gauge));
}

std::vector<KalibrCamera> ReadKalibrCamchain(const std::filesystem::path& path) {
  const std::string file = path.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    throw std::runtime_error(file + ": cannot read the Kalibr camchain");
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(file + ":" + std::to_string(e.mark.line + 1) + ": invalid YAML: " + e.msg);
  }
  if (!root.IsMap() || !root["cam0"]) throw std::runtime_error(file + ": not a Kalibr camchain (no cam0)");
  std::vector<KalibrCamera> cameras;
  Rigid3d previous_from_cam0;
  for (int i = 0;; ++i) {
    const std::string key = "cam" + std::to_string(i);
    const YAML::Node node = root[key];
    if (!node) break;
    const auto fail = [&](const std::string& what) { return std::runtime_error(file + ": " + key + ": " + what); };
    KalibrCamera cam;
    cam.key = key;
    try {
      if (const YAML::Node topic = node["rostopic"]) {
        const std::string t = topic.as<std::string>();  // "/<name>/image_raw"
        const size_t begin = t.find_first_not_of('/');
        const size_t end = t.find('/', begin);
        if (begin != std::string::npos) cam.name = t.substr(begin, end == std::string::npos ? end : end - begin);
      }
      if (const YAML::Node res = node["resolution"]) {
        cam.width = res[0].as<int>();
        cam.height = res[1].as<int>();
      }
      if (const YAML::Node v = node["camera_model"]) cam.camera_model = v.as<std::string>();
      if (const YAML::Node v = node["distortion_model"]) cam.distortion_model = v.as<std::string>();
      if (const YAML::Node v = node["intrinsics"]) cam.intrinsics = v.as<std::vector<double>>();
      if (const YAML::Node v = node["distortion_coeffs"]) cam.distortion_coeffs = v.as<std::vector<double>>();
      Rigid3d cam_from_previous;
      if (i > 0) {
        const YAML::Node t = node["T_cn_cnm1"];
        if (!t || !t.IsSequence() || t.size() != 4) throw fail("T_cn_cnm1 must be a 4x4 matrix (4 rows)");
        Eigen::Matrix3d r;
        Eigen::Vector3d tr;
        for (int row = 0; row < 3; ++row) {
          if (!t[row].IsSequence() || t[row].size() != 4) throw fail("T_cn_cnm1 row " + std::to_string(row) + " must have 4 numbers");
          for (int col = 0; col < 3; ++col) r(row, col) = t[row][col].as<double>();
          tr[row] = t[row][3].as<double>();
        }
        if (!((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() < 1e-3 && r.determinant() > 0)) {
          throw fail("T_cn_cnm1's top-left 3x3 is not a rotation");
        }
        cam_from_previous = Rigid3d(r, tr);
      }
      cam.cam_from_cam0 = cam_from_previous * previous_from_cam0;
    } catch (const YAML::Exception& e) {
      throw fail(std::string("unexpected value: ") + e.msg);
    }
    previous_from_cam0 = cam.cam_from_cam0;
    cameras.push_back(std::move(cam));
  }
  return cameras;
}

Camera KalibrIntrinsics(const KalibrCamera& c) {
  if (c.camera_model != "pinhole") {
    throw std::invalid_argument(
        c.camera_model.empty() ? std::string("no camera_model")
                               : "camera_model '" + c.camera_model + "': rigsim has pinhole cameras only (with radtan, "
                                 "equidistant or no distortion); omni, ds and eucm have no rigsim model");
  }
  if (c.intrinsics.size() != 4) throw std::invalid_argument("intrinsics must be 4 numbers [fu, fv, pu, pv]");
  if (c.width <= 0 || c.height <= 0) throw std::invalid_argument("no resolution [width, height]");
  std::vector<double> params = c.intrinsics;
  const std::string& d = c.distortion_model;
  CameraModelId model = CameraModelId::kPinhole;
  if (d == "radtan" || d == "equidistant") {
    if (c.distortion_coeffs.size() != 4) {
      throw std::invalid_argument("distortion_coeffs of " + d + " must be 4 numbers, not " +
                                  std::to_string(c.distortion_coeffs.size()));
    }
    const bool all_zero = std::all_of(c.distortion_coeffs.begin(), c.distortion_coeffs.end(), [](double v) { return v == 0.0; });
    if (d == "equidistant") {
      model = CameraModelId::kOpenCVFisheye;
    } else if (!all_zero) {
      model = CameraModelId::kOpenCV;
    }
    if (model != CameraModelId::kPinhole) params.insert(params.end(), c.distortion_coeffs.begin(), c.distortion_coeffs.end());
  } else if (d.empty() && !c.distortion_coeffs.empty()) {
    throw std::invalid_argument("distortion_coeffs without a distortion_model (radtan or equidistant)");
  } else if (d != "none" && !d.empty()) {
    throw std::invalid_argument("distortion_model '" + d + "': rigsim reads radtan, equidistant and none (the fov model "
                                "has no rigsim equivalent)");
  }
  return Camera(model, c.width, c.height, params);
}

}  // namespace rigsim
