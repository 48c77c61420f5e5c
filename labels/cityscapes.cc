#include "labels/cityscapes.h"

#include "common/did_you_mean.h"

#include <stdexcept>
#include <vector>

namespace rigsim {
namespace {

// From cityscapesScripts/helpers/labels.py.
constexpr std::array<LabelClass, 34> kClasses = {{
    {0, 255, "unlabeled", "void", {0, 0, 0}, false},
    {1, 255, "ego vehicle", "void", {0, 0, 0}, false},
    {2, 255, "rectification border", "void", {0, 0, 0}, false},
    {3, 255, "out of roi", "void", {0, 0, 0}, false},
    {4, 255, "static", "void", {0, 0, 0}, false},
    {5, 255, "dynamic", "void", {111, 74, 0}, false},
    {6, 255, "ground", "void", {81, 0, 81}, true},
    {7, 0, "road", "flat", {128, 64, 128}, true},
    {8, 1, "sidewalk", "flat", {244, 35, 232}, true},
    {9, 255, "parking", "flat", {250, 170, 160}, true},
    {10, 255, "rail track", "flat", {230, 150, 140}, true},
    {11, 2, "building", "construction", {70, 70, 70}, true},
    {12, 3, "wall", "construction", {102, 102, 156}, true},
    {13, 4, "fence", "construction", {190, 153, 153}, true},
    {14, 255, "guard rail", "construction", {180, 165, 180}, true},
    {15, 255, "bridge", "construction", {150, 100, 100}, true},
    {16, 255, "tunnel", "construction", {150, 120, 90}, true},
    {17, 5, "pole", "object", {153, 153, 153}, true},
    {18, 255, "polegroup", "object", {153, 153, 153}, true},
    {19, 6, "traffic light", "object", {250, 170, 30}, true},
    {20, 7, "traffic sign", "object", {220, 220, 0}, true},
    {21, 8, "vegetation", "nature", {107, 142, 35}, false},
    {22, 9, "terrain", "nature", {152, 251, 152}, false},
    {23, 10, "sky", "sky", {70, 130, 180}, false},
    {24, 11, "person", "human", {220, 20, 60}, false},
    {25, 12, "rider", "human", {255, 0, 0}, false},
    {26, 13, "car", "vehicle", {0, 0, 142}, false},
    {27, 14, "truck", "vehicle", {0, 0, 70}, false},
    {28, 15, "bus", "vehicle", {0, 60, 100}, false},
    {29, 255, "caravan", "vehicle", {0, 0, 90}, false},
    {30, 255, "trailer", "vehicle", {0, 0, 110}, false},
    {31, 16, "train", "vehicle", {0, 80, 100}, false},
    {32, 17, "motorcycle", "vehicle", {0, 0, 230}, false},
    {33, 18, "bicycle", "vehicle", {119, 11, 32}, false},
}};

}  // namespace

std::span<const LabelClass> CityscapesClasses() { return kClasses; }

const LabelClass* FindClassById(int id) {
  if (id < 0 || id >= static_cast<int>(kClasses.size())) return nullptr;
  return &kClasses[id];
}

const LabelClass* FindClassByName(std::string_view name) {
  for (const LabelClass& c : kClasses) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

std::optional<uint8_t> ClassIdFromColor(const std::array<uint8_t, 3>& rgb) {
  // Several void classes share black; they all map to unlabeled (the first with that colour).
  for (const LabelClass& c : kClasses) {
    if (c.color == rgb) return c.id;
  }
  return std::nullopt;
}

std::span<const uint8_t> ConfusableClasses(int id) {
  // Indexed by label id; the first entry of each list is the most frequent confusion.
  static const std::array<std::vector<uint8_t>, 34> kConfusable = {{
      {}, {}, {}, {}, {}, {},  // void
      {7, 22},                 // ground -> road, terrain
      {8, 9},                  // road -> sidewalk, parking
      {7, 22},                 // sidewalk -> road, terrain
      {7, 8},                  // parking -> road, sidewalk
      {7},                     // rail track -> road
      {12, 13, 21},            // building -> wall, fence, vegetation
      {11, 13},                // wall -> building, fence
      {12, 11, 21},            // fence -> wall, building, vegetation
      {13},                    // guard rail -> fence
      {11},                    // bridge -> building
      {11},                    // tunnel -> building
      {20, 11, 21},            // pole -> traffic sign, building, vegetation (tree trunks)
      {17},                    // polegroup -> pole
      {17, 20},                // traffic light -> pole, traffic sign
      {17, 19},                // traffic sign -> pole, traffic light
      {22, 11},                // vegetation -> terrain, building
      {21, 8},                 // terrain -> vegetation, sidewalk
      {11, 21},                // sky -> building, vegetation
      {25},                    // person -> rider
      {24},                    // rider -> person
      {27},                    // car -> truck
      {26, 28},                // truck -> car, bus
      {27, 31},                // bus -> truck, train
      {27},                    // caravan -> truck
      {27},                    // trailer -> truck
      {28},                    // train -> bus
      {33},                    // motorcycle -> bicycle
      {32},                    // bicycle -> motorcycle
  }};
  if (id < 0 || id >= static_cast<int>(kConfusable.size())) return {};
  return kConfusable[id];
}

std::string ClassNameSuggestion(std::string_view typed) {
  std::vector<std::string> names;
  for (const LabelClass& c : kClasses) names.emplace_back(c.name);
  return DidYouMean(typed, names);
}

ReliableClasses::ReliableClasses() {
  for (const LabelClass& c : kClasses) reliable_[c.id] = c.reliable;
}

ReliableClasses ReliableClasses::FromNames(const std::vector<std::string>& names) {
  ReliableClasses r;
  r.reliable_.fill(false);
  for (const std::string& n : names) {
    const LabelClass* c = FindClassByName(n);
    if (!c) {
      throw std::invalid_argument("unknown class '" + n + "'" + ClassNameSuggestion(n) +
                                  "; the classes are Cityscapes' (docs/datasets.md, 'Cityscapes classes')");
    }
    r.reliable_[c->id] = true;
  }
  return r;
}

std::bitset<256> ReliableClasses::Ids() const {
  std::bitset<256> ids;
  for (size_t id = 0; id < reliable_.size(); ++id) ids[id] = reliable_[id];
  return ids;
}

}  // namespace rigsim
