#include "evaluation/verdicts.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(Verdicts, WithinToleranceJudgesTheDirectionOnlyWhereThereIsOne) {
  EXPECT_EQ(WithinTolerance(0.9, 4.9, kCameraTolerance), true);
  EXPECT_EQ(WithinTolerance(1.1, 0.0, kCameraTolerance), false);
  EXPECT_EQ(WithinTolerance(0.5, 5.1, kCameraTolerance), false);
  EXPECT_EQ(WithinTolerance(1.5, 3.0, kPairTolerance), true);   // a pair's rotation bound is 2 deg
  EXPECT_EQ(WithinTolerance(0.5, std::nullopt, kCameraTolerance), true);  // rotation only: its rotation
  EXPECT_FALSE(WithinTolerance(std::nullopt, 1.0, kCameraTolerance).has_value());  // no truth
}

TEST(Verdicts, PoseErrorIsTheWorseOfRotationAndDirection) {
  EXPECT_EQ(PoseErrorDeg(true, 0.5, 3.0, true), 3.0);
  EXPECT_EQ(PoseErrorDeg(true, 4.0, 3.0, true), 4.0);
  EXPECT_EQ(PoseErrorDeg(false, 0.5, std::nullopt, true), kInf);  // no full pose: a failure
  EXPECT_EQ(PoseErrorDeg(true, 0.5, std::nullopt, true), kInf);   // the direction is missing
  EXPECT_EQ(PoseErrorDeg(true, 0.5, std::nullopt, false), 0.5);   // the truth has no direction to judge
}

TEST(Verdicts, SuccessNeedsTheReferenceAndEveryCameraWithinTheLimit) {
  EXPECT_TRUE(RigSucceeds(true, {0.5, 0.9}, kSuccessLimitsDeg[0]));
  EXPECT_FALSE(RigSucceeds(true, {0.5, 1.5}, kSuccessLimitsDeg[0]));
  EXPECT_TRUE(RigSucceeds(true, {0.5, 1.5}, kSuccessLimitsDeg[1]));
  EXPECT_FALSE(RigSucceeds(true, {0.5, kInf}, kSuccessLimitsDeg[1]));  // a camera without a full pose
  EXPECT_FALSE(RigSucceeds(false, {}, kSuccessLimitsDeg[1]));
}

// An error 4 stated sd off is overconfident, 2 sd off not; below the 0.05 deg floor nothing is,
// however small the stated sd; an error without a stated sd is not judged.
TEST(Verdicts, OverconfidentIsBeyondThreeStatedDeviationsAndTheFloor) {
  EXPECT_TRUE((StatedError{0.4, 0.1}.Beyond()));   // 4 sd
  EXPECT_FALSE((StatedError{0.2, 0.1}.Beyond()));  // 2 sd
  EXPECT_DOUBLE_EQ(StatedError({0.4, 0.1}).Ratio().value(), 4.0);
  EXPECT_FALSE((StatedError{0.04, 0.001}.Beyond()));  // 40 sd, but under the floor
  EXPECT_TRUE((StatedError{0.06, 0.001}.Beyond()));   // 60 sd and over the floor
  EXPECT_EQ(StatedError({0.04, 0.0}).Ratio(), kInf);  // a stated 0
  EXPECT_FALSE(StatedError({0.4, std::nullopt}).Ratio().has_value());
  EXPECT_FALSE(StatedError({0.4, std::nullopt}).Beyond());
  EXPECT_EQ(Overconfident({{0.2, 0.1}, {0.4, 0.1}}), true);   // one component is enough
  EXPECT_EQ(Overconfident({{0.2, 0.1}, {0.4, std::nullopt}}), false);
  EXPECT_FALSE(Overconfident({{0.4, std::nullopt}, {std::nullopt, 0.1}}).has_value());  // nothing to judge
}

// The truth's own deviation (a survey's) counts beside the stated one: 0.2 deg at a stated 0.05 is
// 4 sd against an exact truth, 1.9 against one good to 0.1.
TEST(Verdicts, TheTruthsOwnDeviationCountsBesideTheStatedOne) {
  EXPECT_TRUE((StatedError{0.2, 0.05}.Beyond()));
  EXPECT_FALSE((StatedError{0.2, 0.05, 0.1}.Beyond()));
  EXPECT_DOUBLE_EQ(StatedError({0.2, 0.05, 0.1}).JudgedSd().value(), std::hypot(0.05, 0.1));
  EXPECT_DOUBLE_EQ(StatedError({0.2, 0.05, 0.1}).Ratio().value(), 0.2 / std::hypot(0.05, 0.1));
  EXPECT_DOUBLE_EQ(StatedError({0.2, 0.05, 0.0}).Ratio().value(), 4.0);
  EXPECT_FALSE(StatedError({0.2, std::nullopt, 0.1}).JudgedSd().has_value());  // nothing stated: not judged
  EXPECT_FALSE(StatedError({0.2, std::nullopt, 0.1}).Beyond());
  EXPECT_TRUE((StatedError{0.2, 0.0, 0.05}.Beyond()));  // a stated 0 against a truth good to 0.05
}

TEST(Verdicts, ConfidentlyWrongIsAFullPoseBeyondFiveDegrees) {
  EXPECT_TRUE(ConfidentlyWrong(true, 5.7));
  EXPECT_FALSE(ConfidentlyWrong(true, 5.0));
  EXPECT_FALSE(ConfidentlyWrong(false, kInf));  // not reported as placed: not confident
}

// A camera placed but for one axis claims a rotation and the direction of its centre across the
// axis: either more than 5 deg off makes it confidently wrong; without a full pose it never succeeds.
TEST(Verdicts, ACameraPlacedButForOneAxisIsJudgedOnWhatItClaims) {
  EXPECT_EQ(OpenAxisErrorDeg(0.5, 3.0, true), 3.0);
  EXPECT_EQ(OpenAxisErrorDeg(4.0, 3.0, true), 4.0);
  EXPECT_EQ(OpenAxisErrorDeg(0.5, std::nullopt, false), 0.5);  // on the axis: its rotation alone
  EXPECT_EQ(OpenAxisErrorDeg(0.5, std::nullopt, true), kInf);   // the truth has a direction it does not give
  EXPECT_TRUE(ConfidentlyWrong(true, OpenAxisErrorDeg(0.5, 6.0, true)));
  EXPECT_TRUE(ConfidentlyWrong(true, OpenAxisErrorDeg(6.0, 1.0, true)));
  EXPECT_FALSE(ConfidentlyWrong(true, OpenAxisErrorDeg(4.0, 4.9, true)));
  EXPECT_FALSE(RigSucceeds(true, {PoseErrorDeg(false, 0.1, std::nullopt, true)}, kSuccessLimitsDeg[1]));
}

// The verdicts answer different questions: one camera can be within tolerance and still fail
// success at 2 deg (its direction is 3 deg off), or be outside tolerance and not confidently
// wrong (3 deg of rotation).
TEST(Verdicts, WithinToleranceSuccessAndConfidentlyWrongAreDifferentQuestions) {
  EXPECT_EQ(WithinTolerance(0.5, 3.0, kCameraTolerance), true);
  EXPECT_FALSE(RigSucceeds(true, {PoseErrorDeg(true, 0.5, 3.0, true)}, kSuccessLimitsDeg[1]));
  EXPECT_EQ(WithinTolerance(3.0, 1.0, kCameraTolerance), false);
  EXPECT_FALSE(ConfidentlyWrong(true, PoseErrorDeg(true, 3.0, 1.0, true)));
}

}  // namespace
}  // namespace rigsim
