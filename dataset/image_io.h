// Reading and writing images (dataset/image_codecs.h: PNG, JPEG, WebP, TIFF, OpenEXR). Every
// error throws std::runtime_error whose message starts with the file name.
#pragma once

#include <filesystem>

#include "geometry/image.h"

namespace rigsim {

// PNG or JPEG (by the extension) with 1..4 channels of 8 bits (JPEG: 1 or 3). Writes atomically
// (temporary file, rename).
void WriteImage(const std::filesystem::path& path, const ImageU8& image);
// 16-bit single-channel PNG (instance ids).
void WriteImage(const std::filesystem::path& path, const ImageU16& image);
// float EXR: depth (1 channel, uncompressed), or 3 or 4 channels R, G, B(, A) (zip).
void WriteImage(const std::filesystem::path& path, const ImageF& image);

// Reads PNG, JPEG, WebP, TIFF (as 8-bit) or OpenEXR, whatever the extension says, converted to the
// requested type. `channels` > 0 demands
// that channel count (RGB wanted from an RGBA file drops alpha; grey to RGB replicates);
// 0 keeps the file's.
ImageU8 ReadImageU8(const std::filesystem::path& path, int channels = 0);
ImageU16 ReadImageU16(const std::filesystem::path& path);
ImageF ReadImageF(const std::filesystem::path& path);
// Any number of float channels (correspondence maps, normals).
ImageF ReadImageFChannels(const std::filesystem::path& path);

// The size in the file's header, without decoding the pixels (a whole dataset's photos are
// checked in moments before any is decoded). Throws like the readers.
struct ImageSize {
  int width = 0, height = 0;
};
ImageSize ReadImageSize(const std::filesystem::path& path);

}  // namespace rigsim
