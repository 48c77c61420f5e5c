// The on-disk dataset layout that render writes and calibrate reads:
//
//   DATASET/rig.json                        geometry/rig.h
//   DATASET/frames.json                     per frame: name, rig_from_world, timestamp; scene, seed
//   DATASET/images/<cam>/<frame>.png        RGB, 8 bit (COLMAP's per-camera image prefix)
//   DATASET/labels/<cam>/<frame>.png        uint8 Cityscapes label ids
//   DATASET/labels_color/<cam>/<frame>.png  colour preview of the labels
//   DATASET/instances/<cam>/<frame>.png     uint16 instance ids, 0 = none
//   DATASET/depth/<cam>/<frame>.exr         float32 range along the pixel's ray (m), 0 = no surface
//   DATASET/overlap.json                    ground-truth co-visibility per camera pair
//   Only when asked for (docs/datasets.md): depth_color/ instances_color/ normals/
//   correspondence/<a>/<b>/ flow/ per camera and frame, instances_coco.json; poses.json when
//   cameras capture over time.
//   DATASET/photometric.json                per-camera exposure, white balance, vignetting, noise
//                                           drawn for the images (only when render varied them;
//                                           renderer/photometric.h)
//   DATASET/sensor.json                     the sensor preset, defocus and JPEG the images went
//                                           through (only with render --sensor other than ideal;
//                                           renderer/sensor_model.h)
//
// A real-photo dataset has rig.json (intrinsics, no poses), frames.json may be absent (frames
// are then the image file stems found for the first camera), and labels/ is optional.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dataset/output_folder.h"  // StagedOutput, for the commands that write datasets
#include "geometry/rigid3.h"

namespace rigsim {

struct Frame {
  std::string name;                       // file stem, e.g. "000000"
  std::optional<Rigid3d> rig_from_world;  // known for rendered data
  double timestamp_s = 0.0;
};

struct FramesFile {
  std::vector<Frame> frames;
  std::string scene;          // scene file the frames were rendered from
  std::string label_rules;    // label-rules file that classified the scene, if any
  uint64_t seed = 0;
  std::string tool_version;
};

FramesFile FramesFromJsonText(const std::string& text, const std::string& source);
std::string FramesToJsonText(const FramesFile& frames);
FramesFile ReadFrames(const std::filesystem::path& path);
void WriteFrames(const FramesFile& frames, const std::filesystem::path& path);

// Paths inside a dataset folder.
class DatasetLayout {
 public:
  explicit DatasetLayout(std::filesystem::path root) : root_(std::move(root)) {}
  const std::filesystem::path& root() const { return root_; }
  std::filesystem::path RigJson() const { return root_ / "rig.json"; }
  std::filesystem::path FramesJson() const { return root_ / "frames.json"; }
  std::filesystem::path OverlapJson() const { return root_ / "overlap.json"; }
  std::filesystem::path PhotometricJson() const { return root_ / "photometric.json"; }
  std::filesystem::path SensorJson() const { return root_ / "sensor.json"; }
  std::filesystem::path EvaluationJson() const { return root_ / "evaluation.json"; }
  std::filesystem::path Image(const std::string& cam, const std::string& frame) const;
  std::filesystem::path Label(const std::string& cam, const std::string& frame) const;
  std::filesystem::path LabelColor(const std::string& cam, const std::string& frame) const;
  std::filesystem::path Instance(const std::string& cam, const std::string& frame) const;
  std::filesystem::path Depth(const std::string& cam, const std::string& frame) const;
  // Written only when asked for (render --previews, --normals, --correspondence, --coco) or when
  // the rig's cameras capture over time (poses.json).
  std::filesystem::path DepthColor(const std::string& cam, const std::string& frame) const;
  std::filesystem::path InstanceColor(const std::string& cam, const std::string& frame) const;
  std::filesystem::path Normal(const std::string& cam, const std::string& frame) const;
  // Camera a's pixels in camera b at the same frame.
  std::filesystem::path Correspondence(const std::string& cam_a, const std::string& cam_b, const std::string& frame) const;
  // The camera's pixels at `frame` in its image of the next frame.
  std::filesystem::path Flow(const std::string& cam, const std::string& frame) const;
  std::filesystem::path PosesJson() const { return root_ / "poses.json"; }
  std::filesystem::path CocoJson() const { return root_ / "instances_coco.json"; }

  // Finds the image of a frame whatever its extension (.png, .jpg, .jpeg, .tif, .tiff, .exr, and
  // .PNG, .JPG, .JPEG); nullopt if absent.
  std::optional<std::filesystem::path> FindImage(const std::string& cam, const std::string& frame) const;
  // FindImage, or a std::runtime_error naming the camera, the frame and the extensions tried (or,
  // when images/<cam>/ is missing, NoCameraFolderMessage).
  std::filesystem::path RequireImage(const std::string& cam, const std::string& frame) const;
  // The image's name relative to images/, "<cam>/<frame><ext>" with the extension of the file
  // found, ".png" (what render writes) when there is none: what COLMAP and nerfstudio exports name.
  std::string ImageName(const std::string& cam, const std::string& frame) const;
  // Frames of a dataset: from frames.json when present, else the sorted stems of the photos of
  // `cam` (files with an extension FindImage takes; hidden files such as .DS_Store are not photos).
  FramesFile ReadFramesOrScan(const std::string& first_camera) const;

 private:
  std::filesystem::path root_;
};

// The error for a camera of rig.json without its folder `parent`/<cam> (of `what`: "photos",
// "label images"): what the folder must be called, the nearest folder there is ("did you mean")
// and the folders `parent` holds.
std::string NoCameraFolderMessage(const std::filesystem::path& parent, const std::string& cam, const std::string& what);

}  // namespace rigsim
