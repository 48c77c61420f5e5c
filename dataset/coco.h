// Instance annotations in the COCO format (https://cocodataset.org/#format-data, "Object
// Detection"), so that COCO tools (pycocotools, detectron2, mmdetection) load a rendered dataset's
// instances: one image per camera and frame, one annotation per instance and class seen in it,
// with its 2D box, area and mask.
//
// Conventions: image file_name is "<cam>/<frame>.png" under the dataset's images/ folder (as
// COLMAP's export names them); bbox is [x, y, width, height] in COCO's pixel convention (pixel
// (0, 0) covers [0, 1) x [0, 1), so a box from column x0 to x1 inclusive is [x0, ., x1 - x0 + 1, .]);
// segmentation is a compressed RLE ({"size": [height, width], "counts": "..."}, column-major, as
// pycocotools' mask.encode writes it); area is the mask's pixel count. category_id is the Cityscapes
// label id (labels/cityscapes.h), every Cityscapes class is listed with its name and category as
// supercategory. Extra field: instance_id, the id in instances/<cam>/<frame>.png. A node with
// parts of several classes gives one annotation per class.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/image.h"

namespace rigsim {

// COCO's compressed RLE of a column-major run-length list (pycocotools rleToString).
std::string CocoRleString(const std::vector<uint32_t>& counts);
// Its inverse (pycocotools rleFrString). Throws std::invalid_argument on a malformed string.
std::vector<uint32_t> CocoRleCounts(const std::string& text);

class CocoInstances {
 public:
  // Adds one view: its labels and instances (same size); `file_name` as described above.
  void AddImage(const std::string& file_name, const ImageU8& labels, const ImageU16& instances);
  // Adds every image and annotation of another instances_coco.json (ToJson's), after these, with
  // the ids they would have had if added here one by one.
  void AddAll(const nlohmann::json& coco);
  nlohmann::json ToJson() const;

 private:
  nlohmann::json images_ = nlohmann::json::array();
  nlohmann::json annotations_ = nlohmann::json::array();
};

}  // namespace rigsim
