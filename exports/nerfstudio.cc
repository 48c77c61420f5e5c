#include "exports/nerfstudio.h"

#include <stdexcept>

#include <nlohmann/json.hpp>

#include "exports/export_common.h"
#include "geometry/json_io.h"

namespace rigsim {
namespace {

using Json = nlohmann::ordered_json;

Json FrameEntry(const RigCamera& rc, const Frame& f, const NerfstudioExportOptions& o) {
  const Camera& cam = rc.camera;
  const std::vector<double>& p = cam.params();
  const Rigid3d world_from_cam = (*rc.cam_from_rig * *f.rig_from_world).Inverse();
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = world_from_cam.RotationMatrix() * Eigen::Vector3d(1, -1, -1).asDiagonal();  // GL axes
  m.topRightCorner<3, 1>() = world_from_cam.translation;
  Json tm = Json::array();
  for (int r = 0; r < 4; ++r) tm.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  Json e;
  e["file_path"] = o.image_prefix + "/" + o.image_name(rc.name, f.name);
  e["transform_matrix"] = tm;
  e["fl_x"] = p[0];
  e["fl_y"] = p[1];
  e["cx"] = p[2] + 0.5;  // pixel centres at +0.5
  e["cy"] = p[3] + 0.5;
  e["w"] = cam.width();
  e["h"] = cam.height();
  switch (cam.model()) {
    case CameraModelId::kPinhole:
      e["k1"] = 0.0;
      e["k2"] = 0.0;
      e["p1"] = 0.0;
      e["p2"] = 0.0;
      break;
    case CameraModelId::kOpenCV:
      e["k1"] = p[4];
      e["k2"] = p[5];
      e["p1"] = p[6];
      e["p2"] = p[7];
      break;
    case CameraModelId::kFullOpenCV:
      if (p[9] != 0.0 || p[10] != 0.0 || p[11] != 0.0) {
        throw std::invalid_argument("nerfstudio export: camera '" + rc.name +
                                    "' is FULL_OPENCV with rational terms k4..k6, which nerfstudio's OPENCV model lacks");
      }
      e["k1"] = p[4];
      e["k2"] = p[5];
      e["k3"] = p[8];
      e["p1"] = p[6];
      e["p2"] = p[7];
      break;
    case CameraModelId::kOpenCVFisheye:
      e["k1"] = p[4];
      e["k2"] = p[5];
      e["k3"] = p[6];
      e["k4"] = p[7];
      break;
  }
  return e;
}

}  // namespace

std::vector<NerfstudioFile> NerfstudioTransforms(const Rig& rig, const FramesFile& frames,
                                                 const NerfstudioExportOptions& options) {
  exports_internal::RequireAllPoses(rig, "nerfstudio");
  exports_internal::RequireFramePoses(frames, "nerfstudio");
  Json groups[2];  // 0 = perspective, 1 = fisheye
  for (int g = 0; g < 2; ++g) {
    groups[g]["camera_model"] = g ? "OPENCV_FISHEYE" : "OPENCV";
    groups[g]["frames"] = Json::array();
    if (options.gauge) groups[g]["rigsim_estimate"] = options.gauge->Describe();
  }
  for (const Frame& f : frames.frames) {
    for (const RigCamera& rc : rig.cameras) {
      groups[IsFisheyeModel(rc.camera.model()) ? 1 : 0]["frames"].push_back(FrameEntry(rc, f, options));
    }
  }
  const bool has[2] = {!groups[0]["frames"].empty(), !groups[1]["frames"].empty()};
  std::vector<NerfstudioFile> out;
  for (int g = 0; g < 2; ++g) {
    if (!has[g]) continue;
    std::string name = "transforms.json";
    if (has[0] && has[1]) name = g ? "transforms_fisheye.json" : "transforms_perspective.json";
    out.push_back({name, groups[g].dump(2) + "\n"});
  }
  return out;
}

void WriteNerfstudioTransforms(const Rig& rig, const FramesFile& frames, const std::filesystem::path& dir,
                               const NerfstudioExportOptions& options) {
  const std::vector<NerfstudioFile> files = NerfstudioTransforms(rig, frames, options);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir.string() + ": cannot create folder: " + ec.message());
  for (const NerfstudioFile& f : files) json_io::WriteTextAtomic(dir / f.filename, f.text);
}

}  // namespace rigsim
