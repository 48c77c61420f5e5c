// What rigsim needs to know of an ONNX model before OpenCV runs it: the name and shape of the
// image input and the name of the first output (torchvision's exports add an auxiliary output
// after it). Read from the protocol-buffer bytes with a small reader of the few fields involved
// (onnx.proto: ModelProto.graph, GraphProto.input/output/initializer, ValueInfoProto's tensor
// shape), so that the input size a model was exported with is known and checked up front.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rigsim {

struct OnnxModelInfo {
  std::string input_name;
  std::vector<int64_t> input_shape;  // e.g. {1, 3, 520, 520}; -1 for a dimension left open (dim_param)
  std::string output_name;           // the graph's first output
  int64_t ir_version = 0;
};

// Parses `bytes`, the contents of an .onnx file. Throws std::runtime_error saying what is wrong
// (not a protocol buffer, no graph, no input or output); the caller adds the file name.
OnnxModelInfo ParseOnnxModelInfo(std::string_view bytes);

}  // namespace rigsim
