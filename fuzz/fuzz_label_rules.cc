// Fuzzes the label-rules reader (gltf/label_rules.h) and matching with the rules it accepted.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "gltf/label_rules.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  rigsim::LabelRules rules;
  try {
    rules = rigsim::LabelRules::FromJsonText(text, "fuzz.json");
  } catch (const std::runtime_error&) {
    return 0;  // rejected with a message: fine
  }
  rigsim::LabelRules::Names names;
  names.node_path = {"Car_01", "street", ""};
  names.mesh = "tree_12";
  names.material = "asphalt [old]";
  rules.Classify(names);
  return 0;
}
