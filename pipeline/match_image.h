// A camera pair's matches drawn for a person: the two images side by side, each match a line
// between its two keypoints. Written by `rigsim calibrate` to <mode>/matches/<cam_a>-<cam_b>.jpg.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "geometry/image.h"

namespace rigsim {

struct MatchImageOptions {
  int max_width = 1600;  // the pair is scaled down (never up) to fit
  int max_lines = 300;   // at most this many matches drawn, spread evenly over the list
};

// What the image says about the pair besides the lines: the cameras' names (written over each
// photo) and, per match, whether the ground truth calls it right (1), wrong (0) or cannot tell
// (-1). With verdicts, right matches are green and wrong ones red, and a legend counts them;
// without (empty), every line is coloured by its height in the first photo.
struct MatchAnnotation {
  std::string name_a, name_b;
  std::vector<signed char> correct;  // one per match, or empty
};

// `a` and `b`: RGB (3 channels). `points`: (pixel in a, pixel in b), OpenCV pixel-centre
// convention. Throws std::invalid_argument for an empty image or one without 3 channels, or
// verdicts that are not one per match.
ImageU8 DrawMatches(const ImageU8& a, const ImageU8& b, const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& points,
                    const MatchImageOptions& options = {}, const MatchAnnotation& annotation = {});

}  // namespace rigsim
