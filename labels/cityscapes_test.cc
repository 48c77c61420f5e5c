#include "labels/cityscapes.h"

#include <gtest/gtest.h>

namespace rigsim {
namespace {

TEST(Cityscapes, IdsIndexTheTable) {
  const auto classes = CityscapesClasses();
  ASSERT_EQ(classes.size(), 34u);
  for (size_t i = 0; i < classes.size(); ++i) EXPECT_EQ(classes[i].id, i);
  EXPECT_EQ(FindClassByName("sky")->id, kSkyId);
  EXPECT_EQ(FindClassByName("building")->id, 11);
  EXPECT_EQ(FindClassByName("car")->train_id, 13);
  EXPECT_EQ(FindClassById(200), nullptr);
  EXPECT_EQ(FindClassByName("spaceship"), nullptr);
}

TEST(Cityscapes, ColoursMapBackToIds) {
  for (const LabelClass& c : CityscapesClasses()) {
    const auto id = ClassIdFromColor(c.color);
    ASSERT_TRUE(id.has_value());
    // Classes that share a colour with an earlier one map to the earlier one.
    EXPECT_EQ(CityscapesClasses()[*id].color, c.color);
  }
  EXPECT_EQ(*ClassIdFromColor({128, 64, 128}), 7);  // road
  EXPECT_FALSE(ClassIdFromColor({1, 2, 3}).has_value());
}

TEST(Cityscapes, StaticStructureIsReliableAndMovablesAreNot) {
  const ReliableClasses r;
  for (const char* name : {"road", "sidewalk", "building", "wall", "pole", "traffic sign"}) {
    EXPECT_TRUE(r.IsReliable(FindClassByName(name)->id)) << name;
  }
  for (const char* name : {"sky", "vegetation", "person", "car", "bus", "unlabeled"}) {
    EXPECT_FALSE(r.IsReliable(FindClassByName(name)->id)) << name;
  }
}

TEST(Cityscapes, ConfusableClassesAreOtherKnownClasses) {
  int with_confusions = 0;
  for (const LabelClass& c : CityscapesClasses()) {
    const auto confusable = ConfusableClasses(c.id);
    if (c.id <= 5) {
      EXPECT_TRUE(confusable.empty()) << c.name;
    }
    with_confusions += !confusable.empty();
    for (uint8_t other : confusable) {
      EXPECT_NE(other, c.id) << c.name;
      ASSERT_NE(FindClassById(other), nullptr) << c.name;
      EXPECT_GT(other, 5) << c.name << ": confused with a void class";
    }
  }
  EXPECT_EQ(with_confusions, 28);
  EXPECT_EQ(ConfusableClasses(7)[0], 8);  // road -> sidewalk first
  EXPECT_TRUE(ConfusableClasses(99).empty());
  EXPECT_TRUE(ConfusableClasses(-1).empty());
}

TEST(Cityscapes, UserCanOverrideReliableClasses) {
  const ReliableClasses r = ReliableClasses::FromNames({"car", "road"});
  EXPECT_TRUE(r.IsReliable(26));
  EXPECT_TRUE(r.IsReliable(7));
  EXPECT_FALSE(r.IsReliable(11));
  EXPECT_THROW(ReliableClasses::FromNames({"spaceship"}), std::invalid_argument);
}

// The set the calibrator's mask modes take holds the same ids.
TEST(Cityscapes, ReliableIdsAreTheReliableClasses) {
  const ReliableClasses r = ReliableClasses::FromNames({"car", "road"});
  const std::bitset<256> ids = r.Ids();
  EXPECT_EQ(ids.count(), 2u);
  for (int id = 0; id < 256; ++id) EXPECT_EQ(ids[id], r.IsReliable(static_cast<uint8_t>(id))) << id;
}

}  // namespace
}  // namespace rigsim
