// A camera pair's matches drawn for a person: the two images side by side, each match a line
// between its two keypoints. Written by `rigsim calibrate` to <mode>/matches/<cam_a>-<cam_b>.jpg.
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "dataset/image.h"

namespace rigsim {

struct MatchImageOptions {
  int max_width = 1600;  // the pair is scaled down (never up) to fit
  int max_lines = 300;   // at most this many matches drawn, spread evenly over the list
};

// `a` and `b`: RGB (3 channels). `points`: (pixel in a, pixel in b), OpenCV pixel-centre
// convention. Throws std::invalid_argument for an empty image or one without 3 channels.
ImageU8 DrawMatches(const ImageU8& a, const ImageU8& b, const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& points,
                    const MatchImageOptions& options = {});

}  // namespace rigsim
