#include "scenes/gltf_loader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <set>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <tiny_gltf.h>

#include "labels/cityscapes.h"
#include "scenes/gltf_compression.h"
#include "scenes/label_rules.h"
#include "scenes/morphing.h"
#include "scenes/skinning.h"

namespace rigsim {
namespace {

// A class given explicitly somewhere (node, mesh or material); nullopt = not specified there.
using ClassTag = std::optional<uint8_t>;

std::string Quote(const std::string& s) { return "'" + s + "'"; }

std::string MeshLabel(const tinygltf::Model& model, int mesh, int prim) {
  return PrimitiveLabel(size_t(mesh), model.meshes[mesh].name, size_t(prim));
}

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

// A quaternion too short to normalise into a rotation (glTF stores unit ones; exporters round).
bool IsZeroQuaternion(const Eigen::Vector4d& q) { return !(q.norm() > 1e-6); }

Eigen::Matrix4d LocalTransform(const tinygltf::Node& node) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (node.matrix.size() == 16) {
    for (int i = 0; i < 16; ++i) m(i % 4, i / 4) = node.matrix[i];  // column-major in glTF
    return m;
  }
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (node.translation.size() == 3) t.translate(Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4) {
    // glTF stores quaternions as (x, y, z, w); Eigen's constructor takes (w, x, y, z).
    t.rotate(Eigen::Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]).normalized());
  }
  if (node.scale.size() == 3) t.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
  return t.matrix();
}

// Width and height of a WebP file (RIFF "WEBP" with a VP8, VP8L or VP8X first chunk, as the
// WebP container specification lays them out), read without decoding; nullopt otherwise.
std::optional<std::pair<uint64_t, uint64_t>> EncodedWebpSize(const unsigned char* b, size_t size) {
  if (size < 30 || std::memcmp(b, "RIFF", 4) != 0 || std::memcmp(b + 8, "WEBP", 4) != 0) return std::nullopt;
  auto le16 = [&](size_t i) { return uint64_t(b[i]) | uint64_t(b[i + 1]) << 8; };
  auto le24 = [&](size_t i) { return le16(i) | uint64_t(b[i + 2]) << 16; };
  if (std::memcmp(b + 12, "VP8 ", 4) == 0 && b[23] == 0x9d && b[24] == 0x01 && b[25] == 0x2a) {  // lossy key frame
    return std::make_pair(le16(26) & 0x3fff, le16(28) & 0x3fff);
  }
  if (std::memcmp(b + 12, "VP8L", 4) == 0 && b[20] == 0x2f) {  // lossless: 14-bit width - 1, height - 1
    const uint64_t bits = le16(21) | le16(23) << 16;
    return std::make_pair((bits & 0x3fff) + 1, ((bits >> 14) & 0x3fff) + 1);
  }
  if (std::memcmp(b + 12, "VP8X", 4) == 0) return std::make_pair(le24(24) + 1, le24(27) + 1);  // extended: canvas
  return std::nullopt;
}

// Width and height of an encoded PNG (its IHDR), JPEG (its start-of-frame segment) or WebP, read
// without decoding; nullopt for anything else.
std::optional<std::pair<uint64_t, uint64_t>> EncodedImageSize(const unsigned char* bytes, size_t size) {
  auto be16 = [&](size_t i) { return uint64_t(bytes[i]) << 8 | bytes[i + 1]; };
  auto be32 = [&](size_t i) { return be16(i) << 16 | be16(i + 2); };
  if (size >= 24 && std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) == 0 && std::memcmp(bytes + 12, "IHDR", 4) == 0) {
    return std::make_pair(be32(16), be32(20));
  }
  if (auto webp = EncodedWebpSize(bytes, size)) return webp;
  if (size < 4 || bytes[0] != 0xFF || bytes[1] != 0xD8) return std::nullopt;
  for (size_t i = 2; i + 9 <= size;) {  // JPEG segments: FF, marker, 16-bit length (itself included)
    if (bytes[i] != 0xFF) return std::nullopt;
    const int marker = bytes[i + 1];
    if (marker == 0xFF) {  // fill byte
      ++i;
      continue;
    }
    const bool start_of_frame = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (start_of_frame) return std::make_pair(be16(i + 7), be16(i + 5));  // length, precision, height, width
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) {  // markers without a segment
      i += 2;
      continue;
    }
    i += 2 + be16(i + 2);
  }
  return std::nullopt;
}

// What LoadCheckedImage is given and what it leaves for the loader: why each image it did not
// decode was refused. The loader fails on such an image only when a texture it uses samples it:
// an optional extension's image (KTX2 for KHR_texture_basisu, say) whose texture falls back to its
// PNG or JPEG `source` is skipped, as glTF asks of a client without the extension.
struct ImageChecks {
  uint64_t max_pixels = 0;
  std::map<int, std::string> refused;  // image index -> why it was not decoded
};

// Decodes glTF images with OpenCV (libpng, libjpeg, libwebp) in place of tinygltf's stb_image,
// after two checks on the encoded bytes: the image is a PNG or a JPEG, the formats glTF 2.0
// allows, or a WebP (EXT_texture_webp) (stb would also take BMP, PSD, GIF, ...), and its header
// asks for no more pixels than the limit. stb inflated a PNG's compressed data into a buffer
// without bound: a 1x1 PNG of a few hundred bytes (found by fuzzing) made it allocate 1.2 GB.
// libpng inflates row by row into the image's own size. An image that fails a check or does not
// decode is left empty, its reason kept in the ImageChecks `user_data`, and tinygltf goes on.
bool LoadCheckedImage(tinygltf::Image* image, const int index, std::string* /*err*/, std::string* /*warn*/,
                      int /*req_width*/, int /*req_height*/, const unsigned char* bytes, int size, void* user_data) {
  ImageChecks& checks = *static_cast<ImageChecks*>(user_data);
  auto refuse = [&](const std::string& why) {
    checks.refused[index] = "image " + std::to_string(index) + why;
    return true;
  };
  const auto dims = EncodedImageSize(bytes, size_t(std::max(size, 0)));
  if (!dims) return refuse(" is not a PNG, JPEG or WebP image (the formats glTF 2.0 and EXT_texture_webp allow)");
  if (dims->second != 0 && dims->first > checks.max_pixels / dims->second) {  // width x height > max
    return refuse(" is " + std::to_string(dims->first) + "x" + std::to_string(dims->second) +
                  " pixels, more than the limit of " + std::to_string(checks.max_pixels) +
                  " (GltfLoadOptions::max_image_pixels)");
  }
  cv::Mat decoded;
  try {
    decoded = cv::imdecode(cv::Mat(1, size, CV_8U, const_cast<unsigned char*>(bytes)), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    decoded.release();
  }
  const int channels = decoded.empty() ? 0 : decoded.channels();
  if (decoded.empty() || (decoded.depth() != CV_8U && decoded.depth() != CV_16U) || channels > 4) {
    return refuse(": cannot decode it");
  }
  if (channels == 3) cv::cvtColor(decoded, decoded, cv::COLOR_BGR2RGB);
  if (channels == 4) cv::cvtColor(decoded, decoded, cv::COLOR_BGRA2RGBA);
  if (!decoded.isContinuous()) decoded = decoded.clone();
  image->width = decoded.cols;
  image->height = decoded.rows;
  image->component = channels;
  image->bits = decoded.depth() == CV_16U ? 16 : 8;
  image->pixel_type = decoded.depth() == CV_16U ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image->image.assign(decoded.data, decoded.data + decoded.total() * decoded.elemSize());
  return true;
}

WrapMode ToWrap(int gl) {
  switch (gl) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return WrapMode::kClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return WrapMode::kMirroredRepeat;
    default: return WrapMode::kRepeat;
  }
}

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

// tinygltf 2.7 refuses an index accessor without a bufferView, which glTF allows (zeros, with
// sparse values), in words that name no primitive: "accessor[N] invalid bufferView". This names
// the primitives whose indices are accessor N, from the file's JSON; "" for any other error.
std::string IndexAccessorUsers(const nlohmann::json& doc, const std::string& err) {
  constexpr std::string_view kBefore = "accessor[", kAfter = "] invalid bufferView";
  const size_t after = err.find(kAfter);
  const size_t before = after == std::string::npos ? std::string::npos : err.rfind(kBefore, after);
  if (before == std::string::npos) return "";
  const char* last = err.data() + after;
  int accessor = -1;
  const auto [end, error] = std::from_chars(err.data() + before + kBefore.size(), last, accessor);
  if (error != std::errc() || end != last || !doc.is_object() || !doc.contains("meshes") || !doc["meshes"].is_array()) return "";
  std::string users;
  for (size_t m = 0; m < doc["meshes"].size(); ++m) {
    const nlohmann::json& mesh = doc["meshes"][m];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    const std::string name = mesh.contains("name") && mesh["name"].is_string() ? mesh["name"].get<std::string>() : "";
    for (size_t p = 0; p < mesh["primitives"].size(); ++p) {
      const nlohmann::json& prim = mesh["primitives"][p];
      if (prim.is_object() && prim.contains("indices") && prim["indices"] == accessor) {
        users += (users.empty() ? "" : ", ") + PrimitiveLabel(m, name, p);
      }
    }
  }
  return users;
}

constexpr const char* kGpuInstancing = "EXT_mesh_gpu_instancing";

// Extensions whose content we fully honour; everything else in extensionsRequired is fatal.
// KHR_texture_transform is honoured on the textures rigsim renders: base colour, emissive,
// normal, occlusion. EXT_mesh_gpu_instancing's custom attributes (_ID, ...) are named as ignored.
bool SupportedExtension(const std::string& name) {
  return name == "KHR_mesh_quantization" || name == "KHR_texture_transform" || name == "KHR_materials_unlit" ||
         name == "KHR_materials_emissive_strength" || name == "EXT_texture_webp" || name == kGpuInstancing ||
         name == kDracoExtension || name == kMeshoptExtension;
}

// The texture coordinates a material's texture samples: the TEXCOORD_<set> attribute, mapped by
// KHR_texture_transform (identity without it). Baked into SceneMesh::texcoords (base colour),
// emissive_texcoords and normal_texcoords, which is exact because a SceneMesh is one primitive
// with one material.
struct TextureUv {
  int set = 0;
  Eigen::Matrix<double, 2, 3> uv_from_texcoord = Eigen::Matrix<double, 2, 3>::Identity();
};

struct MaterialUvs {
  TextureUv base_color;
  std::optional<TextureUv> emissive;  // only with an emissive texture
  std::optional<TextureUv> normal;    // only with a normal texture
  std::optional<TextureUv> occlusion;  // only with an occlusion texture
};

class Loader {
 public:
  Loader(const std::filesystem::path& path, const GltfLoadOptions& options) : path_(path), options_(options) {}

  Scene Load() {
    ReadModel();
    scene_.source = path_.string();
    ReportFileLevelUnsupported();
    ParseClasses();
    ConvertMaterials();
    CheckNodeTransforms();
    ParseAnimations();
    ParseSkins();
    Traverse();
    SkinAtRestPose();
    Summarise();
    return std::move(scene_);
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const { throw std::runtime_error(path_.string() + ": " + what); }

  void Warn(const std::string& what) {
    if (options_.warnings_are_errors) Fail(what);
    scene_.warnings.push_back(what);
  }

  // Unsupported features that may occur many times are counted and reported once each.
  void Ignore(const std::string& what) { ++ignored_[what]; }

  void ReadModel() {
    // Read once: the look for compressed meshes, tinygltf and the extension check share it.
    std::ifstream in(path_, std::ios::binary);
    if (!in) Fail("cannot open file");
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) Fail("cannot read file");
    if (bytes.empty()) Fail("the file is empty");
    const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;

    // Compressed meshes: tinygltf reads a version it accepts (scenes/gltf_compression.h).
    std::optional<ReadableGltf> readable;
    try {
      readable = ReadableGltfOf(bytes);
    } catch (const std::invalid_argument& e) {
      Fail(e.what());
    }
    const std::vector<unsigned char>& load = readable ? readable->bytes : bytes;

    tinygltf::TinyGLTF gltf;
    image_checks_.max_pixels = options_.max_image_pixels;
    gltf.SetImageLoader(&LoadCheckedImage, &image_checks_);
    std::string err, warn;
    const std::string folder = path_.parent_path().string();  // for external buffers and images
    const bool ok = binary ? gltf.LoadBinaryFromMemory(&model_, &err, &warn, load.data(), unsigned(load.size()), folder)
                           : gltf.LoadASCIIFromString(&model_, &err, &warn, reinterpret_cast<const char*>(load.data()),
                                                      unsigned(load.size()), folder);
    if (readable) readable->bytes = {};  // tinygltf keeps what it needs
    if (const std::string why = ok ? UnsupportedVersion(model_.asset) : ""; !why.empty()) Fail(why);
    const int nodeless_channels = TakeErrorsGltfAllows(&err);
    err = AbbreviateDataUris(err);
    warn = AbbreviateDataUris(warn);
    auto missing_file = [](const std::string& line) {
      return line.find("Failed to load external") != std::string::npos || line.find("File not found") != std::string::npos;
    };
    std::string unsupported_used, index_users;  // named when the file is refused anyway
    if (!ok || !err.empty() || missing_file(warn)) {
      const nlohmann::json doc = nlohmann::json::parse(GltfJson(bytes), nullptr, /*allow_exceptions=*/false);
      const DeclaredExtensions declared = ReadDeclaredExtensions(doc);
      for (const std::string& ext : declared.required) {
        if (!SupportedExtension(ext)) Fail("requires extension " + ext + ", which rigsim does not support");
      }
      for (const std::string& ext : declared.used) {
        if (!SupportedExtension(ext)) unsupported_used += (unsupported_used.empty() ? "" : ", ") + ext;
      }
      index_users = IndexAccessorUsers(doc, err);
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
      if (!index_users.empty()) {
        err += " (the indices of " + index_users + ": glTF allows an index accessor without a bufferView, its values " +
               "all sparse, but tinygltf, which reads the file for rigsim, does not)";
      }
      if (!unsupported_used.empty()) err += " (the file also uses " + unsupported_used + ", which rigsim does not read)";
      Fail(std::string(binary ? "invalid .glb: " : "invalid .gltf: ") + (err.empty() ? "tinygltf failed" : err));
    }
    if (nodeless_channels > 0) {
      Warn(std::to_string(nodeless_channels) + " animation channel(s) without a target node ignored (an extension " +
           "such as KHR_animation_pointer names what they animate)");
    }
    bytes = {};  // what follows needs only the model
    try {
      if (readable) {
        // Decoded data is bounded like accessors: elements of at most 16 bytes (VEC4 float).
        scene_.meshopt_views = DecodeMeshoptBufferViews(model_, readable->fallback_lengths, options_.max_accessor_count * 16);
        scene_.draco_primitives = DecodeDracoPrimitives(model_, options_.max_accessor_count);
      }
    } catch (const std::invalid_argument& e) {
      Fail(e.what());
    }
  }

  void ReportFileLevelUnsupported() {
    for (const std::string& ext : model_.extensionsRequired) {
      if (!SupportedExtension(ext)) Fail("requires extension " + ext + ", which rigsim does not support");
    }
    for (const std::string& ext : model_.extensionsUsed) {
      if (!SupportedExtension(ext)) Warn("extension " + ext + " is not supported; its data is ignored");
    }
  }

  ClassTag ParseClass(const tinygltf::Value& extras, const std::string& owner) {
    if (!extras.IsObject() || !extras.Has("class")) return std::nullopt;
    const tinygltf::Value& v = extras.Get("class");
    if (!v.IsString()) {
      Warn(owner + ": extras.class is not a string; treated as unlabeled");
      return kUnlabeledId;
    }
    const std::string& name = v.Get<std::string>();
    if (const LabelClass* c = FindClassByName(name)) return c->id;
    Warn(owner + ": unknown class " + Quote(name) + "; treated as unlabeled");
    return kUnlabeledId;
  }

  void ParseClasses() {
    for (size_t i = 0; i < model_.nodes.size(); ++i) {
      node_class_.push_back(ParseClass(model_.nodes[i].extras, "node " + std::to_string(i) + " " + Quote(model_.nodes[i].name)));
    }
    for (size_t i = 0; i < model_.meshes.size(); ++i) {
      mesh_class_.push_back(ParseClass(model_.meshes[i].extras, "mesh " + std::to_string(i) + " " + Quote(model_.meshes[i].name)));
    }
    for (size_t i = 0; i < model_.materials.size(); ++i) {
      material_class_.push_back(
          ParseClass(model_.materials[i].extras, "material " + std::to_string(i) + " " + Quote(model_.materials[i].name)));
    }
  }

  void ConvertMaterials() {
    material_uv_.resize(model_.materials.size());
    for (size_t i = 0; i < model_.materials.size(); ++i) {
      const tinygltf::Material& m = model_.materials[i];
      Material out;
      out.name = m.name;
      const auto& pbr = m.pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() == 4) {
        out.base_color_factor = Eigen::Vector4d(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2],
                                                pbr.baseColorFactor[3]).cast<float>();
      }
      const std::string material_label = "material " + std::to_string(i) + " " + Quote(m.name);
      MaterialUvs& uvs = material_uv_[i];
      if (pbr.baseColorTexture.index >= 0) {
        uvs.base_color = ParseTextureInfoUv(pbr.baseColorTexture, material_label + " baseColorTexture");
        out.base_color_texture = ConvertTexture(pbr.baseColorTexture.index);
      }
      ConvertEmission(m, material_label, &out, &uvs);
      if (m.normalTexture.index >= 0) {
        const std::string where = material_label + " normalTexture";
        if (!std::isfinite(m.normalTexture.scale)) Fail(where + ": scale is not finite");
        uvs.normal = ParseTextureInfoUv(m.normalTexture, where);
        out.normal_texture = ConvertTexture(m.normalTexture.index);
        out.normal_scale = float(m.normalTexture.scale);
      }
      if (m.occlusionTexture.index >= 0) {
        const std::string where = material_label + " occlusionTexture";
        const double strength = m.occlusionTexture.strength;
        if (!(strength >= 0.0 && strength <= 1.0)) Fail(where + ": strength must be in [0, 1], got " + std::to_string(strength));
        uvs.occlusion = ParseTextureInfoUv(m.occlusionTexture, where);
        out.occlusion_texture = ConvertTexture(m.occlusionTexture.index);
        out.occlusion_strength = float(strength);
      }
      if (m.alphaMode == "MASK") {
        out.alpha_mode = AlphaMode::kMask;
      } else if (m.alphaMode == "BLEND") {
        out.alpha_mode = AlphaMode::kBlend;
      }
      out.alpha_cutoff = float(m.alphaCutoff);
      out.double_sided = m.doubleSided;
      if (pbr.metallicRoughnessTexture.index >= 0) Ignore("metallicRoughnessTexture (materials)");
      for (const auto& [name, value] : m.extensions) {
        if (name == "KHR_materials_unlit") {
          out.unlit = true;
        } else if (name == "KHR_materials_emissive_strength") {
          // read by ConvertEmission
        } else {
          Ignore("material extension " + name);
        }
      }
      scene_.materials.push_back(std::move(out));
    }
    // ConvertTexture failed on every refused image a texture samples: the rest are used by none.
    for (const auto& [index, why] : image_checks_.refused) Warn(why + "; no texture rigsim uses samples it, so it is skipped");
  }

  // JOINTS_0 (unsigned byte or short) and WEIGHTS_0 (float, or normalized unsigned byte or
  // short), weights rescaled to sum to 1.
  void ReadSkinning(const tinygltf::Primitive& prim, int skin, size_t nverts, const std::string& where, SceneMesh* out) {
    if (size_t(skin) >= scene_.skins.size()) Fail(where + ": skin " + std::to_string(skin) + " out of range");
    const int joints_acc = prim.attributes.at("JOINTS_0"), weights_acc = prim.attributes.at("WEIGHTS_0");
    const std::string joints_label = "accessor " + std::to_string(joints_acc) + " (" + where + " JOINTS_0)";
    const std::string weights_label = "accessor " + std::to_string(weights_acc) + " (" + where + " WEIGHTS_0)";
    size_t nj = 0, nw = 0;
    const std::vector<double> joints = ReadAccessor(joints_acc, TINYGLTF_TYPE_VEC4, where + " JOINTS_0", &nj);
    const std::vector<double> weights = ReadAccessor(weights_acc, TINYGLTF_TYPE_VEC4, where + " WEIGHTS_0", &nw);
    const int joint_type = model_.accessors[joints_acc].componentType;  // in range: ReadAccessor checked
    if (joint_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && joint_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
      Fail(joints_label + ": componentType must be UNSIGNED_BYTE or UNSIGNED_SHORT");
    }
    if (nj != nverts) Fail(joints_label + ": count differs from POSITION");
    if (nw != nverts) Fail(weights_label + ": count differs from POSITION");
    const size_t num_joints = scene_.skins[skin].joints.size();
    out->skin = skin;
    out->joints.resize(nverts);
    out->weights.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) {
      double sum = 0;
      for (int k = 0; k < 4; ++k) {
        const double w = weights[4 * i + k];
        if (!(w >= 0.0) || !std::isfinite(w)) Fail(weights_label + ": weight of vertex " + std::to_string(i) + " is negative or not finite");
        const double j = joints[4 * i + k];
        if (w > 0.0 && j >= double(num_joints)) {
          Fail(joints_label + ": vertex " + std::to_string(i) + " names joint " + std::to_string(int(j)) + " of a skin with " +
               std::to_string(num_joints));
        }
        out->joints[i][k] = uint16_t(j);
        sum += w;
      }
      if (!(sum > 0.0)) Fail(weights_label + ": vertex " + std::to_string(i) + " has no joint weight");
      for (int k = 0; k < 4; ++k) out->weights[i][k] = float(weights[4 * i + k] / sum);
    }
  }

  // The primitive's TEXCOORD_<uv.set> mapped by uv's transform; empty when it has no such attribute.
  std::vector<Eigen::Vector2f> ReadTexcoords(const tinygltf::Primitive& prim, const TextureUv& uv, size_t nverts,
                                             const std::string& where) {
    const std::string name = "TEXCOORD_" + std::to_string(uv.set);
    const auto it = prim.attributes.find(name);
    if (it == prim.attributes.end()) return {};
    size_t n = 0;
    const std::vector<double> raw = ReadAccessor(it->second, TINYGLTF_TYPE_VEC2, where + " " + name, &n);
    if (n != nverts) Fail("accessor " + std::to_string(it->second) + " (" + where + " " + name + "): count differs from POSITION");
    std::vector<Eigen::Vector2f> out(n);
    for (size_t i = 0; i < n; ++i) {
      out[i] = (uv.uv_from_texcoord * Eigen::Vector3d(raw[2 * i], raw[2 * i + 1], 1.0)).cast<float>();
    }
    return out;
  }

  // The coordinates a textureInfo samples: its texCoord, or KHR_texture_transform's.
  template <typename TextureInfo>
  TextureUv ParseTextureInfoUv(const TextureInfo& info, const std::string& where) {
    TextureUv uv;
    uv.set = info.texCoord;
    for (const auto& [name, value] : info.extensions) {
      if (name == "KHR_texture_transform") {
        uv = ParseTextureTransform(value, where, uv.set);
      } else {
        Ignore("texture-info extension " + name);
      }
    }
    if (uv.set < 0) Fail(where + ": texCoord " + std::to_string(uv.set) + " is negative");
    return uv;
  }

  // emissiveFactor (glTF: each in [0, 1]), scaled by KHR_materials_emissive_strength (>= 0), and the
  // emissive texture with its coordinates.
  void ConvertEmission(const tinygltf::Material& m, const std::string& where, Material* out, MaterialUvs* uvs) {
    const std::vector<double>& f = m.emissiveFactor;
    if (f.size() != 3) Fail(where + ": emissiveFactor must have 3 numbers, got " + std::to_string(f.size()));
    for (double v : f) {
      if (!(v >= 0.0) || !std::isfinite(v)) Fail(where + ": emissiveFactor must be finite and >= 0, got " + std::to_string(v));
      if (v > 1.0) Warn(where + ": emissiveFactor " + std::to_string(v) + " is above glTF's maximum of 1; used as given");
    }
    double strength = 1.0;
    if (auto it = m.extensions.find("KHR_materials_emissive_strength"); it != m.extensions.end()) {
      const tinygltf::Value& ext = it->second;
      if (!ext.IsObject()) Fail(where + ": KHR_materials_emissive_strength is not an object");
      if (ext.Has("emissiveStrength")) {
        const tinygltf::Value& v = ext.Get("emissiveStrength");
        strength = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
        if (!(strength >= 0.0) || !std::isfinite(strength)) {
          Fail(where + ": KHR_materials_emissive_strength: emissiveStrength must be a finite number >= 0");
        }
      }
    }
    out->emissive = (Eigen::Vector3d(f[0], f[1], f[2]) * strength).cast<float>();
    if (m.emissiveTexture.index >= 0 && out->emissive != Eigen::Vector3f::Zero()) {
      uvs->emissive = ParseTextureInfoUv(m.emissiveTexture, where + " emissiveTexture");
      out->emissive_texture = ConvertTexture(m.emissiveTexture.index);
    }
  }

  // KHR_texture_transform on a textureInfo: uv' = T(offset) * R(rotation) * S(scale) * uv, and an
  // optional texCoord that overrides the textureInfo's `texcoord_set`.
  //
  // Rotation: the extension rotates UVs counter-clockwise *in UV space*, where v points down, so
  // (u, v) -> (cos r * u + sin r * v, -sin r * u + cos r * v): at 90 deg, (1, 0) -> (0, -1). This is
  // what the Khronos sample viewer, three.js, Babylon.js, Blender and CesiumGltf compute and what the
  // TextureTransformTest sample model checks; the README's GLSL listing shows the transpose (a
  // counter-clockwise turn in a v-up space), a known erratum (KhronosGroup/glTF issue #1563).
  TextureUv ParseTextureTransform(const tinygltf::Value& ext, const std::string& where, int texcoord_set) {
    const std::string w = where + ": KHR_texture_transform";
    if (!ext.IsObject()) Fail(w + " is not an object");
    auto vec2 = [&](const char* key, Eigen::Vector2d fallback) {
      if (!ext.Has(key)) return fallback;
      const tinygltf::Value& v = ext.Get(key);
      if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber()) {
        Fail(w + ": " + key + " must be an array of 2 numbers");
      }
      const Eigen::Vector2d out(v.Get(0).GetNumberAsDouble(), v.Get(1).GetNumberAsDouble());
      if (!out.allFinite()) Fail(w + ": " + key + " is not finite");
      return out;
    };
    const Eigen::Vector2d offset = vec2("offset", Eigen::Vector2d::Zero());
    const Eigen::Vector2d scale = vec2("scale", Eigen::Vector2d::Ones());
    double rotation = 0.0;
    if (ext.Has("rotation")) {
      const tinygltf::Value& r = ext.Get("rotation");
      if (!r.IsNumber() || !std::isfinite(r.GetNumberAsDouble())) Fail(w + ": rotation must be a finite number (radians)");
      rotation = r.GetNumberAsDouble();
    }
    TextureUv out;
    out.set = texcoord_set;
    if (ext.Has("texCoord")) {
      const tinygltf::Value& t = ext.Get("texCoord");
      if (!t.IsInt() || t.GetNumberAsInt() < 0) Fail(w + ": texCoord must be a non-negative integer");
      out.set = t.GetNumberAsInt();
    }
    const double c = std::cos(rotation), s = std::sin(rotation);
    Eigen::Matrix2d rot;
    rot << c, s, -s, c;
    out.uv_from_texcoord.leftCols<2>() = rot * scale.asDiagonal();
    out.uv_from_texcoord.col(2) = offset;
    return out;
  }

  int ConvertTexture(int index) {
    if (index < 0 || size_t(index) >= model_.textures.size()) Fail("texture " + std::to_string(index) + " out of range");
    if (auto it = texture_map_.find(index); it != texture_map_.end()) return it->second;
    const tinygltf::Texture& t = model_.textures[index];
    int source = t.source;
    for (const auto& [name, value] : t.extensions) {
      if (name == "EXT_texture_webp") {  // the WebP image, in place of the optional PNG or JPEG fallback
        if (!value.IsObject() || !value.Has("source") || !value.Get("source").IsInt()) {
          Fail("texture " + std::to_string(index) + ": EXT_texture_webp has no integer source");
        }
        source = value.Get("source").GetNumberAsInt();
      } else {
        Ignore("texture extension " + name);
      }
    }
    if (source < 0 || size_t(source) >= model_.images.size()) {
      Warn("texture " + std::to_string(index) + " has no usable image source; texture ignored");
      return texture_map_[index] = -1;
    }
    if (auto refused = image_checks_.refused.find(source); refused != image_checks_.refused.end()) Fail(refused->second);
    const tinygltf::Image& img = model_.images[source];
    const std::string image_label = "image " + std::to_string(source) + (img.uri.empty() ? "" : " " + Quote(img.uri));
    if (img.image.empty() || img.width <= 0 || img.height <= 0) {
      if (!img.uri.empty()) Fail(image_label + ": cannot read " + (path_.parent_path() / img.uri).string());
      Fail(image_label + ": no decoded pixels");
    }
    const int comp = img.component;
    const int bytes = img.bits == 16 ? 2 : 1;
    if ((img.bits != 8 && img.bits != 16) || comp < 1 || comp > 4) {
      Fail(image_label + ": unsupported pixel format (" + std::to_string(img.bits) + " bits, " + std::to_string(comp) + " channels)");
    }
    const size_t n = size_t(img.width) * img.height;
    if (img.image.size() < n * comp * bytes) Fail(image_label + ": decoded data shorter than its size");
    Texture out;
    out.name = img.name.empty() ? img.uri : img.name;
    out.width = img.width;
    out.height = img.height;
    out.rgba.resize(n * 4);
    auto channel = [&](size_t pixel, int c) -> uint8_t {
      const unsigned char* p = img.image.data() + (pixel * comp + c) * bytes;
      if (bytes == 1) return p[0];
      uint16_t v;
      std::memcpy(&v, p, 2);
      return uint8_t((uint32_t(v) * 255 + 32767) / 65535);
    };
    for (size_t i = 0; i < n; ++i) {
      uint8_t* o = &out.rgba[i * 4];
      if (comp <= 2) {
        o[0] = o[1] = o[2] = channel(i, 0);
        o[3] = comp == 2 ? channel(i, 1) : 255;
      } else {
        o[0] = channel(i, 0);
        o[1] = channel(i, 1);
        o[2] = channel(i, 2);
        o[3] = comp == 4 ? channel(i, 3) : 255;
      }
    }
    if (t.sampler >= 0) {
      if (size_t(t.sampler) >= model_.samplers.size()) Fail("texture " + std::to_string(index) + ": sampler out of range");
      const tinygltf::Sampler& s = model_.samplers[t.sampler];
      out.wrap_s = ToWrap(s.wrapS);
      out.wrap_t = ToWrap(s.wrapT);
      out.nearest = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
      switch (s.minFilter) {
        case TINYGLTF_TEXTURE_FILTER_NEAREST: out.min_nearest = true; out.mip = MipFilter::kNone; break;
        case TINYGLTF_TEXTURE_FILTER_LINEAR: out.mip = MipFilter::kNone; break;
        case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST: out.min_nearest = true; out.mip = MipFilter::kNearest; break;
        case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST: out.mip = MipFilter::kNearest; break;
        case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR: out.min_nearest = true; out.mip = MipFilter::kLinear; break;
        default: out.mip = MipFilter::kLinear; break;  // LINEAR_MIPMAP_LINEAR, or undefined
      }
    }
    scene_.textures.push_back(std::move(out));
    return texture_map_[index] = int(scene_.textures.size()) - 1;
  }

  // Reads accessor `index` into doubles (count * components), checking every byte it touches.
  std::vector<double> ReadAccessor(int index, int expected_type, const std::string& use, size_t* count_out) {
    const std::string label = "accessor " + std::to_string(index) + " (" + use + ")";
    if (index < 0 || size_t(index) >= model_.accessors.size()) Fail(label + ": index out of range");
    const tinygltf::Accessor& a = model_.accessors[index];
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

  void ApplySparse(const tinygltf::Accessor& a, int ncomp, int csize, const std::string& label, std::vector<double>* out) {
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
  const unsigned char* CheckedView(int index, const std::string& label) const {
    if (index < 0 || size_t(index) >= model_.bufferViews.size()) Fail(label + ": bufferView " + std::to_string(index) + " out of range");
    const tinygltf::BufferView& bv = model_.bufferViews[index];
    if (bv.buffer < 0 || size_t(bv.buffer) >= model_.buffers.size()) Fail(label + ": buffer " + std::to_string(bv.buffer) + " out of range");
    const std::vector<unsigned char>& data = model_.buffers[bv.buffer].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset) {
      Fail(label + ": bufferView " + std::to_string(index) + " (byteOffset " + std::to_string(bv.byteOffset) + ", byteLength " +
           std::to_string(bv.byteLength) + ") out of range of buffer " + std::to_string(bv.buffer) + " (" +
           std::to_string(data.size()) + " bytes)");
    }
    return data.data() + bv.byteOffset;
  }

  std::vector<int> RootNodes() {
    int scene = options_.scene >= 0 ? options_.scene : std::max(model_.defaultScene, 0);
    if (model_.scenes.empty()) {
      // No scene at all: treat every node that is nobody's child as a root.
      std::vector<bool> is_child(model_.nodes.size(), false);
      for (const tinygltf::Node& n : model_.nodes) {
        for (int c : n.children) {
          if (c >= 0 && size_t(c) < is_child.size()) is_child[c] = true;
        }
      }
      std::vector<int> roots;
      for (size_t i = 0; i < model_.nodes.size(); ++i) {
        if (!is_child[i]) roots.push_back(int(i));
      }
      if (!model_.nodes.empty()) Warn("file defines no scene; loading all " + std::to_string(roots.size()) + " root node(s)");
      return roots;
    }
    if (size_t(scene) >= model_.scenes.size()) Fail("scene " + std::to_string(scene) + " out of range");
    if (model_.scenes.size() > 1) {
      Warn("file has " + std::to_string(model_.scenes.size()) + " scenes; only scene " + std::to_string(scene) + " is loaded");
    }
    return model_.scenes[scene].nodes;
  }

  // How many morph targets the mesh on `node` has (its first primitive's: all must have as many);
  // 0 without a mesh.
  size_t MorphTargetCount(int node) const {
    const int mesh = model_.nodes[node].mesh;
    if (mesh < 0 || size_t(mesh) >= model_.meshes.size() || model_.meshes[mesh].primitives.empty()) return 0;
    return model_.meshes[mesh].primitives[0].targets.size();
  }

  // glTF: a node's matrix has 16 numbers, translation and scale 3, rotation 4 and not zero (a unit
  // quaternion; LocalTransform normalises it, as exporters round). tinygltf takes any count, and
  // LocalTransform would read a wrong one, or a zero quaternion, as identity.
  void CheckNodeTransforms() const {
    for (size_t i = 0; i < model_.nodes.size(); ++i) {
      const tinygltf::Node& node = model_.nodes[i];
      const std::tuple<const char*, const std::vector<double>&, size_t> properties[] = {
          {"matrix", node.matrix, 16}, {"translation", node.translation, 3}, {"rotation", node.rotation, 4}, {"scale", node.scale, 3}};
      for (const auto& [name, values, size] : properties) {
        if (!values.empty() && values.size() != size) {
          Fail(NodeLabel(int(i)) + ": " + name + " has " + std::to_string(values.size()) + " numbers, glTF requires " +
               std::to_string(size));
        }
      }
      if (node.rotation.size() == 4 && IsZeroQuaternion(Eigen::Map<const Eigen::Vector4d>(node.rotation.data()))) {
        Fail(NodeLabel(int(i)) + ": rotation is a zero quaternion, which is no rotation");
      }
    }
  }

  // Node animations: the node tree (rest transforms, parents) and every translation, rotation,
  // scale and morph-weights channel. CUBICSPLINE keys are sampled at their values and interpolated
  // linearly (warned).
  void ParseAnimations() {
    if (model_.animations.empty()) return;
    for (size_t a = 0; a < model_.animations.size(); ++a) {
      const tinygltf::Animation& anim = model_.animations[a];
      const std::string aname = "animation " + std::to_string(a) + (anim.name.empty() ? "" : " " + Quote(anim.name));
      for (size_t c = 0; c < anim.channels.size(); ++c) {
        const tinygltf::AnimationChannel& ch = anim.channels[c];
        const std::string where = aname + " channel " + std::to_string(c);
        if (ch.target_node < 0) continue;  // glTF: no target node means the channel is ignored
        if (size_t(ch.target_node) >= model_.nodes.size()) Fail(where + ": target node " + std::to_string(ch.target_node) + " out of range");
        AnimationChannel out;
        out.node = ch.target_node;
        int ncomp = 3;  // values per key (the morph target count for weights)
        if (ch.target_path == "weights") {
          out.path = AnimationPath::kWeights;
          ncomp = int(MorphTargetCount(ch.target_node));
          if (ncomp == 0) {
            Warn(where + ": animates the morph weights of node " + std::to_string(ch.target_node) +
                 ", whose mesh has no morph targets; ignored");
            continue;
          }
        } else if (ch.target_path == "translation") {
          out.path = AnimationPath::kTranslation;
        } else if (ch.target_path == "rotation") {
          out.path = AnimationPath::kRotation;
          ncomp = 4;
        } else if (ch.target_path == "scale") {
          out.path = AnimationPath::kScale;
        } else {
          Ignore("animation path " + ch.target_path);
          continue;
        }
        if (ch.sampler < 0 || size_t(ch.sampler) >= anim.samplers.size()) Fail(where + ": sampler " + std::to_string(ch.sampler) + " out of range");
        const tinygltf::AnimationSampler& sampler = anim.samplers[ch.sampler];
        bool cubic = false;
        if (sampler.interpolation == "STEP") {
          out.interpolation = AnimationInterpolation::kStep;
        } else if (sampler.interpolation == "CUBICSPLINE") {
          cubic = true;
          Warn(where + ": CUBICSPLINE interpolation is rendered as LINEAR between the keys");
        }
        size_t nkeys = 0, nvalues = 0;
        const std::vector<double> times = ReadAccessor(sampler.input, TINYGLTF_TYPE_SCALAR, where + " input", &nkeys);
        const bool weights = out.path == AnimationPath::kWeights;
        const int output_type = weights ? TINYGLTF_TYPE_SCALAR : ncomp == 4 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3;
        const std::vector<double> values = ReadAccessor(sampler.output, output_type, where + " output", &nvalues);
        if (nkeys == 0) Fail(where + ": no keyframes");
        // Weights: one scalar per morph target per key (glTF 2.0, "Animations").
        const size_t per_key = weights ? size_t(ncomp) : 1;
        if (nvalues != (cubic ? 3 : 1) * nkeys * per_key) {
          Fail(where + ": " + std::to_string(nvalues) + " output values for " + std::to_string(nkeys) + " keyframes" +
               (weights ? " of " + std::to_string(ncomp) + " morph target weights" : ""));
        }
        for (size_t k = 0; k < nkeys; ++k) {
          if (!std::isfinite(times[k]) || (k > 0 && !(times[k] > times[k - 1]))) {
            Fail(where + ": keyframe times must be finite and strictly increasing (key " + std::to_string(k) + ")");
          }
          const size_t v = cubic ? 3 * k + 1 : k;  // cubic: (in-tangent, value, out-tangent)
          out.times_s.push_back(times[k]);
          if (weights) {
            const Eigen::VectorXd w = Eigen::Map<const Eigen::VectorXd>(values.data() + ncomp * v, ncomp);
            if (!w.allFinite()) Fail(where + ": keyframe weights " + std::to_string(k) + " are not finite");
            out.weights.push_back(w);
            continue;
          }
          Eigen::Vector4d value(values[ncomp * v], values[ncomp * v + 1], values[ncomp * v + 2], ncomp == 4 ? values[ncomp * v + 3] : 0.0);
          if (!value.allFinite()) Fail(where + ": keyframe value " + std::to_string(k) + " is not finite");
          out.values.push_back(value);
        }
        // Morph weights move no node: the mesh alone is re-posed, not the node's subtree.
        (weights ? morph_animated_nodes_ : animated_nodes_).insert(out.node);
        scene_.animation_channels.push_back(std::move(out));
      }
    }
    if (scene_.animation_channels.empty()) return;
    scene_.nodes.resize(model_.nodes.size());
    for (size_t i = 0; i < model_.nodes.size(); ++i) {
      const tinygltf::Node& n = model_.nodes[i];
      SceneNode& out = scene_.nodes[i];
      out.name = n.name;
      if (n.matrix.size() == 16) {
        out.has_matrix = true;
        out.matrix = LocalTransform(n);
        if (animated_nodes_.count(int(i))) Warn("node " + std::to_string(i) + " has a matrix and an animation; glTF forbids this, the animation wins");
      }
      if (n.translation.size() == 3) out.translation = Eigen::Vector3d(n.translation[0], n.translation[1], n.translation[2]);
      if (n.rotation.size() == 4) out.rotation_xyzw = Eigen::Vector4d(n.rotation[0], n.rotation[1], n.rotation[2], n.rotation[3]);
      if (n.scale.size() == 3) out.scale = Eigen::Vector3d(n.scale[0], n.scale[1], n.scale[2]);
      for (int c : n.children) {
        if (c >= 0 && size_t(c) < model_.nodes.size()) scene_.nodes[c].parent = int(i);
      }
    }
  }

  // glTF skins: joints (nodes) and inverse bind matrices (identity when the file gives none).
  void ParseSkins() {
    for (size_t k = 0; k < model_.skins.size(); ++k) {
      const tinygltf::Skin& in = model_.skins[k];
      const std::string where = "skin " + std::to_string(k) + (in.name.empty() ? "" : " " + Quote(in.name));
      SceneSkin out;
      for (int joint : in.joints) {
        if (joint < 0 || size_t(joint) >= model_.nodes.size()) Fail(where + ": joint node " + std::to_string(joint) + " out of range");
        out.joints.push_back(joint);
      }
      out.inverse_bind.assign(out.joints.size(), Eigen::Matrix4d::Identity());
      if (in.inverseBindMatrices >= 0) {
        size_t count = 0;
        const std::vector<double> m = ReadAccessor(in.inverseBindMatrices, TINYGLTF_TYPE_MAT4, where + " inverseBindMatrices", &count);
        if (count < out.joints.size()) {
          Fail(where + ": " + std::to_string(count) + " inverse bind matrices for " + std::to_string(out.joints.size()) + " joints");
        }
        for (size_t j = 0; j < out.joints.size(); ++j) {
          for (int i = 0; i < 16; ++i) out.inverse_bind[j](i % 4, i / 4) = m[16 * j + i];  // column-major in glTF
          if (!out.inverse_bind[j].allFinite()) Fail(where + ": inverse bind matrix " + std::to_string(j) + " is not finite");
        }
      }
      scene_.skins.push_back(std::move(out));
    }
  }

  // Places the skinned meshes by their joints at the nodes' rest transforms, as Traverse found
  // them (the mesh node's own transform does not apply, glTF 2.0 "Skins"; a skin's joints must be
  // in the scene that uses it).
  void SkinAtRestPose() {
    for (SceneMesh& m : scene_.meshes) {
      if (m.skin < 0) continue;
      for (int joint : scene_.skins[m.skin].joints) {
        if (!traversed_[joint]) {
          Fail("skin " + std::to_string(m.skin) + ": joint node " + std::to_string(joint) +
               " is not in the loaded scene (glTF requires a skin's joints to be)");
        }
      }
      try {
        SkinMesh(scene_.skins[m.skin], rest_world_, &m);
      } catch (const std::invalid_argument& e) {
        Fail(e.what());
      }
      for (const Eigen::Vector3f& p : m.positions) {
        if (!p.allFinite()) Fail("skinned mesh '" + m.name + "': a vertex is not finite at the rest pose");
      }
    }
  }

  void Traverse() {
    struct Item {
      int node;
      Eigen::Matrix4d parent_from_world;  // the parent's world transform (world_from_parent)
      ClassTag inherited;
      bool animated = false;  // an ancestor is animated
    };
    std::vector<bool>& visited = traversed_;
    visited.assign(model_.nodes.size(), false);
    rest_world_.assign(model_.nodes.size(), Eigen::Matrix4d::Identity());
    std::vector<Item> stack;
    const std::vector<int> roots = RootNodes();
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, Eigen::Matrix4d::Identity(), std::nullopt});
    while (!stack.empty()) {
      const Item item = stack.back();
      stack.pop_back();
      if (item.node < 0 || size_t(item.node) >= model_.nodes.size()) Fail("node " + std::to_string(item.node) + " out of range");
      if (visited[item.node]) {
        Fail("node " + std::to_string(item.node) + " is reached twice: the node graph is recursive or shares a node (glTF requires a tree)");
      }
      visited[item.node] = true;
      const tinygltf::Node& node = model_.nodes[item.node];
      const Eigen::Matrix4d world = item.parent_from_world * LocalTransform(node);
      if (!world.allFinite()) Fail("node " + std::to_string(item.node) + ": transform is not finite");
      rest_world_[item.node] = world;
      const ClassTag cls = node_class_[item.node] ? node_class_[item.node] : item.inherited;
      for (const auto& [name, value] : node.extensions) {
        if (name != kGpuInstancing) Ignore("node extension " + name);
      }
      const bool animated = item.animated || animated_nodes_.count(item.node) > 0;
      current_mesh_animated_ = animated;
      if (node.camera >= 0) AddCamera(item.node, world, animated);
      if (node.mesh >= 0) {
        AddMeshInstance(item.node, world, cls);
      } else if (node.extensions.count(kGpuInstancing)) {
        Warn(NodeLabel(item.node) + ": " + kGpuInstancing + " on a node without a mesh, where it means nothing; ignored");
      }
      for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.push_back({*c, world, cls, animated});
    }
    size_t unreached_meshes = 0, unreached_cameras = 0;
    for (size_t i = 0; i < model_.nodes.size(); ++i) {
      if (!visited[i] && model_.nodes[i].mesh >= 0) ++unreached_meshes;
      if (!visited[i] && model_.nodes[i].camera >= 0) ++unreached_cameras;
    }
    if (unreached_meshes > 0) {
      Warn(std::to_string(unreached_meshes) + " node(s) with a mesh are not part of the loaded scene and are ignored");
    }
    scene_.skipped_camera_nodes += unreached_cameras;
    if (unreached_cameras > 0) {
      Warn(std::to_string(unreached_cameras) + " node(s) with a camera are not part of the loaded scene and are ignored");
    }
    // File order (node index), whatever the traversal order: the first camera is a rig's reference.
    std::stable_sort(scene_.cameras.begin(), scene_.cameras.end(),
                     [](const SceneCamera& a, const SceneCamera& b) { return a.node < b.node; });
  }

  // A glTF camera on a node: its rest pose in the OpenCV frame and its perspective parameters.
  // A camera that cannot be a rig camera (bad parameters, mirrored or singular transform, unknown
  // type) is skipped with a warning rather than failing the load: rendering does not need it.
  void AddCamera(int node_index, const Eigen::Matrix4d& world, bool animated) {
    const tinygltf::Node& node = model_.nodes[node_index];
    if (size_t(node.camera) >= model_.cameras.size()) {
      Fail("node " + std::to_string(node_index) + ": camera " + std::to_string(node.camera) + " out of range");
    }
    const tinygltf::Camera& cam = model_.cameras[node.camera];
    const std::string where = "node " + std::to_string(node_index) + (node.name.empty() ? "" : " " + Quote(node.name)) +
                              " (camera " + std::to_string(node.camera) + (cam.name.empty() ? "" : " " + Quote(cam.name)) + ")";
    auto skip = [&](const std::string& why) {
      Warn(where + ": " + why + "; camera skipped");
      ++scene_.skipped_camera_nodes;
    };
    SceneCamera out;
    out.node = node_index;
    out.camera = node.camera;
    out.name = !node.name.empty() ? node.name : !cam.name.empty() ? cam.name : "camera" + std::to_string(node_index);
    if (cam.type == "perspective") {
      const tinygltf::PerspectiveCamera& p = cam.perspective;
      if (!(p.yfov > 0.0 && p.yfov < std::numbers::pi)) {
        skip("yfov " + std::to_string(p.yfov) + " is not in (0, pi) radians");
        return;
      }
      if (!(p.aspectRatio >= 0.0 && std::isfinite(p.aspectRatio))) {
        skip("aspectRatio " + std::to_string(p.aspectRatio) + " is not a positive number");
        return;
      }
      out.yfov_rad = p.yfov;
      out.aspect_ratio = p.aspectRatio;
      out.znear_m = p.znear;
      out.zfar_m = p.zfar;
    } else if (cam.type == "orthographic") {
      out.orthographic = true;
      out.znear_m = cam.orthographic.znear;
      out.zfar_m = cam.orthographic.zfar;
    } else {
      skip("camera type " + Quote(cam.type) + " is neither perspective nor orthographic");
      return;
    }
    const Eigen::Matrix3d linear = world.topLeftCorner<3, 3>();
    if (!(linear.determinant() > 1e-12)) {
      skip("the node's transform mirrors or collapses space, which no camera pose can");
      return;
    }
    Eigen::Matrix3d r = linear;
    for (int c = 0; c < 3; ++c) r.col(c).normalize();
    if (!(r.transpose() * r).isIdentity(1e-6)) {
      Warn(where + ": the node's transform shears (non-uniform scale under a rotation); its orientation is approximated");
    }
    if (animated) Warn(where + ": is animated; cameras are loaded at their rest pose");
    out.cam_from_world = CamFromWorldFromGltfCameraNode(world);
    scene_.cameras.push_back(std::move(out));
  }

  // Where one copy of a node's mesh goes: the instance's transform in the node's frame (identity
  // without EXT_mesh_gpu_instancing), its instance id and its index among the node's instances
  // (-1 = not instanced).
  struct Placement {
    Eigen::Matrix4d node_from_instance = Eigen::Matrix4d::Identity();
    uint16_t instance_id = 0;
    int gpu_instance = -1;
  };

  // 1, 2, ... for each instance (a mesh node, or one instance of an instanced node); 0 after 65535.
  uint16_t NextInstanceId() {
    if (next_instance_ <= 65535) return uint16_t(next_instance_++);
    if (!instance_overflow_warned_) {
      instance_overflow_warned_ = true;
      Warn("more than 65535 mesh nodes or instances: further ones get instance id 0");
    }
    return 0;
  }

  std::string NodeLabel(int node_index) const {
    const std::string& name = model_.nodes[node_index].name;
    return "node " + std::to_string(node_index) + (name.empty() ? "" : " " + Quote(name));
  }

  void AddMeshInstance(int node_index, const Eigen::Matrix4d& world, ClassTag node_cls) {
    const tinygltf::Node& node = model_.nodes[node_index];
    if (size_t(node.mesh) >= model_.meshes.size()) Fail("node " + std::to_string(node_index) + ": mesh " + std::to_string(node.mesh) + " out of range");
    std::vector<Placement> placements = GpuInstances(node_index);
    if (placements.empty()) placements.push_back({});
    for (Placement& p : placements) p.instance_id = NextInstanceId();
    const tinygltf::Mesh& mesh = model_.meshes[node.mesh];
    const ClassTag mesh_cls = mesh_class_[node.mesh] ? mesh_class_[node.mesh] : node_cls;
    const std::vector<double> morph_weights = RestMorphWeights(node_index);
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      AddPrimitive(node_index, node.mesh, int(p), world, mesh_cls, placements, morph_weights);
    }
  }

  // EXT_mesh_gpu_instancing on a mesh node: each instance's T * R * S (node_from_instance) and
  // index, in accessor order, without instance ids yet; empty when the node has no such extension (or is skinned, which the extension
  // leaves undefined: drawn once, by its joints, with a warning). TRANSLATION and SCALE are VEC3
  // float, ROTATION VEC4 float or normalized byte/short (x, y, z, w), all of one count; a missing
  // one is identity. The geometry all instances make is bounded before anything is decoded.
  std::vector<Placement> GpuInstances(int node_index) {
    const tinygltf::Node& node = model_.nodes[node_index];
    const auto ext_it = node.extensions.find(kGpuInstancing);
    if (ext_it == node.extensions.end()) return {};
    const std::string where = NodeLabel(node_index) + " " + kGpuInstancing;
    if (node.skin >= 0) {
      Warn(where + ": on a skinned node, which the extension leaves undefined; the mesh is drawn once, placed by its joints");
      return {};
    }
    const tinygltf::Value& ext = ext_it->second;
    if (!ext.IsObject() || !ext.Has("attributes") || !ext.Get("attributes").IsObject()) Fail(where + ": has no attributes object");
    const tinygltf::Value& attributes = ext.Get("attributes");
    struct Attribute {
      const char* name;
      int type;
      int accessor = -1;
    };
    Attribute trs[3] = {{"TRANSLATION", TINYGLTF_TYPE_VEC3}, {"ROTATION", TINYGLTF_TYPE_VEC4}, {"SCALE", TINYGLTF_TYPE_VEC3}};
    for (const std::string& key : attributes.Keys()) {
      Attribute* known = nullptr;
      for (Attribute& a : trs) known = key == a.name ? &a : known;
      if (!known) {
        Ignore(std::string(kGpuInstancing) + " attribute " + key);  // custom (_ID, ...): nothing rigsim draws
        continue;
      }
      const tinygltf::Value& v = attributes.Get(key);
      if (!v.IsInt()) Fail(where + ": attribute " + key + " is not an accessor index");
      known->accessor = v.GetNumberAsInt();
    }
    // Metadata first (types, counts), so that the size bound holds before anything is read.
    size_t count = 0;
    const Attribute* first = nullptr;
    for (const Attribute& a : trs) {
      if (a.accessor < 0 && attributes.Has(a.name)) Fail(where + ": " + a.name + " accessor " + std::to_string(a.accessor) + " out of range");
      if (a.accessor < 0) continue;
      const std::string label = "accessor " + std::to_string(a.accessor) + " (" + where + " " + a.name + ")";
      if (size_t(a.accessor) >= model_.accessors.size()) Fail(label + ": index out of range");
      const tinygltf::Accessor& acc = model_.accessors[a.accessor];
      const bool rotation = a.type == TINYGLTF_TYPE_VEC4;
      if (acc.type != a.type) Fail(label + ": type must be " + (rotation ? "VEC4" : "VEC3"));
      const bool normalized_signed =
          acc.normalized && (acc.componentType == TINYGLTF_COMPONENT_TYPE_BYTE || acc.componentType == TINYGLTF_COMPONENT_TYPE_SHORT);
      if (acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !(rotation && normalized_signed)) {
        Fail(label + ": componentType must be FLOAT" + (rotation ? ", or normalized BYTE or SHORT" : ""));
      }
      if (acc.count == 0) Fail(label + ": count is 0 (an instanced node needs at least one instance)");
      if (first && acc.count != count) {
        Fail(label + ": count " + std::to_string(acc.count) + " differs from " + first->name + "'s " + std::to_string(count) +
             " (all instance attributes must have the same count)");
      }
      first = &a;
      count = acc.count;
    }
    if (!first) {
      Warn(where + ": no TRANSLATION, ROTATION or SCALE attribute; the mesh is drawn once");
      return {};
    }
    CheckInstancedSize(node_index, count, where);
    std::vector<double> values[3];  // per attribute: count x (3 or 4), empty when not given
    for (int k = 0; k < 3; ++k) {
      const Attribute& a = trs[k];
      if (a.accessor < 0) continue;
      const std::string label = "accessor " + std::to_string(a.accessor) + " (" + where + " " + a.name + ")";
      size_t n = 0;
      values[k] = ReadAccessor(a.accessor, a.type, where + " " + a.name, &n);
      const size_t ncomp = size_t(NumComponents(a.type));
      for (size_t i = 0; i < values[k].size(); ++i) {
        if (!std::isfinite(values[k][i])) Fail(label + ": instance " + std::to_string(i / ncomp) + " is not finite");
      }
      for (size_t i = 0; k == 1 && i < n; ++i) {
        if (IsZeroQuaternion(Eigen::Map<const Eigen::Vector4d>(&values[k][4 * i]))) {
          Fail(label + ": instance " + std::to_string(i) + " has a zero quaternion, which is no rotation");
        }
      }
    }
    std::vector<Placement> out(count);  // count is bounded now: ReadAccessor checked it
    for (size_t i = 0; i < count; ++i) {
      Eigen::Affine3d t = Eigen::Affine3d::Identity();
      if (!values[0].empty()) t.translate(Eigen::Map<const Eigen::Vector3d>(&values[0][3 * i]));
      if (!values[1].empty()) {
        const double* q = &values[1][4 * i];  // glTF (x, y, z, w); quantized (and float) ones are unit only nearly
        t.rotate(Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized());
      }
      if (!values[2].empty()) t.scale(Eigen::Map<const Eigen::Vector3d>(&values[2][3 * i]));
      out[i].node_from_instance = t.matrix();
      out[i].gpu_instance = int(i);
    }
    return out;
  }

  // Instances copy their mesh's geometry, which is decoded once per node: this bounds the copies
  // (vertices and indices of every instance, summed over the file) by max_accessor_count, as
  // ReadAccessor bounds what is decoded, so that a small file cannot ask for billions of vertices.
  void CheckInstancedSize(int node_index, size_t count, const std::string& where) {
    const tinygltf::Mesh& mesh = model_.meshes[model_.nodes[node_index].mesh];
    auto accessor_count = [&](int a) -> size_t { return a >= 0 && size_t(a) < model_.accessors.size() ? model_.accessors[a].count : 0; };
    size_t per_instance = 0;  // accessor metadata only: AddPrimitive checks the accessors themselves
    for (const tinygltf::Primitive& prim : mesh.primitives) {
      const auto pos = prim.attributes.find("POSITION");
      if (pos == prim.attributes.end()) continue;
      per_instance += std::min(accessor_count(pos->second), options_.max_accessor_count);
      per_instance += std::min(accessor_count(prim.indices), options_.max_accessor_count);
    }
    const size_t limit = options_.max_accessor_count;
    const size_t room = limit - std::min(limit, instanced_elements_);
    if (per_instance > 0 && count > room / per_instance) {
      Fail(where + ": " + std::to_string(count) + " instances of a mesh of " + std::to_string(per_instance) +
           " vertices and indices each exceed the limit of " + std::to_string(limit) +
           " on all instanced geometry (GltfLoadOptions::max_accessor_count; instanced nodes before this one made " +
           std::to_string(instanced_elements_) + ")");
    }
    instanced_elements_ += count * per_instance;
  }

  // The morph weights of the mesh on `node` at rest: node.weights, else mesh.weights, else zeros;
  // one per morph target, which every primitive of the mesh must have as many of.
  std::vector<double> RestMorphWeights(int node_index) {
    const tinygltf::Node& node = model_.nodes[node_index];
    const tinygltf::Mesh& mesh = model_.meshes[node.mesh];
    const size_t count = MorphTargetCount(node_index);
    for (size_t p = 1; p < mesh.primitives.size(); ++p) {
      if (mesh.primitives[p].targets.size() != count) {
        Fail(MeshLabel(model_, node.mesh, int(p)) + ": " + std::to_string(mesh.primitives[p].targets.size()) +
             " morph targets, primitive 0 has " + std::to_string(count) + " (glTF requires the same number)");
      }
    }
    const bool from_node = !node.weights.empty();
    const std::vector<double>& weights = from_node ? node.weights : mesh.weights;
    const std::string owner = from_node ? "node " + std::to_string(node_index) + (node.name.empty() ? "" : " " + Quote(node.name))
                                        : "mesh " + std::to_string(node.mesh) + (mesh.name.empty() ? "" : " " + Quote(mesh.name));
    if (weights.empty()) return std::vector<double>(count, 0.0);
    if (count == 0) {  // invalid glTF, but nothing to morph: exporters write such weights
      Warn(owner + ": " + std::to_string(weights.size()) + " morph weights but no morph targets; weights ignored");
      return {};
    }
    if (weights.size() != count) {
      Fail(owner + ": " + std::to_string(weights.size()) + " morph weights for " + std::to_string(count) + " morph targets");
    }
    for (size_t i = 0; i < weights.size(); ++i) {
      if (!std::isfinite(weights[i])) Fail(owner + ": morph weight " + std::to_string(i) + " is not finite");
    }
    return weights;
  }

  // The primitive's morph targets: POSITION and (when the primitive has normals) NORMAL
  // displacements, VEC3 of float or, under KHR_mesh_quantization, of (normalized) byte or short.
  // TANGENT, which rigsim does not use, and other attributes are ignored.
  std::vector<MorphTarget> ReadMorphTargets(const tinygltf::Primitive& prim, size_t nverts, const std::string& where) {
    std::vector<MorphTarget> targets(prim.targets.size());
    for (size_t t = 0; t < prim.targets.size(); ++t) {
      for (const auto& [name, accessor] : prim.targets[t]) {
        const bool normal = name == "NORMAL" && prim.attributes.count("NORMAL");
        if (name != "POSITION" && !normal) {
          Ignore("morph target attribute " + name);
          continue;
        }
        const std::string use = where + " target " + std::to_string(t) + " " + name;
        const std::string label = "accessor " + std::to_string(accessor) + " (" + use + ")";
        size_t n = 0;
        const std::vector<double> d = ReadAccessor(accessor, TINYGLTF_TYPE_VEC3, use, &n);
        const int type = model_.accessors[accessor].componentType;  // in range: ReadAccessor checked
        if (type != TINYGLTF_COMPONENT_TYPE_FLOAT && type != TINYGLTF_COMPONENT_TYPE_BYTE && type != TINYGLTF_COMPONENT_TYPE_SHORT) {
          Fail(label + ": componentType must be FLOAT, BYTE or SHORT");
        }
        if (n != nverts) Fail(label + ": count " + std::to_string(n) + " differs from POSITION's " + std::to_string(nverts));
        std::vector<Eigen::Vector3f>& out = normal ? targets[t].normals : targets[t].positions;
        out.resize(n);
        for (size_t i = 0; i < n; ++i) {
          const Eigen::Vector3d v(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
          if (!v.allFinite()) Fail(label + ": vertex " + std::to_string(i) + " is not finite");
          out[i] = v.cast<float>();
        }
      }
    }
    return targets;
  }

  // The class the label rules give a primitive (node names: the node, then its ancestors).
  ClassTag ClassFromLabelRules(int node_index, int mesh_index, int material_index) {
    if (rule_parent_.empty()) {
      rule_parent_.assign(model_.nodes.size(), -1);
      for (size_t i = 0; i < model_.nodes.size(); ++i) {
        for (int c : model_.nodes[i].children) {
          if (c >= 0 && size_t(c) < rule_parent_.size()) rule_parent_[c] = int(i);
        }
      }
    }
    LabelRules::Names names;
    for (int n = node_index, depth = 0; n >= 0 && depth <= int(model_.nodes.size()); n = rule_parent_[n], ++depth) {
      names.node_path.push_back(model_.nodes[n].name);
    }
    names.mesh = model_.meshes[mesh_index].name;
    if (material_index >= 0) names.material = model_.materials[material_index].name;
    return options_.label_rules->Classify(names);
  }

  // Applies the rest morph weights to the primitive's node-frame positions and normals (xyz
  // triples). A mesh whose weights are animated keeps its base vertices and targets for posing.
  void Morph(const tinygltf::Primitive& prim, size_t nverts, const std::vector<double>& weights, bool keep, const std::string& where,
             std::vector<double>* pos, std::vector<double>* nrm, SceneMesh* out) {
    auto to_vectors = [](const std::vector<double>& xyz) {
      std::vector<Eigen::Vector3f> v(xyz.size() / 3);
      for (size_t i = 0; i < v.size(); ++i) v[i] = Eigen::Vector3d(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]).normalized().cast<float>();
      return v;
    };
    SceneMesh& m = *out;
    m.morph_targets = ReadMorphTargets(prim, nverts, where);
    m.morph_base_positions.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) m.morph_base_positions[i] = Eigen::Vector3d((*pos)[3 * i], (*pos)[3 * i + 1], (*pos)[3 * i + 2]).cast<float>();
    m.morph_base_normals = to_vectors(*nrm);
    try {
      MorphMesh(weights, &m);  // the one implementation, which PoseSceneAt uses too
    } catch (const std::invalid_argument& e) {
      Fail(where + ": " + e.what());
    }
    for (size_t i = 0; i < nverts; ++i) {
      for (int c = 0; c < 3; ++c) (*pos)[3 * i + c] = m.local_positions[i][c];
    }
    for (size_t i = 0; i < m.local_normals.size(); ++i) {
      for (int c = 0; c < 3; ++c) (*nrm)[3 * i + c] = m.local_normals[i][c];
    }
    m.local_positions.clear();
    m.local_normals.clear();
    if (!keep) {
      m.morph_base_positions.clear();
      m.morph_base_normals.clear();
      m.morph_targets.clear();
    }
  }

  // Decodes the primitive once and adds one SceneMesh per placement (one, or one per
  // EXT_mesh_gpu_instancing instance), each at world * node_from_instance.
  void AddPrimitive(int node_index, int mesh_index, int prim_index, const Eigen::Matrix4d& world, ClassTag cls,
                    const std::vector<Placement>& placements, const std::vector<double>& morph_weights) {
    const tinygltf::Node& node = model_.nodes[node_index];
    const tinygltf::Mesh& mesh = model_.meshes[mesh_index];
    const tinygltf::Primitive& prim = mesh.primitives[prim_index];
    const std::string where = MeshLabel(model_, mesh_index, prim_index);
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP && prim.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      const char* kind = prim.mode == TINYGLTF_MODE_POINTS ? "points" : "lines";
      Warn(where + ": " + kind + " primitive (mode " + std::to_string(prim.mode) + ") skipped; only triangles are rendered");
      return;
    }
    for (const auto& [name, value] : prim.extensions) Ignore("primitive extension " + name);
    // The texture coordinates the material's textures sample (TEXCOORD_0 without a texture).
    const MaterialUvs uvs =
        prim.material >= 0 && size_t(prim.material) < material_uv_.size() ? material_uv_[prim.material] : MaterialUvs{};
    const TextureUv& uv_map = uvs.base_color;
    const std::string texcoord_name = "TEXCOORD_" + std::to_string(uv_map.set);
    const std::string emissive_texcoord_name = uvs.emissive ? "TEXCOORD_" + std::to_string(uvs.emissive->set) : "";
    const std::string normal_texcoord_name = uvs.normal ? "TEXCOORD_" + std::to_string(uvs.normal->set) : "";
    const std::string occlusion_texcoord_name = uvs.occlusion ? "TEXCOORD_" + std::to_string(uvs.occlusion->set) : "";
    const bool skinned = node.skin >= 0 && prim.attributes.count("JOINTS_0") && prim.attributes.count("WEIGHTS_0");
    if (node.skin >= 0 && !skinned) {
      Warn(where + ": on a skinned node but without JOINTS_0 and WEIGHTS_0; placed by its node");
    }
    for (const auto& [name, acc] : prim.attributes) {
      if (name != "POSITION" && name != "NORMAL" && name != texcoord_name && name != emissive_texcoord_name &&
          name != normal_texcoord_name && name != occlusion_texcoord_name && name != "COLOR_0" &&
          !(skinned && (name == "JOINTS_0" || name == "WEIGHTS_0"))) {
        Ignore("vertex attribute " + name);
      }
    }
    const auto pos_it = prim.attributes.find("POSITION");
    if (pos_it == prim.attributes.end()) {
      Warn(where + ": no POSITION attribute; skipped");
      return;
    }
    SceneMesh out;  // what every placement shares; positions, normals and winding are per placement
    out.name = !node.name.empty() ? node.name : mesh.name;
    if (prim.material >= 0) {
      if (size_t(prim.material) >= model_.materials.size()) Fail(where + ": material " + std::to_string(prim.material) + " out of range");
      out.material = prim.material;
      if (material_class_[prim.material]) cls = material_class_[prim.material];
    }
    if (!cls && options_.label_rules) cls = ClassFromLabelRules(node_index, mesh_index, prim.material);
    if (cls) {
      out.class_id = *cls;
    } else {
      out.class_id = kUnlabeledId;
    }

    size_t nverts = 0;
    std::vector<double> pos = ReadAccessor(pos_it->second, TINYGLTF_TYPE_VEC3, where + " POSITION", &nverts);
    std::vector<double> nrm;
    if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
      size_t n = 0;
      nrm = ReadAccessor(it->second, TINYGLTF_TYPE_VEC3, where + " NORMAL", &n);
      if (n != nverts) Fail("accessor " + std::to_string(it->second) + " (" + where + " NORMAL): count differs from POSITION");
    }
    out.num_morph_targets = int(prim.targets.size());
    const bool morph_animated = !prim.targets.empty() && morph_animated_nodes_.count(node_index) > 0;
    if (!prim.targets.empty()) Morph(prim, nverts, morph_weights, morph_animated, where, &pos, &nrm, &out);
    for (size_t i = 0; i < nverts; ++i) {
      if (!Eigen::Vector3d(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]).allFinite()) {
        Fail("accessor " + std::to_string(pos_it->second) + " (" + where + " POSITION): vertex " + std::to_string(i) + " is not finite");
      }
    }
    if (skinned) ReadSkinning(prim, node.skin, nverts, where, &out);
    const bool posed_later = current_mesh_animated_ || skinned || morph_animated;
    if (posed_later) {
      // PoseSceneAt re-poses this mesh from its node-frame vertices (SkinAtRestPose places a
      // skinned one); local_normals are set per placement, as a placement may drop its normals.
      out.node = node_index;
      out.local_positions.resize(nverts);
      for (size_t i = 0; i < nverts; ++i) out.local_positions[i] = Eigen::Vector3d(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]).cast<float>();
    }
    out.texcoords = ReadTexcoords(prim, uv_map, nverts, where);
    if (out.texcoords.empty() && out.material >= 0 && scene_.materials[out.material].base_color_texture >= 0) {
      Ignore("textured primitives without their texture's " + texcoord_name + " (rendered untextured)");
    }
    if (uvs.emissive) {
      out.emissive_texcoords = ReadTexcoords(prim, *uvs.emissive, nverts, where);
      if (out.emissive_texcoords.empty()) {
        Ignore("emissive primitives without their texture's " + emissive_texcoord_name + " (emissive texture not shown)");
      }
    }
    if (uvs.normal) {
      out.normal_texcoords = ReadTexcoords(prim, *uvs.normal, nverts, where);
      if (out.normal_texcoords.empty()) {
        Ignore("normal-mapped primitives without their texture's " + normal_texcoord_name + " (normal map not used)");
      }
    }
    if (uvs.occlusion) {
      out.occlusion_texcoords = ReadTexcoords(prim, *uvs.occlusion, nverts, where);
      if (out.occlusion_texcoords.empty()) {
        Ignore("occluded primitives without their texture's " + occlusion_texcoord_name + " (occlusion not used)");
      }
    }

    if (auto it = prim.attributes.find("COLOR_0"); it != prim.attributes.end()) ReadVertexColors(it->second, where, nverts, &out);

    // The vertex sequence the mode is applied to: the indices, or 0..n-1 when non-indexed.
    std::vector<uint32_t> seq;
    if (prim.indices >= 0) {
      if (size_t(prim.indices) >= model_.accessors.size()) Fail(where + ": indices accessor " + std::to_string(prim.indices) + " out of range");
      const tinygltf::Accessor& ia = model_.accessors[prim.indices];
      if (ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
          ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        Fail("accessor " + std::to_string(prim.indices) + " (" + where + " indices): componentType must be an unsigned integer");
      }
      size_t n = 0;
      const std::vector<double> idx = ReadAccessor(prim.indices, TINYGLTF_TYPE_SCALAR, where + " indices", &n);
      seq.resize(n);
      for (size_t i = 0; i < n; ++i) {
        if (idx[i] >= double(nverts)) {
          Fail("accessor " + std::to_string(prim.indices) + " (" + where + " indices): index " + std::to_string(uint64_t(idx[i])) +
               " at position " + std::to_string(i) + " is >= vertex count " + std::to_string(nverts));
        }
        seq[i] = uint32_t(idx[i]);
      }
    } else {
      seq.resize(nverts);
      for (size_t i = 0; i < nverts; ++i) seq[i] = uint32_t(i);
    }

    // In the file's winding; PlacePrimitive turns it for a mirroring placement.
    auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
      out.indices.push_back(a);
      out.indices.push_back(b);
      out.indices.push_back(c);
    };
    if (prim.mode == TINYGLTF_MODE_TRIANGLES) {
      if (seq.size() % 3 != 0) Warn(where + ": vertex/index count " + std::to_string(seq.size()) + " is not a multiple of 3; the remainder is ignored");
      out.indices.reserve(seq.size());
      for (size_t i = 0; i + 2 < seq.size(); i += 3) emit(seq[i], seq[i + 1], seq[i + 2]);
    } else if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      // glTF spec: triangle i = (v_i, v_{i+1+i%2}, v_{i+2-i%2}); degenerate joiners are dropped.
      for (size_t i = 0; i + 2 < seq.size(); ++i) {
        const uint32_t a = seq[i], b = seq[i + 1 + i % 2], c = seq[i + 2 - i % 2];
        if (a != b && b != c && a != c) emit(a, b, c);
      }
    } else {  // fan: triangle i = (v_{i+1}, v_{i+2}, v_0)
      for (size_t i = 0; i + 2 < seq.size(); ++i) {
        const uint32_t a = seq[i + 1], b = seq[i + 2], c = seq[0];
        if (a != b && b != c && a != c) emit(a, b, c);
      }
    }
    if (out.indices.empty()) {
      Warn(where + ": no triangles; skipped");
      return;
    }
    size_t singular = 0, bad_normals = 0;  // placements whose normals were dropped, warned once below
    for (size_t k = 0; k < placements.size(); ++k) {
      const Placement& place = placements[k];
      const bool last = k + 1 == placements.size();
      SceneMesh copy = last ? std::move(out) : out;
      copy.instance_id = place.instance_id;
      copy.gpu_instance = place.gpu_instance;
      copy.node_from_instance = place.node_from_instance;
      const std::string instance_where = place.gpu_instance < 0 ? where : where + " instance " + std::to_string(place.gpu_instance);
      PlacePrimitive(world * place.node_from_instance, pos, nrm, posed_later, pos_it->second, instance_where, &singular, &bad_normals,
                     &copy);
      if (!cls) {
        unlabeled_triangles_ += copy.indices.size() / 3;
        ++unlabeled_meshes_;
      }
      scene_.meshes.push_back(std::move(copy));
    }
    const bool instanced = placements.front().gpu_instance >= 0;
    const std::string of = instanced ? " (" + std::to_string(placements.size()) + " instances)" : "";
    if (singular) {
      Warn(where + ": singular node transform" + (instanced ? " for " + std::to_string(singular) + " instance(s)" : "") +
           "; normals dropped (face normals used)");
    }
    if (bad_normals) {
      Warn(where + ": zero or non-finite normals" + (instanced ? " in " + std::to_string(bad_normals) + " instance(s)" : "") +
           "; normals dropped (face normals used)");
    }
  }

  // Places one copy of a decoded primitive (node-frame positions `pos` and normals `nrm`, xyz
  // triples) at `world`: world positions, normals by the inverse transpose, the winding turned
  // when `world` mirrors, and local_normals for a mesh PoseSceneAt re-poses. A placement whose
  // normals cannot be transformed counts in *singular or *bad_normals and uses face normals.
  void PlacePrimitive(const Eigen::Matrix4d& world, const std::vector<double>& pos, const std::vector<double>& nrm, bool posed_later,
                      int pos_accessor, const std::string& where, size_t* singular, size_t* bad_normals, SceneMesh* out) {
    const size_t nverts = pos.size() / 3;
    const Eigen::Matrix3d linear = world.topLeftCorner<3, 3>();
    const Eigen::Vector3d offset = world.topRightCorner<3, 1>();
    out->positions.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) {
      const Eigen::Vector3d w = linear * Eigen::Vector3d(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]) + offset;
      if (!w.allFinite()) {
        Fail("accessor " + std::to_string(pos_accessor) + " (" + where + " POSITION): vertex " + std::to_string(i) +
             " is not finite once transformed");
      }
      out->positions[i] = w.cast<float>();
    }
    if (!nrm.empty()) {
      if (std::abs(linear.determinant()) < 1e-300) {
        ++*singular;
      } else {
        const Eigen::Matrix3d normal_matrix = linear.inverse().transpose();
        out->normals.resize(nverts);
        bool bad = false;
        for (size_t i = 0; i < nverts && !bad; ++i) {
          const Eigen::Vector3d v = normal_matrix * Eigen::Vector3d(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
          const double len = v.norm();
          if (!std::isfinite(len) || len < 1e-12) bad = true;
          else out->normals[i] = (v / len).cast<float>();
        }
        if (bad) {
          ++*bad_normals;
          out->normals.clear();
        }
      }
    }
    if (posed_later && !out->normals.empty()) {
      out->local_normals.resize(nverts);
      for (size_t i = 0; i < nverts; ++i) out->local_normals[i] = Eigen::Vector3d(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]).normalized().cast<float>();
    }
    if (out->normals.empty()) out->morph_base_normals.clear();  // as local_normals: face normals are used
    // A mirroring transform turns counter-clockwise faces clockwise: swap two corners to undo it.
    if (linear.determinant() < 0) {
      for (size_t t = 0; t + 2 < out->indices.size(); t += 3) std::swap(out->indices[t + 1], out->indices[t + 2]);
    }
  }

  // COLOR_0 (glTF 2.0: VEC3 or VEC4 of float, or of normalized unsigned byte or short), linear
  // RGBA with alpha 1 when it is VEC3.
  void ReadVertexColors(int accessor, const std::string& where, size_t nverts, SceneMesh* out) {
    const std::string label = "accessor " + std::to_string(accessor) + " (" + where + " COLOR_0)";
    if (accessor < 0 || size_t(accessor) >= model_.accessors.size()) Fail(label + ": index out of range");
    const tinygltf::Accessor& a = model_.accessors[accessor];
    if (a.type != TINYGLTF_TYPE_VEC3 && a.type != TINYGLTF_TYPE_VEC4) Fail(label + ": type must be VEC3 or VEC4");
    const bool normalized_integer = a.normalized && (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                                     a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
    if (a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !normalized_integer) {
      Fail(label + ": componentType must be FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT");
    }
    size_t n = 0;
    const std::vector<double> rgba = ReadAccessor(accessor, a.type, where + " COLOR_0", &n);
    if (n != nverts) Fail(label + ": count differs from POSITION");
    const int ncomp = a.type == TINYGLTF_TYPE_VEC4 ? 4 : 3;
    out->colors.resize(n);
    for (size_t i = 0; i < n; ++i) {
      Eigen::Vector4d c(rgba[ncomp * i], rgba[ncomp * i + 1], rgba[ncomp * i + 2], ncomp == 4 ? rgba[ncomp * i + 3] : 1.0);
      if (!c.allFinite()) Fail(label + ": vertex " + std::to_string(i) + " is not finite");
      out->colors[i] = c.cwiseMax(0.0).cwiseMin(1.0).cast<float>();  // the spec's range
    }
  }

  void Summarise() {
    for (const auto& [what, count] : ignored_) Warn("not supported, ignored: " + what + " (" + std::to_string(count) + "x)");
    if (unlabeled_triangles_ > 0) {
      Warn(std::to_string(unlabeled_triangles_) + " triangles in " + std::to_string(unlabeled_meshes_) +
           " primitive(s) have no class (extras.class on node, mesh or material" +
           std::string(options_.label_rules ? ", or a label rule" : "") + ") and are unlabeled");
    }
  }

  std::filesystem::path path_;
  GltfLoadOptions options_;
  tinygltf::Model model_;
  Scene scene_;
  std::vector<ClassTag> node_class_, mesh_class_, material_class_;
  std::vector<MaterialUvs> material_uv_;  // per glTF material: its textures' coordinates
  std::map<int, int> texture_map_;  // glTF texture -> Scene::textures index
  ImageChecks image_checks_;        // filled by LoadCheckedImage while tinygltf reads the file
  std::set<int> animated_nodes_;    // nodes targeted by a translation, rotation or scale channel
  std::set<int> morph_animated_nodes_;  // nodes whose morph weights a channel animates
  std::vector<bool> traversed_;                 // per glTF node: reached from the loaded scene's roots
  std::vector<Eigen::Matrix4d> rest_world_;     // per glTF node: world_from_node at rest (when traversed)
  bool current_mesh_animated_ = false;  // the node being traversed moves with an animation
  std::map<std::string, size_t> ignored_;
  uint32_t next_instance_ = 1;
  bool instance_overflow_warned_ = false;
  size_t unlabeled_triangles_ = 0;
  size_t unlabeled_meshes_ = 0;
  size_t decoded_elements_ = 0;  // accessor elements read so far (ReadAccessor's total bound)
  size_t instanced_elements_ = 0;  // vertices and indices of every GPU instance so far (CheckInstancedSize)
  std::vector<int> rule_parent_;  // parent node of each node, for label rules (built on first use)
};

}  // namespace

Scene LoadGltf(const std::filesystem::path& path, const GltfLoadOptions& options) { return Loader(path, options).Load(); }

}  // namespace rigsim
