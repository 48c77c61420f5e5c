#include "calibrator/features/byte_product.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "calibrator/features/matching.h"

namespace rigsim {
namespace {

// n random descriptors of `dim` whole numbers in [0, 255], with both ends of the range present.
FeatureSet RandomByteSet(int n, int dim, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> value(0, 255);
  FeatureSet f;
  f.descriptor_size = dim;
  f.keypoints.resize(n);
  for (int i = 0; i < n * dim; ++i) f.descriptors.push_back(static_cast<float>(i % 97 == 0 ? 255 : value(rng)));
  f.descriptors[1] = 0.f;
  return f;
}

std::vector<int> AllRows(const FeatureSet& f) {
  std::vector<int> rows(f.size());
  for (int i = 0; i < f.size(); ++i) rows[i] = i;
  return rows;
}

// Every CPU path with an integer kernel, on the same input: the float product's numbers bit for
// bit (the baseline path is the float product itself). A path this CPU lacks is skipped.
class ByteProductPath : public ::testing::TestWithParam<CpuPath> {};

TEST_P(ByteProductPath, EqualsTheFloatProductBitForBit) {
  const CpuPath path = GetParam();
  if (!CpuSupports(path)) GTEST_SKIP() << "this CPU has no " << CpuPathName(path) << " (the path still compiles)";
  ASSERT_TRUE(ByteProductAvailable(path));
  using RowMatrixXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  // SIFT's 128 and lengths that are not a whole number of 4-byte groups; row and column counts
  // that fill no tile exactly.
  for (int dim : {128, 61, 3}) {
    const FeatureSet a = RandomByteSet(37, dim, 1), b = RandomByteSet(141, dim, 2);
    std::vector<int> ia = AllRows(a), ib = AllRows(b);
    std::swap(ia[0], ia[5]);  // through the index lists, not the storage order
    std::swap(ib[3], ib[140]);
    ASSERT_TRUE(DescriptorsAreBytes(a, ia));
    ASSERT_TRUE(DescriptorsAreBytes(b, ib));
    RowMatrixXf da(a.size(), dim), db(b.size(), dim);
    for (int i = 0; i < a.size(); ++i) da.row(i) = Eigen::Map<const Eigen::RowVectorXf>(a.descriptor(ia[i]), dim);
    for (int j = 0; j < b.size(); ++j) db.row(j) = Eigen::Map<const Eigen::RowVectorXf>(b.descriptor(ib[j]), dim);
    const RowMatrixXf expected = -2.f * (da * db.transpose());

    const ByteProductColumns columns(b, ib, path);
    const size_t stride = b.size() + 3;  // the padding after each row must stay untouched
    std::vector<float> out(size_t(a.size()) * stride, 7.f);
    columns.MinusTwoDot(a, ia, 0, 20, out.data(), stride);  // two calls: rows [0, 20), [20, 37)
    columns.MinusTwoDot(a, ia, 20, a.size(), out.data() + 20 * stride, stride);
    for (int i = 0; i < a.size(); ++i) {
      for (int j = 0; j < b.size(); ++j) ASSERT_EQ(out[i * stride + j], expected(i, j)) << dim << ": " << i << "," << j;
      for (size_t j = b.size(); j < stride; ++j) ASSERT_EQ(out[i * stride + j], 7.f);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(IntegerKernels, ByteProductPath, ::testing::Values(CpuPath::kAvx2, CpuPath::kAvx512Vnni),
                         [](const auto& info) { return info.param == CpuPath::kAvx2 ? "Avx2" : "Avx512Vnni"; });

TEST(ByteProduct, TheBaselinePathHasNoIntegerKernelAndRefusesColumns) {
  EXPECT_FALSE(ByteProductAvailable(CpuPath::kBaseline));
  const FeatureSet b = RandomByteSet(4, 8, 1);
  EXPECT_THROW(ByteProductColumns(b, AllRows(b), CpuPath::kBaseline), std::logic_error);
}

TEST(CpuPath, TheVariableChoosesAPathOrNamesTheProblem) {
  const std::vector<CpuPath> supported = SupportedCpuPaths();
  ASSERT_FALSE(supported.empty());
  EXPECT_EQ(supported.front(), CpuPath::kBaseline);
  EXPECT_EQ(CpuPathFor(nullptr), supported.back());  // unset: the fastest
  EXPECT_EQ(CpuPathFor(""), supported.back());
  EXPECT_EQ(CpuPathFor("auto"), supported.back());
  for (CpuPath p : supported) EXPECT_EQ(CpuPathFor(std::string(CpuPathName(p)).c_str()), p);
  EXPECT_THROW(CpuPathFor("avx3"), std::runtime_error);
  EXPECT_THROW(CpuPathFor("AVX2"), std::runtime_error);
  for (CpuPath p : {CpuPath::kAvx2, CpuPath::kAvx512Vnni}) {
    if (!CpuSupports(p)) {
      EXPECT_THROW(CpuPathFor(std::string(CpuPathName(p)).c_str()), std::runtime_error);
    }
  }
}

TEST(ByteProduct, DescriptorsAreBytesOnlyForWholeNumbersFrom0To255) {
  FeatureSet f = RandomByteSet(3, 8, 3);
  EXPECT_TRUE(DescriptorsAreBytes(f, {0, 1, 2}));
  for (float bad : {0.5f, -1.f, 256.f}) {
    FeatureSet g = f;
    g.descriptors[13] = bad;
    EXPECT_FALSE(DescriptorsAreBytes(g, {0, 1, 2})) << bad;
    EXPECT_TRUE(DescriptorsAreBytes(g, {0, 2})) << bad;  // only the rows asked about count
  }
}

// Halving every value takes the matcher off the integer product (halves are not whole numbers) and
// halves every distance exactly: the matches must be the same and the distances exactly half.
TEST(ByteProduct, MatchingGivesTheSameMatchesAsTheFloatPath) {
  FeatureSet a = RandomByteSet(300, 128, 4), b = RandomByteSet(280, 128, 5);
  std::mt19937 rng(6);
  std::normal_distribution<float> noise(0.f, 6.f);
  for (int i = 0; i < 250; ++i) {  // b's first 250 are noisy copies of a's: true matches
    for (int k = 0; k < 128; ++k) {
      b.descriptors[i * 128 + k] = std::clamp(std::round(a.descriptors[i * 128 + k] + noise(rng)), 0.f, 255.f);
    }
  }
  FeatureSet ha = a, hb = b;
  for (float& v : ha.descriptors) v *= 0.5f;
  for (float& v : hb.descriptors) v *= 0.5f;
  ASSERT_FALSE(DescriptorsAreBytes(ha, AllRows(ha)));
  const std::vector<Match> m = MatchFeatures(a, b, MatchOptions());
  const std::vector<Match> h = MatchFeatures(ha, hb, MatchOptions());
  ASSERT_GT(m.size(), 200u);
  ASSERT_EQ(m.size(), h.size());
  for (size_t k = 0; k < m.size(); ++k) {
    EXPECT_EQ(m[k].a, h[k].a);
    EXPECT_EQ(m[k].b, h[k].b);
    EXPECT_EQ(m[k].distance, 2.f * h[k].distance);
  }
}

}  // namespace
}  // namespace rigsim
