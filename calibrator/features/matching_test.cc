#include "calibrator/features/matching.h"

#include <cmath>
#include <limits>
#include <tuple>
#include <random>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "testing/expect_error.h"

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

// Small integer descriptors make distances exact in any summation order and give many ties (equal
// nearest neighbours, a second-best equal to the best): the matcher must equal the obvious scan,
// with ties to the lowest index, for sets smaller and larger than its scan lanes and at any blocking.
TEST(MatchFeatures, L2MatchesEqualThePlainReferenceWithTies) {
  for (const auto& [na, nb, seed] : {std::tuple{300, 347, 5u}, std::tuple{9, 13, 6u}, std::tuple{40, 2, 7u}}) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> value(0, 3);
    FeatureSet a, b;
    auto random_descriptor = [&] {
      std::vector<float> d(kDim);
      for (float& x : d) x = static_cast<float>(value(rng));
      return d;
    };
    for (int i = 0; i < na; ++i) Add(&a, random_descriptor(), 0);
    for (int j = 0; j < nb; ++j) Add(&b, random_descriptor(), 0);
    std::vector<std::vector<double>> d(na, std::vector<double>(nb));
    for (int i = 0; i < na; ++i) {
      for (int j = 0; j < nb; ++j) {
        for (int k = 0; k < kDim; ++k) d[i][j] += std::pow(a.descriptor(i)[k] - b.descriptor(j)[k], 2);
      }
    }
    const double ratio = 0.8;
    std::vector<Match> expected;
    for (int i = 0; i < na; ++i) {
      int best = -1;
      double b1 = std::numeric_limits<double>::infinity(), b2 = b1;
      for (int j = 0; j < nb; ++j) {
        if (d[i][j] < b1) {
          b2 = b1;
          b1 = d[i][j];
          best = j;
        } else if (d[i][j] < b2) {
          b2 = d[i][j];
        }
      }
      if (!(b1 < ratio * ratio * b2)) continue;
      int col_best = 0;
      for (int k = 1; k < na; ++k) col_best = d[k][best] < d[col_best][best] ? k : col_best;
      if (col_best == i) expected.push_back({i, best, static_cast<float>(std::sqrt(b1))});
    }
    for (int block : {1, 7, 1024}) {
      MatchOptions options;
      options.ratio = ratio;
      options.block_rows = block;
      const std::vector<Match> m = MatchFeatures(a, b, options);
      ASSERT_EQ(m.size(), expected.size()) << na << "x" << nb << " block " << block;
      for (size_t k = 0; k < m.size(); ++k) {
        EXPECT_EQ(m[k].a, expected[k].a) << k;
        EXPECT_EQ(m[k].b, expected[k].b) << k;
        EXPECT_EQ(m[k].distance, expected[k].distance) << k;
      }
    }
    if (na == 300) {
      EXPECT_GT(expected.size(), 10u);
    }
  }
}

// --- Binary descriptors (ORB, AKAZE): Hamming distance ----------------------------------------

void AddBinary(FeatureSet* f, const std::vector<uint8_t>& d, uint8_t cls) {
  f->kind = DescriptorKind::kBinary;
  f->descriptor_size = static_cast<int>(d.size());
  Keypoint k;
  k.px = Eigen::Vector2d(f->size(), 0);
  k.class_id = cls;
  f->keypoints.push_back(k);
  f->binary_descriptors.insert(f->binary_descriptors.end(), d.begin(), d.end());
}

// Hamming distance bit by bit: the reference the matcher's word-wise popcount must equal.
int ReferenceHamming(const uint8_t* x, const uint8_t* y, int bytes) {
  int d = 0;
  for (int i = 0; i < bytes; ++i)
    for (int bit = 0; bit < 8; ++bit) d += ((x[i] >> bit) & 1) != ((y[i] >> bit) & 1);
  return d;
}

// A random set, and a copy with a few bits flipped per descriptor (the true matches), shuffled
// with distractors. Sizes of ORB (32 bytes), AKAZE (61: not a whole number of 64-bit words) and odd.
struct BinaryPair {
  FeatureSet a, b;
};

BinaryPair MakeBinaryPair(int bytes, int n, unsigned seed, int num_classes = 1) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> byte(0, 255), bit(0, bytes * 8 - 1), flips(0, bytes * 8 / 6);
  BinaryPair p;
  for (int i = 0; i < n; ++i) {
    std::vector<uint8_t> d(bytes);
    for (uint8_t& x : d) x = static_cast<uint8_t>(byte(rng));
    AddBinary(&p.a, d, static_cast<uint8_t>(i % num_classes));
    for (int k = flips(rng); k > 0; --k) {
      const int b = bit(rng);
      d[b / 8] ^= static_cast<uint8_t>(1 << (b % 8));
    }
    AddBinary(&p.b, d, static_cast<uint8_t>(i % num_classes));
    if (i % 4 == 0) {  // distractor in B
      for (uint8_t& x : d) x = static_cast<uint8_t>(byte(rng));
      AddBinary(&p.b, d, static_cast<uint8_t>(i % num_classes));
    }
  }
  return p;
}

// Brute force written the obvious way: every distance by ReferenceHamming, Lowe's ratio test,
// mutual check, ties to the lowest index.
std::vector<Match> ReferenceMatches(const FeatureSet& a, const FeatureSet& b, double ratio) {
  const int bytes = a.descriptor_size;
  std::vector<std::vector<int>> d(a.size(), std::vector<int>(b.size()));
  for (int i = 0; i < a.size(); ++i)
    for (int j = 0; j < b.size(); ++j) d[i][j] = ReferenceHamming(a.binary_descriptor(i), b.binary_descriptor(j), bytes);
  std::vector<Match> out;
  for (int i = 0; i < a.size(); ++i) {
    int best = -1, b1 = std::numeric_limits<int>::max(), b2 = b1;
    for (int j = 0; j < b.size(); ++j) {
      if (d[i][j] < b1) {
        b2 = b1;
        b1 = d[i][j];
        best = j;
      } else if (d[i][j] < b2) {
        b2 = d[i][j];
      }
    }
    if (!(b1 < ratio * b2)) continue;
    int col_best = -1, cb = std::numeric_limits<int>::max();
    for (int k = 0; k < a.size(); ++k) {
      if (d[k][best] < cb) {
        cb = d[k][best];
        col_best = k;
      }
    }
    if (col_best == i) out.push_back({i, best, static_cast<float>(b1)});
  }
  return out;
}

TEST(MatchFeaturesHamming, DistancesAndMatchesEqualTheBitwiseReference) {
  for (int bytes : {32, 61, 13}) {
    const BinaryPair p = MakeBinaryPair(bytes, 300, 3 + bytes);
    MatchStats stats;
    const std::vector<Match> m = MatchFeatures(p.a, p.b, MatchOptions(), &stats);
    const std::vector<Match> ref = ReferenceMatches(p.a, p.b, MatchOptions().ratio);
    ASSERT_GT(ref.size(), 250u) << bytes;
    ASSERT_EQ(m.size(), ref.size()) << bytes;
    for (size_t i = 0; i < m.size(); ++i) {
      EXPECT_EQ(m[i].a, ref[i].a);
      EXPECT_EQ(m[i].b, ref[i].b);
      EXPECT_EQ(m[i].distance, ref[i].distance);
      EXPECT_EQ(m[i].distance, ReferenceHamming(p.a.binary_descriptor(m[i].a), p.b.binary_descriptor(m[i].b), bytes));
    }
    EXPECT_EQ(stats.distance_evaluations, int64_t(p.a.size()) * p.b.size());
  }
}

TEST(MatchFeaturesHamming, LastByteAndHighBitsCount) {
  // 61 bytes (AKAZE): the last word is partly padding; a difference in the very last bit counts.
  FeatureSet a, b;
  std::vector<uint8_t> d(61, 0);
  AddBinary(&a, d, 0);
  d[60] = 0x80;
  AddBinary(&b, d, 0);  // 1 bit away
  std::vector<uint8_t> far(61, 0xFF);
  AddBinary(&b, far, 0);  // 488 bits away
  const std::vector<Match> m = MatchFeatures(a, b, MatchOptions());
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].b, 0);
  EXPECT_EQ(m[0].distance, 1.0f);
}

TEST(MatchFeaturesHamming, TiesGoToTheLowestIndexWhateverTheBlocking) {
  // A holds some descriptors twice, so B's nearest A is an exact tie: it must go to the lower
  // index (the original), or the mutual check would drop the original and keep the duplicate.
  FeatureSet a, b;
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int i = 0; i < 100; ++i) {
    std::vector<uint8_t> d(32);
    for (uint8_t& x : d) x = static_cast<uint8_t>(byte(rng));
    AddBinary(&a, d, 0);
    AddBinary(&b, d, 0);
  }
  for (int i = 0; i < 100; i += 3) {  // duplicates of a[i] appended at the end of A
    AddBinary(&a, std::vector<uint8_t>(a.binary_descriptor(i), a.binary_descriptor(i) + 32), 0);
  }
  for (int block : {1, 7, 64, 1024}) {
    MatchOptions o;
    o.block_rows = block;
    const std::vector<Match> m = MatchFeatures(a, b, o);
    ASSERT_EQ(m.size(), 100u) << block;  // the duplicates (index >= 100) lose every tie
    for (int i = 0; i < 100; ++i) {
      EXPECT_EQ(m[i].a, i);
      EXPECT_EQ(m[i].b, i);
      EXPECT_EQ(m[i].distance, 0.f);
    }
  }
}

TEST(MatchFeaturesHamming, GatingNeverPairsDifferentClasses) {
  const BinaryPair p = MakeBinaryPair(32, 300, 17, 3);
  FeatureSet b = p.b;
  // Every fifth B keypoint moves to another class: its true partner may no longer match it.
  for (int j = 0; j < b.size(); j += 5) b.keypoints[j].class_id = static_cast<uint8_t>((b.keypoints[j].class_id + 1) % 3);
  MatchOptions gated;
  gated.gate_by_class = true;
  MatchStats gs, us;
  const std::vector<Match> ungated = MatchFeatures(p.a, b, MatchOptions(), &us);
  const std::vector<Match> m = MatchFeatures(p.a, b, gated, &gs);
  int cross = 0;
  for (const Match& x : ungated) cross += p.a.keypoints[x.a].class_id != b.keypoints[x.b].class_id;
  ASSERT_GT(cross, 20);
  ASSERT_GT(m.size(), 150u);
  for (const Match& x : m) EXPECT_EQ(p.a.keypoints[x.a].class_id, b.keypoints[x.b].class_id);
  for (size_t i = 1; i < m.size(); ++i) EXPECT_LT(m[i - 1].a, m[i].a);
  EXPECT_LT(gs.distance_evaluations, us.distance_evaluations / 2);
}

TEST(MatchFeatures, MixingFloatAndBinaryDescriptorsIsRefused) {
  FeatureSet f, bin;
  Add(&f, Unit(0), 0);
  Add(&f, Unit(1), 0);
  AddBinary(&bin, std::vector<uint8_t>(32, 1), 0);
  AddBinary(&bin, std::vector<uint8_t>(32, 2), 0);
  EXPECT_THAT([&] { MatchFeatures(f, bin, MatchOptions()); }, ThrowsWith<std::invalid_argument>("binary"));
  EXPECT_THROW(MatchFeatures(bin, f, MatchOptions()), std::invalid_argument);
  // Even when one side found nothing: a mix is a caller's bug, not an empty result.
  FeatureSet empty_binary;
  empty_binary.kind = DescriptorKind::kBinary;
  empty_binary.descriptor_size = 32;
  EXPECT_THROW(MatchFeatures(f, empty_binary, MatchOptions()), std::invalid_argument);
  // Binary sets of different lengths (ORB against AKAZE) are refused too.
  FeatureSet akaze;
  AddBinary(&akaze, std::vector<uint8_t>(61, 1), 0);
  AddBinary(&akaze, std::vector<uint8_t>(61, 2), 0);
  EXPECT_THROW(MatchFeatures(bin, akaze, MatchOptions()), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
