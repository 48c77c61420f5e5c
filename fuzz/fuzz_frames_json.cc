// Fuzzes the frames.json reader (dataset/dataset.h FramesFromJsonText), then requires that an
// accepted file survives writing and reading back unchanged.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "dataset/dataset.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  rigsim::FramesFile frames;
  try {
    frames = rigsim::FramesFromJsonText(text, "fuzz.json");
  } catch (const std::runtime_error&) {
    return 0;  // rejected with a message: fine
  }
  const rigsim::FramesFile back = rigsim::FramesFromJsonText(rigsim::FramesToJsonText(frames), "round trip");
  if (back.frames.size() != frames.frames.size() || back.scene != frames.scene || back.seed != frames.seed) __builtin_trap();
  for (size_t i = 0; i < frames.frames.size(); ++i) {
    const rigsim::Frame &a = frames.frames[i], &b = back.frames[i];
    if (a.name != b.name || a.timestamp_s != b.timestamp_s || a.rig_from_world.has_value() != b.rig_from_world.has_value()) {
      __builtin_trap();
    }
  }
  return 0;
}
