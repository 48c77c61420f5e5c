#include "gltf/gltf_compression.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <utility>

#include <draco/compression/decode.h>
#include <draco/core/decoder_buffer.h>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

namespace rigsim {
namespace {

using nlohmann::json;

// Appends `bytes` as a new buffer with a tightly packed buffer view over it and returns the view.
int AppendBufferView(tinygltf::Model& model, std::vector<unsigned char> bytes) {
  tinygltf::BufferView view;
  view.buffer = int(model.buffers.size());
  view.byteOffset = 0;
  view.byteLength = bytes.size();
  view.byteStride = 0;
  tinygltf::Buffer buffer;
  buffer.data = std::move(bytes);
  model.buffers.push_back(std::move(buffer));
  model.bufferViews.push_back(std::move(view));
  return int(model.bufferViews.size() - 1);
}

// A copy of `accessor` reading `count` elements from the start of `view`.
int AppendAccessor(tinygltf::Model& model, tinygltf::Accessor accessor, int view, size_t count) {
  accessor.bufferView = view;
  accessor.byteOffset = 0;
  accessor.count = count;
  accessor.sparse.isSparse = false;  // the decoded values are the whole data
  model.accessors.push_back(std::move(accessor));
  return int(model.accessors.size() - 1);
}

template <typename T>
std::vector<unsigned char> AsBytes(const std::vector<T>& values) {
  std::vector<unsigned char> bytes(values.size() * sizeof(T));
  if (!bytes.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

// The mesh's triangles as indices of the accessor's component type.
template <typename T>
std::vector<unsigned char> IndexBytes(const draco::Mesh& mesh) {
  std::vector<T> indices;
  indices.reserve(size_t(mesh.num_faces()) * 3);
  for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f) {
    for (const draco::PointIndex& p : mesh.face(f)) indices.push_back(T(p.value()));
  }
  return AsBytes(indices);
}

// Every point's value of `attribute`, converted to T (Draco scales normalized integers to floats
// and back as glTF means them).
template <typename T>
bool AttributeBytes(const draco::Mesh& mesh, const draco::PointAttribute& attribute, int components,
                    std::vector<unsigned char>* bytes) {
  std::vector<T> values(size_t(mesh.num_points()) * components);
  for (draco::PointIndex p(0); p < mesh.num_points(); ++p) {
    if (!attribute.ConvertValue<T>(attribute.mapped_index(p), int8_t(components), &values[size_t(p.value()) * components])) {
      return false;
    }
  }
  *bytes = AsBytes(values);
  return true;
}

class PrimitiveDecoder {
 public:
  PrimitiveDecoder(tinygltf::Model& model, tinygltf::Primitive& prim, std::string where, size_t max_elements)
      : model_(model), prim_(prim), where_(std::move(where)), max_elements_(max_elements) {}

  void Decode(const tinygltf::Value& extension) {
    if (!extension.IsObject() || !extension.Has("bufferView") || !extension.Get("bufferView").IsInt()) {
      Fail("the extension object has no integer bufferView");
    }
    const std::unique_ptr<draco::Mesh> mesh = DecodeMesh(extension.Get("bufferView").Get<int>());
    if (size_t(mesh->num_points()) > max_elements_ || size_t(mesh->num_faces()) * 3 > max_elements_) {
      Fail("decodes to " + std::to_string(mesh->num_points()) + " vertices and " + std::to_string(mesh->num_faces()) +
           " triangles, beyond the limit of " + std::to_string(max_elements_) + " elements");
    }
    ReplaceIndices(*mesh);
    const tinygltf::Value& attributes = extension.Get("attributes");
    if (!attributes.IsObject()) Fail("the extension object has no attributes object");
    for (const std::string& name : attributes.Keys()) {
      const tinygltf::Value& id = attributes.Get(name);
      if (!id.IsInt() || id.Get<int>() < 0) Fail("attribute " + name + ": its Draco id is not a non-negative integer");
      // An attribute the primitive itself does not list is not part of the glTF mesh.
      if (prim_.attributes.count(name)) ReplaceAttribute(*mesh, name, uint32_t(id.Get<int>()));
    }
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const {
    throw std::invalid_argument(where_ + ": " + std::string(kDracoExtension) + ": " + what);
  }

  std::unique_ptr<draco::Mesh> DecodeMesh(int view_index) const {
    if (view_index < 0 || size_t(view_index) >= model_.bufferViews.size()) {
      Fail("bufferView " + std::to_string(view_index) + " out of range");
    }
    const tinygltf::BufferView& view = model_.bufferViews[view_index];
    if (view.buffer < 0 || size_t(view.buffer) >= model_.buffers.size()) {
      Fail("bufferView " + std::to_string(view_index) + " names buffer " + std::to_string(view.buffer) + ", out of range");
    }
    const std::vector<unsigned char>& data = model_.buffers[view.buffer].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) {
      Fail("bufferView " + std::to_string(view_index) + " (bytes " + std::to_string(view.byteOffset) + " + " +
           std::to_string(view.byteLength) + ") lies beyond its buffer's " + std::to_string(data.size()) + " bytes");
    }
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(data.data() + view.byteOffset), view.byteLength);
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok()) Fail("the Draco data in bufferView " + std::to_string(view_index) + " does not decode: " +
                            decoded.status().error_msg_string());
    std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    if (mesh == nullptr) Fail("the Draco data in bufferView " + std::to_string(view_index) + " holds no mesh");
    return mesh;
  }

  void ReplaceIndices(const draco::Mesh& mesh) {
    tinygltf::Accessor accessor;
    if (prim_.indices >= 0) {
      if (size_t(prim_.indices) >= model_.accessors.size()) Fail("indices accessor out of range");
      accessor = model_.accessors[prim_.indices];
    } else {  // glTF expects indices with Draco; without them the decoded triangles still say how to draw
      accessor.type = TINYGLTF_TYPE_SCALAR;
      accessor.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    }
    if (accessor.type != TINYGLTF_TYPE_SCALAR) Fail("the indices accessor is not SCALAR");
    const uint64_t largest = mesh.num_points() == 0 ? 0 : uint64_t(mesh.num_points()) - 1;
    std::vector<unsigned char> bytes;
    switch (accessor.componentType) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        if (largest > std::numeric_limits<uint8_t>::max()) Fail(TooManyPoints(mesh, "unsigned byte"));
        bytes = IndexBytes<uint8_t>(mesh);
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        if (largest > std::numeric_limits<uint16_t>::max()) Fail(TooManyPoints(mesh, "unsigned short"));
        bytes = IndexBytes<uint16_t>(mesh);
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        bytes = IndexBytes<uint32_t>(mesh);
        break;
      default:
        Fail("the indices accessor's componentType " + std::to_string(accessor.componentType) +
             " is not an unsigned byte, short or int");
    }
    prim_.indices = AppendAccessor(model_, accessor, AppendBufferView(model_, std::move(bytes)), size_t(mesh.num_faces()) * 3);
  }

  static std::string TooManyPoints(const draco::Mesh& mesh, const std::string& type) {
    return std::to_string(mesh.num_points()) + " vertices cannot be indexed by the indices accessor's " + type + "s";
  }

  void ReplaceAttribute(const draco::Mesh& mesh, const std::string& name, uint32_t id) {
    const int accessor_index = prim_.attributes.at(name);
    if (accessor_index < 0 || size_t(accessor_index) >= model_.accessors.size()) {
      Fail("attribute " + name + ": accessor " + std::to_string(accessor_index) + " out of range");
    }
    const tinygltf::Accessor& accessor = model_.accessors[accessor_index];
    const draco::PointAttribute* attribute = mesh.GetAttributeByUniqueId(id);
    if (attribute == nullptr) Fail("attribute " + name + ": the Draco data has no attribute with id " + std::to_string(id));
    const int components = tinygltf::GetNumComponentsInType(uint32_t(accessor.type));
    if (components <= 0 || attribute->num_components() != components) {
      Fail("attribute " + name + ": the Draco attribute has " + std::to_string(int(attribute->num_components())) +
           " components, its accessor " + std::to_string(components));
    }
    std::vector<unsigned char> bytes;
    bool converted = false;
    switch (accessor.componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: converted = AttributeBytes<float>(mesh, *attribute, components, &bytes); break;
      case TINYGLTF_COMPONENT_TYPE_BYTE: converted = AttributeBytes<int8_t>(mesh, *attribute, components, &bytes); break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: converted = AttributeBytes<uint8_t>(mesh, *attribute, components, &bytes); break;
      case TINYGLTF_COMPONENT_TYPE_SHORT: converted = AttributeBytes<int16_t>(mesh, *attribute, components, &bytes); break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: converted = AttributeBytes<uint16_t>(mesh, *attribute, components, &bytes); break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: converted = AttributeBytes<uint32_t>(mesh, *attribute, components, &bytes); break;
      default: Fail("attribute " + name + ": componentType " + std::to_string(accessor.componentType) + " is not a vertex type");
    }
    if (!converted) Fail("attribute " + name + ": the Draco values do not convert to the accessor's componentType");
    prim_.attributes[name] = AppendAccessor(model_, accessor, AppendBufferView(model_, std::move(bytes)), size_t(mesh.num_points()));
  }

  tinygltf::Model& model_;
  tinygltf::Primitive& prim_;
  std::string where_;
  size_t max_elements_;
};

}  // namespace

bool MakeCompressedMeshesReadable(json& doc, std::map<int, size_t>* fallback_lengths) {
  if (!doc.is_object()) return false;
  bool changed = false;
  // EXT_meshopt_compression's fallback buffers: one zero byte each for tinygltf (which refuses a
  // .gltf buffer without a URI and gives a GLB's BIN chunk to every such buffer); their length is
  // kept for DecodeMeshoptBufferViews.
  if (doc.contains("buffers") && doc["buffers"].is_array()) {
    for (size_t b = 0; b < doc["buffers"].size(); ++b) {
      json& buffer = doc["buffers"][b];
      if (!buffer.is_object() || buffer.contains("uri") || !buffer.contains("extensions") ||
          !buffer["extensions"].is_object() || !buffer["extensions"].contains(kMeshoptExtension)) {
        continue;
      }
      const json& extension = buffer["extensions"][std::string(kMeshoptExtension)];
      if (!extension.is_object() || !extension.value("fallback", false)) continue;
      if (!buffer.contains("byteLength") || !buffer["byteLength"].is_number_unsigned()) {
        throw std::invalid_argument("buffer " + std::to_string(b) + ": " + std::string(kMeshoptExtension) +
                                    " fallback buffer without an unsigned byteLength");
      }
      (*fallback_lengths)[int(b)] = buffer["byteLength"].get<size_t>();
      buffer["byteLength"] = 1;
      buffer["uri"] = "data:application/octet-stream;base64,AA==";
      changed = true;
    }
  }
  if (!doc.contains("meshes") || !doc["meshes"].is_array()) return changed;
  // KHR_draco_mesh_compression: tinygltf refuses an index accessor without a bufferView.
  json* accessors = doc.contains("accessors") && doc["accessors"].is_array() ? &doc["accessors"] : nullptr;
  const size_t num_views = doc.contains("bufferViews") && doc["bufferViews"].is_array() ? doc["bufferViews"].size() : 0;
  for (size_t m = 0; m < doc["meshes"].size(); ++m) {
    json& mesh = doc["meshes"][m];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (size_t p = 0; p < mesh["primitives"].size(); ++p) {
      json& prim = mesh["primitives"][p];
      if (!prim.is_object() || !prim.contains("extensions") || !prim["extensions"].is_object() ||
          !prim["extensions"].contains(kDracoExtension)) {
        continue;
      }
      const std::string name = mesh.contains("name") && mesh["name"].is_string() ? mesh["name"].get<std::string>() : "";
      const json& extension = prim["extensions"][std::string(kDracoExtension)];
      const json* view = extension.is_object() && extension.contains("bufferView") ? &extension["bufferView"] : nullptr;
      if (view == nullptr || !view->is_number_integer() || view->get<int64_t>() < 0 || size_t(view->get<int64_t>()) >= num_views) {
        throw std::invalid_argument(PrimitiveLabel(m, name, p) + ": " + std::string(kDracoExtension) +
                                    ": bufferView is missing or not one of the file's " + std::to_string(num_views) +
                                    " buffer views");
      }
      if (!prim.contains("indices") || !prim["indices"].is_number_integer() || accessors == nullptr) continue;
      const int64_t indices = prim["indices"].get<int64_t>();
      if (indices < 0 || size_t(indices) >= accessors->size() || !(*accessors)[indices].is_object()) continue;
      if (!(*accessors)[indices].contains("bufferView")) {
        (*accessors)[indices]["bufferView"] = *view;
        changed = true;
      }
    }
  }
  return changed;
}

namespace {

// An EXT_meshopt_compression buffer view's extension object, read and checked.
struct MeshoptView {
  int source = -1;  // buffer
  size_t offset = 0, length = 0, stride = 0, count = 0;
  std::string mode, filter = "NONE";
};

MeshoptView ReadMeshoptView(const tinygltf::Value& extension, const std::function<void(const std::string&)>& fail) {
  if (!extension.IsObject()) fail("the extension is not an object");
  auto number = [&](const char* key, bool required, size_t fallback) -> size_t {
    if (!extension.Has(key)) {
      if (required) fail(std::string("has no ") + key);
      return fallback;
    }
    const tinygltf::Value& v = extension.Get(key);
    if (!v.IsNumber() || v.GetNumberAsDouble() < 0 || v.GetNumberAsDouble() != std::floor(v.GetNumberAsDouble()) ||
        v.GetNumberAsDouble() > 9.0e15) {
      fail(std::string(key) + " is not a non-negative integer");
    }
    return size_t(v.GetNumberAsDouble());
  };
  auto text = [&](const char* key, bool required, const std::string& fallback) -> std::string {
    if (!extension.Has(key)) {
      if (required) fail(std::string("has no ") + key);
      return fallback;
    }
    if (!extension.Get(key).IsString()) fail(std::string(key) + " is not a string");
    return extension.Get(key).Get<std::string>();
  };
  MeshoptView v;
  v.source = int(std::min<size_t>(number("buffer", true, 0), size_t(std::numeric_limits<int>::max())));
  v.offset = number("byteOffset", false, 0);
  v.length = number("byteLength", true, 0);
  v.stride = number("byteStride", true, 0);
  v.count = number("count", true, 0);
  v.mode = text("mode", true, "");
  v.filter = text("filter", false, "NONE");
  return v;
}

// Decodes `v`'s compressed bytes into `out` (count * stride bytes), as its mode and filter say.
void DecodeMeshopt(const MeshoptView& v, const unsigned char* compressed, unsigned char* out,
                   const std::function<void(const std::string&)>& fail) {
  int result = 0;
  if (v.mode == "ATTRIBUTES") {
    if (v.stride == 0 || v.stride % 4 != 0 || v.stride > 256) fail("ATTRIBUTES need a byteStride of 4, 8, ... 256");
    result = meshopt_decodeVertexBuffer(out, v.count, v.stride, compressed, v.length);
  } else if (v.mode == "TRIANGLES" || v.mode == "INDICES") {
    if (v.stride != 2 && v.stride != 4) fail(v.mode + " need a byteStride of 2 or 4");
    if (v.mode == "TRIANGLES" && v.count % 3 != 0) fail("TRIANGLES need a count that is a multiple of 3");
    result = v.mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out, v.count, v.stride, compressed, v.length)
                                   : meshopt_decodeIndexSequence(out, v.count, v.stride, compressed, v.length);
  } else {
    fail("mode '" + v.mode + "' is none of ATTRIBUTES, TRIANGLES, INDICES");
  }
  if (result != 0) fail("the compressed bytes do not decode (meshoptimizer error " + std::to_string(result) + ")");
  if (v.filter == "NONE") return;
  if (v.mode != "ATTRIBUTES") fail("filter " + v.filter + " on " + v.mode + ", which takes none");
  if (v.filter == "OCTAHEDRAL") {
    if (v.stride != 4 && v.stride != 8) fail("OCTAHEDRAL needs a byteStride of 4 or 8");
    meshopt_decodeFilterOct(out, v.count, v.stride);
  } else if (v.filter == "QUATERNION") {
    if (v.stride != 8) fail("QUATERNION needs a byteStride of 8");
    meshopt_decodeFilterQuat(out, v.count, v.stride);
  } else if (v.filter == "EXPONENTIAL") {
    meshopt_decodeFilterExp(out, v.count, v.stride);
  } else {
    fail("filter '" + v.filter + "' is none of NONE, OCTAHEDRAL, QUATERNION, EXPONENTIAL");
  }
}

}  // namespace

std::string PrimitiveLabel(size_t mesh, const std::string& mesh_name, size_t prim) {
  std::string label = "mesh " + std::to_string(mesh);
  if (!mesh_name.empty()) label += " '" + mesh_name + "'";
  return label + " primitive " + std::to_string(prim);
}

size_t DecodeMeshoptBufferViews(tinygltf::Model& model, const std::map<int, size_t>& fallback_lengths, size_t max_bytes) {
  size_t total = 0, decoded = 0;
  for (const auto& [index, length] : fallback_lengths) {
    if (size_t(index) >= model.buffers.size()) continue;
    total += std::min(length, max_bytes + 1);
    if (total > max_bytes) {
      throw std::invalid_argument("buffer " + std::to_string(index) + ": " + std::string(kMeshoptExtension) +
                                  ": the fallback buffers' " + std::to_string(total) + "+ bytes exceed the limit of " +
                                  std::to_string(max_bytes) + " decoded bytes");
    }
    model.buffers[index].data.assign(length, 0);
  }
  for (size_t i = 0; i < model.bufferViews.size(); ++i) {
    tinygltf::BufferView& view = model.bufferViews[i];
    const auto it = view.extensions.find(std::string(kMeshoptExtension));
    if (it == view.extensions.end()) continue;
    const tinygltf::Value extension = it->second;
    view.extensions.erase(it);
    if (!fallback_lengths.count(view.buffer)) continue;  // the buffer holds the data uncompressed too
    const std::string where = "bufferView " + std::to_string(i) + ": " + std::string(kMeshoptExtension) + ": ";
    auto fail = [&](const std::string& what) { throw std::invalid_argument(where + what); };
    const MeshoptView v = ReadMeshoptView(extension, fail);
    if (size_t(v.source) >= model.buffers.size()) fail("buffer " + std::to_string(v.source) + " out of range");
    const std::vector<unsigned char>& source = model.buffers[v.source].data;
    if (v.offset > source.size() || v.length > source.size() - v.offset) {
      fail("bytes " + std::to_string(v.offset) + " + " + std::to_string(v.length) + " lie beyond buffer " +
           std::to_string(v.source) + "'s " + std::to_string(source.size()));
    }
    std::vector<unsigned char>& target = model.buffers[view.buffer].data;
    if (v.stride != 0 && v.count > view.byteLength / v.stride) {
      fail(std::to_string(v.count) + " elements of " + std::to_string(v.stride) + " bytes do not fit the view's " +
           std::to_string(view.byteLength) + " bytes");
    }
    if (view.byteOffset > target.size() || view.byteLength > target.size() - view.byteOffset) {
      fail("the view (bytes " + std::to_string(view.byteOffset) + " + " + std::to_string(view.byteLength) +
           ") lies beyond its fallback buffer's " + std::to_string(target.size()));
    }
    DecodeMeshopt(v, source.data() + v.offset, target.data() + view.byteOffset, fail);
    ++decoded;
  }
  return decoded;
}

size_t DecodeDracoPrimitives(tinygltf::Model& model, size_t max_elements) {
  size_t decoded = 0;
  for (size_t m = 0; m < model.meshes.size(); ++m) {
    for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
      tinygltf::Primitive& prim = model.meshes[m].primitives[p];
      const auto it = prim.extensions.find(std::string(kDracoExtension));
      if (it == prim.extensions.end()) continue;
      const tinygltf::Value extension = it->second;
      prim.extensions.erase(it);
      PrimitiveDecoder(model, prim, PrimitiveLabel(m, model.meshes[m].name, p), max_elements).Decode(extension);
      ++decoded;
    }
  }
  return decoded;
}

}  // namespace rigsim
