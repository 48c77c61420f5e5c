#include "dataset/image_codecs.h"

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>

#include <jpeglib.h>
#include <png.h>
#include <tiffio.h>
#include <webp/decode.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

namespace rigsim {
namespace fs = std::filesystem;
namespace {

[[noreturn]] void Fail(const std::string& name, const std::string& why) { throw std::runtime_error(name + ": " + why); }

// Checks a header's size against the limits before anything is allocated.
void CheckHeader(const std::string& name, int64_t width, int64_t height, int channels, const DecodeLimits& limits) {
  if (width <= 0 || height <= 0 || channels <= 0) Fail(name, "not a 2D image");
  if (channels > 4) Fail(name, "has " + std::to_string(channels) + " channels (at most 4 are read)");
  if (limits.max_pixels > 0 && width * height > limits.max_pixels) {
    Fail(name, "image size " + std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(channels) +
                   " exceeds the limit of " + std::to_string(limits.max_pixels / 1'000'000) + " megapixels");
  }
}

// --- PNG ----------------------------------------------------------------------------------------
// libpng reports errors by longjmp: the functions that call it hold no object with a destructor
// between setjmp and the calls, and the caller throws with the message kept here.
struct CodecError {
  char message[200] = "";
};

extern "C" void OnPngError(png_structp png, png_const_charp message) {
  auto* error = static_cast<CodecError*>(png_get_error_ptr(png));
  std::snprintf(error->message, sizeof(error->message), "%s", message);
  png_longjmp(png, 1);
}
extern "C" void OnPngWarning(png_structp, png_const_charp) {}

struct MemoryReader {
  const uint8_t* bytes;
  size_t size, offset;
};
extern "C" void ReadFromMemory(png_structp png, png_bytep out, png_size_t n) {
  auto* r = static_cast<MemoryReader*>(png_get_io_ptr(png));
  if (n > r->size - r->offset) png_error(png, "file ends early");
  std::memcpy(out, r->bytes + r->offset, n);
  r->offset += n;
}
extern "C" void WriteToVector(png_structp png, png_bytep data, png_size_t n) {
  auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + n);
}
extern "C" void FlushNothing(png_structp) {}

// Reads the header, then (unless header_only, or `rows` is null) the rows. Returns false with
// error->message set on failure.
bool RunPngRead(MemoryReader* reader, CodecError* error, DecodedPixels* out, const DecodeLimits& limits,
                std::vector<png_bytep>* rows) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, error, OnPngError, OnPngWarning);
  if (png == nullptr) return false;
  png_infop info = png_create_info_struct(png);
  if (info == nullptr || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_set_read_fn(png, reader, ReadFromMemory);
  png_read_info(png, info);
  const int color = png_get_color_type(png, info);
  const int depth = png_get_bit_depth(png, info);
  if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (color == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
  if (depth == 16) png_set_swap(png);  // to this machine's byte order
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  out->width = int(png_get_image_width(png, info));
  out->height = int(png_get_image_height(png, info));
  out->channels = png_get_channels(png, info);
  out->type = png_get_bit_depth(png, info) == 16 ? DecodedPixels::Type::kU16 : DecodedPixels::Type::kU8;
  if (!limits.header_only && rows != nullptr) {
    // The caller allocates once the header has passed its checks (second call).
    png_read_image(png, rows->data());
    png_read_end(png, nullptr);
  }
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

DecodedPixels DecodePng(const uint8_t* bytes, size_t size, const std::string& name, const DecodeLimits& limits) {
  DecodedPixels out;
  CodecError error;
  MemoryReader header{bytes, size, 0};
  if (!RunPngRead(&header, &error, &out, limits, nullptr)) Fail(name, std::string("cannot read PNG: ") + error.message);
  CheckHeader(name, out.width, out.height, out.channels, limits);
  if (limits.header_only) return out;
  const size_t row_values = size_t(out.width) * out.channels;
  std::vector<png_bytep> rows(out.height);
  if (out.type == DecodedPixels::Type::kU16) {
    out.u16.resize(row_values * out.height);
    for (int y = 0; y < out.height; ++y) rows[y] = reinterpret_cast<png_bytep>(out.u16.data() + y * row_values);
  } else {
    out.u8.resize(row_values * out.height);
    for (int y = 0; y < out.height; ++y) rows[y] = out.u8.data() + y * row_values;
  }
  MemoryReader pixels{bytes, size, 0};
  if (!RunPngRead(&pixels, &error, &out, limits, &rows)) Fail(name, std::string("cannot decode PNG: ") + error.message);
  return out;
}

bool RunPngWrite(const std::vector<png_bytep>& rows, int width, int height, int channels, int bits,
                 const PngSettings& s, std::vector<uint8_t>* out, CodecError* error) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, error, OnPngError, OnPngWarning);
  if (png == nullptr) return false;
  png_infop info = png_create_info_struct(png);
  if (info == nullptr || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, out, WriteToVector, FlushNothing);
  png_set_compression_level(png, s.compression_level);
  png_set_compression_strategy(png, s.strategy);
  if (s.filters >= 0) png_set_filter(png, PNG_FILTER_TYPE_BASE, s.filters);
  static constexpr int kColor[] = {0, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                   PNG_COLOR_TYPE_RGB_ALPHA};
  png_set_IHDR(png, info, width, height, bits, kColor[channels], PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  if (s.zero_offset_chunk) png_set_oFFs(png, info, 0, 0, PNG_OFFSET_PIXEL);
  png_write_info(png, info);
  if (bits == 16) png_set_swap(png);  // PNG stores big-endian samples
  png_write_image(png, const_cast<png_bytepp>(rows.data()));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

// --- JPEG ---------------------------------------------------------------------------------------
struct JpegErrorManager {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
  CodecError error;
};

extern "C" void OnJpegError(j_common_ptr cinfo) {
  auto* e = reinterpret_cast<JpegErrorManager*>(cinfo->err);
  char text[JMSG_LENGTH_MAX];
  (*cinfo->err->format_message)(cinfo, text);
  std::snprintf(e->error.message, sizeof(e->error.message), "%s", text);
  std::longjmp(e->jump, 1);
}
extern "C" void OnJpegMessage(j_common_ptr, int) {}

bool RunJpegRead(const uint8_t* bytes, size_t size, JpegErrorManager* err, DecodedPixels* out,
                 const DecodeLimits& limits, bool read_pixels) {
  jpeg_decompress_struct cinfo;
  cinfo.err = jpeg_std_error(&err->manager);
  err->manager.error_exit = OnJpegError;
  err->manager.emit_message = OnJpegMessage;
  if (setjmp(err->jump)) {
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, bytes, static_cast<unsigned long>(size));
  jpeg_read_header(&cinfo, TRUE);
  if (cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK) {
    std::snprintf(err->error.message, sizeof(err->error.message), "CMYK JPEG images are not supported");
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  cinfo.out_color_space = cinfo.num_components == 1 ? JCS_GRAYSCALE : JCS_RGB;
  cinfo.dct_method = JDCT_ISLOW;  // the default, pinned (see RunJpegWrite)
  out->width = int(cinfo.image_width);
  out->height = int(cinfo.image_height);
  out->channels = cinfo.num_components == 1 ? 1 : 3;
  out->type = DecodedPixels::Type::kU8;
  if (read_pixels && !limits.header_only) {
    jpeg_start_decompress(&cinfo);
    const size_t row_bytes = size_t(out->width) * out->channels;
    while (cinfo.output_scanline < cinfo.output_height) {
      JSAMPROW row = out->u8.data() + size_t(cinfo.output_scanline) * row_bytes;
      jpeg_read_scanlines(&cinfo, &row, 1);
    }
    jpeg_finish_decompress(&cinfo);
  }
  jpeg_destroy_decompress(&cinfo);
  return true;
}

DecodedPixels DecodeJpeg(const uint8_t* bytes, size_t size, const std::string& name, const DecodeLimits& limits) {
  DecodedPixels out;
  JpegErrorManager err;
  if (!RunJpegRead(bytes, size, &err, &out, limits, false)) {
    Fail(name, std::string("cannot read JPEG: ") + err.error.message);
  }
  CheckHeader(name, out.width, out.height, out.channels, limits);
  if (limits.header_only) return out;
  out.u8.resize(size_t(out.width) * out.height * out.channels);
  if (!RunJpegRead(bytes, size, &err, &out, limits, true)) {
    Fail(name, std::string("cannot decode JPEG: ") + err.error.message);
  }
  return out;
}

bool RunJpegWrite(const uint8_t* samples, int width, int height, int channels, const JpegSettings& s,
                  JpegErrorManager* err, unsigned char** buffer, unsigned long* size) {
  jpeg_compress_struct cinfo;
  cinfo.err = jpeg_std_error(&err->manager);
  err->manager.error_exit = OnJpegError;
  err->manager.emit_message = OnJpegMessage;
  if (setjmp(err->jump)) {
    jpeg_destroy_compress(&cinfo);
    return false;
  }
  jpeg_create_compress(&cinfo);
  jpeg_mem_dest(&cinfo, buffer, size);
  cinfo.image_width = width;
  cinfo.image_height = height;
  cinfo.input_components = channels;
  cinfo.in_color_space = channels == 1 ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, s.quality, TRUE);
  cinfo.dct_method = JDCT_ISLOW;  // the default, pinned: the integer DCT gives the same bytes on every SIMD path
  cinfo.optimize_coding = s.optimize_coding ? TRUE : FALSE;
  jpeg_start_compress(&cinfo, TRUE);
  if (s.empty_exif) {
    // "Exif\0\0", a little-endian TIFF header and an IFD without entries.
    static const JOCTET kExif[] = {'E', 'x', 'i', 'f', 0, 0, 'I', 'I', 42, 0, 8, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    jpeg_write_marker(&cinfo, JPEG_APP0 + 1, kExif, sizeof(kExif));
  }
  const size_t row_bytes = size_t(width) * channels;
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW row = const_cast<uint8_t*>(samples) + size_t(cinfo.next_scanline) * row_bytes;
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  return true;
}

// --- WebP ---------------------------------------------------------------------------------------
DecodedPixels DecodeWebp(const uint8_t* bytes, size_t size, const std::string& name, const DecodeLimits& limits) {
  WebPBitstreamFeatures features;
  if (WebPGetFeatures(bytes, size, &features) != VP8_STATUS_OK) Fail(name, "cannot read WebP header");
  DecodedPixels out;
  out.width = features.width;
  out.height = features.height;
  out.channels = features.has_alpha ? 4 : 3;
  CheckHeader(name, out.width, out.height, out.channels, limits);
  if (limits.header_only) return out;
  out.u8.resize(size_t(out.width) * out.height * out.channels);
  const int stride = out.width * out.channels;
  const uint8_t* ok = features.has_alpha ? WebPDecodeRGBAInto(bytes, size, out.u8.data(), out.u8.size(), stride)
                                         : WebPDecodeRGBInto(bytes, size, out.u8.data(), out.u8.size(), stride);
  if (ok == nullptr) Fail(name, "cannot decode WebP");
  return out;
}

// --- TIFF (photos: integer samples, read as 8-bit through libtiff's RGBA interface) ---------------
extern "C" void OnTiffMessage(const char*, const char*, va_list) {}

DecodedPixels DecodeTiff(const fs::path& path, const DecodeLimits& limits) {
  const std::string name = path.string();
  TIFFSetErrorHandler(OnTiffMessage);
  TIFFSetWarningHandler(OnTiffMessage);
  std::unique_ptr<TIFF, void (*)(TIFF*)> tif(TIFFOpen(name.c_str(), "r"), TIFFClose);
  if (!tif) Fail(name, "cannot read TIFF");
  uint32_t width = 0, height = 0;
  uint16_t samples = 1, bits = 8;
  TIFFGetField(tif.get(), TIFFTAG_IMAGEWIDTH, &width);
  TIFFGetField(tif.get(), TIFFTAG_IMAGELENGTH, &height);
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_SAMPLESPERPIXEL, &samples);
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_BITSPERSAMPLE, &bits);
  DecodedPixels out;
  out.width = int(width);
  out.height = int(height);
  out.channels = samples >= 4 ? 4 : samples >= 3 ? 3 : 1;
  CheckHeader(name, width, height, samples, limits);
  if (limits.header_only) return out;
  std::vector<uint32_t> rgba(size_t(width) * height);
  if (!TIFFReadRGBAImageOriented(tif.get(), width, height, rgba.data(), ORIENTATION_TOPLEFT, 0)) {
    Fail(name, "cannot decode TIFF (" + std::to_string(bits) +
                   "-bit samples; TIFF is read with 8- or 16-bit integer samples)");
  }
  out.u8.resize(rgba.size() * out.channels);
  for (size_t i = 0; i < rgba.size(); ++i) {
    const uint32_t p = rgba[i];
    const uint8_t v[4] = {uint8_t(TIFFGetR(p)), uint8_t(TIFFGetG(p)), uint8_t(TIFFGetB(p)), uint8_t(TIFFGetA(p))};
    for (int c = 0; c < out.channels; ++c) out.u8[i * out.channels + c] = v[c];
  }
  return out;
}

// --- OpenEXR ------------------------------------------------------------------------------------
// The file's channels in the order R, G, B, A, then the others in the file's (alphabetical) order.
std::vector<std::string> ExrChannelOrder(const Imf::ChannelList& list) {
  std::vector<std::string> first, rest;
  for (const char* c : {"R", "G", "B", "A"}) {
    if (list.findChannel(c) != nullptr) first.push_back(c);
  }
  for (auto it = list.begin(); it != list.end(); ++it) {
    const std::string n = it.name();
    if (n != "R" && n != "G" && n != "B" && n != "A") rest.push_back(n);
  }
  first.insert(first.end(), rest.begin(), rest.end());
  return first;
}

DecodedPixels DecodeExr(const fs::path& path, const DecodeLimits& limits) {
  const std::string name = path.string();
  try {
    Imf::InputFile file(name.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const std::vector<std::string> channels = ExrChannelOrder(file.header().channels());
    DecodedPixels out;
    out.type = DecodedPixels::Type::kFloat;
    out.width = dw.max.x - dw.min.x + 1;
    out.height = dw.max.y - dw.min.y + 1;
    out.channels = int(channels.size());
    CheckHeader(name, int64_t(dw.max.x) - dw.min.x + 1, int64_t(dw.max.y) - dw.min.y + 1, out.channels, limits);
    if (limits.header_only) return out;
    out.f.assign(size_t(out.width) * out.height * out.channels, 0.f);
    Imf::FrameBuffer fb;
    const size_t xs = sizeof(float) * out.channels, ys = xs * out.width;
    // The slice's origin is placed so that the data window's first pixel lands on out.f[0].
    char* origin = reinterpret_cast<char*>(out.f.data()) - dw.min.x * ptrdiff_t(xs) - dw.min.y * ptrdiff_t(ys);
    for (int c = 0; c < out.channels; ++c) {
      fb.insert(channels[c], Imf::Slice(Imf::FLOAT, origin + c * sizeof(float), xs, ys));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return out;
  } catch (const std::runtime_error&) {
    throw;
  } catch (const std::exception& e) {
    Fail(name, std::string("cannot read OpenEXR: ") + e.what());
  }
}

std::vector<uint8_t> ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) Fail(path.string(), "cannot open");
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

ImageFormat SniffImageFormat(const uint8_t* b, size_t n) {
  if (n >= 8 && std::memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0) return ImageFormat::kPng;
  if (n >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return ImageFormat::kJpeg;
  if (n >= 12 && std::memcmp(b, "RIFF", 4) == 0 && std::memcmp(b + 8, "WEBP", 4) == 0) return ImageFormat::kWebp;
  if (n >= 4 && (std::memcmp(b, "II*\0", 4) == 0 || std::memcmp(b, "MM\0*", 4) == 0)) return ImageFormat::kTiff;
  if (n >= 4 && std::memcmp(b, "v/1\x01", 4) == 0) return ImageFormat::kExr;
  return ImageFormat::kUnknown;
}

DecodedPixels DecodeImageBytes(const uint8_t* bytes, size_t size, const std::string& name, const DecodeLimits& limits) {
  switch (SniffImageFormat(bytes, size)) {
    case ImageFormat::kPng: return DecodePng(bytes, size, name, limits);
    case ImageFormat::kJpeg: return DecodeJpeg(bytes, size, name, limits);
    case ImageFormat::kWebp: return DecodeWebp(bytes, size, name, limits);
    default: Fail(name, "not a PNG, JPEG or WebP image");
  }
}

DecodedPixels DecodeImageFile(const fs::path& path, const DecodeLimits& limits) {
  const std::string name = path.string();
  if (!fs::exists(path)) Fail(name, "no such file");
  uint8_t head[12] = {};
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) Fail(name, "cannot open");
    in.read(reinterpret_cast<char*>(head), sizeof(head));
    const ImageFormat format = SniffImageFormat(head, size_t(in.gcount()));
    if (format == ImageFormat::kTiff) return DecodeTiff(path, limits);
    if (format == ImageFormat::kExr) return DecodeExr(path, limits);
    if (format == ImageFormat::kUnknown) Fail(name, "cannot read image: not a PNG, JPEG, WebP, TIFF or OpenEXR file");
  }
  const std::vector<uint8_t> bytes = ReadAll(path);
  return DecodeImageBytes(bytes.data(), bytes.size(), name, limits);
}

std::vector<uint8_t> EncodePng(const void* samples, int width, int height, int channels, int bits,
                               const PngSettings& settings, const std::string& name) {
  if (channels < 1 || channels > 4 || (bits != 8 && bits != 16)) {
    Fail(name, "PNG takes 1 to 4 channels of 8 or 16 bits");
  }
  const size_t row_bytes = size_t(width) * channels * (bits / 8);
  std::vector<png_bytep> rows(height);
  const auto* first = static_cast<const uint8_t*>(samples);
  for (int y = 0; y < height; ++y) rows[y] = const_cast<png_bytep>(first + y * row_bytes);
  std::vector<uint8_t> out;
  CodecError error;
  if (!RunPngWrite(rows, width, height, channels, bits, settings, &out, &error)) {
    Fail(name, std::string("cannot encode PNG: ") + error.message);
  }
  return out;
}

std::vector<uint8_t> EncodeJpeg(const uint8_t* samples, int width, int height, int channels,
                                const JpegSettings& settings, const std::string& name) {
  if (channels != 1 && channels != 3) Fail(name, "JPEG takes 1 or 3 channels");
  JpegErrorManager err;
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  const bool ok = RunJpegWrite(samples, width, height, channels, settings, &err, &buffer, &size);
  std::vector<uint8_t> out;
  if (ok) out.assign(buffer, buffer + size);
  std::free(buffer);
  if (!ok) Fail(name, std::string("cannot encode JPEG: ") + err.error.message);
  return out;
}

void WriteExrFile(const fs::path& path, const float* samples, int width, int height, int channels, bool zip) {
  static const char* const kNames[5][4] = {{}, {"Y"}, {}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
  if (channels != 1 && channels != 3 && channels != 4) {
    Fail(path.string(), "OpenEXR is written with 1, 3 or 4 channels");
  }
  try {
    Imf::Header header(width, height);
    header.compression() = zip ? Imf::ZIP_COMPRESSION : Imf::NO_COMPRESSION;
    header.insert("capDate", Imf::StringAttribute(""));
    for (int c = 0; c < channels; ++c) header.channels().insert(kNames[channels][c], Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(path.c_str(), header);
    Imf::FrameBuffer fb;
    const size_t xs = sizeof(float) * channels;
    for (int c = 0; c < channels; ++c) {
      char* base = reinterpret_cast<char*>(const_cast<float*>(samples) + c);
      fb.insert(kNames[channels][c], Imf::Slice(Imf::FLOAT, base, xs, xs * width));
    }
    file.setFrameBuffer(fb);
    file.writePixels(height);
  } catch (const std::exception& e) {
    Fail(path.string(), std::string("cannot write OpenEXR: ") + e.what());
  }
}

}  // namespace rigsim
