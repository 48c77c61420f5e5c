#include "exports/opencv_yaml.h"

#include <string>
#include <vector>

#include "exports/export_common.h"
#include "geometry/json_io.h"

namespace rigsim {
namespace {

// A real number as OpenCV writes it: always with a '.' or an exponent, so it reads as a real.
std::string Real(double v) {
  std::string s = exports_internal::Num(v);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".";
  return s;
}

std::string Matrix(const std::string& indent, const std::string& key, int rows, int cols, const std::vector<double>& data) {
  std::string s = indent + key + ": !!opencv-matrix\n";
  s += indent + "   rows: " + std::to_string(rows) + "\n";
  s += indent + "   cols: " + std::to_string(cols) + "\n";
  s += indent + "   dt: d\n";
  s += indent + "   data: [ ";
  for (size_t i = 0; i < data.size(); ++i) s += (i ? ", " : "") + Real(data[i]);
  return s + " ]\n";
}

std::string Quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

std::string OpenCvRigYaml(const Rig& rig, const std::optional<EstimateGauge>& gauge) {
  std::string out = "%YAML:1.0\n---\n";
  if (gauge) out += EstimateGaugeComment(*gauge);
  out += "num_cameras: " + std::to_string(rig.cameras.size()) + "\n";
  out += "cameras:\n";
  const std::string in = "      ";
  for (const RigCamera& rc : rig.cameras) {
    const Camera& cam = rc.camera;
    const std::vector<double>& p = cam.params();
    std::vector<double> dist(p.begin() + 4, p.end());
    if (cam.model() == CameraModelId::kPinhole) dist = {0.0, 0.0, 0.0, 0.0};
    out += "   -\n";
    out += in + "name: " + Quoted(rc.name) + "\n";
    out += in + "model: " + Quoted(std::string(CameraModelName(cam.model()))) + "\n";
    out += in + "fisheye: " + std::string(IsFisheyeModel(cam.model()) ? "1" : "0") + "\n";
    out += in + "image_width: " + std::to_string(cam.width()) + "\n";
    out += in + "image_height: " + std::to_string(cam.height()) + "\n";
    out += Matrix(in, "camera_matrix", 3, 3, {p[0], 0.0, p[2], 0.0, p[1], p[3], 0.0, 0.0, 1.0});
    out += Matrix(in, "distortion_coefficients", 1, int(dist.size()), dist);
    if (rc.cam_from_rig) {
      const Eigen::Matrix3d r = rc.cam_from_rig->RotationMatrix();
      const Eigen::Vector3d& t = rc.cam_from_rig->translation;
      out += Matrix(in, "R", 3, 3, {r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2)});
      out += Matrix(in, "T", 3, 1, {t.x(), t.y(), t.z()});
    }
  }
  return out;
}

void WriteOpenCvRigYaml(const Rig& rig, const std::filesystem::path& path, const std::optional<EstimateGauge>& gauge) {
  json_io::WriteTextAtomic(path, OpenCvRigYaml(rig, gauge));
}

}  // namespace rigsim
