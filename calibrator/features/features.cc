#include "calibrator/features/features.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include "calibrator/features/cpu_path.h"
#include "calibrator/features/keep_freed_memory.h"
#include "calibrator/features/parallel_scope.h"
#include "calibrator/features/semantics.h"
#include "common/param_spec.h"

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

// The detector's own keypoint budget for ORB when the user asks for all keypoints (ORB has no
// "unlimited"; 0 would keep none).
constexpr int kOrbUnlimited = 1000000;

// Keypoint order that does not depend on OpenCV's threading: response, then position, size, angle.
bool StrongerFirst(const cv::KeyPoint& a, const cv::KeyPoint& b) {
  if (a.response != b.response) return a.response > b.response;
  if (a.pt.y != b.pt.y) return a.pt.y < b.pt.y;
  if (a.pt.x != b.pt.x) return a.pt.x < b.pt.x;
  if (a.size != b.size) return a.size < b.size;
  return a.angle < b.angle;
}

// Pixel of a keypoint (nearest, clamped): where its class and mask are read.
std::pair<int, int> PixelOf(const cv::KeyPoint& k, int width, int height) {
  return {std::clamp(static_cast<int>(std::lround(k.pt.x)), 0, width - 1),
          std::clamp(static_cast<int>(std::lround(k.pt.y)), 0, height - 1)};
}

// RootSIFT (Arandjelovic & Zisserman 2012): L1-normalise, then square root element-wise. The
// result has unit L2 norm, since the squares of the roots sum to the L1 norm, 1.
void RootSiftInPlace(float* d, int n) {
  double l1 = 0.0;
  for (int i = 0; i < n; ++i) l1 += std::abs(d[i]);
  if (l1 <= 0.0) return;  // an all-zero histogram stays zero
  for (int i = 0; i < n; ++i) d[i] = static_cast<float>(std::sqrt(std::abs(d[i]) / l1));
}

}  // namespace

std::string_view FeatureTypeName(FeatureType type) {
  switch (type) {
    case FeatureType::kSift: return "sift";
    case FeatureType::kRootSift: return "rootsift";
    case FeatureType::kOrb: return "orb";
    case FeatureType::kAkaze: return "akaze";
  }
  throw std::invalid_argument("FeatureTypeName: invalid feature type " + std::to_string(static_cast<int>(type)));
}

FeatureType FeatureTypeFromName(std::string_view name) {
  for (FeatureType t : kAllFeatureTypes) {
    if (FeatureTypeName(t) == name) return t;
  }
  throw std::invalid_argument("unknown feature type '" + std::string(name) + "' (accepted: " +
                              JoinNames(NamesOf(kAllFeatureTypes, FeatureTypeName)) + ")");
}

FeatureSet FeatureSet::Head(int n) const {
  if (n < 0) throw std::invalid_argument("FeatureSet::Head: n must be >= 0");
  FeatureSet out = *this;
  if (size() <= n) return out;
  out.keypoints.resize(n);
  if (kind == DescriptorKind::kBinary) {
    out.binary_descriptors.resize(size_t(n) * descriptor_size);
  } else {
    out.descriptors.resize(size_t(n) * descriptor_size);
  }
  return out;
}

void FeatureOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("FeatureOptions: " + why); };
  FeatureTypeName(type);  // throws on a value outside the enum
  if (max_features < 0) fail("max_features must be >= 0");
  if (octave_layers < 1) fail("octave_layers must be >= 1");
  if (!(contrast_threshold > 0)) fail("contrast_threshold must be > 0");
  if (!(edge_threshold > 0)) fail("edge_threshold must be > 0");
  if (!(sigma > 0)) fail("sigma must be > 0");
  if (mask_erosion_px < 0) fail("mask_erosion_px must be >= 0");
  if (orb_fast_threshold < 1 || orb_fast_threshold > 255) fail("orb_fast_threshold must be in [1, 255]");
  if (!(akaze_threshold > 0)) fail("akaze_threshold must be > 0");
}

FeatureSet DetectFeatures(const ImageU8& rgb, const ImageU8* labels, const FeatureOptions& options,
                          const LabelIdSet* detect_only_on, const ImageU8* rig_mask) {
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
  if (rig_mask != nullptr && (rig_mask->channels != 1 || !rig_mask->SameSize(rgb.width, rgb.height))) {
    throw std::invalid_argument("DetectFeatures: the rig mask must have 1 channel and the image's size");
  }

  UseOpenCvBaselinePaths();
  // Every detector gets 8-bit grey (AKAZE requires one channel; SIFT and ORB convert anyway).
  const cv::Mat grey = GreyFromImage(rgb);
  cv::Mat mask;
  ImageU8 mask_img;
  if (detect_only_on != nullptr) mask_img = ReliableMask(*labels, *detect_only_on, options.mask_erosion_px);
  // SIFT and AKAZE detect everywhere and then drop what lies outside the mask they are given
  // (OpenCV's KeyPointsFilter::runByPixelsMask), so the rig mask is applied below, where what it
  // drops is counted. ORB spends its budget level by level inside its mask: it gets the rig mask.
  const bool orb = options.type == FeatureType::kOrb;
  if (rig_mask != nullptr && orb) {
    if (mask_img.empty()) {
      mask_img = *rig_mask;
    } else {
      for (size_t i = 0; i < mask_img.data.size(); ++i) {
        if (rig_mask->data[i] == 0) mask_img.data[i] = 0;
      }
    }
  }
  if (!mask_img.empty()) mask = cv::Mat(mask_img.height, mask_img.width, CV_8UC1, mask_img.data.data());
  const ImageU8* drop_by_rig_mask = orb ? nullptr : rig_mask;

  const bool sift_like = options.type == FeatureType::kSift || options.type == FeatureType::kRootSift;
  std::vector<cv::KeyPoint> kps;
  cv::Mat all_desc;  // descriptors of every detected keypoint, row i for kps[i]
  int descriptor_size = 0;
  if (sift_like) {
    // detectAndCompute builds the scale space once (detect, then compute for the kept keypoints,
    // built it twice). Without a mask, OpenCV keeps the strongest max_features (and any tied with
    // the last) before computing descriptors: the same keypoints as keeping them below, without
    // computing the descriptors of the rest. With a mask, OpenCV would keep the strongest
    // before masking, which leaves fewer than max_features, so every keypoint is computed, masked,
    // and the strongest kept below (the rig mask likewise).
    const int opencv_budget = mask.empty() && drop_by_rig_mask == nullptr ? options.max_features : 0;
    cv::Ptr<cv::SIFT> sift = cv::SIFT::create(opencv_budget, options.octave_layers, options.contrast_threshold,
                                              options.edge_threshold, options.sigma);
    sift->detectAndCompute(grey, mask, kps, all_desc);
    descriptor_size = sift->descriptorSize();
    // OpenCV 4.6's SIFT doubles the image with a pixel-centre-aligned resize but reports positions
    // as if it had mapped x to 2x, so every keypoint comes out 0.25 px right of and below its
    // feature (opencv/opencv#23123; DetectFeatures.KeypointsAreEquivariantUnderA180DegreeRotation
    // measures it). Uncorrected, it acts like a principal point off by a quarter pixel.
    for (cv::KeyPoint& k : kps) k.pt -= cv::Point2f(0.25f, 0.25f);
  } else if (options.type == FeatureType::kOrb) {
    // ORB masks each pyramid level before keeping its share of nfeatures, so the budget is spent
    // inside the mask. detectAndCompute builds the pyramid once.
    cv::Ptr<cv::ORB> orb =
        cv::ORB::create(options.max_features > 0 ? options.max_features : kOrbUnlimited, 1.2f, 8, 31, 0, 2,
                        cv::ORB::HARRIS_SCORE, 31, options.orb_fast_threshold);
    orb->detectAndCompute(grey, mask, kps, all_desc);
    descriptor_size = orb->descriptorSize();
  } else {
    // OpenCV 4.6's AKAZE has no keypoint limit: detect all in the mask and keep the strongest
    // below. detectAndCompute, because detect then compute would build the scale space twice.
    cv::Ptr<cv::AKAZE> akaze = cv::AKAZE::create(cv::AKAZE::DESCRIPTOR_MLDB, 0, 3,
                                                 static_cast<float>(options.akaze_threshold), 4, 4,
                                                 cv::KAZE::DIFF_PM_G2);
    akaze->detectAndCompute(grey, mask, kps, all_desc);
    descriptor_size = akaze->descriptorSize();
  }
  if (!kps.empty() && (all_desc.rows != static_cast<int>(kps.size()) || all_desc.cols != descriptor_size ||
                       all_desc.type() != (sift_like ? CV_32F : CV_8U))) {
    throw std::runtime_error("DetectFeatures: OpenCV returned " + std::to_string(all_desc.rows) + "x" +
                             std::to_string(all_desc.cols) + " descriptors for " + std::to_string(kps.size()) +
                             " keypoints of " + std::to_string(descriptor_size) + " elements");
  }

  // Candidates: inside the mask at the keypoint's own pixel (ORB masks its downscaled levels, so
  // a keypoint scaled back to full resolution can land just outside), strongest first.
  std::vector<int> order;
  order.reserve(kps.size());
  int removed_by_mask = 0;
  for (int i = 0; i < static_cast<int>(kps.size()); ++i) {
    if (!mask.empty()) {
      const auto [x, y] = PixelOf(kps[i], mask_img.width, mask_img.height);
      if (mask_img.at(x, y) == 0) continue;
    }
    if (drop_by_rig_mask != nullptr) {
      const auto [x, y] = PixelOf(kps[i], drop_by_rig_mask->width, drop_by_rig_mask->height);
      if (drop_by_rig_mask->at(x, y) == 0) {
        ++removed_by_mask;
        continue;
      }
    }
    order.push_back(i);
  }
  std::sort(order.begin(), order.end(), [&](int i, int j) { return StrongerFirst(kps[i], kps[j]); });
  if (options.max_features > 0 && static_cast<int>(order.size()) > options.max_features) {
    order.resize(options.max_features);
  }
  std::vector<cv::KeyPoint> kept;
  kept.reserve(order.size());
  for (int i : order) kept.push_back(kps[i]);

  FeatureSet out;
  out.descriptor_size = descriptor_size;
  out.removed_by_mask = removed_by_mask;
  if (sift_like) {
    out.kind = DescriptorKind::kFloat;
    out.descriptors.resize(kept.size() * size_t(descriptor_size));
    for (size_t r = 0; r < order.size(); ++r) {
      float* row = out.descriptors.data() + r * descriptor_size;
      std::copy_n(all_desc.ptr<float>(order[r]), descriptor_size, row);
      if (options.type == FeatureType::kRootSift) RootSiftInPlace(row, descriptor_size);
    }
  } else {
    out.kind = DescriptorKind::kBinary;
    out.binary_descriptors.resize(kept.size() * size_t(descriptor_size));
    for (size_t r = 0; r < order.size(); ++r) {
      std::copy_n(all_desc.ptr<uint8_t>(order[r]), descriptor_size, out.binary_descriptors.data() + r * descriptor_size);
    }
  }

  out.keypoints.reserve(kept.size());
  for (const cv::KeyPoint& k : kept) {
    Keypoint kp;
    kp.px = Eigen::Vector2d(k.pt.x, k.pt.y);
    kp.size = k.size;
    kp.angle = k.angle;
    if (labels != nullptr) {
      const auto [x, y] = PixelOf(k, labels->width, labels->height);
      kp.class_id = labels->at(x, y);
    }
    out.keypoints.push_back(kp);
  }
  return out;
}

std::vector<std::vector<FeatureSet>> DetectFeaturesInImages(int num_images,
                                                           const std::function<LabelledImage(int)>& load,
                                                           const FeatureOptions& options,
                                                           const std::vector<const LabelIdSet*>& detect_only_on,
                                                           int num_threads, std::vector<std::vector<double>>* time_s,
                                                           const std::function<void(int done)>& images_done) {
  options.Check();
  const size_t kinds = detect_only_on.size();
  std::vector<std::vector<FeatureSet>> out(kinds, std::vector<FeatureSet>(std::max(num_images, 0)));
  if (time_s) time_s->assign(kinds, std::vector<double>(std::max(num_images, 0), 0.0));
  const ParallelScope parallel(num_threads);
  const KeepFreedMemory keep_freed_memory;  // each image's scale space reuses the last one's memory
  std::mutex done_mutex;
  int done = 0;
  tbb::parallel_for(0, num_images, [&](int i) {
    const LabelledImage image = load(i);
    for (size_t k = 0; k < kinds; ++k) {
      const auto start = std::chrono::steady_clock::now();
      out[k][i] = DetectFeatures(image.rgb, image.labels.empty() ? nullptr : &image.labels, options, detect_only_on[k],
                                 image.rig_mask);
      if (time_s) (*time_s)[k][i] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    if (images_done) {
      const std::lock_guard<std::mutex> lock(done_mutex);
      images_done(++done);
    }
  });
  return out;
}

}  // namespace rigsim
