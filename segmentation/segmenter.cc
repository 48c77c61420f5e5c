#include "segmentation/segmenter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>

#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "segmentation/onnx_model_info.h"

namespace rigsim {
namespace {

constexpr int kDefaultShorterSide = 520;

[[noreturn]] void Fail(SegmenterErrorKind kind, const std::filesystem::path& model, const std::string& what) {
  throw SegmenterError(kind, model.string() + ": " + what);
}

// OpenCV's message on one line, without its "> " continuation marks.
std::string OneLine(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n') {
      if (!out.empty() && out.back() != ' ') out += ' ';
      if (i + 2 < text.size() && text[i + 1] == '>' && text[i + 2] == ' ') i += 2;
    } else if (!(out.empty() && (text[i] == '>' || text[i] == ' '))) {
      out += text[i];
    }
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

std::string SizeText(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

int RoundTo8(double v) { return std::max(8, int(std::lround(v / 8.0)) * 8); }

// OpenCV logs its own line for a network it cannot build or run; the exception carries the same
// and rigsim's message says which file and what to change, so its log is quiet meanwhile.
class QuietOpenCvLog {
 public:
  QuietOpenCvLog() : previous_(cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT)) {}
  ~QuietOpenCvLog() { cv::utils::logging::setLogLevel(previous_); }
  QuietOpenCvLog(const QuietOpenCvLog&) = delete;
  QuietOpenCvLog& operator=(const QuietOpenCvLog&) = delete;

 private:
  cv::utils::logging::LogLevel previous_;
};

}  // namespace

void SegmenterOptions::Check() const {
  auto fail = [](const std::string& what) { throw SegmenterError(SegmenterErrorKind::kBadOptions, what); };
  if ((input_width > 0) != (input_height > 0) || input_width < 0 || input_height < 0) {
    fail("--input-size: give WIDTHxHEIGHT with both above 0, or one number for the shorter side");
  }
  if (input_width > 8192 || input_height > 8192 || shorter_side < 0 || shorter_side > 8192) {
    fail("--input-size: at most 8192 px a side");
  }
  if (input_width > 0 && shorter_side > 0) fail("--input-size: give WIDTHxHEIGHT or the shorter side, not both");
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(mean[c])) fail("--mean: every value must be a finite number");
    if (!std::isfinite(std[c]) || !(std[c] > 0)) fail("--std: every value must be more than 0");
  }
}

struct Segmenter::Network {
  cv::dnn::Net net;
  OnnxModelInfo info;
  int fixed_width = 0, fixed_height = 0;  // the model's own input size, when it declares one
  mutable double inference_seconds = 0.0;
};

Segmenter::Segmenter(const SegmenterOptions& options) : options_(options), net_(std::make_unique<Network>()) {
  options_.Check();
  classes_ = LoadClassTable(options_.classes);
  const std::filesystem::path& model = options_.model;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(model, ec)) Fail(SegmenterErrorKind::kUnreadableModel, model, "no such model file");
  std::ifstream in(model, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) Fail(SegmenterErrorKind::kUnreadableModel, model, "cannot read the model file");
  try {
    net_->info = ParseOnnxModelInfo(std::string_view(bytes.data(), bytes.size()));
  } catch (const std::runtime_error& e) {
    Fail(SegmenterErrorKind::kUnreadableModel, model,
         std::string(e.what()) + "; give a segmentation network exported to ONNX (README, 'Labels from a network')");
  }
  const std::vector<int64_t>& shape = net_->info.input_shape;
  if (shape.size() == 4) {
    if (shape[1] > 0 && shape[1] != 3) {
      Fail(SegmenterErrorKind::kUnreadableModel, model,
           "the network takes " + std::to_string(shape[1]) + " channels per pixel; rigsim gives it a colour photo (3)");
    }
    if (shape[2] > 0 && shape[3] > 0) {
      net_->fixed_width = int(shape[3]);
      net_->fixed_height = int(shape[2]);
    }
  }
  const int fw = net_->fixed_width, fh = net_->fixed_height;
  if (fw > 0 && ((options_.input_width > 0 && (options_.input_width != fw || options_.input_height != fh)) ||
                 options_.shorter_side > 0)) {
    Fail(SegmenterErrorKind::kInputSizeMismatch, model,
         "the model was exported for a " + SizeText(fw, fh) + " input, and --input-size asks for " +
             (options_.shorter_side > 0 ? std::to_string(options_.shorter_side) + " px on the shorter side"
                                        : SizeText(options_.input_width, options_.input_height)) +
             "; leave --input-size out, or export the model for that size or with dynamic height and width");
  }
  try {
    const QuietOpenCvLog quiet;
    net_->net = cv::dnn::readNetFromONNX(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    net_->net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
    net_->net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  } catch (const cv::Exception& e) {
    Fail(SegmenterErrorKind::kUnreadableModel, model,
         "OpenCV " CV_VERSION " cannot build this network (" + OneLine(e.err) +
             "); README, 'Labels from a network', says which exports work and how to make one");
  }
  if (net_->net.empty()) Fail(SegmenterErrorKind::kUnreadableModel, model, "OpenCV built an empty network from it");
}

Segmenter::~Segmenter() = default;

double Segmenter::inference_seconds() const { return net_->inference_seconds; }

std::array<int, 2> Segmenter::InputSize(int width, int height) const {
  if (net_->fixed_width > 0) return {net_->fixed_width, net_->fixed_height};
  if (options_.input_width > 0) return {options_.input_width, options_.input_height};
  const double side = options_.shorter_side > 0 ? options_.shorter_side : kDefaultShorterSide;
  const double scale = side / std::min(width, height);
  return {RoundTo8(width * scale), RoundTo8(height * scale)};
}

ImageU8 Segmenter::Segment(const ImageU8& photo) const {
  if (photo.channels != 3 || photo.empty()) throw std::invalid_argument("Segment: the photo must be RGB");
  const auto [in_w, in_h] = InputSize(photo.width, photo.height);
  // Pre-processing: resize, scale, normalise, planar in the network's channel order.
  const cv::Mat rgb(photo.height, photo.width, CV_8UC3, const_cast<uint8_t*>(photo.data.data()));
  cv::Mat resized;
  const bool shrink = in_w < photo.width && in_h < photo.height;
  cv::resize(rgb, resized, cv::Size(in_w, in_h), 0, 0, shrink ? cv::INTER_AREA : cv::INTER_LINEAR);
  const int blob_shape[] = {1, 3, in_h, in_w};
  cv::Mat blob(4, blob_shape, CV_32F);
  float* planes = blob.ptr<float>();
  for (int c = 0; c < 3; ++c) {
    const int src = options_.channel_order == ChannelOrder::kRgb ? c : 2 - c;
    const float scale = float(1.0 / (255.0 * options_.std[c])), offset = float(-options_.mean[c] / options_.std[c]);
    float* plane = planes + size_t(c) * in_w * in_h;
    for (int y = 0; y < in_h; ++y) {
      const uint8_t* row = resized.ptr<uint8_t>(y);
      for (int x = 0; x < in_w; ++x) plane[size_t(y) * in_w + x] = row[3 * x + src] * scale + offset;
    }
  }

  cv::Mat out;
  const auto start = std::chrono::steady_clock::now();
  try {
    const QuietOpenCvLog quiet;
    net_->net.setInput(blob, net_->info.input_name);
    out = net_->net.forward(net_->info.output_name);
  } catch (const cv::Exception& e) {
    Fail(SegmenterErrorKind::kInputSizeMismatch, options_.model,
         "the network failed on a " + SizeText(in_w, in_h) + " input (" + OneLine(e.err) +
             "); give --input-size WIDTHxHEIGHT as the model was exported, or export it with dynamic height and width");
  }
  net_->inference_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // N x C x h x w scores, or N x h x w (N x 1 x h x w) class indices.
  const int dims = out.dims;
  const bool indices = dims == 3 || (dims == 4 && out.size[1] == 1);
  if ((dims != 3 && dims != 4) || out.size[0] != 1) {
    Fail(SegmenterErrorKind::kClassCountMismatch, options_.model,
         "the network's output has " + std::to_string(dims) + " dimensions; a segmentation network gives 1 x classes x "
         "height x width scores (or 1 x height x width class indices)");
  }
  const int h = out.size[dims - 2], w = out.size[dims - 1];
  const int channels = indices ? 1 : out.size[1];
  if (!indices && channels != classes_.size()) {
    const std::string builtin = BuiltinClassTableWithSize(channels);
    Fail(SegmenterErrorKind::kClassCountMismatch, options_.model,
         "the network gives " + std::to_string(channels) + " class scores per pixel, the class table '" + classes_.name +
             "' has " + std::to_string(classes_.size()) + " classes; " +
             (builtin.empty() ? "give --classes FILE with one line per channel (README, 'Class tables')"
                              : "give --classes " + builtin + " if the network was trained on it, or a class-table file"));
  }
  cv::Mat values;
  out.reshape(1, channels * h).convertTo(values, CV_32F);
  Image<uint16_t> channel_of_pixel;
  if (indices) {
    channel_of_pixel = Image<uint16_t>(photo.width, photo.height, 1);
    for (int y = 0; y < photo.height; ++y) {
      const int sy = std::min(h - 1, int((y + 0.5) * h / photo.height));
      for (int x = 0; x < photo.width; ++x) {
        const int sx = std::min(w - 1, int((x + 0.5) * w / photo.width));
        const float v = values.at<float>(sy, sx);
        if (!(v >= 0) || v >= float(classes_.size()) || v != std::floor(v)) {
          Fail(SegmenterErrorKind::kClassCountMismatch, options_.model,
               "the network gives class index " + std::to_string(v) + ", the class table '" + classes_.name + "' has " +
                   std::to_string(classes_.size()) + " classes (0 to " + std::to_string(classes_.size() - 1) + ")");
        }
        channel_of_pixel.at(x, y) = uint16_t(v);
      }
    }
  } else {
    channel_of_pixel = ArgmaxOfResizedScores(values.ptr<float>(), channels, w, h, photo.width, photo.height);
  }
  ImageU8 labels(photo.width, photo.height, 1);
  for (size_t i = 0; i < labels.data.size(); ++i) labels.data[i] = classes_.label_ids[channel_of_pixel.data[i]];
  return labels;
}

Image<uint16_t> ArgmaxOfResizedScores(const float* scores, int channels, int w, int h, int width, int height) {
  const size_t plane = size_t(w) * h;
  // The class at each score pixel: where the four score pixels around a photo pixel agree, their
  // class wins the interpolation too (a convex combination keeps the order), so only pixels near
  // class boundaries interpolate every channel.
  std::vector<uint16_t> best(plane, 0);
  for (size_t i = 0; i < plane; ++i) {
    float top = scores[i];
    for (int c = 1; c < channels; ++c) {
      if (scores[c * plane + i] > top) {
        top = scores[c * plane + i];
        best[i] = uint16_t(c);
      }
    }
  }
  auto source = [](int x, int n_out, int n_in, int& i0, int& i1, float& f) {
    const double s = std::clamp((x + 0.5) * n_in / n_out - 0.5, 0.0, double(n_in - 1));
    i0 = int(s);
    i1 = std::min(i0 + 1, n_in - 1);
    f = float(s - i0);
  };
  Image<uint16_t> out(width, height, 1);
  for (int y = 0; y < height; ++y) {
    int y0, y1;
    float fy;
    source(y, height, h, y0, y1, fy);
    for (int x = 0; x < width; ++x) {
      int x0, x1;
      float fx;
      source(x, width, w, x0, x1, fx);
      const size_t i00 = size_t(y0) * w + x0, i01 = size_t(y0) * w + x1, i10 = size_t(y1) * w + x0,
                   i11 = size_t(y1) * w + x1;
      const uint16_t b = best[i00];
      if (best[i01] == b && best[i10] == b && best[i11] == b) {
        out.at(x, y) = b;
        continue;
      }
      const float w00 = (1 - fx) * (1 - fy), w01 = fx * (1 - fy), w10 = (1 - fx) * fy, w11 = fx * fy;
      uint16_t arg = 0;
      float top = -std::numeric_limits<float>::infinity();
      for (int c = 0; c < channels; ++c) {
        const float* p = scores + c * plane;
        const float v = w00 * p[i00] + w01 * p[i01] + w10 * p[i10] + w11 * p[i11];
        if (v > top) {
          top = v;
          arg = uint16_t(c);
        }
      }
      out.at(x, y) = arg;
    }
  }
  return out;
}

}  // namespace rigsim
