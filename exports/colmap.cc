#include "exports/colmap.h"

#include <algorithm>
#include <fstream>
#include <sstream>
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

std::vector<ColmapImage> ReadColmapImages(const std::filesystem::path& images_txt) {
  std::ifstream in(images_txt);
  if (!in) throw std::runtime_error(images_txt.string() + ": cannot read the COLMAP model's images");
  std::vector<ColmapImage> images;
  std::string line;
  int line_number = 0;
  bool pose_line = true;  // pose and points lines alternate; comments do not count
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty() && line[0] == '#') continue;
    if (!pose_line) {
      pose_line = true;
      continue;
    }
    if (line.find_first_not_of(" \t") == std::string::npos) continue;  // trailing blank lines
    std::istringstream fields(line);
    ColmapImage image;
    double qw, qx, qy, qz, tx, ty, tz;
    if (!(fields >> image.image_id >> qw >> qx >> qy >> qz >> tx >> ty >> tz >> image.camera_id) ||
        !std::getline(fields >> std::ws, image.name) || image.name.empty()) {
      throw std::runtime_error(images_txt.string() + ":" + std::to_string(line_number) +
                               ": not an image line (IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME)");
    }
    const Eigen::Quaterniond q(qw, qx, qy, qz);
    if (!(q.norm() > 0.5 && q.norm() < 2.0)) {
      throw std::runtime_error(images_txt.string() + ":" + std::to_string(line_number) + ": the rotation is not a unit quaternion");
    }
    image.cam_from_world = Rigid3d(q, Eigen::Vector3d(tx, ty, tz));
    images.push_back(std::move(image));
    pose_line = false;
  }
  return images;
}

std::filesystem::path FindColmapTextModel(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  if (fs::is_regular_file(path) && path.filename() == "images.txt") return path.parent_path();
  if (!fs::is_directory(path)) throw std::runtime_error(path.string() + ": not a COLMAP model folder");
  if (fs::exists(path / "images.txt")) return path;
  if (fs::exists(path / "images.bin")) {
    throw std::runtime_error(path.string() + ": a binary COLMAP model; convert it first: colmap model_converter " +
                             "--input_path " + path.string() + " --output_path " + path.string() + " --output_type TXT");
  }
  // The mapper's sub-models: take the one with the most images.
  fs::path best;
  size_t best_images = 0;
  std::vector<fs::path> subs;
  for (const auto& e : fs::directory_iterator(path)) subs.push_back(e.path());
  std::sort(subs.begin(), subs.end());
  for (const fs::path& sub : subs) {
    if (!fs::exists(sub / "images.txt")) continue;
    const size_t n = ReadColmapImages(sub / "images.txt").size();
    if (best.empty() || n > best_images) {
      best = sub;
      best_images = n;
    }
  }
  if (best.empty()) throw std::runtime_error(path.string() + ": no images.txt here or in a sub-model folder (0, 1, ...)");
  return best;
}

}  // namespace rigsim
