#include "gltf/readable_gltf.h"


#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string_view>

#include <nlohmann/json.hpp>

#include "common/base64.h"
#include "gltf/gltf_compression.h"

namespace rigsim {
namespace {

using nlohmann::json;

constexpr uint32_t kJsonChunk = 0x4E4F534A, kBinChunk = 0x004E4942;
constexpr const char* kPlaceholderUri = "data:application/octet-stream;base64,AA==";  // one zero byte

uint32_t ReadU32(const unsigned char* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);  // GLB is little-endian, as is every machine rigsim builds on
  return v;
}

void AppendU32(std::vector<unsigned char>& out, uint32_t v) {
  const auto* p = reinterpret_cast<const unsigned char*>(&v);
  out.insert(out.end(), p, p + 4);
}

bool StartsWith(const std::string& s, std::string_view prefix) { return s.compare(0, prefix.size(), prefix) == 0; }

// The data URIs tinygltf 2.7 decodes (its IsDataURI): base64 with one of these media types.
bool TinygltfDecodes(const std::string& uri) {
  for (std::string_view prefix : {"data:application/octet-stream;base64,", "data:image/jpeg;base64,", "data:image/png;base64,",
                                  "data:image/bmp;base64,", "data:image/gif;base64,", "data:text/plain;base64,",
                                  "data:application/gltf-buffer;base64,"}) {
    if (StartsWith(uri, prefix)) return true;
  }
  return false;
}

// A URI with a scheme other than data: (http:, https:, file:, ...); a one-letter "scheme" is a
// Windows drive ("C:/textures/a.png"), a path.
bool IsRemote(const std::string& uri) {
  const size_t colon = uri.find(':');
  if (colon == std::string::npos || colon < 2 || StartsWith(uri, "data:")) return false;
  for (size_t i = 0; i < colon; ++i) {
    const char c = uri[i];
    const bool letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
    if (!letter && (i == 0 || !((c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.'))) return false;
  }
  return true;
}

int Base64Value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+' || c == '-') return 62;
  if (c == '/' || c == '_') return 63;
  return -1;
}

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// The bytes of a data URI, "data:[<media type>][;base64],<data>" (RFC 2397): base64, or
// percent-encoded text without ";base64". Throws std::invalid_argument saying what is malformed.
std::vector<unsigned char> DecodeDataUri(const std::string& uri) {
  const size_t comma = uri.find(',');
  if (comma == std::string::npos) throw std::invalid_argument("its data URI has no ',' before the data");
  const std::string header = uri.substr(0, comma);
  const bool base64 = header.size() >= 7 && header.compare(header.size() - 7, 7, ";base64") == 0;
  std::vector<unsigned char> out;
  if (base64) {
    uint32_t bits = 0;
    int nbits = 0;
    for (size_t i = comma + 1; i < uri.size(); ++i) {
      const char c = uri[i];
      if (c == '=' || c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
      const int v = Base64Value(c);
      if (v < 0) throw std::invalid_argument("its base64 data URI holds '" + std::string(1, c) + "', which is not base64");
      bits = (bits << 6) | uint32_t(v);
      nbits += 6;
      if (nbits >= 8) {
        nbits -= 8;
        out.push_back(static_cast<unsigned char>((bits >> nbits) & 0xFF));
      }
    }
    return out;
  }
  for (size_t i = comma + 1; i < uri.size(); ++i) {
    if (uri[i] != '%') {
      out.push_back(static_cast<unsigned char>(uri[i]));
      continue;
    }
    const int hi = i + 2 < uri.size() ? HexValue(uri[i + 1]) : -1, lo = hi >= 0 ? HexValue(uri[i + 2]) : -1;
    if (lo < 0) throw std::invalid_argument("its data URI has a '%' not followed by two hexadecimal digits");
    out.push_back(static_cast<unsigned char>(hi * 16 + lo));
    i += 2;
  }
  return out;
}

std::string Base64Uri(const std::vector<unsigned char>& data) {
  return "data:application/octet-stream;base64," +
         Base64Encode(std::string_view(reinterpret_cast<const char*>(data.data()), data.size()));
}

json* ArrayOf(json& doc, const char* key) { return doc.contains(key) && doc[key].is_array() ? &doc[key] : nullptr; }

// Data URIs tinygltf does not decode become ones it does; a remote uri is refused. `what` names
// the object in messages: "buffer 2".
bool MakeUriReadable(json& object, const std::string& what) {
  if (!object.is_object() || !object.contains("uri") || !object["uri"].is_string()) return false;
  const std::string uri = object["uri"].get<std::string>();
  if (IsRemote(uri)) {
    throw std::invalid_argument(what + ": its uri '" + uri.substr(0, 200) +
                                "' is a web address; rigsim reads only the glTF file and the files beside it: download it "
                                "next to the glTF file and give its file name as the uri");
  }
  if (!StartsWith(uri, "data:") || TinygltfDecodes(uri)) return false;
  try {
    object["uri"] = Base64Uri(DecodeDataUri(uri));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(what + ": " + e.what());
  }
  return true;
}

bool IsAccessorType(const std::string& type) {
  for (const char* t : {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"}) {
    if (type == t) return true;
  }
  return false;
}

bool IsComponentType(int64_t type) {
  return type == 5120 || type == 5121 || type == 5122 || type == 5123 || type == 5125 || type == 5126;
}

// The rewrites of the header comment, each recorded in *out; whether any was made.
bool MakeReadable(json& doc, bool glb, bool glb_has_bin, ReadableGltf* out) {
  bool changed = MakeCompressedMeshesReadable(doc, &out->fallback_lengths);
  if (json* buffers = ArrayOf(doc, "buffers")) {
    for (size_t b = 0; b < buffers->size(); ++b) {
      json& buffer = (*buffers)[b];
      if (!buffer.is_object()) continue;
      changed |= MakeUriReadable(buffer, "buffer " + std::to_string(b));
      const bool takes_bin = glb && b == 0 && glb_has_bin;  // the GLB's BIN chunk
      if (buffer.contains("uri") || takes_bin) continue;
      buffer["uri"] = kPlaceholderUri;
      buffer["byteLength"] = 1;
      out->dataless_buffers.insert(int(b));
      changed = true;
    }
  }
  if (json* images = ArrayOf(doc, "images")) {
    for (size_t i = 0; i < images->size(); ++i) changed |= MakeUriReadable((*images)[i], "image " + std::to_string(i));
  }
  json* accessors = ArrayOf(doc, "accessors");
  if (accessors == nullptr) return changed;
  for (size_t a = 0; a < accessors->size(); ++a) {
    json& accessor = (*accessors)[a];
    if (!accessor.is_object()) continue;
    if (accessor.contains("type") && accessor["type"].is_string() && !IsAccessorType(accessor["type"].get<std::string>())) {
      out->unknown_types[int(a)] = accessor["type"].get<std::string>();
      accessor["type"] = "SCALAR";
      changed = true;
    }
    if (accessor.contains("componentType") && accessor["componentType"].is_number_integer() &&
        !IsComponentType(accessor["componentType"].get<int64_t>())) {
      const int64_t type = accessor["componentType"].get<int64_t>();
      out->unknown_component_types[int(a)] = int(std::max<int64_t>(std::min<int64_t>(type, INT32_MAX), INT32_MIN));
      accessor["componentType"] = 5126;
      changed = true;
    }
  }
  // Index accessors without a bufferView: tinygltf wants one; a placeholder view over a
  // placeholder buffer, appended so that no index in the file changes.
  json* meshes = ArrayOf(doc, "meshes");
  int placeholder_view = -1;
  for (size_t m = 0; meshes != nullptr && m < meshes->size(); ++m) {
    json& mesh = (*meshes)[m];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (const json& prim : mesh["primitives"]) {
      if (!prim.is_object() || !prim.contains("indices") || !prim["indices"].is_number_integer()) continue;
      const int64_t a = prim["indices"].get<int64_t>();
      if (a < 0 || size_t(a) >= accessors->size() || !(*accessors)[a].is_object() || (*accessors)[a].contains("bufferView")) continue;
      if (placeholder_view < 0) {
        if (!doc.contains("buffers") || !doc["buffers"].is_array()) doc["buffers"] = json::array();
        if (!doc.contains("bufferViews") || !doc["bufferViews"].is_array()) doc["bufferViews"] = json::array();
        out->dataless_buffers.insert(int(doc["buffers"].size()));
        doc["buffers"].push_back({{"byteLength", 1}, {"uri", kPlaceholderUri}});
        placeholder_view = int(doc["bufferViews"].size());
        doc["bufferViews"].push_back({{"buffer", doc["buffers"].size() - 1}, {"byteLength", 1}});
      }
      (*accessors)[a]["bufferView"] = placeholder_view;
      out->viewless_accessors.insert(int(a));
      changed = true;
    }
  }
  return changed;
}

}  // namespace

std::string_view GltfJson(const std::vector<unsigned char>& file) {
  const std::string_view all(reinterpret_cast<const char*>(file.data()), file.size());
  if (file.size() < 4 || std::memcmp(file.data(), "glTF", 4) != 0) return all;  // .gltf: all JSON
  // GLB: header (magic, version, length), then chunks of (length, type, data); the first is JSON.
  if (file.size() < 20 || ReadU32(&file[16]) != kJsonChunk || ReadU32(&file[12]) > file.size() - 20) return {};
  return all.substr(20, ReadU32(&file[12]));
}

ReadableGltf ReadableGltfOf(const std::vector<unsigned char>& file) {
  ReadableGltf out;
  const std::string_view text = GltfJson(file);
  json doc = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!doc.is_object()) return out;
  const bool glb = text.size() != file.size();
  const size_t rest = glb ? 20 + text.size() : file.size();  // the chunks after the JSON, unchanged
  const bool has_bin = glb && file.size() >= rest + 8 && ReadU32(&file[rest + 4]) == kBinChunk;
  if (!MakeReadable(doc, glb, has_bin, &out)) return out;
  std::string rewritten = doc.dump();
  if (!glb) {
    out.bytes.assign(rewritten.begin(), rewritten.end());
    return out;
  }
  while (rewritten.size() % 4 != 0) rewritten.push_back(' ');  // chunks stay 4-byte aligned
  out.bytes.assign(file.begin(), file.begin() + 8);
  AppendU32(out.bytes, uint32_t(12 + 8 + rewritten.size() + (file.size() - rest)));
  AppendU32(out.bytes, uint32_t(rewritten.size()));
  AppendU32(out.bytes, kJsonChunk);
  out.bytes.insert(out.bytes.end(), rewritten.begin(), rewritten.end());
  out.bytes.insert(out.bytes.end(), file.begin() + std::ptrdiff_t(rest), file.end());
  return out;
}

}  // namespace rigsim
