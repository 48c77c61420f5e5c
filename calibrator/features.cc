#include "calibrator/features.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "calibrator/semantics.h"

namespace rigsim {
namespace {

cv::Mat GreyFromImage(const ImageU8& img) {
  // cv::Mat over our buffer (no copy); cvtColor writes a new one.
  cv::Mat src(img.height, img.width, CV_8UC(img.channels), const_cast<uint8_t*>(img.data.data()));
  cv::Mat grey;
  switch (img.channels) {
    case 1: grey = src.clone(); break;
    case 3: cv::cvtColor(src, grey, cv::COLOR_RGB2GRAY); break;
    case 4: cv::cvtColor(src, grey, cv::COLOR_RGBA2GRAY); break;
    default: throw std::invalid_argument("DetectFeatures: image has " + std::to_string(img.channels) + " channels");
  }
  return grey;
}

}  // namespace

void FeatureOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("FeatureOptions: " + why); };
  if (max_features < 0) fail("max_features must be >= 0");
  if (octave_layers < 1) fail("octave_layers must be >= 1");
  if (!(contrast_threshold > 0)) fail("contrast_threshold must be > 0");
  if (!(edge_threshold > 0)) fail("edge_threshold must be > 0");
  if (!(sigma > 0)) fail("sigma must be > 0");
  if (mask_erosion_px < 0) fail("mask_erosion_px must be >= 0");
}

FeatureSet DetectFeatures(const ImageU8& rgb, const ImageU8* labels, const FeatureOptions& options,
                          const ReliableClasses* detect_only_on) {
  options.Check();
  if (rgb.empty()) throw std::invalid_argument("DetectFeatures: empty image");
  if (labels != nullptr) {
    if (labels->channels != 1 || !labels->SameSize(rgb.width, rgb.height)) {
      throw std::invalid_argument("DetectFeatures: label image must have 1 channel and the image's size");
    }
  }
  if (detect_only_on != nullptr && labels == nullptr) {
    throw std::invalid_argument("DetectFeatures: detection on reliable classes needs a label image");
  }

  const cv::Mat grey = GreyFromImage(rgb);
  cv::Mat mask;
  ImageU8 mask_img;
  if (detect_only_on != nullptr) {
    mask_img = ReliableMask(*labels, *detect_only_on, options.mask_erosion_px);
    mask = cv::Mat(mask_img.height, mask_img.width, CV_8UC1, mask_img.data.data());
  }

  // OpenCV's SIFT applies its mask *after* keeping the nfeatures best keypoints, which would
  // spend the budget on masked-out regions. So detect without a limit, mask, keep the best here,
  // and only then compute descriptors (for the kept keypoints only).
  cv::Ptr<cv::SIFT> sift = cv::SIFT::create(0, options.octave_layers, options.contrast_threshold,
                                            options.edge_threshold, options.sigma);
  std::vector<cv::KeyPoint> kps;
  sift->detect(grey, kps, mask);

  // Deterministic order whatever OpenCV's threading: response, then position, size, angle.
  std::vector<int> order(kps.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int i, int j) {
    const cv::KeyPoint& a = kps[i];
    const cv::KeyPoint& b = kps[j];
    if (a.response != b.response) return a.response > b.response;
    if (a.pt.y != b.pt.y) return a.pt.y < b.pt.y;
    if (a.pt.x != b.pt.x) return a.pt.x < b.pt.x;
    if (a.size != b.size) return a.size < b.size;
    return a.angle < b.angle;
  });
  if (options.max_features > 0 && static_cast<int>(order.size()) > options.max_features) {
    order.resize(options.max_features);
  }
  std::vector<cv::KeyPoint> kept;
  kept.reserve(order.size());
  for (int i : order) kept.push_back(kps[i]);

  cv::Mat desc;
  if (!kept.empty()) sift->compute(grey, kept, desc);
  if (desc.rows != static_cast<int>(kept.size())) {
    throw std::runtime_error("DetectFeatures: OpenCV returned " + std::to_string(desc.rows) + " descriptors for " +
                             std::to_string(kept.size()) + " keypoints");
  }

  FeatureSet out;
  out.descriptor_size = sift->descriptorSize();
  out.keypoints.reserve(kept.size());
  out.descriptors.resize(kept.size() * size_t(out.descriptor_size));
  if (!kept.empty()) {
    cv::Mat desc_f;
    desc.convertTo(desc_f, CV_32F);
    for (int r = 0; r < desc_f.rows; ++r) {
      std::copy_n(desc_f.ptr<float>(r), out.descriptor_size, out.descriptors.data() + size_t(r) * out.descriptor_size);
    }
  }
  for (const cv::KeyPoint& k : kept) {
    Keypoint kp;
    kp.px = Eigen::Vector2d(k.pt.x, k.pt.y);
    kp.size = k.size;
    kp.angle = k.angle;
    if (labels != nullptr) {
      const int x = std::clamp(static_cast<int>(std::lround(k.pt.x)), 0, labels->width - 1);
      const int y = std::clamp(static_cast<int>(std::lround(k.pt.y)), 0, labels->height - 1);
      kp.class_id = labels->at(x, y);
    }
    out.keypoints.push_back(kp);
  }
  return out;
}

}  // namespace rigsim
