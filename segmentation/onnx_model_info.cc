#include "segmentation/onnx_model_info.h"

#include <optional>
#include <set>
#include <stdexcept>

namespace rigsim {
namespace {

// One field of a protocol-buffer message: its number and, by wire type, an integer or bytes.
struct Field {
  uint32_t number = 0;
  int wire_type = 0;
  uint64_t value = 0;      // wire types 0 (varint), 1 (64 bit), 5 (32 bit)
  std::string_view bytes;  // wire type 2 (length-delimited)
};

class Reader {
 public:
  explicit Reader(std::string_view data) : data_(data) {}
  bool done() const { return pos_ >= data_.size(); }

  Field Next() {
    Field f;
    const uint64_t key = Varint();
    f.number = static_cast<uint32_t>(key >> 3);
    f.wire_type = static_cast<int>(key & 7);
    if (f.number == 0) throw std::runtime_error("not an ONNX model (field number 0)");
    switch (f.wire_type) {
      case 0: f.value = Varint(); break;
      case 1: f.value = Fixed(8); break;
      case 5: f.value = Fixed(4); break;
      case 2: {
        const uint64_t n = Varint();
        if (n > data_.size() - pos_) throw std::runtime_error("not an ONNX model (a field runs past the end of the file)");
        f.bytes = data_.substr(pos_, n);
        pos_ += n;
        break;
      }
      default: throw std::runtime_error("not an ONNX model (wire type " + std::to_string(f.wire_type) + ")");
    }
    return f;
  }

 private:
  uint64_t Varint() {
    uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (pos_ >= data_.size()) throw std::runtime_error("not an ONNX model (truncated)");
      const uint8_t b = static_cast<uint8_t>(data_[pos_++]);
      v |= uint64_t(b & 0x7f) << shift;
      if ((b & 0x80) == 0) return v;
    }
    throw std::runtime_error("not an ONNX model (a number longer than 10 bytes)");
  }
  uint64_t Fixed(size_t n) {
    if (n > data_.size() - pos_) throw std::runtime_error("not an ONNX model (truncated)");
    uint64_t v = 0;
    for (size_t i = 0; i < n; ++i) v |= uint64_t(static_cast<uint8_t>(data_[pos_ + i])) << (8 * i);
    pos_ += n;
    return v;
  }
  std::string_view data_;
  size_t pos_ = 0;
};

// The first length-delimited field `number` of a message, if any.
std::optional<std::string_view> FirstBytes(std::string_view message, uint32_t number) {
  Reader r(message);
  while (!r.done()) {
    const Field f = r.Next();
    if (f.number == number && f.wire_type == 2) return f.bytes;
  }
  return std::nullopt;
}

std::string NameOf(std::string_view message, uint32_t name_field) {
  const auto name = FirstBytes(message, name_field);
  return name ? std::string(*name) : std::string();
}

// ValueInfoProto.type (2) -> TypeProto.tensor_type (1) -> shape (2) -> dim (1): dim_value (1) or
// dim_param (2).
std::vector<int64_t> ShapeOf(std::string_view value_info) {
  std::vector<int64_t> shape;
  const auto type = FirstBytes(value_info, 2);
  const auto tensor = type ? FirstBytes(*type, 1) : std::nullopt;
  const auto shape_proto = tensor ? FirstBytes(*tensor, 2) : std::nullopt;
  if (!shape_proto) return shape;
  Reader r(*shape_proto);
  while (!r.done()) {
    const Field dim = r.Next();
    if (dim.number != 1 || dim.wire_type != 2) continue;
    int64_t value = -1;
    Reader d(dim.bytes);
    while (!d.done()) {
      const Field f = d.Next();
      if (f.number == 1 && f.wire_type == 0 && static_cast<int64_t>(f.value) > 0) value = static_cast<int64_t>(f.value);
    }
    shape.push_back(value);
  }
  return shape;
}

}  // namespace

OnnxModelInfo ParseOnnxModelInfo(std::string_view bytes) {
  OnnxModelInfo info;
  std::optional<std::string_view> graph;
  Reader model(bytes);
  while (!model.done()) {
    const Field f = model.Next();
    if (f.number == 1 && f.wire_type == 0) info.ir_version = static_cast<int64_t>(f.value);
    if (f.number == 7 && f.wire_type == 2) graph = f.bytes;
  }
  if (!graph || info.ir_version <= 0) throw std::runtime_error("not an ONNX model (no graph or no IR version)");
  // Models of IR version 3 and older list their weights among the inputs too: the image is the
  // first input that is not an initializer.
  std::set<std::string> initializers;
  std::vector<std::string_view> inputs;
  Reader r(*graph);
  while (!r.done()) {
    const Field f = r.Next();
    if (f.wire_type != 2) continue;
    if (f.number == 5) initializers.insert(NameOf(f.bytes, 8));
    if (f.number == 11) inputs.push_back(f.bytes);
    if (f.number == 12 && info.output_name.empty()) info.output_name = NameOf(f.bytes, 1);
  }
  for (std::string_view input : inputs) {
    const std::string name = NameOf(input, 1);
    if (initializers.count(name) > 0) continue;
    info.input_name = name;
    info.input_shape = ShapeOf(input);
    break;
  }
  if (info.input_name.empty()) throw std::runtime_error("the ONNX graph has no input");
  if (info.output_name.empty()) throw std::runtime_error("the ONNX graph has no output");
  return info;
}

}  // namespace rigsim
