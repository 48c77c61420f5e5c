#include "dataset/coco.h"

#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

// The mask a COCO RLE describes (column-major runs of 0s and 1s), as pycocotools' mask.decode.
std::vector<uint8_t> DecodeColumnMajor(const nlohmann::json& rle) {
  const int h = rle["size"][0], w = rle["size"][1];
  std::vector<uint8_t> mask;
  uint8_t value = 0;
  for (uint32_t run : CocoRleCounts(rle["counts"].get<std::string>())) {
    mask.insert(mask.end(), run, value);
    value ^= 1;
  }
  EXPECT_EQ(mask.size(), size_t(w) * h);
  return mask;
}

TEST(CocoRle, MatchesPycocotoolsEncoding) {
  // Counts [4, 2, 5, 1] as pycocotools' rleToString writes them: the first three as they are,
  // the fourth as its difference from two runs back (1 - 2 = -1: 5 bits 11111, '0' + 31 = 'O').
  EXPECT_EQ(CocoRleString({4, 2, 5, 1}), "425O");
  for (const std::vector<uint32_t>& counts :
       {std::vector<uint32_t>{0, 5}, {921600}, {3, 100000, 7, 1, 900000, 2}, {1, 1, 1, 1, 1, 40, 0}}) {
    EXPECT_EQ(CocoRleCounts(CocoRleString(counts)), counts);
  }
  EXPECT_THROW(CocoRleCounts("\x7f"), std::invalid_argument);
}

// The COCO "instances" schema as pycocotools' COCO() and loadRes rely on it, and each annotation
// against the images it came from.
TEST(CocoInstances, PassesTheSchemaAndDescribesEachInstance) {
  ImageU8 labels(6, 4, 1, 23);
  ImageU16 instances(6, 4, 1, 0);
  for (int y = 1; y <= 2; ++y) {
    for (int x = 2; x <= 4; ++x) {
      instances.at(x, y) = 7;
      labels.at(x, y) = 26;  // car
    }
  }
  instances.at(0, 3) = 9;
  labels.at(0, 3) = 11;  // building
  CocoInstances coco;
  coco.AddImage("cam0/000000.png", labels, instances);
  coco.AddImage("cam1/000000.png", ImageU8(6, 4, 1, 23), ImageU16(6, 4, 1, 0));
  const nlohmann::json j = nlohmann::json::parse(coco.ToJson().dump());

  ASSERT_TRUE(j["images"].is_array() && j["annotations"].is_array() && j["categories"].is_array());
  std::set<int> image_ids, category_ids, annotation_ids;
  for (const auto& im : j["images"]) {
    ASSERT_TRUE(im["id"].is_number_integer() && im["file_name"].is_string() && im["width"].is_number_integer() &&
                im["height"].is_number_integer());
    EXPECT_TRUE(image_ids.insert(im["id"].get<int>()).second);
  }
  for (const auto& c : j["categories"]) {
    ASSERT_TRUE(c["id"].is_number_integer() && c["name"].is_string() && c["supercategory"].is_string());
    EXPECT_TRUE(category_ids.insert(c["id"].get<int>()).second);
  }
  ASSERT_EQ(j["annotations"].size(), 2u);
  for (const auto& a : j["annotations"]) {
    EXPECT_TRUE(annotation_ids.insert(a["id"].get<int>()).second);
    EXPECT_TRUE(image_ids.count(a["image_id"].get<int>()));
    EXPECT_TRUE(category_ids.count(a["category_id"].get<int>()));
    ASSERT_TRUE(a["bbox"].is_array() && a["bbox"].size() == 4u);
    EXPECT_EQ(a["iscrowd"], 0);
    // The mask decodes to exactly the instance's pixels; area and box agree with it.
    const std::vector<uint8_t> mask = DecodeColumnMajor(a["segmentation"]);
    const int id = a["instance_id"];
    int area = 0, x0 = 99, y0 = 99, x1 = -1, y1 = -1;
    for (int x = 0; x < 6; ++x) {
      for (int y = 0; y < 4; ++y) {
        const bool in = instances.at(x, y) == id;
        EXPECT_EQ(mask[size_t(y + x * 4)], in ? 1 : 0) << x << "," << y;
        if (!in) continue;
        ++area;
        x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
      }
    }
    EXPECT_EQ(a["area"].get<int>(), area);
    EXPECT_EQ(a["bbox"], nlohmann::json({x0, y0, x1 - x0 + 1, y1 - y0 + 1}));
  }
  EXPECT_EQ(j["annotations"][0]["category_id"], 26);
  EXPECT_EQ(j["annotations"][0]["bbox"], nlohmann::json({2, 1, 3, 2}));
}

}  // namespace
}  // namespace rigsim
