#include "exports/colmap.h"

#include <algorithm>
#include <fstream>
#include <locale>
#include <sstream>
#include <stdexcept>

#include "exports/export_common.h"
#include "geometry/json_io.h"

namespace rigsim {

using exports_internal::Num;

namespace {

// COLMAP puts the centre of the top-left pixel at (0.5, 0.5) where rigsim has it at (0, 0): its
// principal point is rigsim's plus this.
constexpr double kColmapPixelCentreShift = 0.5;

// Whether a quaternion read from a model's text is a rotation: within a factor of 2 of unit length
// (Rigid3d normalises it), so that rounding passes and a zero or a typo does not.
bool NearUnitQuaternion(const Eigen::Quaterniond& q) { return q.norm() > 0.5 && q.norm() < 2.0; }

// COLMAP's intrinsics of `cam`: model name and parameters.
std::vector<double> ColmapParams(const Camera& cam) {
  std::vector<double> p = cam.params();
  p[2] += kColmapPixelCentreShift;
  p[3] += kColmapPixelCentreShift;
  return p;
}

// One image of the model: its camera (index in the rig), frame and name.
struct ModelImage {
  size_t camera;
  const Frame* frame;
  std::string name;
};

// The model's images in id order (ids 1..): camera by camera in rig order, each camera's images in
// the order of their names, as COLMAP's feature_extractor numbers them (see colmap.h).
std::vector<ModelImage> ImagesInIdOrder(const Rig& rig, const FramesFile& frames, const ColmapExportOptions& options) {
  std::vector<ModelImage> images;
  for (size_t c = 0; c < rig.cameras.size(); ++c) {
    const size_t first = images.size();
    for (const Frame& f : frames.frames) images.push_back({c, &f, options.image_name(rig.cameras[c].name, f.name)});
    std::sort(images.begin() + first, images.end(), [](const ModelImage& a, const ModelImage& b) { return a.name < b.name; });
  }
  return images;
}

std::string TriangulateScript(const Rig& rig, const std::vector<ModelImage>& images) {
  std::string s = R"SH(#!/usr/bin/env bash
# COLMAP's points at the poses of this model, with COLMAP's own tools (its FAQ: "Reconstruct
# sparse/dense model from known camera poses"). Written by rigsim export and calibrate.
#   bash triangulate.sh IMAGES_DIR OUT_DIR
# IMAGES_DIR: the dataset's images/ folder. OUT_DIR (a new or empty folder) gets database.db,
# model/ (this model with the points, COLMAP text) and colmap.log. COLMAP_USE_GPU=1 extracts and
# matches on the GPU.
# Each camera's images get their features in a run of their own, listed in this model's id order,
# with the camera's intrinsics and one thread: the database then gives every image and camera the
# id this model has, which point_triangulator requires.
set -euo pipefail
if [ $# -ne 2 ]; then
  echo "usage: bash $0 IMAGES_DIR OUT_DIR" >&2
  exit 1
fi
model=$(cd "$(dirname "$0")" && pwd)
images=$1
out=$2
if ! command -v colmap > /dev/null; then
  echo "triangulate.sh: colmap is not on the PATH (Debian and Ubuntu: apt-get install colmap)" >&2
  exit 1
fi
if [ ! -d "$images" ]; then
  echo "triangulate.sh: $images: no such folder (give the dataset's images/ folder)" >&2
  exit 1
fi
if [ -e "$out" ] && [ -n "$(ls -A "$out")" ]; then
  echo "triangulate.sh: $out: not empty; give a new or empty folder" >&2
  exit 1
fi
mkdir -p "$out/model"
gpu=${COLMAP_USE_GPU:-0}
run() {
  if ! "$@" >> "$out/colmap.log" 2>&1; then
    tail -n 20 "$out/colmap.log" >&2
    echo "triangulate.sh: colmap $2 failed; its whole output: $out/colmap.log" >&2
    exit 1
  fi
}
# extract MODEL PARAMS: the images listed on stdin, as one camera, in the order given.
extract() {
  cat > "$out/image_list.txt"
  run colmap feature_extractor --database_path "$out/database.db" --image_path "$images" \
    --image_list_path "$out/image_list.txt" --ImageReader.single_camera 1 --ImageReader.camera_model "$1" \
    --ImageReader.camera_params "$2" --SiftExtraction.use_gpu "$gpu" --SiftExtraction.num_threads 1
}
)SH";
  size_t k = 0;
  for (size_t c = 0; c < rig.cameras.size(); ++c) {
    const Camera& cam = rig.cameras[c].camera;
    std::string params;
    for (double v : ColmapParams(cam)) {
      if (!params.empty()) params += ',';
      params += Num(v);
    }
    s.append("# ").append(rig.cameras[c].name).append("\n");
    s.append("extract ").append(CameraModelName(cam.model())).append(" ").append(params).append(" << 'END_OF_LIST'\n");
    for (; k < images.size() && images[k].camera == c; ++k) s.append(images[k].name).append("\n");
    s += "END_OF_LIST\n";
  }
  s += R"SH(rm "$out/image_list.txt"
run colmap exhaustive_matcher --database_path "$out/database.db" --SiftMatching.use_gpu "$gpu"
run colmap point_triangulator --database_path "$out/database.db" --image_path "$images" --input_path "$model" \
  --output_path "$out/model" --clear_points 1
run colmap model_converter --input_path "$out/model" --output_path "$out/model" --output_type TXT
rm "$out/model/cameras.bin" "$out/model/images.bin" "$out/model/points3D.bin"
echo "triangulate.sh: $(grep -c '^[0-9]' "$out/model/points3D.txt") points in $out/model"
)SH";
  return s;
}

}  // namespace

ColmapModelText ColmapModel(const Rig& rig, const FramesFile& frames, const ColmapExportOptions& options) {
  exports_internal::RequireAllPoses(rig, "colmap");
  exports_internal::RequireFramePoses(frames, "colmap");
  ColmapModelText out;
  out.cameras = "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n";
  out.cameras += "# Number of cameras: " + std::to_string(rig.cameras.size()) + "\n";
  if (options.gauge) out.cameras += EstimateGaugeComment(*options.gauge);
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const Camera& cam = rig.cameras[i].camera;
    out.cameras += std::to_string(i + 1) + " " + std::string(CameraModelName(cam.model())) + " " +
                   std::to_string(cam.width()) + " " + std::to_string(cam.height());
    for (double v : ColmapParams(cam)) out.cameras.append(" ").append(Num(v));
    out.cameras += "\n";
  }
  const std::vector<ModelImage> images = ImagesInIdOrder(rig, frames, options);
  out.images = "# Image list with two lines of data per image:\n"
               "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
               "#   POINTS2D[] as (X, Y, POINT3D_ID)\n";
  out.images += "# Number of images: " + std::to_string(images.size()) + ", mean observations per image: 0\n";
  if (options.gauge) out.images += EstimateGaugeComment(*options.gauge);
  for (size_t k = 0; k < images.size(); ++k) {
    const ModelImage& im = images[k];
    const Rigid3d cam_from_world = *rig.cameras[im.camera].cam_from_rig * *im.frame->rig_from_world;
    Eigen::Quaterniond q = cam_from_world.rotation.normalized();
    if (q.w() < 0) q.coeffs() *= -1.0;  // one canonical sign
    const Eigen::Vector3d& t = cam_from_world.translation;
    out.images += std::to_string(k + 1) + " " + Num(q.w()) + " " + Num(q.x()) + " " + Num(q.y()) + " " + Num(q.z()) + " " +
                  Num(t.x()) + " " + Num(t.y()) + " " + Num(t.z()) + " " + std::to_string(im.camera + 1) + " " + im.name + "\n\n";
  }
  out.points3d = "# 3D point list with one line of data per point:\n"
                 "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
                 "# Number of points: 0, mean track length: 0\n";
  out.triangulate_script = TriangulateScript(rig, images);
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
  json_io::WriteTextAtomic(dir / "triangulate.sh", text.triangulate_script);
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
    if (!NearUnitQuaternion(q)) {
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

namespace {

// The data lines of a COLMAP text file with their line numbers ('#' comments and blank lines left
// out).
std::vector<std::pair<int, std::string>> DataLines(const std::filesystem::path& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot read the COLMAP model's " + what);
  std::vector<std::pair<int, std::string>> lines;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    lines.push_back({number, line});
  }
  return lines;
}

}  // namespace

std::vector<ColmapCamera> ReadColmapCameras(const std::filesystem::path& cameras_txt) {
  std::vector<ColmapCamera> cameras;
  for (const auto& [number, line] : DataLines(cameras_txt, "cameras")) {
    std::istringstream fields(line);
    fields.imbue(std::locale::classic());
    ColmapCamera camera;
    if (!(fields >> camera.camera_id >> camera.model >> camera.width >> camera.height)) {
      throw std::runtime_error(cameras_txt.string() + ":" + std::to_string(number) +
                               ": not a camera line (CAMERA_ID MODEL WIDTH HEIGHT PARAMS[])");
    }
    std::string value;
    while (fields >> value) {
      try {
        size_t used = 0;
        camera.params.push_back(std::stod(value, &used));
        if (used != value.size()) throw std::invalid_argument(value);
      } catch (const std::exception&) {
        throw std::runtime_error(cameras_txt.string() + ":" + std::to_string(number) + ": parameter '" + value +
                                 "' is not a number");
      }
    }
    cameras.push_back(std::move(camera));
  }
  return cameras;
}

Camera CameraFromColmap(const ColmapCamera& c) {
  // COLMAP's models rigsim has, with the parameters in rigsim's order: {rigsim model, count,
  // where each rigsim parameter comes from (-1: 0), the focal length repeated where COLMAP has one}.
  struct Mapping {
    const char* name;
    CameraModelId model;
    size_t count;
    std::vector<int> from;
  };
  static const Mapping kMappings[] = {
      {"PINHOLE", CameraModelId::kPinhole, 4, {0, 1, 2, 3}},
      {"OPENCV", CameraModelId::kOpenCV, 8, {0, 1, 2, 3, 4, 5, 6, 7}},
      {"FULL_OPENCV", CameraModelId::kFullOpenCV, 12, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}},
      {"OPENCV_FISHEYE", CameraModelId::kOpenCVFisheye, 8, {0, 1, 2, 3, 4, 5, 6, 7}},
      {"SIMPLE_PINHOLE", CameraModelId::kPinhole, 3, {0, 0, 1, 2}},
      {"SIMPLE_RADIAL", CameraModelId::kOpenCV, 4, {0, 0, 1, 2, 3, -1, -1, -1}},
      {"RADIAL", CameraModelId::kOpenCV, 5, {0, 0, 1, 2, 3, 4, -1, -1}},
      {"SIMPLE_RADIAL_FISHEYE", CameraModelId::kOpenCVFisheye, 4, {0, 0, 1, 2, 3, -1, -1, -1}},
      {"RADIAL_FISHEYE", CameraModelId::kOpenCVFisheye, 5, {0, 0, 1, 2, 3, 4, -1, -1}},
  };
  for (const Mapping& m : kMappings) {
    if (c.model != m.name) continue;
    if (c.params.size() != m.count) {
      throw std::invalid_argument(c.model + " has " + std::to_string(m.count) + " parameters, not " +
                                  std::to_string(c.params.size()));
    }
    std::vector<double> params;
    for (int k : m.from) params.push_back(k < 0 ? 0.0 : c.params[k]);
    params[2] -= kColmapPixelCentreShift;
    params[3] -= kColmapPixelCentreShift;
    return Camera(m.model, c.width, c.height, params);
  }
  std::string names;
  for (const Mapping& m : kMappings) names += (names.empty() ? "" : ", ") + std::string(m.name);
  throw std::invalid_argument("model " + c.model + " has no rigsim equivalent (rigsim reads " + names + ")");
}

std::vector<ColmapRig> ReadColmapRigs(const std::filesystem::path& rigs_txt) {
  std::vector<ColmapRig> rigs;
  for (const auto& [number, line] : DataLines(rigs_txt, "rigs")) {
    const auto fail = [&, number = number](const std::string& what) {
      return std::runtime_error(rigs_txt.string() + ":" + std::to_string(number) + ": " + what);
    };
    std::istringstream fields(line);
    fields.imbue(std::locale::classic());
    ColmapRig rig;
    int num_sensors = 0;
    if (!(fields >> rig.rig_id >> num_sensors) || num_sensors < 0) {
      throw fail("not a rig line (RIG_ID NUM_SENSORS REF_SENSOR_TYPE REF_SENSOR_ID SENSORS[])");
    }
    for (int k = 0; k < num_sensors; ++k) {
      ColmapRig::Sensor sensor;
      if (!(fields >> sensor.type >> sensor.sensor_id)) throw fail("sensor " + std::to_string(k + 1) + " is not SENSOR_TYPE SENSOR_ID");
      if (k == 0) {
        sensor.sensor_from_rig = Rigid3d();  // the reference sensor defines the rig frame
      } else {
        int has_pose = 0;
        if (!(fields >> has_pose) || (has_pose != 0 && has_pose != 1)) {
          throw fail("sensor " + std::to_string(k + 1) + ": HAS_POSE must be 0 or 1");
        }
        if (has_pose == 1) {
          double qw, qx, qy, qz, tx, ty, tz;
          if (!(fields >> qw >> qx >> qy >> qz >> tx >> ty >> tz)) {
            throw fail("sensor " + std::to_string(k + 1) + ": its pose is not QW QX QY QZ TX TY TZ");
          }
          const Eigen::Quaterniond q(qw, qx, qy, qz);
          if (!NearUnitQuaternion(q)) throw fail("sensor " + std::to_string(k + 1) + ": the rotation is not a unit quaternion");
          sensor.sensor_from_rig = Rigid3d(q, Eigen::Vector3d(tx, ty, tz));
        }
      }
      rig.sensors.push_back(std::move(sensor));
    }
    std::string rest;
    if (fields >> rest) throw fail("more values than its " + std::to_string(num_sensors) + " sensors take");
    rigs.push_back(std::move(rig));
  }
  return rigs;
}

}  // namespace rigsim
