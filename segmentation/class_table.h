// Which Cityscapes class (labels/cityscapes.h) each output channel of a segmentation network
// stands for: the network's classes mapped onto rigsim's, so that its output becomes a label image
// calibrate reads.
//
// Built in: "cityscapes" (the 19 training classes, channel k = train id k), "ade20k" (the 150
// classes of the ADE20K scene-parsing benchmark, each mapped to the nearest Cityscapes class:
// indoor furniture to static, movable things to dynamic, water to terrain) and "voc" (the 21
// classes of torchvision's pretrained DeepLabV3 and LR-ASPP: background to unlabeled). Anything
// else is a class-table file, one line per channel:
//
//   # CHANNEL  CITYSCAPES CLASS (name or label id)   # the network's name, optional
//   0  road
//   1  sidewalk
//   2  building        # house, skyscraper
//
// Every channel 0..N-1 appears once; blank lines and text after '#' are ignored.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace rigsim {

// Why a segmentation run refused its input, for callers and tests to tell apart without reading
// the message (which names the file and says what to change).
enum class SegmenterErrorKind {
  kClassTableFile,      // the class-table file is missing, unreadable or malformed
  kUnreadableModel,     // the model file is missing, not ONNX, or OpenCV cannot run it
  kClassCountMismatch,  // the model's output channels differ from the class table's size
  kInputSizeMismatch,   // --input-size differs from the size the model was exported with
  kBadOptions,          // mean, std or input size out of range
};

struct SegmenterError : std::runtime_error {
  SegmenterError(SegmenterErrorKind k, const std::string& message) : std::runtime_error(message), kind(k) {}
  SegmenterErrorKind kind;
};

struct ClassTable {
  std::string name;                   // "cityscapes", "ade20k", "voc", or the file's path
  std::vector<uint8_t> label_ids;     // per channel: the Cityscapes label id
  std::vector<std::string> channel_names;  // per channel: the network's own name ("" when unknown)

  int size() const { return int(label_ids.size()); }
};

// The names of the built-in tables.
std::vector<std::string> BuiltinClassTableNames();
// A built-in table by name, or the file at `name_or_path` (ReadClassTable).
ClassTable LoadClassTable(const std::string& name_or_path);
// Throws SegmenterError(kClassTableFile) naming the file (and line) when it is missing,
// unreadable, names no Cityscapes class, or does not list every channel 0..N-1 exactly once.
ClassTable ReadClassTable(const std::filesystem::path& path);
// The built-in table with `channels` entries, for the message that refuses a mismatch; "" if none.
std::string BuiltinClassTableWithSize(int channels);

}  // namespace rigsim
