// COLMAP text model export (cameras.txt, images.txt, points3D.txt), one image per camera x frame,
// named "<cam>/<frame><ext>" relative to DATASET/images, so COLMAP runs on the dataset as it is
// (--image_path DATASET/images), and triangulate.sh, which runs COLMAP's own tools on it.
//
//   cameras.txt: CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]   (ids 1..N in rig order)
//   images.txt:  IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME, then an empty POINTS2D line;
//                the pose is cam_from_world = cam_from_rig * rig_from_world. Ids 1.. camera by
//                camera in rig order, each camera's images in the order of their names: the ids
//                COLMAP's feature_extractor gives them when triangulate.sh runs it.
//   points3D.txt: header only.
//   triangulate.sh IMAGES_DIR OUT_DIR: COLMAP's recipe for a model of known poses (its FAQ,
//                "Reconstruct sparse/dense model from known camera poses"): feature_extractor once
//                per camera (that camera's images listed in id order, its intrinsics given, one
//                thread so that the ids follow the list), exhaustive_matcher, point_triangulator
//                on this model; OUT_DIR gets database.db, model/ (text, with the points) and
//                colmap.log. COLMAP's image ids are its database's, so the model's must be the
//                same: the ids COLMAP would give in another order make point_triangulator abort.
//
// Model names and parameter orders are COLMAP's (PINHOLE, OPENCV, FULL_OPENCV, OPENCV_FISHEYE are
// identical in rigsim). COLMAP puts the centre of the top-left pixel at (0.5, 0.5), rigsim at
// (0, 0): cx and cy get +0.5 here, and nowhere else.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dataset/dataset.h"
#include "geometry/estimate_gauge.h"
#include "exports/image_name.h"
#include "geometry/rig.h"

namespace rigsim {

struct ColmapExportOptions {
  // Name in images.txt of camera `cam`'s image of frame `frame`, relative to the images folder;
  // by default "<cam>/<frame>.png" (what render writes). DatasetLayout::ImageName gives the
  // files a dataset has, whatever their extension.
  ImageNameFn image_name = DefaultImageName;
  // An estimate's gauge, said in the header comments of cameras.txt and images.txt.
  std::optional<EstimateGauge> gauge;
};

struct ColmapModelText {
  std::string cameras, images, points3d;
  std::string triangulate_script;  // triangulate.sh
};

// Throws std::invalid_argument when a camera has no cam_from_rig or a frame no rig_from_world.
ColmapModelText ColmapModel(const Rig& rig, const FramesFile& frames, const ColmapExportOptions& options = {});
// Writes cameras.txt, images.txt, points3D.txt and triangulate.sh into `dir` (created if needed).
void WriteColmapModel(const Rig& rig, const FramesFile& frames, const std::filesystem::path& dir,
                      const ColmapExportOptions& options = {});

}  // namespace rigsim

namespace rigsim {

// One registered image of a COLMAP text model.
struct ColmapImage {
  int image_id = 0;
  int camera_id = 0;
  std::string name;  // as in images.txt, e.g. "cam1/000000.png"
  Rigid3d cam_from_world;
};

// The images of a model's images.txt (two lines per image: the pose line, then the points line,
// which may be empty; '#' lines are comments). Throws std::runtime_error naming the file and the
// line when a pose line does not parse.
std::vector<ColmapImage> ReadColmapImages(const std::filesystem::path& images_txt);

// The model folder to read in `path`: `path` itself when it holds images.txt; else, among its
// numbered sub-models (COLMAP's mapper writes sparse/0, sparse/1, ...), the one with the most
// images. Throws std::runtime_error saying what was found instead (a binary model needs
// `colmap model_converter --output_type TXT`).
std::filesystem::path FindColmapTextModel(const std::filesystem::path& path);

// One camera of cameras.txt as COLMAP writes it (its pixel convention: the centre of the top-left
// pixel at (0.5, 0.5)).
struct ColmapCamera {
  int camera_id = 0;
  std::string model;  // COLMAP's model name
  int width = 0, height = 0;
  std::vector<double> params;
};

// The cameras of a model's cameras.txt. Throws std::runtime_error naming the file and the line
// when a line does not parse.
std::vector<ColmapCamera> ReadColmapCameras(const std::filesystem::path& cameras_txt);

// The rigsim camera of a COLMAP camera: cx, cy less 0.5; PINHOLE, OPENCV, FULL_OPENCV and
// OPENCV_FISHEYE as they are, SIMPLE_PINHOLE as PINHOLE, SIMPLE_RADIAL and RADIAL as OPENCV,
// SIMPLE_RADIAL_FISHEYE and RADIAL_FISHEYE as OPENCV_FISHEYE (the other coefficients 0). Throws
// std::invalid_argument saying why for a model rigsim has no equivalent of or a wrong number of
// parameters.
Camera CameraFromColmap(const ColmapCamera& camera);

// One rig of a model's rigs.txt (COLMAP 3.12): its sensors, the reference sensor first (its
// sensor_from_rig is the identity); sensor_from_rig is nullopt where the file gives no pose.
struct ColmapRig {
  int rig_id = 0;
  struct Sensor {
    std::string type;  // "CAMERA", "IMU"
    int sensor_id = 0;
    std::optional<Rigid3d> sensor_from_rig;
  };
  std::vector<Sensor> sensors;
};

// The rigs of a model's rigs.txt
// (RIG_ID NUM_SENSORS REF_SENSOR_TYPE REF_SENSOR_ID [SENSOR_TYPE SENSOR_ID HAS_POSE [QW QX QY QZ TX TY TZ]]...).
// Throws std::runtime_error naming the file and the line when a line does not parse.
std::vector<ColmapRig> ReadColmapRigs(const std::filesystem::path& rigs_txt);

}  // namespace rigsim
