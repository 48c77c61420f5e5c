#include "segmentation/class_table.h"

#include <gtest/gtest.h>

#include "labels/cityscapes.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

uint8_t Id(const char* name) { return FindClassByName(name)->id; }

SegmenterErrorKind KindOf(const std::string& name_or_path) {
  try {
    LoadClassTable(name_or_path);
  } catch (const SegmenterError& e) {
    return e.kind;
  }
  ADD_FAILURE() << name_or_path << " was accepted";
  return SegmenterErrorKind::kBadOptions;
}

TEST(ClassTable, CityscapesChannelsAreTheTrainIds) {
  const ClassTable t = LoadClassTable("cityscapes");
  ASSERT_EQ(t.size(), 19);
  for (int k = 0; k < t.size(); ++k) EXPECT_EQ(FindClassById(t.label_ids[k])->train_id, k);
  EXPECT_EQ(t.label_ids[0], Id("road"));
  EXPECT_EQ(t.label_ids[10], Id("sky"));
  EXPECT_EQ(t.label_ids[18], Id("bicycle"));
}

TEST(ClassTable, Ade20kHasItsHundredAndFiftyClassesInOrder) {
  const ClassTable t = LoadClassTable("ade20k");
  ASSERT_EQ(t.size(), 150);
  EXPECT_EQ(t.channel_names[0], "wall");
  EXPECT_EQ(t.label_ids[0], Id("wall"));
  EXPECT_EQ(t.label_ids[2], Id("sky"));
  EXPECT_EQ(t.label_ids[6], Id("road"));
  EXPECT_EQ(t.label_ids[12], Id("person"));
  EXPECT_EQ(t.label_ids[20], Id("car"));
  EXPECT_EQ(t.channel_names[136], "traffic light");
  EXPECT_EQ(t.label_ids[136], Id("traffic light"));
  EXPECT_EQ(t.channel_names[149], "flag");
  // Movable things are never reliable, whatever class they map to.
  const ReliableClasses reliable;
  for (const char* movable : {"person", "car", "chair", "bicycle", "boat", "animal", "bus", "truck"}) {
    for (int k = 0; k < t.size(); ++k) {
      if (t.channel_names[k] == movable) {
        EXPECT_FALSE(reliable.IsReliable(t.label_ids[k])) << movable;
      }
    }
  }
}

TEST(ClassTable, VocBackgroundIsUnlabeled) {
  const ClassTable t = LoadClassTable("voc");
  ASSERT_EQ(t.size(), 21);
  EXPECT_EQ(t.label_ids[0], kUnlabeledId);
  EXPECT_EQ(t.label_ids[15], Id("person"));
  EXPECT_EQ(t.label_ids[7], Id("car"));
}

TEST(ClassTable, BuiltinBySize) {
  EXPECT_EQ(BuiltinClassTableWithSize(19), "cityscapes");
  EXPECT_EQ(BuiltinClassTableWithSize(150), "ade20k");
  EXPECT_EQ(BuiltinClassTableWithSize(21), "voc");
  EXPECT_EQ(BuiltinClassTableWithSize(7), "");
}

TEST(ClassTable, FileMapsChannelsByNameOrId) {
  TempDir dir;
  WriteFile(dir / "t.txt",
            "# my network\n"
            "\n"
            "2 traffic light   # signal\n"
            "0 road\n"
            "1 11              # house\n"
            "3 sky\r\n");
  const ClassTable t = LoadClassTable((dir / "t.txt").string());
  ASSERT_EQ(t.size(), 4);
  EXPECT_EQ(t.label_ids, (std::vector<uint8_t>{Id("road"), Id("building"), Id("traffic light"), Id("sky")}));
  EXPECT_EQ(t.channel_names[2], "signal");
  EXPECT_EQ(t.channel_names[1], "house");
  EXPECT_EQ(t.channel_names[0], "");
}

TEST(ClassTable, BadFilesAreRefused) {
  TempDir dir;
  EXPECT_EQ(KindOf((dir / "missing.txt").string()), SegmenterErrorKind::kClassTableFile);
  WriteFile(dir / "unknown.txt", "0 road\n1 biulding\n");
  EXPECT_EQ(KindOf((dir / "unknown.txt").string()), SegmenterErrorKind::kClassTableFile);
  WriteFile(dir / "twice.txt", "0 road\n0 sky\n");
  EXPECT_EQ(KindOf((dir / "twice.txt").string()), SegmenterErrorKind::kClassTableFile);
  WriteFile(dir / "gap.txt", "0 road\n2 sky\n");
  EXPECT_EQ(KindOf((dir / "gap.txt").string()), SegmenterErrorKind::kClassTableFile);
  WriteFile(dir / "one.txt", "0 road\n");
  EXPECT_EQ(KindOf((dir / "one.txt").string()), SegmenterErrorKind::kClassTableFile);
  WriteFile(dir / "noclass.txt", "0 road\n1\n");
  EXPECT_EQ(KindOf((dir / "noclass.txt").string()), SegmenterErrorKind::kClassTableFile);
  WriteFile(dir / "badid.txt", "0 road\n1 99\n");
  EXPECT_EQ(KindOf((dir / "badid.txt").string()), SegmenterErrorKind::kClassTableFile);
  WriteFile(dir / "notanumber.txt", "zero road\n1 sky\n");
  EXPECT_EQ(KindOf((dir / "notanumber.txt").string()), SegmenterErrorKind::kClassTableFile);
}

}  // namespace
}  // namespace rigsim
