// How likely a model's inliers are by chance: the a contrario test of Moisan and Stival's ORSA
// (and of AC-RANSAC), which weighs k inliers among n matches by how easily a match that means
// nothing falls within the inlier threshold in the image area the matches occupy. A fixed count
// of inliers cannot: 20 inliers of 100 matches are strong evidence, 30 of 3000 are what RANSAC
// finds between views that share nothing.
#pragma once

#include <functional>

namespace rigsim {

// log10 of the number of false alarms: the number of models RANSAC can form from `n` matches with
// samples of `sample_size` (C(n, sample_size)), times the probability that the other n -
// sample_size matches, each within the threshold with probability `p`, give k - sample_size
// inliers or more. Below 0 (fewer than one such model expected by chance), the inliers are
// meaningful. k <= sample_size gives log10 C(n, sample_size): nothing beyond the sample agrees.
double Log10FalseAlarms(int n, int k, double p, int sample_size);

// The chance that a match that means nothing lies within the inlier threshold: `residual(i, j)`
// pairs the i-th match's first point with the j-th's second (j != i), which breaks any true
// correspondence but keeps where in the images the keypoints are (clustered on texture, not
// uniform). Up to `samples` pairs drawn with a fixed seed; (hits + 1) / (samples + 1), so never 0.
double ChanceWithinThreshold(int n, const std::function<double(int, int)>& residual, double threshold,
                             int samples = 20000);

}  // namespace rigsim
