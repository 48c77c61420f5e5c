#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "gltf/loader.h"

namespace rigsim::gltf {
namespace {

int ComponentSize(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return -1;
  }
}

// One component at `p` (possibly unaligned), with glTF's normalized-integer mapping when asked.
double ReadComponent(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      uint8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? v / 255.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return normalized ? v / 4294967295.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: return 0.0;
  }
}

}  // namespace

int NumComponents(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return -1;
  }
}

// Reads accessor `index` into doubles (count * components), checking every byte it touches.
std::vector<double> Loader::ReadAccessor(int index, int expected_type, const std::string& use, size_t* count_out) {
  const std::string label = "accessor " + std::to_string(index) + " (" + use + ")";
  if (index < 0 || size_t(index) >= model_.accessors.size()) Fail(label + ": index out of range");
  const tinygltf::Accessor& a = model_.accessors[index];
  if (const auto it = unknown_accessor_types_.find(index); it != unknown_accessor_types_.end()) {
    Fail(label + ": type '" + it->second + "' is not a glTF accessor type (SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3, MAT4)");
  }
  const int ncomp = NumComponents(a.type);
  const int csize = ComponentSize(a.componentType);
  if (csize < 0) Fail(label + ": invalid componentType " + std::to_string(a.componentType));
  if (a.type != expected_type) Fail(label + ": unexpected type (expected " + std::to_string(NumComponents(expected_type)) + " components)");
  if (a.count > options_.max_accessor_count) {
    Fail(label + ": count " + std::to_string(a.count) + " exceeds the limit " + std::to_string(options_.max_accessor_count));
  }
  // Bounds on what a small file can make us allocate. (1) An accessor without a bufferView is
  // zeros (plus sparse values) and costs no file bytes: its count may not exceed the bytes of all
  // buffers, which any genuine accessor of that count needs elsewhere. (2) Meshes instanced by
  // many nodes are decoded once per node: the sum over the whole load has the per-accessor limit.
  if (a.bufferView < 0) {
    size_t buffer_bytes = 0;
    for (const tinygltf::Buffer& b : model_.buffers) buffer_bytes += b.data.size();
    if (a.count > buffer_bytes + 4096) {
      Fail(label + ": has no bufferView and declares " + std::to_string(a.count) +
           " elements, more than the file's buffers hold (" + std::to_string(buffer_bytes) + " bytes)");
    }
  }
  decoded_elements_ += a.count;
  if (decoded_elements_ > options_.max_accessor_count) {
    Fail(label + ": the scene decodes more than " + std::to_string(options_.max_accessor_count) +
         " accessor elements in total (meshes instanced by many nodes?)");
  }
  const size_t elem = size_t(ncomp) * csize;
  std::vector<double> out;
  if (a.bufferView >= 0) {
    const unsigned char* base = CheckedView(a.bufferView, label);
    const tinygltf::BufferView& bv = model_.bufferViews[a.bufferView];
    const int stride = a.ByteStride(bv);
    if (stride <= 0 || size_t(stride) < elem) Fail(label + ": invalid byteStride " + std::to_string(bv.byteStride));
    if (a.count > 0 && (a.byteOffset > bv.byteLength || (a.count - 1) * size_t(stride) + elem > bv.byteLength - a.byteOffset)) {
      Fail(label + ": byteOffset " + std::to_string(a.byteOffset) + " + " + std::to_string(a.count) + " elements of stride " +
           std::to_string(stride) + " out of range of bufferView " + std::to_string(a.bufferView) + " (byteLength " +
           std::to_string(bv.byteLength) + ")");
    }
    out.resize(a.count * ncomp);
    for (size_t i = 0; i < a.count; ++i) {
      const unsigned char* p = base + a.byteOffset + i * size_t(stride);
      for (int c = 0; c < ncomp; ++c) out[i * ncomp + c] = ReadComponent(p + c * csize, a.componentType, a.normalized);
    }
  } else {
    out.assign(a.count * ncomp, 0.0);  // glTF: no bufferView means zeros (usually with sparse data)
  }
  if (a.sparse.isSparse) ApplySparse(a, ncomp, csize, label, &out);
  *count_out = a.count;
  return out;
}

void Loader::ApplySparse(const tinygltf::Accessor& a, int ncomp, int csize, const std::string& label, std::vector<double>* out) {
  const auto& sp = a.sparse;
  if (sp.count < 0 || size_t(sp.count) > a.count) Fail(label + ": sparse count " + std::to_string(sp.count) + " out of range");
  const int isize = ComponentSize(sp.indices.componentType);
  if (sp.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      sp.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      sp.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    Fail(label + ": invalid sparse index componentType");
  }
  const size_t n = size_t(sp.count);
  const unsigned char* ibase = CheckedView(sp.indices.bufferView, label + " sparse indices");
  const unsigned char* vbase = CheckedView(sp.values.bufferView, label + " sparse values");
  const size_t ilen = model_.bufferViews[sp.indices.bufferView].byteLength;
  const size_t vlen = model_.bufferViews[sp.values.bufferView].byteLength;
  const size_t ioff = size_t(std::max(0, sp.indices.byteOffset));
  const size_t voff = size_t(std::max(0, sp.values.byteOffset));
  const size_t elem = size_t(ncomp) * csize;
  if (ioff > ilen || n * isize > ilen - ioff) Fail(label + ": sparse indices out of range of their bufferView");
  if (voff > vlen || n * elem > vlen - voff) Fail(label + ": sparse values out of range of their bufferView");
  for (size_t k = 0; k < n; ++k) {
    const size_t target = size_t(ReadComponent(ibase + ioff + k * isize, sp.indices.componentType, false));
    if (target >= a.count) Fail(label + ": sparse index " + std::to_string(target) + " out of range");
    for (int c = 0; c < ncomp; ++c) {
      (*out)[target * ncomp + c] = ReadComponent(vbase + voff + k * elem + c * csize, a.componentType, a.normalized);
    }
  }
}

// Start of bufferView `index`'s bytes, after checking it lies inside its buffer.
const unsigned char* Loader::CheckedView(int index, const std::string& label) const {
  if (index < 0 || size_t(index) >= model_.bufferViews.size()) Fail(label + ": bufferView " + std::to_string(index) + " out of range");
  const tinygltf::BufferView& bv = model_.bufferViews[index];
  if (bv.buffer < 0 || size_t(bv.buffer) >= model_.buffers.size()) Fail(label + ": buffer " + std::to_string(bv.buffer) + " out of range");
  const std::vector<unsigned char>& data = model_.buffers[bv.buffer].data;
  if (dataless_buffers_.count(bv.buffer)) {
    Fail(label + ": bufferView " + std::to_string(index) + " lies in buffer " + std::to_string(bv.buffer) +
         ", which has no uri and so no data (glTF allows such a buffer only when nothing reads it)");
  }
  if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset) {
    Fail(label + ": bufferView " + std::to_string(index) + " (byteOffset " + std::to_string(bv.byteOffset) + ", byteLength " +
         std::to_string(bv.byteLength) + ") out of range of buffer " + std::to_string(bv.buffer) + " (" +
         std::to_string(data.size()) + " bytes)");
  }
  return data.data() + bv.byteOffset;
}

}  // namespace rigsim::gltf
