#include <algorithm>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

#include "dataset/image_codecs.h"
#include "gltf/loader.h"

namespace rigsim::gltf {
namespace {

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

WrapMode ToWrap(int gl) {
  switch (gl) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return WrapMode::kClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return WrapMode::kMirroredRepeat;
    default: return WrapMode::kRepeat;
  }
}

}  // namespace

// Decodes glTF images with libpng, libjpeg and libwebp (dataset/image_codecs.h) in place of
// tinygltf's stb_image, after two checks on the encoded bytes: the image is a PNG or a JPEG, the
// formats glTF 2.0 allows, or a WebP (EXT_texture_webp) (stb would also take BMP, PSD, GIF, ...),
// and its header asks for no more pixels than the limit. stb inflates a PNG's compressed data into
// a buffer without bound: a 1x1 PNG of a few hundred bytes (found by fuzzing) makes it allocate
// 1.2 GB. libpng inflates row by row into the image's own size. An image that fails a check or
// does not decode is left empty, its reason kept in the ImageChecks `user_data`, and tinygltf
// goes on.
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
  DecodedPixels decoded;
  try {
    const DecodeLimits limits{int64_t(std::min<uint64_t>(checks.max_pixels, INT64_MAX)), false};
    decoded = DecodeImageBytes(bytes, size_t(size), "image " + std::to_string(index), limits);
  } catch (const std::runtime_error&) {
    return refuse(": cannot decode it");
  }
  const bool wide = decoded.type == DecodedPixels::Type::kU16;
  if (decoded.channels == 2) {  // grey + alpha as RGBA, as OpenCV gave it and the renderer takes it
    auto to_rgba = [](const auto& grey_alpha) {
      std::remove_cvref_t<decltype(grey_alpha)> rgba(grey_alpha.size() * 2);
      for (size_t i = 0; i < grey_alpha.size() / 2; ++i) {
        for (int c = 0; c < 4; ++c) rgba[i * 4 + c] = grey_alpha[i * 2 + (c == 3 ? 1 : 0)];
      }
      return rgba;
    };
    if (wide) decoded.u16 = to_rgba(decoded.u16);
    else decoded.u8 = to_rgba(decoded.u8);
    decoded.channels = 4;
  }
  image->width = decoded.width;
  image->height = decoded.height;
  image->component = decoded.channels;
  image->bits = wide ? 16 : 8;
  image->pixel_type = wide ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  if (wide) {
    const auto* b = reinterpret_cast<const unsigned char*>(decoded.u16.data());
    image->image.assign(b, b + decoded.u16.size() * sizeof(uint16_t));
  } else {
    image->image = std::move(decoded.u8);
  }
  return true;
}

int Loader::ConvertTexture(int index) {
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
  const std::string image_label = "image " + std::to_string(source) + NameSuffix(img.uri);
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

}  // namespace rigsim::gltf
