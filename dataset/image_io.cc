#include "dataset/image_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <unistd.h>

#include "dataset/image_codecs.h"
#include "geometry/camera_validation.h"

namespace rigsim {
namespace fs = std::filesystem;
namespace {

// PNG at zlib's fastest level, rows filtered by Paeth alone rather than libpng's per-row choice
// among all five filters: a little larger and much faster to write than the defaults
// (BENCHMARKS.md, "Writing a dataset"). The zero oFFs chunk is what OpenImageIO, which wrote
// rigsim's images before, adds: kept so that the bytes stay the same.
constexpr PngSettings kPngSettings{1, 0, 0x80 /* PNG_FILTER_PAETH */, true};
// JPEG (the teaching report's pictures) as OpenImageIO wrote it: quality 98, with an empty Exif segment.
constexpr JpegSettings kJpegSettings{98, false, true};

std::string Extension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// A temporary name beside `path`; renaming it over `path` makes the write atomic.
fs::path TemporaryFor(const fs::path& path) {
  return path.parent_path() / (".tmp" + std::to_string(::getpid()) + "-" + path.filename().string());
}

void WriteBytesAtomically(const fs::path& path, const std::vector<uint8_t>& bytes) {
  const fs::path tmp = TemporaryFor(path);
  {
    std::ofstream out(tmp, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error(path.string() + ": cannot write image");
    }
  }
  fs::rename(tmp, path);
}

template <typename T>
void CheckWritable(const fs::path& path, const Image<T>& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.data.size() != size_t(image.width) * image.height * image.channels) {
    throw std::runtime_error(path.string() + ": refusing to write an empty or inconsistent image");
  }
}

DecodeLimits Limits(bool header_only) { return {kMaxCameraPixels, header_only}; }

// Sample conversions between the file's type and the one asked for, as OpenImageIO made them:
// integers scale to the full range of the other type, floats map [0, 1] to it (rounded, clamped).
template <typename T>
T FromU8(uint8_t v) {
  if constexpr (std::is_same_v<T, uint8_t>) return v;
  else if constexpr (std::is_same_v<T, uint16_t>) return uint16_t(v * 257);
  else return v / 255.f;
}
template <typename T>
T FromU16(uint16_t v) {
  if constexpr (std::is_same_v<T, uint8_t>) return uint8_t((uint32_t(v) * 255 + 32767) / 65535);
  else if constexpr (std::is_same_v<T, uint16_t>) return v;
  else return v / 65535.f;
}
template <typename T>
T FromFloat(float v) {
  if constexpr (std::is_same_v<T, float>) {
    return v;
  } else {
    constexpr float kMax = float(std::numeric_limits<T>::max());
    const float scaled = std::isnan(v) ? 0.f : std::clamp(v * kMax + 0.5f, 0.f, kMax);
    return T(scaled);
  }
}

template <typename T>
Image<T> ReadTyped(const fs::path& path, int channels) {
  const DecodedPixels d = DecodeImageFile(path, Limits(false));
  const int file_channels = d.channels;
  Image<T> file_image(d.width, d.height, file_channels);
  for (size_t i = 0; i < file_image.data.size(); ++i) {
    switch (d.type) {
      case DecodedPixels::Type::kU8: file_image.data[i] = FromU8<T>(d.u8[i]); break;
      case DecodedPixels::Type::kU16: file_image.data[i] = FromU16<T>(d.u16[i]); break;
      case DecodedPixels::Type::kFloat: file_image.data[i] = FromFloat<T>(d.f[i]); break;
    }
  }
  if (channels == 0 || channels == file_channels) return file_image;
  // Channel conversion: grey -> replicate; more channels -> keep the first ones.
  Image<T> out(d.width, d.height, channels);
  for (int y = 0; y < d.height; ++y) {
    for (int x = 0; x < d.width; ++x) {
      for (int c = 0; c < channels; ++c) {
        out.at(x, y, c) = file_image.at(x, y, file_channels == 1 ? 0 : std::min(c, file_channels - 1));
      }
    }
  }
  if (file_channels > 1 && file_channels < channels && channels != 3) {
    throw std::runtime_error(path.string() + ": has " + std::to_string(file_channels) + " channels, need " +
                             std::to_string(channels));
  }
  return out;
}

}  // namespace

void WriteImage(const fs::path& path, const ImageU8& image) {
  CheckWritable(path, image);
  const std::string ext = Extension(path);
  if (ext == ".png") {
    WriteBytesAtomically(path, EncodePng(image.data.data(), image.width, image.height, image.channels, 8, kPngSettings,
                                         path.string()));
  } else if (ext == ".jpg" || ext == ".jpeg") {
    WriteBytesAtomically(path, EncodeJpeg(image.data.data(), image.width, image.height, image.channels, kJpegSettings,
                                          path.string()));
  } else {
    throw std::runtime_error(path.string() + ": no image writer for this extension (8-bit images: .png, .jpg)");
  }
}

void WriteImage(const fs::path& path, const ImageU16& image) {
  CheckWritable(path, image);
  if (Extension(path) != ".png") throw std::runtime_error(path.string() + ": 16-bit images are written as .png only");
  WriteBytesAtomically(path, EncodePng(image.data.data(), image.width, image.height, image.channels, 16, kPngSettings,
                                       path.string()));
}

void WriteImage(const fs::path& path, const ImageF& image) {
  CheckWritable(path, image);
  if (Extension(path) != ".exr") throw std::runtime_error(path.string() + ": float images are written as .exr only");
  // Depth uncompressed: zip shrinks a range image little and takes five times as long to write
  // (BENCHMARKS.md, "Writing a longer dataset"). Multi-channel float images (correspondence maps,
  // normals: opt-in, large uncompressed) are zip-compressed: their many no-surface pixels are the
  // same value.
  const fs::path tmp = TemporaryFor(path);
  try {
    WriteExrFile(tmp, image.data.data(), image.width, image.height, image.channels, image.channels != 1);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() + ": cannot write image (" + std::to_string(image.channels) +
                             " float channels; 1, 3 or 4 are written)");
  }
  fs::rename(tmp, path);
}

ImageSize ReadImageSize(const fs::path& path) {
  const DecodedPixels d = DecodeImageFile(path, Limits(true));
  return {d.width, d.height};
}

ImageU8 ReadImageU8(const fs::path& path, int channels) { return ReadTyped<uint8_t>(path, channels); }

ImageU16 ReadImageU16(const fs::path& path) {
  ImageU16 img = ReadTyped<uint16_t>(path, 0);
  if (img.channels != 1) throw std::runtime_error(path.string() + ": expected a single-channel image");
  return img;
}

ImageF ReadImageFChannels(const fs::path& path) { return ReadTyped<float>(path, 0); }

ImageF ReadImageF(const fs::path& path) {
  ImageF img = ReadTyped<float>(path, 0);
  if (img.channels != 1) throw std::runtime_error(path.string() + ": expected a single-channel image");
  return img;
}

}  // namespace rigsim
