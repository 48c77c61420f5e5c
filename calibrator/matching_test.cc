#include "calibrator/matching.h"

#include <random>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

constexpr int kDim = 8;

void Add(FeatureSet* f, const std::vector<float>& d, uint8_t cls) {
  f->descriptor_size = kDim;
  Keypoint k;
  k.px = Eigen::Vector2d(f->size(), 0);
  k.class_id = cls;
  f->keypoints.push_back(k);
  f->descriptors.insert(f->descriptors.end(), d.begin(), d.end());
}

std::vector<float> Unit(int axis, float scale = 10.f) {
  std::vector<float> d(kDim, 0.f);
  d[axis] = scale;
  return d;
}

TEST(MatchFeatures, RatioTestRejectsAmbiguousMatches) {
  FeatureSet a, b;
  Add(&a, Unit(0), 0);  // ambiguous: two B descriptors at almost the same distance
  Add(&a, Unit(3), 0);  // distinctive: one B descriptor very close
  std::vector<float> b0 = Unit(0), b1 = Unit(0);
  b0[1] = 1.0f;
  b1[2] = 1.05f;
  Add(&b, b0, 0);
  Add(&b, b1, 0);
  std::vector<float> b2 = Unit(3);
  b2[4] = 0.5f;
  Add(&b, b2, 0);
  MatchStats stats;
  const std::vector<Match> m = MatchFeatures(a, b, MatchOptions(), &stats);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].a, 1);
  EXPECT_EQ(m[0].b, 2);
  EXPECT_NEAR(m[0].distance, 0.5f, 1e-4);
  EXPECT_EQ(stats.distance_evaluations, 6);
  // A looser ratio accepts the ambiguous one too.
  MatchOptions loose;
  loose.ratio = 1.0;
  loose.mutual = false;
  EXPECT_EQ(MatchFeatures(a, b, loose).size(), 2u);
}

TEST(MatchFeatures, MutualCheckKeepsOnlyTheReciprocalPair) {
  FeatureSet a, b;
  std::vector<float> a0 = Unit(0), a1 = Unit(0);
  a1[1] = 1.0f;  // both A keypoints are nearest to b0; b0's nearest is a0
  Add(&a, a0, 0);
  Add(&a, a1, 0);
  Add(&b, Unit(0), 0);
  Add(&b, Unit(5), 0);
  MatchOptions options;
  options.ratio = 0.9;
  const std::vector<Match> m = MatchFeatures(a, b, options);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].a, 0);
  EXPECT_EQ(m[0].b, 0);
  options.mutual = false;
  EXPECT_EQ(MatchFeatures(a, b, options).size(), 2u);
}

TEST(MatchFeatures, GatingNeverPairsDifferentClasses) {
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.f, 1.f);
  const uint8_t classes[] = {7, 11, 21};
  FeatureSet a, b;
  for (int i = 0; i < 300; ++i) {
    std::vector<float> d(kDim);
    for (float& x : d) x = 10.f * noise(rng);
    Add(&a, d, classes[i % 3]);
    for (float& x : d) x += 0.05f * noise(rng);
    // Every third B keypoint has the same descriptor as its A twin but another class.
    Add(&b, d, i % 3 == 0 ? classes[(i + 1) % 3] : classes[i % 3]);
  }
  const std::vector<Match> ungated = MatchFeatures(a, b, MatchOptions());
  int cross = 0;
  for (const Match& m : ungated) cross += a.keypoints[m.a].class_id != b.keypoints[m.b].class_id;
  ASSERT_GT(cross, 50) << "the test must offer cross-class look-alikes";

  MatchOptions gated;
  gated.gate_by_class = true;
  MatchStats gs, us;
  MatchFeatures(a, b, MatchOptions(), &us);
  const std::vector<Match> m = MatchFeatures(a, b, gated, &gs);
  ASSERT_GT(m.size(), 100u);
  for (const Match& x : m) EXPECT_EQ(a.keypoints[x.a].class_id, b.keypoints[x.b].class_id);
  for (size_t i = 1; i < m.size(); ++i) EXPECT_LT(m[i - 1].a, m[i].a);
  EXPECT_LT(gs.distance_evaluations, us.distance_evaluations / 2);
}

TEST(MatchFeatures, BlockingDoesNotChangeTheResult) {
  std::mt19937 rng(11);
  std::normal_distribution<float> noise(0.f, 1.f);
  FeatureSet a, b;
  for (int i = 0; i < 200; ++i) {
    std::vector<float> d(kDim);
    for (float& x : d) x = noise(rng);
    Add(&a, d, 0);
    for (float& x : d) x += 0.1f * noise(rng);
    Add(&b, d, 0);
  }
  MatchOptions small;
  small.block_rows = 7;
  const auto m1 = MatchFeatures(a, b, MatchOptions());
  const auto m2 = MatchFeatures(a, b, small);
  ASSERT_EQ(m1.size(), m2.size());
  for (size_t i = 0; i < m1.size(); ++i) {
    EXPECT_EQ(m1[i].a, m2[i].a);
    EXPECT_EQ(m1[i].b, m2[i].b);
  }
  FeatureSet other;
  Add(&other, std::vector<float>(kDim, 0.f), 0);
  other.descriptor_size = 4;
  other.descriptors.resize(4);
  EXPECT_THROW(MatchFeatures(a, other, MatchOptions()), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
