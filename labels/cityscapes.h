// The Cityscapes class taxonomy (label ids, train ids, names, categories, colours) and which
// classes count as reliable for calibration.
//
// Label images store the Cityscapes *label id* (0..33) so that the output of a
// Cityscapes-trained network drops in. `reliable` marks static structure whose appearance does
// not change between views or over time: flat ground, construction, poles and signs. Sky,
// vegetation, terrain and every movable object (people, vehicles) are unreliable.
#pragma once

#include <array>
#include <bitset>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rigsim {

struct LabelClass {
  uint8_t id;            // Cityscapes label id, stored in label images
  int train_id;          // 255 = ignored in training
  std::string_view name;  // e.g. "building"
  std::string_view category;  // "flat", "construction", "object", "nature", "sky", "human", "vehicle", "void"
  std::array<uint8_t, 3> color;  // RGB of the colour preview
  bool reliable;         // default: may features on this class be used for calibration?
};

inline constexpr uint8_t kUnlabeledId = 0;
inline constexpr uint8_t kSkyId = 23;

// All 34 classes, ordered by id (index == id).
std::span<const LabelClass> CityscapesClasses();
// nullptr when unknown.
const LabelClass* FindClassById(int id);
const LabelClass* FindClassByName(std::string_view name);
// " (did you mean 'building'?)" for a misspelt class name (letter case and near misses), "" when
// no class name is close: to append to the message that refuses `typed`.
std::string ClassNameSuggestion(std::string_view typed);
// Label id whose preview colour equals `rgb`, if any.
std::optional<uint8_t> ClassIdFromColor(const std::array<uint8_t, 3>& rgb);

// Classes a segmentation network plausibly predicts instead of class `id` (its most frequent
// confusions on Cityscapes: road/sidewalk, building/wall/fence, vegetation/terrain, pole/sign,
// car/truck, person/rider, ...). Some cross the reliable/unreliable line (building/vegetation,
// sidewalk/terrain, sky/building), as real errors do. Empty for the void classes (ids 0..5) and
// unknown ids. Used by the segmentation-noise model (dataset/segmentation_noise.h).
std::span<const uint8_t> ConfusableClasses(int id);

// Per-id reliability, defaulting to each class's `reliable` flag; the user can override.
class ReliableClasses {
 public:
  ReliableClasses();  // the defaults
  // Names of classes to treat as reliable instead of the defaults. Throws on unknown names.
  static ReliableClasses FromNames(const std::vector<std::string>& names);
  bool IsReliable(uint8_t id) const { return reliable_[id]; }
  void Set(uint8_t id, bool reliable) { reliable_[id] = reliable; }
  // The reliable ids as a set, as the calibrator's mask modes take them (calibrator/features/semantics.h).
  std::bitset<256> Ids() const;

 private:
  std::array<bool, 256> reliable_{};
};

}  // namespace rigsim
