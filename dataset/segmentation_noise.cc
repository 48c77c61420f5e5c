#include "dataset/segmentation_noise.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "common/splitmix64.h"
#include "labels/cityscapes.h"

namespace rigsim {
namespace {

// Streams of random numbers, so that the choices of one step never depend on those of another.
enum Salt : uint64_t { kCellJitter = 1, kConfusion = 2, kConfusedClass = 3, kClassBias = 4, kBoundaryWobble = 5 };

uint64_t Hash(uint64_t seed, uint64_t salt, uint64_t a, uint64_t b = 0, uint64_t c = 0) {
  return SplitMix64(SplitMix64(SplitMix64(SplitMix64(seed) ^ salt) ^ a) ^ (b * 0xD1B54A32D192ED03ull + c));
}

// Uniform in [0, 1).
double Uniform(uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

uint64_t Fnv1a(std::string_view s) {
  uint64_t h = 0xCBF29CE484222325ull;
  for (unsigned char ch : s) {
    h ^= ch;
    h *= 0x100000001B3ull;
  }
  return h;
}

// Superpixel of every pixel: index of the nearest jittered cell centre.
std::vector<int> Superpixels(int width, int height, int cell, uint64_t image_seed) {
  const int nx = width / cell + 1, ny = height / cell + 1;
  std::vector<double> cx(size_t(nx) * ny), cy(size_t(nx) * ny);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const size_t k = size_t(j) * nx + i;
      const double jx = 0.9 * (Uniform(Hash(image_seed, kCellJitter, k, 0)) - 0.5);
      const double jy = 0.9 * (Uniform(Hash(image_seed, kCellJitter, k, 1)) - 0.5);
      cx[k] = (i + 0.5 + jx) * cell;
      cy[k] = (j + 0.5 + jy) * cell;
    }
  }
  std::vector<int> out(size_t(width) * height);
  for (int y = 0; y < height; ++y) {
    const int cj = y / cell;
    for (int x = 0; x < width; ++x) {
      const int ci = x / cell;
      double best = 1e300;
      int best_k = 0;
      for (int j = std::max(0, cj - 1); j <= std::min(ny - 1, cj + 1); ++j) {
        for (int i = std::max(0, ci - 1); i <= std::min(nx - 1, ci + 1); ++i) {
          const int k = j * nx + i;
          const double d = (x - cx[k]) * (x - cx[k]) + (y - cy[k]) * (y - cy[k]);
          if (d < best) {
            best = d;
            best_k = k;
          }
        }
      }
      out[size_t(y) * width + x] = best_k;
    }
  }
  return out;
}

// Growth of one class over the image: g(x, y) in [-amplitude, amplitude], half a constant bias of
// the class, half smooth value noise on a grid of `kWobbleCell` pixels.
class ClassGrowth {
 public:
  static constexpr int kWobbleCell = 32;

  ClassGrowth(uint64_t image_seed, uint8_t id, int width, int height, double amplitude)
      : nx_(width / kWobbleCell + 2), amplitude_(amplitude) {
    bias_ = 2.0 * Uniform(Hash(image_seed, kClassBias, id)) - 1.0;
    const int ny = height / kWobbleCell + 2;
    corners_.resize(size_t(nx_) * ny);
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx_; ++i) {
        corners_[size_t(j) * nx_ + i] = 2.0 * Uniform(Hash(image_seed, kBoundaryWobble, id, uint64_t(i), uint64_t(j))) - 1.0;
      }
    }
  }

  double At(int x, int y) const {
    const int i = x / kWobbleCell, j = y / kWobbleCell;
    double fx = double(x % kWobbleCell) / kWobbleCell, fy = double(y % kWobbleCell) / kWobbleCell;
    fx = fx * fx * (3 - 2 * fx);
    fy = fy * fy * (3 - 2 * fy);
    auto c = [&](int di, int dj) { return corners_[size_t(j + dj) * nx_ + (i + di)]; };
    const double a = c(0, 0) + fx * (c(1, 0) - c(0, 0));
    const double b = c(0, 1) + fx * (c(1, 1) - c(0, 1));
    return amplitude_ * (0.5 * bias_ + 0.5 * (a + fy * (b - a)));
  }

 private:
  int nx_;
  double amplitude_;
  double bias_ = 0.0;
  std::vector<double> corners_;
};

void RelabelConfusedBlobs(ImageU8& labels, double rate, int blob_size_px, uint64_t image_seed) {
  const LabelBlobs blobs = FindLabelBlobs(labels, blob_size_px, image_seed);
  std::vector<uint8_t> new_class(blobs.blob_class);
  for (int b = 0; b < blobs.count(); ++b) {
    const auto confusable = ConfusableClasses(blobs.blob_class[b]);
    if (confusable.empty()) continue;
    if (Uniform(Hash(image_seed, kConfusion, uint64_t(b))) >= rate) continue;
    new_class[b] = confusable[Hash(image_seed, kConfusedClass, uint64_t(b)) % confusable.size()];
  }
  for (size_t i = 0; i < labels.data.size(); ++i) labels.data[i] = new_class[blobs.blob_of_pixel[i]];
}

ImageU8 ShiftBoundaries(const ImageU8& labels, int boundary_px, uint64_t image_seed) {
  const int w = labels.width, h = labels.height, n = boundary_px;
  // Pixels with a 4-neighbour of another class, and their integral image: a pixel with another
  // class within distance n has such a pixel within the (2n+1)^2 box around it.
  std::vector<int> integral(size_t(w + 1) * (h + 1), 0);
  for (int y = 0; y < h; ++y) {
    int row = 0;
    for (int x = 0; x < w; ++x) {
      const uint8_t l = labels.at(x, y);
      const bool edge = (x > 0 && labels.at(x - 1, y) != l) || (x + 1 < w && labels.at(x + 1, y) != l) ||
                        (y > 0 && labels.at(x, y - 1) != l) || (y + 1 < h && labels.at(x, y + 1) != l);
      row += edge;
      integral[size_t(y + 1) * (w + 1) + x + 1] = integral[size_t(y) * (w + 1) + x + 1] + row;
    }
  }
  auto edges_in_box = [&](int x, int y) {
    const int x0 = std::max(0, x - n), x1 = std::min(w, x + n + 1), y0 = std::max(0, y - n), y1 = std::min(h, y + n + 1);
    return integral[size_t(y1) * (w + 1) + x1] - integral[size_t(y0) * (w + 1) + x1] -
           integral[size_t(y1) * (w + 1) + x0] + integral[size_t(y0) * (w + 1) + x0];
  };

  // Offsets of the disc of radius n, nearest first.
  struct Offset {
    int dx, dy;
    double d;
  };
  std::vector<Offset> disc;
  for (int dy = -n; dy <= n; ++dy) {
    for (int dx = -n; dx <= n; ++dx) {
      if ((dx || dy) && dx * dx + dy * dy <= n * n) disc.push_back({dx, dy, std::sqrt(double(dx * dx + dy * dy))});
    }
  }
  std::stable_sort(disc.begin(), disc.end(), [](const Offset& a, const Offset& b) { return a.d < b.d; });

  // Growths in [-(n+1)/2, (n+1)/2]: a difference of up to n + 1, so that a shift of the full n
  // whole pixels occurs; the disc caps it at n.
  const double amplitude = 0.5 * (n + 1);
  std::array<std::unique_ptr<ClassGrowth>, 256> growth;
  auto growth_of = [&](uint8_t id) -> const ClassGrowth& {
    if (!growth[id]) growth[id] = std::make_unique<ClassGrowth>(image_seed, id, w, h, amplitude);
    return *growth[id];
  };

  ImageU8 out = labels;
  std::array<bool, 256> seen{};
  std::vector<uint8_t> touched;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (edges_in_box(x, y) == 0) continue;
      const uint8_t own = labels.at(x, y);
      double best = -growth_of(own).At(x, y);
      uint8_t best_class = own;
      for (const Offset& o : disc) {
        if (o.d - amplitude >= best) break;  // no farther class can win
        const int qx = x + o.dx, qy = y + o.dy;
        if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
        const uint8_t c = labels.at(qx, qy);
        if (c == own || seen[c]) continue;
        seen[c] = true;
        touched.push_back(c);
        const double score = o.d - growth_of(c).At(x, y);
        if (score < best) {
          best = score;
          best_class = c;
        }
      }
      for (uint8_t c : touched) seen[c] = false;
      touched.clear();
      out.at(x, y) = best_class;
    }
  }
  return out;
}

}  // namespace

void SegmentationNoiseOptions::Check() const {
  if (boundary_px < 0 || boundary_px > 64) {
    throw std::invalid_argument("segmentation noise: boundary_px must be in [0, 64], got " + std::to_string(boundary_px));
  }
  if (!(confusion_rate >= 0.0 && confusion_rate <= 1.0)) {
    throw std::invalid_argument("segmentation noise: confusion_rate must be in [0, 1], got " +
                                std::to_string(confusion_rate));
  }
  if (blob_size_px < 4 || blob_size_px > 4096) {
    throw std::invalid_argument("segmentation noise: blob_size_px must be in [4, 4096], got " +
                                std::to_string(blob_size_px));
  }
}

uint64_t SegmentationNoiseImageSeed(uint64_t seed, std::string_view camera, std::string_view frame) {
  return SplitMix64(SplitMix64(SplitMix64(seed) ^ Fnv1a(camera)) ^ Fnv1a(frame));
}

LabelBlobs FindLabelBlobs(const ImageU8& labels, int blob_size_px, uint64_t image_seed) {
  if (labels.channels != 1) throw std::invalid_argument("FindLabelBlobs: label image must have 1 channel");
  if (blob_size_px < 1) throw std::invalid_argument("FindLabelBlobs: blob_size_px must be positive");
  const int w = labels.width, h = labels.height;
  const std::vector<int> cell = Superpixels(w, h, blob_size_px, image_seed);
  LabelBlobs blobs;
  blobs.blob_of_pixel.assign(size_t(w) * h, -1);
  std::vector<size_t> stack;
  for (size_t start = 0; start < blobs.blob_of_pixel.size(); ++start) {
    if (blobs.blob_of_pixel[start] >= 0) continue;
    const int id = blobs.count();
    const uint8_t cls = labels.data[start];
    blobs.blob_class.push_back(cls);
    blobs.blob_of_pixel[start] = id;
    stack.push_back(start);
    while (!stack.empty()) {
      const size_t p = stack.back();
      stack.pop_back();
      const int x = int(p % w), y = int(p / w);
      auto visit = [&](int qx, int qy) {
        if (qx < 0 || qy < 0 || qx >= w || qy >= h) return;
        const size_t q = size_t(qy) * w + qx;
        if (blobs.blob_of_pixel[q] >= 0 || labels.data[q] != cls || cell[q] != cell[p]) return;
        blobs.blob_of_pixel[q] = id;
        stack.push_back(q);
      };
      visit(x - 1, y);
      visit(x + 1, y);
      visit(x, y - 1);
      visit(x, y + 1);
    }
  }
  return blobs;
}

ImageU8 ApplySegmentationNoise(const ImageU8& labels, const SegmentationNoiseOptions& options, uint64_t image_seed) {
  options.Check();
  if (labels.channels != 1) throw std::invalid_argument("segmentation noise: label image must have 1 channel");
  ImageU8 out = labels;
  if (options.confusion_rate > 0.0) RelabelConfusedBlobs(out, options.confusion_rate, options.blob_size_px, image_seed);
  if (options.boundary_px > 0) out = ShiftBoundaries(out, options.boundary_px, image_seed);
  return out;
}

ImageU8 ApplySegmentationNoise(const ImageU8& labels, const SegmentationNoiseOptions& options, std::string_view camera,
                               std::string_view frame) {
  return ApplySegmentationNoise(labels, options, SegmentationNoiseImageSeed(options.seed, camera, frame));
}

}  // namespace rigsim
