#include "exports/kalibr.h"

#include <stdexcept>

#include "exports/export_common.h"
#include "geometry/json_io.h"

namespace rigsim {

using exports_internal::Num;
using exports_internal::NumList;

std::string KalibrCamchainYaml(const Rig& rig) {
  exports_internal::RequireAllPoses(rig, "kalibr");
  std::string out = "# Kalibr camchain written by rigsim. T_cn_cnm1 = cam_n_from_cam_{n-1}.\n";
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

void WriteKalibrCamchain(const Rig& rig, const std::filesystem::path& path) {
  json_io::WriteTextAtomic(path, KalibrCamchainYaml(rig));
}

}  // namespace rigsim
