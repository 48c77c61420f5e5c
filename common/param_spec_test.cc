#include "common/param_spec.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "testing/expect_error.h"

namespace rigsim {
namespace {

using Json = nlohmann::ordered_json;
using E = std::invalid_argument;

const ParamSpec kCameras{"cameras", ParamSpec::Kind::kInt, 4, {}, 1, 64, "ring: number of cameras"};
const ParamSpec kOverlap{"overlap", ParamSpec::Kind::kNumber, nullptr, {}, 0, 99, "overlap (percent)"};
const ParamSpec kLens{"lens", ParamSpec::Kind::kChoice, "preset", {"preset", "pinhole", "fisheye"}, 0, 0, "lens"};

TEST(ParamSpec, NormalisesNumbersAndKeepsWholeNumbersWhole) {
  EXPECT_TRUE(CheckParamValue(kOverlap, 30).is_number_float());
  EXPECT_EQ(CheckParamValue(kOverlap, 30), CheckParamValue(kOverlap, 30.0));
  EXPECT_TRUE(CheckParamValue(kCameras, 3).is_number_integer());
  EXPECT_TRUE(CheckParamValue(kOverlap, nullptr).is_null());  // its default is unset
  EXPECT_EQ(CheckParamValue(kLens, "fisheye"), "fisheye");
}

TEST(ParamSpec, RefusesWhatItsCheckRefuses) {
  EXPECT_THAT([] { CheckParamValue(kCameras, 0); }, ThrowsExactly<E>("0 is outside 1 to 64"));
  EXPECT_THAT([] { CheckParamValue(kCameras, 2.5); }, ThrowsExactly<E>("must be a whole number, got 2.5"));
  EXPECT_THAT([] { CheckParamValue(kCameras, nullptr); }, ThrowsExactly<E>("'cameras' cannot be unset (null)"));
  EXPECT_THAT([] { CheckParamValue(kOverlap, 99.5); }, ThrowsExactly<E>("99.5 is outside 0 to 99"));
  EXPECT_THAT([] { CheckParamValue(kLens, "fishey"); },
              ThrowsExactly<E>("'fishey' is not one of preset, pinhole, fisheye (did you mean 'fisheye'?)"));
}

TEST(ParamSpec, ReadsCommandLineTextAsTheConfigWouldBe) {
  EXPECT_EQ(ParamValueFromText(kCameras, "12"), Json(12));
  EXPECT_EQ(ParamValueFromText(kOverlap, "30"), Json(30.0));
  EXPECT_EQ(ParamValueFromText(kOverlap, ".5"), Json(0.5));
  EXPECT_THAT([] { ParamValueFromText(kCameras, "2.5"); }, ThrowsExactly<E>("'2.5' is not a whole number"));
  EXPECT_THAT([] { ParamValueFromText(kOverlap, "lots"); }, ThrowsExactly<E>("'lots' is not a number"));
  EXPECT_THAT([] { ParamValueFromText(kCameras, "65"); }, ThrowsExactly<E>("65 is outside 1 to 64"));
}

TEST(ParamSpec, FormatsValuesForPeople) {
  EXPECT_EQ(FormatParamValue(30.0), "30");
  EXPECT_EQ(FormatParamValue(0.5), "0.5");
  EXPECT_EQ(FormatParamValue(nullptr), "unset");
  EXPECT_EQ(FormatParamValue("street"), "street");
  EXPECT_EQ(JoinNames({"a", "b", "c"}), "a, b, c");
}

}  // namespace
}  // namespace rigsim
