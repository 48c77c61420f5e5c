// The image formats rigsim reads and writes, each through its own reference library: PNG
// (libpng), JPEG (libjpeg-turbo), WebP (libwebp, glTF textures), TIFF (libtiff, photos) and
// OpenEXR. Small libraries loaded at start-up, where an all-format library would bring in video,
// GIS and medical-imaging stacks. Every error throws std::runtime_error whose message starts with
// the `name` given (the file, or "image 3" of a glTF file).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace rigsim {

enum class ImageFormat { kPng, kJpeg, kWebp, kTiff, kExr, kUnknown };

// The format from the first bytes of a file (its signature), whatever its name says.
ImageFormat SniffImageFormat(const uint8_t* bytes, size_t size);

// Pixels as stored in a file: 8-bit, 16-bit or float samples, interleaved, rows top to bottom.
struct DecodedPixels {
  enum class Type { kU8, kU16, kFloat };
  Type type = Type::kU8;
  int width = 0, height = 0, channels = 0;
  std::vector<uint8_t> u8;
  std::vector<uint16_t> u16;
  std::vector<float> f;
};

// Decoding reads the header first and refuses, before allocating, an image of more than
// `max_pixels` (or of more than 4 channels, or one that is not 2D); `header_only` stops there
// (width, height and channels set, no samples).
struct DecodeLimits {
  int64_t max_pixels = 0;
  bool header_only = false;
};

// PNG, JPEG or WebP bytes in memory (grey, grey + alpha, RGB or RGBA; PNG may be 16-bit).
DecodedPixels DecodeImageBytes(const uint8_t* bytes, size_t size, const std::string& name, const DecodeLimits& limits);
// Any supported file: PNG, JPEG, WebP, TIFF (integer samples, read as 8-bit) or OpenEXR (float;
// R, G, B, A first).
DecodedPixels DecodeImageFile(const std::filesystem::path& path, const DecodeLimits& limits);

// PNG encoding settings: zlib level and strategy, libpng's row filters (PNG_FILTER_* bits), and
// whether to write an oFFs chunk with a zero offset (OpenImageIO writes one; kept for identical bytes).
struct PngSettings {
  int compression_level = 6;
  int strategy = 0;  // Z_DEFAULT_STRATEGY
  int filters = -1;  // libpng's choice
  bool zero_offset_chunk = false;
};
// `samples` holds width x height x channels values of `bits` (8 or 16, native byte order).
std::vector<uint8_t> EncodePng(const void* samples, int width, int height, int channels, int bits,
                               const PngSettings& settings, const std::string& name);

// Baseline JPEG, 4:2:0, standard or optimised Huffman tables; an empty Exif segment when asked
// (OpenImageIO writes one; kept for identical bytes). 1 (grey) or 3 (RGB) channels.
struct JpegSettings {
  int quality = 95;
  bool optimize_coding = false;
  bool empty_exif = false;
};
std::vector<uint8_t> EncodeJpeg(const uint8_t* samples, int width, int height, int channels,
                                const JpegSettings& settings, const std::string& name);

// Writes a scanline OpenEXR file of float samples: 1 channel (Y), 3 (R, G, B) or 4 (R, G, B, A),
// uncompressed or zip-compressed, with an empty capture date (the same bytes on every run).
void WriteExrFile(const std::filesystem::path& path, const float* samples, int width, int height, int channels,
                  bool zip);

}  // namespace rigsim
