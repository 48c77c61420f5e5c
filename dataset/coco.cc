#include "dataset/coco.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <utility>

#include "labels/cityscapes.h"

namespace rigsim {

std::string CocoRleString(const std::vector<uint32_t>& counts) {
  std::string s;
  for (size_t i = 0; i < counts.size(); ++i) {
    long long x = counts[i];
    if (i > 2) x -= counts[i - 2];  // deltas from two runs back (runs alternate zeros and ones)
    for (bool more = true; more;) {
      long long c = x & 0x1f;
      x >>= 5;  // arithmetic: negative deltas end at -1
      more = (c & 0x10) ? x != -1 : x != 0;
      if (more) c |= 0x20;
      s.push_back(char(c + 48));
    }
  }
  return s;
}

std::vector<uint32_t> CocoRleCounts(const std::string& text) {
  std::vector<uint32_t> counts;
  size_t p = 0;
  while (p < text.size()) {
    long long x = 0;
    int k = 0;
    for (bool more = true; more; ++k) {
      if (p >= text.size() || k > 12) throw std::invalid_argument("COCO RLE: truncated or malformed counts");
      const long long c = (long long)text[p++] - 48;
      if (c < 0 || c > 63) throw std::invalid_argument("COCO RLE: character out of range");
      x |= (c & 0x1f) << (5 * k);
      more = (c & 0x20) != 0;
      if (!more && (c & 0x10)) x |= -1LL << (5 * (k + 1));
    }
    if (counts.size() > 2) x += counts[counts.size() - 2];
    if (x < 0) throw std::invalid_argument("COCO RLE: negative run");
    counts.push_back(uint32_t(x));
  }
  return counts;
}

void CocoInstances::AddImage(const std::string& file_name, const ImageU8& labels, const ImageU16& instances) {
  if (!labels.SameSize(instances.width, instances.height)) {
    throw std::invalid_argument("COCO: " + file_name + ": labels and instances differ in size");
  }
  const int w = instances.width, h = instances.height;
  const int image_id = int(images_.size()) + 1;
  images_.push_back({{"id", image_id}, {"file_name", file_name}, {"width", w}, {"height", h}});
  // Each (instance, class) seen: its box and its pixels, column-major as COCO's masks are.
  struct Seen {
    int x0, y0, x1, y1;
    std::vector<uint32_t> column_major;  // pixel indices y + x * h, ascending
  };
  std::map<std::pair<uint16_t, uint8_t>, Seen> seen;
  for (int x = 0; x < w; ++x) {
    for (int y = 0; y < h; ++y) {
      const uint16_t id = instances.at(x, y);
      if (id == 0) continue;
      auto [it, fresh] = seen.try_emplace({id, labels.at(x, y)}, Seen{x, y, x, y, {}});
      Seen& s = it->second;
      s.x0 = std::min(s.x0, x);
      s.y0 = std::min(s.y0, y);
      s.x1 = std::max(s.x1, x);
      s.y1 = std::max(s.y1, y);
      s.column_major.push_back(uint32_t(y + x * h));
    }
  }
  for (const auto& [key, s] : seen) {
    std::vector<uint32_t> counts;  // runs of 0s and 1s, starting with 0s
    uint32_t at = 0;
    for (size_t i = 0; i < s.column_major.size();) {
      size_t j = i + 1;
      while (j < s.column_major.size() && s.column_major[j] == s.column_major[j - 1] + 1) ++j;
      counts.push_back(s.column_major[i] - at);
      counts.push_back(uint32_t(j - i));
      at = s.column_major[j - 1] + 1;
      i = j;
    }
    if (at < uint32_t(w) * uint32_t(h)) counts.push_back(uint32_t(w) * uint32_t(h) - at);
    annotations_.push_back({{"id", int(annotations_.size()) + 1},
                            {"image_id", image_id},
                            {"category_id", int(key.second)},
                            {"instance_id", int(key.first)},
                            {"bbox", {s.x0, s.y0, s.x1 - s.x0 + 1, s.y1 - s.y0 + 1}},
                            {"area", s.column_major.size()},
                            {"iscrowd", 0},
                            {"segmentation", {{"size", {h, w}}, {"counts", CocoRleString(counts)}}}});
  }
}

void CocoInstances::AddAll(const nlohmann::json& coco) {
  const int image_offset = int(images_.size());
  for (nlohmann::json image : coco.at("images")) {
    image["id"] = image.at("id").get<int>() + image_offset;
    images_.push_back(std::move(image));
  }
  for (nlohmann::json annotation : coco.at("annotations")) {
    annotation["id"] = int(annotations_.size()) + 1;
    annotation["image_id"] = annotation.at("image_id").get<int>() + image_offset;
    annotations_.push_back(std::move(annotation));
  }
}

nlohmann::json CocoInstances::ToJson() const {
  nlohmann::json categories = nlohmann::json::array();
  for (const LabelClass& c : CityscapesClasses()) {
    categories.push_back({{"id", int(c.id)}, {"name", std::string(c.name)}, {"supercategory", std::string(c.category)}});
  }
  return {{"info", {{"description", "rigsim ground-truth instances; category_id = Cityscapes label id"}}},
          {"images", images_},
          {"annotations", annotations_},
          {"categories", categories}};
}

}  // namespace rigsim
