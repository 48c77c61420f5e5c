#include "dataset/render_shards.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "dataset/coco.h"

namespace rigsim {
namespace {

TEST(RenderShards, FramesSplitIntoContiguousBlocksCoveringEachOnce) {
  for (int frames : {1, 5, 7, 100}) {
    for (int count = 1; count <= frames && count <= 9; ++count) {
      int next = 0;
      for (int i = 0; i < count; ++i) {
        const FrameRange r = ShardFrames(frames, i, count);
        EXPECT_EQ(r.begin, next) << frames << " frames, shard " << i << "/" << count;
        EXPECT_GE(r.end - r.begin, frames / count);
        EXPECT_LE(r.end - r.begin, frames / count + 1);
        next = r.end;
      }
      EXPECT_EQ(next, frames);
    }
  }
  EXPECT_THROW(ShardFrames(5, 3, 3), std::invalid_argument);
  EXPECT_THROW(ShardFrames(5, -1, 3), std::invalid_argument);
}

TEST(RenderShards, OverlapIsTheMeanOverFramesOfEachDirectionsFraction) {
  // Two cameras: frame 0 a sees 50 of 100 in b, b 10 of 40 in a; frame 1 a has no surface.
  const nlohmann::json j = OverlapJson({"a", "b"}, {{{100, 40}, {0, 50, 10, 0}}, {{0, 20}, {0, 0, 20, 0}}});
  EXPECT_EQ(j["frames"], 2);
  ASSERT_EQ(j["pairs"].size(), 1u);
  EXPECT_DOUBLE_EQ(j["pairs"][0]["overlap_a_in_b"].get<double>(), 0.5 / 2);
  EXPECT_DOUBLE_EQ(j["pairs"][0]["overlap_b_in_a"].get<double>(), (0.25 + 1.0) / 2);
}

TEST(RenderShards, ShardDescriptionsReadBackAndCocoAppendsWithRunningIds) {
  RenderShardInfo info{1, 2, "abc", 3, 1, {{{5, 6}, {0, 1, 2, 0}}, {{7, 8}, {0, 3, 4, 0}}}};
  const nlohmann::json j = RenderShardJson(info);
  EXPECT_EQ(j["first_frame"], 1);
  EXPECT_EQ(j["overlap"][1]["visible"][2], 4);

  ImageU8 labels(2, 1, 1, 26);
  ImageU16 instances(2, 1, 1, 0);
  instances.at(1, 0) = 9;
  CocoInstances one, two, both;
  one.AddImage("a/0.png", labels, instances);
  two.AddImage("a/1.png", labels, instances);
  both.AddImage("a/0.png", labels, instances);
  both.AddImage("a/1.png", labels, instances);
  CocoInstances appended;
  appended.AddAll(one.ToJson());
  appended.AddAll(two.ToJson());
  EXPECT_EQ(appended.ToJson().dump(), both.ToJson().dump());
  EXPECT_EQ(appended.ToJson()["annotations"][1]["image_id"], 2);
}

}  // namespace
}  // namespace rigsim
