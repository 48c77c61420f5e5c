#include "calibrator/match_image.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace rigsim {

ImageU8 DrawMatches(const ImageU8& a, const ImageU8& b, const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& points,
                    const MatchImageOptions& options) {
  for (const ImageU8* image : {&a, &b}) {
    if (image->empty() || image->channels != 3) throw std::invalid_argument("DrawMatches: images must be non-empty RGB");
  }
  const double scale = std::min(1.0, double(options.max_width) / double(a.width + b.width));
  auto scaled = [&](const ImageU8& image) {
    cv::Mat m(image.height, image.width, CV_8UC3, const_cast<uint8_t*>(image.data.data()));
    cv::Mat out;
    cv::resize(m, out, cv::Size(std::max(1, int(std::lround(image.width * scale))), std::max(1, int(std::lround(image.height * scale)))),
               0, 0, cv::INTER_AREA);
    return out;
  };
  const cv::Mat sa = scaled(a), sb = scaled(b);
  cv::Mat canvas(std::max(sa.rows, sb.rows), sa.cols + sb.cols, CV_8UC3, cv::Scalar(0, 0, 0));
  sa.copyTo(canvas(cv::Rect(0, 0, sa.cols, sa.rows)));
  sb.copyTo(canvas(cv::Rect(sa.cols, 0, sb.cols, sb.rows)));
  // Pixel centres: (x + 0.5) * scale - 0.5 in the scaled image; cv's drawing takes 4 fractional bits.
  constexpr int kShift = 4;
  auto to_canvas = [&](const Eigen::Vector2d& p, int x_offset) {
    return cv::Point(int(std::lround(((p.x() + 0.5) * scale - 0.5 + x_offset) * (1 << kShift))),
                     int(std::lround(((p.y() + 0.5) * scale - 0.5) * (1 << kShift))));
  };
  const size_t n = points.size(), drawn = std::min(n, size_t(std::max(0, options.max_lines)));
  for (size_t k = 0; k < drawn; ++k) {
    const auto& [pa, pb] = points[k * n / drawn];
    // Hue by the keypoint's height in the first image, so crossing lines stand apart.
    const double hue = 179.0 * std::clamp(pa.y() / std::max(1, a.height), 0.0, 1.0);
    cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(hue, 255, 255)), rgb;
    cv::cvtColor(hsv, rgb, cv::COLOR_HSV2RGB);
    const cv::Vec3b c = rgb.at<cv::Vec3b>(0, 0);
    const cv::Scalar colour(c[0], c[1], c[2]);
    const cv::Point qa = to_canvas(pa, 0), qb = to_canvas(pb, sa.cols);
    cv::line(canvas, qa, qb, colour, 1, cv::LINE_AA, kShift);
    cv::circle(canvas, qa, 3 << kShift, colour, 1, cv::LINE_AA, kShift);
    cv::circle(canvas, qb, 3 << kShift, colour, 1, cv::LINE_AA, kShift);
  }
  ImageU8 out(canvas.cols, canvas.rows, 3);
  std::copy(canvas.datastart, canvas.dataend, out.data.begin());
  return out;
}

}  // namespace rigsim
