#include "testing/onnx_builder.h"

#include <cstring>

namespace rigsim {
namespace {

// Protocol-buffer encoding: a field key is (number << 3 | wire type); 0 = varint, 2 = bytes.
void Varint(std::string& out, uint64_t v) {
  while (v >= 0x80) {
    out.push_back(char((v & 0x7f) | 0x80));
    v >>= 7;
  }
  out.push_back(char(v));
}
void IntField(std::string& out, int number, int64_t v) {
  Varint(out, uint64_t(number) << 3 | 0);
  Varint(out, uint64_t(v));
}
void BytesField(std::string& out, int number, const std::string& bytes) {
  Varint(out, uint64_t(number) << 3 | 2);
  Varint(out, bytes.size());
  out += bytes;
}

// TensorProto: dims (1), data_type (2; FLOAT = 1), name (8), raw_data (9, little-endian floats).
std::string FloatTensor(const std::string& name, const std::vector<int64_t>& dims, const std::vector<float>& values) {
  std::string t;
  for (int64_t d : dims) IntField(t, 1, d);
  IntField(t, 2, 1);
  BytesField(t, 8, name);
  std::string raw(values.size() * sizeof(float), '\0');
  std::memcpy(raw.data(), values.data(), raw.size());
  BytesField(t, 9, raw);
  return t;
}

// ValueInfoProto: name (1), type (2) = TypeProto { tensor_type (1) = { elem_type (1), shape (2) =
// { dim (1) = { dim_value (1) | dim_param (2) } } } }.
std::string TensorValueInfo(const std::string& name, int elem_type, const std::vector<std::string>& dims) {
  std::string shape;
  for (const std::string& d : dims) {
    std::string dim;
    if (!d.empty() && d.find_first_not_of("0123456789") == std::string::npos) {
      IntField(dim, 1, std::stoll(d));
    } else {
      BytesField(dim, 2, d);
    }
    BytesField(shape, 1, dim);
  }
  std::string tensor;
  IntField(tensor, 1, elem_type);
  BytesField(tensor, 2, shape);
  std::string type;
  BytesField(type, 1, tensor);
  std::string info;
  BytesField(info, 1, name);
  BytesField(info, 2, type);
  return info;
}

// AttributeProto: name (1), i (3), ints (8), type (20; INT = 2, INTS = 7).
std::string IntsAttribute(const std::string& name, const std::vector<int64_t>& values) {
  std::string a;
  BytesField(a, 1, name);
  for (int64_t v : values) IntField(a, 8, v);
  IntField(a, 20, 7);
  return a;
}
std::string IntAttribute(const std::string& name, int64_t value) {
  std::string a;
  BytesField(a, 1, name);
  IntField(a, 3, value);
  IntField(a, 20, 2);
  return a;
}

// NodeProto: input (1), output (2), name (3), op_type (4), attribute (5).
std::string Node(const std::string& op, const std::vector<std::string>& inputs, const std::string& output,
                 const std::vector<std::string>& attributes) {
  std::string n;
  for (const std::string& i : inputs) BytesField(n, 1, i);
  BytesField(n, 2, output);
  BytesField(n, 3, op + "_0");
  BytesField(n, 4, op);
  for (const std::string& a : attributes) BytesField(n, 5, a);
  return n;
}

}  // namespace

std::string OnnxModelBytes(const OnnxConvModel& m) {
  const int64_t classes = int64_t(m.weights.size());
  std::vector<float> w;
  for (const auto& row : m.weights) w.insert(w.end(), row.begin(), row.end());
  const std::string h = m.height > 0 ? std::to_string(m.height) : "height";
  const std::string wd = m.width > 0 ? std::to_string(m.width) : "width";
  // GraphProto: node (1), name (2), initializer (5), input (11), output (12).
  std::string graph;
  BytesField(graph, 1, Node("Conv", {"image", "weight", "bias"}, "scores", {IntsAttribute("kernel_shape", {1, 1})}));
  if (m.argmax) BytesField(graph, 1, Node("ArgMax", {"scores"}, "classes", {IntAttribute("axis", 1), IntAttribute("keepdims", 1)}));
  BytesField(graph, 2, "colour_classifier");
  BytesField(graph, 5, FloatTensor("weight", {classes, 3, 1, 1}, w));
  BytesField(graph, 5, FloatTensor("bias", {classes}, m.bias));
  BytesField(graph, 11, TensorValueInfo("image", 1, {"1", "3", h, wd}));
  if (m.argmax) {
    BytesField(graph, 12, TensorValueInfo("classes", 7, {"1", "1", h, wd}));  // INT64
  } else {
    BytesField(graph, 12, TensorValueInfo("scores", 1, {"1", std::to_string(classes), h, wd}));
  }
  // ModelProto: ir_version (1), producer_name (2), graph (7), opset_import (8) = { domain (1), version (2) }.
  std::string model;
  IntField(model, 1, 6);
  BytesField(model, 2, "rigsim tests");
  BytesField(model, 7, graph);
  std::string opset;
  BytesField(opset, 1, "");
  IntField(opset, 2, 11);
  BytesField(model, 8, opset);
  return model;
}

OnnxConvModel NearestColourModel(const std::vector<std::array<uint8_t, 3>>& colours, const std::array<double, 3>& mean,
                                 const std::array<double, 3>& std) {
  // v = x * std + mean, so 2 p.v - |p|^2 = sum_c (2 p_c std_c) x_c + (2 p.mean - |p|^2).
  OnnxConvModel m;
  for (const auto& colour : colours) {
    std::array<float, 3> row{};
    double bias = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double p = colour[c] / 255.0;
      row[c] = float(2 * p * std[c]);
      bias += 2 * p * mean[c] - p * p;
    }
    m.weights.push_back(row);
    m.bias.push_back(float(bias));
  }
  return m;
}

}  // namespace rigsim
