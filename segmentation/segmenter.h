// A semantic segmentation network (an ONNX file, run by OpenCV's DNN module on the CPU) turned
// into rigsim label images: Cityscapes label ids (labels/cityscapes.h) at the photo's size.
//
// The photo is resized to the network's input (area averaging when shrinking, bilinear when
// enlarging), scaled to 0..1, normalised per channel ((value - mean) / std) in the channel order
// the network takes, and run. The network's class scores (N x C x h x w) are resized back to the
// photo bilinearly (pixel centres aligned, as torch's interpolate with align_corners=False and
// cv::resize do) and each pixel takes the class of the highest score; a network whose output is
// already the class index per pixel (N x h x w, or N x 1 x h x w, an ArgMax at its end) is resized
// by nearest neighbour. The class table (class_table.h) maps channel k to a Cityscapes id.
//
// The defaults suit torchvision's segmentation models (DeepLabV3, LR-ASPP, FCN) exported to ONNX:
// RGB, ImageNet's mean and std, 520 px on the shorter side when the model leaves its input size
// open. A model exported with a fixed input size is run at that size.
//
// Which CPU code OpenCV runs follows cv::setUseOptimized (rigsim turns its wide-vector paths off
// where the program starts, calibrator/features/cpu_path.h), so the labels are the same on every node.
#pragma once

#include <array>
#include <filesystem>
#include <memory>
#include <string>

#include "geometry/image.h"
#include "segmentation/class_table.h"

namespace rigsim {

enum class ChannelOrder { kRgb, kBgr };

struct SegmenterOptions {
  std::filesystem::path model;      // an .onnx file
  std::string classes = "cityscapes";  // a built-in class table or a class-table file
  // The network's input: width x height when both are > 0; otherwise `shorter_side` px on the
  // photo's shorter side, the other side in proportion, both rounded to a multiple of 8. A model
  // exported with a fixed size takes that size, and refuses another given here.
  int input_width = 0, input_height = 0;
  int shorter_side = 0;  // 0: the model's size when fixed, else 520
  // Per network input channel, in the order it takes them, for values scaled to 0..1 (a network
  // trained on 0..255 values without std: std 1/255 = 0.00392).
  std::array<double, 3> mean = {0.485, 0.456, 0.406};
  std::array<double, 3> std = {0.229, 0.224, 0.225};
  ChannelOrder channel_order = ChannelOrder::kRgb;

  // Throws SegmenterError(kBadOptions) naming the field.
  void Check() const;
};

class Segmenter {
 public:
  // Loads the class table and the model. Throws SegmenterError: kClassTableFile,
  // kUnreadableModel (naming the model file: missing, not ONNX, or OpenCV cannot build it),
  // kInputSizeMismatch (an input size the model was not exported for), kBadOptions.
  explicit Segmenter(const SegmenterOptions& options);
  ~Segmenter();
  Segmenter(const Segmenter&) = delete;
  Segmenter& operator=(const Segmenter&) = delete;

  // Cityscapes label ids, photo.width x photo.height, of an RGB photo (3 channels). Throws
  // SegmenterError: kClassCountMismatch when the network's output does not fit the class table,
  // kInputSizeMismatch when the network refuses the input size (both naming the model file).
  ImageU8 Segment(const ImageU8& photo) const;

  // The network input size used for a photo of `width` x `height`.
  std::array<int, 2> InputSize(int width, int height) const;
  const ClassTable& classes() const { return classes_; }
  const SegmenterOptions& options() const { return options_; }
  // Seconds spent in the network (forward passes) so far.
  double inference_seconds() const;

 private:
  struct Network;
  SegmenterOptions options_;
  ClassTable classes_;
  std::unique_ptr<Network> net_;
};

// The channel (class-table index) of the highest score at every pixel of a `width` x `height`
// image, from `scores` laid out C x h x w: the scores are resized bilinearly (pixel centres
// aligned) and ties go to the lower channel. Exposed for its tests.
Image<uint16_t> ArgmaxOfResizedScores(const float* scores, int channels, int w, int h, int width, int height);

}  // namespace rigsim
