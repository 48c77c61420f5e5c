#include "dataset/image_io.h"

#include <memory>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include "geometry/camera_validation.h"

namespace rigsim {
namespace fs = std::filesystem;
namespace {

template <typename T>
void WriteTyped(const fs::path& path, const Image<T>& image, OIIO::TypeDesc type) {
  if (image.width <= 0 || image.height <= 0 || image.data.size() != size_t(image.width) * image.height * image.channels) {
    throw std::runtime_error(path.string() + ": refusing to write an empty or inconsistent image");
  }
  // Same extension so OIIO picks the same format; rename makes the write atomic.
  const fs::path tmp = path.parent_path() / (".tmp" + std::to_string(::getpid()) + "-" + path.filename().string());
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) throw std::runtime_error(path.string() + ": no image writer for this extension: " + OIIO::geterror());
  OIIO::ImageSpec spec(image.width, image.height, image.channels, type);
  // Single-channel float images (depth) uncompressed: zip shrinks a range image little and takes
  // five times as long (BENCHMARKS.md, "Writing a longer dataset"). Multi-channel float images
  // (correspondence maps, normals: opt-in, large uncompressed) are zip-compressed: their many
  // no-surface pixels are the same value.
  if (type == OIIO::TypeDesc::FLOAT) spec.attribute("compression", image.channels == 1 ? "none" : "zip");
  // PNG at zlib's fastest level, rows filtered by Paeth alone rather than libpng's per-row choice
  // among all five filters: a little larger and much faster to write than the defaults
  // (BENCHMARKS.md, "Writing a dataset").
  if (type != OIIO::TypeDesc::FLOAT) {
    spec.attribute("png:compressionLevel", 1);
    spec.attribute("png:filter", 0x80);  // PNG_FILTER_PAETH
  }
  // OpenImageIO stamps EXR files with the current time (capDate) unless told otherwise: the same
  // render a second later would differ in bytes. An empty date keeps output deterministic.
  spec.attribute("DateTime", "");
  if (!out->open(tmp.string(), spec) || !out->write_image(type, image.data.data()) || !out->close()) {
    const std::string err = out->geterror();
    std::error_code ec;
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() + ": cannot write image: " + err);
  }
  fs::rename(tmp, path);
}

// Opens an image and checks its header, without decoding the pixels.
std::unique_ptr<OIIO::ImageInput> OpenImage(const fs::path& path) {
  if (!fs::exists(path)) throw std::runtime_error(path.string() + ": no such file");
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw std::runtime_error(path.string() + ": cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  const int file_channels = spec.nchannels;
  if (spec.width <= 0 || spec.height <= 0 || file_channels <= 0 || spec.depth != 1) {
    throw std::runtime_error(path.string() + ": not a 2D image");
  }
  // The header's size is checked before allocating: a corrupt or hostile header must not make us
  // try to allocate gigabytes.
  if (int64_t(spec.width) * spec.height > kMaxCameraPixels || file_channels > 64) {
    throw std::runtime_error(path.string() + ": image size " + std::to_string(spec.width) + "x" +
                             std::to_string(spec.height) + "x" + std::to_string(file_channels) +
                             " exceeds the limit of " + std::to_string(kMaxCameraPixels / 1'000'000) + " megapixels");
  }
  return in;
}

template <typename T>
Image<T> ReadTyped(const fs::path& path, OIIO::TypeDesc type, int channels) {
  const std::unique_ptr<OIIO::ImageInput> in = OpenImage(path);
  const OIIO::ImageSpec& spec = in->spec();
  const int file_channels = spec.nchannels;
  Image<T> file_image(spec.width, spec.height, file_channels);
  if (!in->read_image(0, 0, 0, file_channels, type, file_image.data.data())) {
    throw std::runtime_error(path.string() + ": cannot decode image: " + in->geterror());
  }
  in->close();
  if (channels == 0 || channels == file_channels) return file_image;
  // Channel conversion: grey -> replicate; more channels -> keep the first ones.
  Image<T> out(spec.width, spec.height, channels);
  for (int y = 0; y < spec.height; ++y) {
    for (int x = 0; x < spec.width; ++x) {
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

void WriteImage(const fs::path& path, const ImageU8& image) { WriteTyped(path, image, OIIO::TypeDesc::UINT8); }
void WriteImage(const fs::path& path, const ImageU16& image) { WriteTyped(path, image, OIIO::TypeDesc::UINT16); }
void WriteImage(const fs::path& path, const ImageF& image) { WriteTyped(path, image, OIIO::TypeDesc::FLOAT); }

ImageSize ReadImageSize(const fs::path& path) {
  const std::unique_ptr<OIIO::ImageInput> in = OpenImage(path);
  return {in->spec().width, in->spec().height};
}

ImageU8 ReadImageU8(const fs::path& path, int channels) { return ReadTyped<uint8_t>(path, OIIO::TypeDesc::UINT8, channels); }

ImageU16 ReadImageU16(const fs::path& path) {
  ImageU16 img = ReadTyped<uint16_t>(path, OIIO::TypeDesc::UINT16, 0);
  if (img.channels != 1) throw std::runtime_error(path.string() + ": expected a single-channel image");
  return img;
}

ImageF ReadImageFChannels(const fs::path& path) { return ReadTyped<float>(path, OIIO::TypeDesc::FLOAT, 0); }

ImageF ReadImageF(const fs::path& path) {
  ImageF img = ReadTyped<float>(path, OIIO::TypeDesc::FLOAT, 0);
  if (img.channels != 1) throw std::runtime_error(path.string() + ": expected a single-channel image");
  return img;
}

}  // namespace rigsim
