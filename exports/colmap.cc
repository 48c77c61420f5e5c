#include "exports/colmap.h"

#include <stdexcept>

#include "exports/export_common.h"
#include "geometry/json_io.h"

namespace rigsim {

using exports_internal::Num;

ColmapModelText ColmapModel(const Rig& rig, const FramesFile& frames, const ColmapExportOptions& options) {
  exports_internal::RequireAllPoses(rig, "colmap");
  exports_internal::RequireFramePoses(frames, "colmap");
  ColmapModelText out;
  out.cameras = "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n";
  out.cameras += "# Number of cameras: " + std::to_string(rig.cameras.size()) + "\n";
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const Camera& cam = rig.cameras[i].camera;
    std::vector<double> p = cam.params();
    p[2] += 0.5;  // COLMAP: centre of the top-left pixel at (0.5, 0.5)
    p[3] += 0.5;
    out.cameras += std::to_string(i + 1) + " " + std::string(CameraModelName(cam.model())) + " " +
                   std::to_string(cam.width()) + " " + std::to_string(cam.height());
    for (double v : p) out.cameras += " " + Num(v);
    out.cameras += "\n";
  }
  const size_t num_images = rig.cameras.size() * frames.frames.size();
  out.images = "# Image list with two lines of data per image:\n"
               "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
               "#   POINTS2D[] as (X, Y, POINT3D_ID)\n";
  out.images += "# Number of images: " + std::to_string(num_images) + ", mean observations per image: 0\n";
  size_t image_id = 1;
  for (const Frame& f : frames.frames) {
    for (size_t c = 0; c < rig.cameras.size(); ++c, ++image_id) {
      const RigCamera& rc = rig.cameras[c];
      const Rigid3d cam_from_world = *rc.cam_from_rig * *f.rig_from_world;
      Eigen::Quaterniond q = cam_from_world.rotation.normalized();
      if (q.w() < 0) q.coeffs() *= -1.0;  // one canonical sign
      const Eigen::Vector3d& t = cam_from_world.translation;
      out.images += std::to_string(image_id) + " " + Num(q.w()) + " " + Num(q.x()) + " " + Num(q.y()) + " " + Num(q.z()) +
                    " " + Num(t.x()) + " " + Num(t.y()) + " " + Num(t.z()) + " " + std::to_string(c + 1) + " " +
                    options.image_name(rc.name, f.name) + "\n\n";
    }
  }
  out.points3d = "# 3D point list with one line of data per point:\n"
                 "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
                 "# Number of points: 0, mean track length: 0\n";
  return out;
}

void WriteColmapModel(const Rig& rig, const FramesFile& frames, const std::filesystem::path& dir,
                      const ColmapExportOptions& options) {
  const ColmapModelText text = ColmapModel(rig, frames, options);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir.string() + ": cannot create folder: " + ec.message());
  json_io::WriteTextAtomic(dir / "cameras.txt", text.cameras);
  json_io::WriteTextAtomic(dir / "images.txt", text.images);
  json_io::WriteTextAtomic(dir / "points3D.txt", text.points3d);
}

}  // namespace rigsim
