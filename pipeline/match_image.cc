#include "pipeline/match_image.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace rigsim {

namespace {

// Text with a dark outline, readable over any photo.
void Label(cv::Mat& canvas, const std::string& text, cv::Point at, const cv::Scalar& colour, double scale) {
  const int thick = std::max(1, int(std::lround(2 * scale)));
  cv::putText(canvas, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0), thick + 2, cv::LINE_AA);
  cv::putText(canvas, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, thick, cv::LINE_AA);
}

const cv::Scalar kRight(60, 230, 60), kWrong(255, 50, 50), kUnknown(200, 200, 200);  // RGB

}  // namespace

ImageU8 DrawMatches(const ImageU8& a, const ImageU8& b, const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& points,
                    const MatchImageOptions& options, const MatchAnnotation& annotation) {
  for (const ImageU8* image : {&a, &b}) {
    if (image->empty() || image->channels != 3) throw std::invalid_argument("DrawMatches: images must be non-empty RGB");
  }
  const bool verdicts = !annotation.correct.empty();
  if (verdicts && annotation.correct.size() != points.size()) {
    throw std::invalid_argument("DrawMatches: one verdict per match needed");
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
    const size_t index = k * n / drawn;
    const auto& [pa, pb] = points[index];
    cv::Scalar colour;
    if (verdicts) {
      colour = annotation.correct[index] > 0 ? kRight : annotation.correct[index] == 0 ? kWrong : kUnknown;
    } else {
      // Hue by the keypoint's height in the first image, so crossing lines stand apart.
      const double hue = 179.0 * std::clamp(pa.y() / std::max(1, a.height), 0.0, 1.0);
      cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(hue, 255, 255)), rgb;
      cv::cvtColor(hsv, rgb, cv::COLOR_HSV2RGB);
      const cv::Vec3b c = rgb.at<cv::Vec3b>(0, 0);
      colour = cv::Scalar(c[0], c[1], c[2]);
    }
    const cv::Point qa = to_canvas(pa, 0), qb = to_canvas(pb, sa.cols);
    cv::line(canvas, qa, qb, colour, 1, cv::LINE_AA, kShift);
    cv::circle(canvas, qa, 3 << kShift, colour, 1, cv::LINE_AA, kShift);
    cv::circle(canvas, qb, 3 << kShift, colour, 1, cv::LINE_AA, kShift);
  }
  // Names over the photos, a legend at the bottom left.
  const double text_scale = std::clamp(canvas.rows / 700.0, 0.4, 1.0);
  const int line_height = int(std::lround(30 * text_scale));
  if (!annotation.name_a.empty()) Label(canvas, annotation.name_a, {8, line_height}, cv::Scalar(255, 255, 255), text_scale);
  if (!annotation.name_b.empty()) Label(canvas, annotation.name_b, {sa.cols + 8, line_height}, cv::Scalar(255, 255, 255), text_scale);
  if (!annotation.name_a.empty() || verdicts) {
    std::vector<std::pair<std::string, cv::Scalar>> legend;
    const std::string of = drawn < n ? " (" + std::to_string(drawn) + " of " + std::to_string(n) + " drawn)" : "";
    if (verdicts) {
      const auto count = [&](int v) { return std::count(annotation.correct.begin(), annotation.correct.end(), v); };
      legend.push_back({"two-view inliers" + of + ":", cv::Scalar(255, 255, 255)});
      legend.push_back({"right by the ground truth: " + std::to_string(count(1)), kRight});
      legend.push_back({"wrong by the ground truth: " + std::to_string(count(0)), kWrong});
      if (count(-1) > 0) legend.push_back({"not checked (no depth): " + std::to_string(count(-1)), kUnknown});
    } else {
      legend.push_back({"two-view inliers" + of + ", coloured by height", cv::Scalar(255, 255, 255)});
    }
    int y = canvas.rows - 8 - line_height * int(legend.size() - 1);
    for (const auto& [text, colour] : legend) {
      Label(canvas, text, {8, y}, colour, text_scale * 0.8);
      y += line_height;
    }
  }
  ImageU8 out(canvas.cols, canvas.rows, 3);
  std::copy(canvas.datastart, canvas.dataend, out.data.begin());
  return out;
}

}  // namespace rigsim
