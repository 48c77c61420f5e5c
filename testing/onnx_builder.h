// Small ONNX models for the segmentation tests, written byte by byte (the protocol-buffer fields
// of onnx.proto that they use), so that a test controls the network exactly without Python:
//
//   OnnxConvModel m = NearestColourModel({{128, 64, 128}, {70, 70, 70}}, mean, std);  // 2 classes
//   WriteFile(dir / "net.onnx", OnnxModelBytes(m));
//
// The network is one 1x1 convolution from the 3 input channels to C class scores (score_k =
// sum_c weight[k][c] * input_c + bias[k]), optionally followed by an ArgMax over the channels
// (output 1 x 1 x h x w class indices instead of 1 x C x h x w scores). Opset 11, IR version 6.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rigsim {

struct OnnxConvModel {
  std::vector<std::array<float, 3>> weights;  // per class, per input channel
  std::vector<float> bias;                    // per class
  int width = -1, height = -1;                // the declared input size; -1: left open (dim_param)
  bool argmax = false;
};

// The .onnx file's bytes.
std::string OnnxModelBytes(const OnnxConvModel& model);

// A model whose highest score at a pixel is the class whose colour is nearest to the pixel's (in
// the network's RGB input, before normalisation): for input x = (rgb / 255 - mean) / std,
// score_k = 2 p_k . v - |p_k|^2 with v = rgb / 255 and p_k colour k / 255, the nearest colour's
// score being the highest. So a photo painted in those colours segments into those classes.
OnnxConvModel NearestColourModel(const std::vector<std::array<uint8_t, 3>>& colours, const std::array<double, 3>& mean,
                                 const std::array<double, 3>& std);

}  // namespace rigsim
