#include <charconv>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "gltf/gltf_compression.h"
#include "gltf/loader.h"
#include "gltf/readable_gltf.h"

namespace rigsim::gltf {
namespace {

// tinygltf 2.7 reports two things glTF allows as errors, although it goes on loading: an
// animation channel without a target node (an extension such as KHR_animation_pointer names its
// target; tinygltf skips the channel, in two lines of `err`) and a skin without
// inverseBindMatrices (identity matrices, as in glTF). This removes those lines from `err` and
// returns how many channels were skipped. A node or matrix index of the wrong type still fails:
// tinygltf words that differently.
int TakeErrorsGltfAllows(std::string* err) {
  std::istringstream lines(*err);
  std::string kept;
  int channels = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line == "`node` field is missing in animation.channels.target") {
      ++channels;
    } else if (line != "'node' property is missing." && line != "'inverseBindMatrices' property is missing in Skin.") {
      kept += line + "\n";
    }
  }
  *err = kept;
  return channels;
}

// tinygltf quotes a data URI whole in its messages, and a buffer's can be megabytes: this keeps
// each one's first characters and says how long it was.
std::string AbbreviateDataUris(std::string text) {
  constexpr size_t kKeep = 32;
  for (size_t at = text.find("data:"); at != std::string::npos; at = text.find("data:", at + 1)) {
    const size_t comma = text.find(',', at);
    if (comma == std::string::npos) break;
    const size_t end = std::min(text.find_first_of(" \n\"'", comma), text.size());  // base64 has none of these
    const size_t length = end - comma - 1;
    if (length > kKeep) text.replace(comma + 1 + kKeep, length - kKeep, "... (" + std::to_string(length) + " characters)");
  }
  return text;
}

// A glTF file's extensionsRequired and extensionsUsed from its JSON, read without tinygltf (best
// effort: empty when the JSON cannot be read). For files tinygltf refuses: a file that needs an
// extension rigsim lacks should be refused for that, not for what tinygltf stumbles on first
// (an index accessor without a bufferView, say).
struct DeclaredExtensions {
  std::vector<std::string> required, used;
};

DeclaredExtensions ReadDeclaredExtensions(const nlohmann::json& doc) {
  auto names = [&](const char* key) {
    std::vector<std::string> out;
    if (!doc.is_object() || !doc.contains(key) || !doc[key].is_array()) return out;
    for (const nlohmann::json& ext : doc[key]) {
      if (ext.is_string()) out.push_back(ext.get<std::string>());
    }
    return out;
  };
  return {names("extensionsRequired"), names("extensionsUsed")};
}

// "<major>.<minor>", the form glTF gives asset.version and asset.minVersion; nullopt otherwise.
std::optional<std::pair<int, int>> ParseGltfVersion(const std::string& text) {
  const char* end = text.data() + text.size();
  int major = 0, minor = 0;
  const auto [dot, major_error] = std::from_chars(text.data(), end, major);
  if (major_error != std::errc() || dot == end || *dot != '.') return std::nullopt;
  const auto [rest, minor_error] = std::from_chars(dot + 1, end, minor);
  if (minor_error != std::errc() || rest != end) return std::nullopt;
  return std::make_pair(major, minor);
}

// Why rigsim, a glTF 2.0 client, must refuse the file; empty when it may load it. glTF 2.0,
// "Asset": a client first checks minVersion, when given, for a version it supports (rigsim: 2.0),
// else that the major version is 2 (a later 2.x only adds what a 2.0 client may ignore).
std::string UnsupportedVersion(const tinygltf::Asset& asset) {
  const std::string& given = asset.minVersion.empty() ? asset.version : asset.minVersion;
  const char* key = asset.minVersion.empty() ? "asset.version" : "asset.minVersion";
  const auto version = ParseGltfVersion(given);
  if (!version) return std::string(key) + " " + Quote(given) + " is not a glTF version (<major>.<minor>)";
  if (asset.minVersion.empty()) return version->first == 2 ? "" : "asset.version is " + given + ": rigsim reads glTF 2.x";
  if (*version == std::make_pair(2, 0)) return "";
  return "asset.minVersion is " + given + ": the file needs a glTF " + given + " reader, and rigsim reads glTF 2.0";
}

// Extensions whose content we fully honour; everything else in extensionsRequired is fatal.
// KHR_texture_transform is honoured on the textures rigsim renders: base colour, emissive,
// normal, occlusion. EXT_mesh_gpu_instancing's custom attributes (_ID, ...) are named as ignored.
bool SupportedExtension(const std::string& name) {
  return name == "KHR_mesh_quantization" || name == "KHR_texture_transform" || name == "KHR_materials_unlit" ||
         name == "KHR_materials_emissive_strength" || name == "EXT_texture_webp" || name == kGpuInstancing ||
         name == kDracoExtension || name == kMeshoptExtension;
}

}  // namespace

void Loader::ReadModel() {
  // Read once: the look for compressed meshes, tinygltf and the extension check share it.
  std::ifstream in(path_, std::ios::binary);
  if (!in) Fail("cannot open file");
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) Fail("cannot read file");
  if (bytes.empty()) Fail("the file is empty");
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;

  // What tinygltf refuses of valid glTF, and compressed meshes: it reads a version it accepts
  // (gltf/readable_gltf.h), and the model it gives back is set right below.
  ReadableGltf readable;
  try {
    readable = ReadableGltfOf(bytes);
  } catch (const std::invalid_argument& e) {
    Fail(e.what());
  }
  const std::vector<unsigned char>& load = readable.bytes.empty() ? bytes : readable.bytes;

  tinygltf::TinyGLTF gltf;
  image_checks_.max_pixels = options_.max_image_pixels;
  gltf.SetImageLoader(&LoadCheckedImage, &image_checks_);
  std::string err, warn;
  const std::string folder = path_.parent_path().string();  // for external buffers and images
  const bool ok = binary ? gltf.LoadBinaryFromMemory(&model_, &err, &warn, load.data(), unsigned(load.size()), folder)
                         : gltf.LoadASCIIFromString(&model_, &err, &warn, reinterpret_cast<const char*>(load.data()),
                                                    unsigned(load.size()), folder);
  readable.bytes = {};  // tinygltf keeps what it needs
  if (const std::string why = ok ? UnsupportedVersion(model_.asset) : ""; !why.empty()) Fail(why);
  const int nodeless_channels = TakeErrorsGltfAllows(&err);
  err = AbbreviateDataUris(err);
  warn = AbbreviateDataUris(warn);
  auto missing_file = [](const std::string& line) {
    return line.find("Failed to load external") != std::string::npos || line.find("File not found") != std::string::npos;
  };
  std::string unsupported_used;  // named when the file is refused anyway
  if (!ok || !err.empty() || missing_file(warn)) {
    const nlohmann::json doc = nlohmann::json::parse(GltfJson(bytes), nullptr, /*allow_exceptions=*/false);
    const DeclaredExtensions declared = ReadDeclaredExtensions(doc);
    for (const std::string& ext : declared.required) {
      if (!SupportedExtension(ext)) Fail("requires extension " + ext + ", which rigsim does not support");
    }
    for (const std::string& ext : declared.used) {
      if (!SupportedExtension(ext)) unsupported_used += (unsupported_used.empty() ? "" : ", ") + ext;
    }
  }
  // tinygltf reports a missing image as a warning; we turn it into an error naming the file.
  std::istringstream warn_lines(warn);
  for (std::string line; std::getline(warn_lines, line);) {
    if (line.empty()) continue;
    if (missing_file(line)) Fail(line);
    Warn("tinygltf: " + line);
  }
  if (!ok || !err.empty()) {
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    // tinygltf's words for a buffer whose data URI is not base64 or not byteLength bytes long.
    if (err.find("Failed to decode 'uri' : ") == 0 && err.find(" in Buffer") != std::string::npos) {
      err += " (the data URI is not base64, or does not decode to the buffer's byteLength)";
    }
    if (!unsupported_used.empty()) err += " (the file also uses " + unsupported_used + ", which rigsim does not read)";
    Fail(std::string(binary ? "invalid .glb: " : "invalid .gltf: ") + (err.empty() ? "tinygltf failed" : err));
  }
  if (nodeless_channels > 0) {
    Warn(std::to_string(nodeless_channels) + " animation channel(s) without a target node ignored (an extension " +
         "such as KHR_animation_pointer names what they animate)");
  }
  bytes = {};  // what follows needs only the model
  UndoReadableRewrites(readable);
  try {
    // Decoded data is bounded like accessors: elements of at most 16 bytes (VEC4 float).
    scene_.meshopt_views = DecodeMeshoptBufferViews(model_, readable.fallback_lengths, options_.max_accessor_count * 16);
    scene_.draco_primitives = DecodeDracoPrimitives(model_, options_.max_accessor_count);
  } catch (const std::invalid_argument& e) {
    Fail(e.what());
  }
}

// The model as the file has it where ReadableGltfOf rewrote it for tinygltf.
void Loader::UndoReadableRewrites(const ReadableGltf& readable) {
  for (int b : readable.dataless_buffers) {
    if (size_t(b) < model_.buffers.size()) model_.buffers[b].data.clear();
  }
  dataless_buffers_ = readable.dataless_buffers;
  for (int a : readable.viewless_accessors) {
    if (size_t(a) < model_.accessors.size()) model_.accessors[a].bufferView = -1;
  }
  for (const auto& [a, type] : readable.unknown_component_types) {
    if (size_t(a) < model_.accessors.size()) model_.accessors[a].componentType = type;
  }
  unknown_accessor_types_ = readable.unknown_types;
}

void Loader::ReportFileLevelUnsupported() {
  for (const std::string& ext : model_.extensionsRequired) {
    if (!SupportedExtension(ext)) Fail("requires extension " + ext + ", which rigsim does not support");
  }
  for (const std::string& ext : model_.extensionsUsed) {
    if (!SupportedExtension(ext)) Warn("extension " + ext + " is not supported; its data is ignored");
  }
}

}  // namespace rigsim::gltf
