#include "dataset/image_io.h"

#include <fstream>
#include <iterator>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

class ImageIo : public testing::Test {
 protected:
  const TempDir dir_;
};

TEST_F(ImageIo, Rgb8RoundTripIsLosslessAndOriented) {
  ImageU8 img(5, 3, 3);
  for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = static_cast<uint8_t>(i * 7);
  img.at(0, 0, 0) = 255;  // top-left stays top-left
  WriteImage(dir_ / "a.png", img);
  const ImageU8 back = ReadImageU8(dir_ / "a.png");
  EXPECT_EQ(back.width, 5);
  EXPECT_EQ(back.height, 3);
  EXPECT_EQ(back.channels, 3);
  EXPECT_EQ(back.data, img.data);
}

TEST_F(ImageIo, SixteenBitAndFloatRoundTrip) {
  ImageU16 inst(4, 2, 1);
  inst.at(3, 1) = 60000;
  WriteImage(dir_ / "i.png", inst);
  EXPECT_EQ(ReadImageU16(dir_ / "i.png").data, inst.data);
  ImageF depth(4, 2, 1);
  depth.at(1, 0) = 12.345678f;
  WriteImage(dir_ / "d.exr", depth);
  EXPECT_EQ(ReadImageF(dir_ / "d.exr").data, depth.data);
}

// The same image written twice gives the same bytes, whenever it is written: no time stamp.
// (OpenImageIO stamps EXR files with the current second unless told otherwise.)
TEST_F(ImageIo, WritingTheSameImageLaterGivesTheSameBytes) {
  ImageF depth(4, 2, 1, 3.5f);
  ImageU8 rgb(4, 2, 3, 77);
  WriteImage(dir_ / "a.exr", depth);
  WriteImage(dir_ / "a.png", rgb);
  ::usleep(1'100'000);
  WriteImage(dir_ / "b.exr", depth);
  WriteImage(dir_ / "b.png", rgb);
  auto bytes = [&](const char* name) {
    std::ifstream in(dir_ / name, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  EXPECT_EQ(bytes("a.exr"), bytes("b.exr"));
  EXPECT_EQ(bytes("a.png"), bytes("b.png"));
}

TEST_F(ImageIo, ChannelConversion) {
  ImageU8 grey(2, 2, 1, 9);
  WriteImage(dir_ / "g.png", grey);
  const ImageU8 rgb = ReadImageU8(dir_ / "g.png", 3);
  EXPECT_EQ(rgb.channels, 3);
  EXPECT_EQ(rgb.at(1, 1, 2), 9);
}

TEST_F(ImageIo, ErrorsNameTheFile) {
  EXPECT_THAT([&] { ReadImageU8(dir_ / "none.png"); }, ThrowsWith<std::runtime_error>("none.png"));
  std::ofstream(dir_ / "bad.png") << "not a png at all";
  EXPECT_THROW(ReadImageU8(dir_ / "bad.png"), std::runtime_error);
  EXPECT_THROW(WriteImage(dir_ / "nodir" / "x.png", ImageU8(2, 2, 1)), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir_ / "nodir"));
}

TEST_F(ImageIo, SizeComesFromTheHeaderWithTheReadersChecks) {
  WriteImage(dir_ / "wide.png", ImageU8(37, 5, 3, 9));
  WriteImage(dir_ / "range.exr", ImageF(4, 11, 1, 2.5f));
  const ImageSize png = ReadImageSize(dir_ / "wide.png");
  EXPECT_EQ(png.width, 37);
  EXPECT_EQ(png.height, 5);
  const ImageSize exr = ReadImageSize(dir_ / "range.exr");
  EXPECT_EQ(exr.width, 4);
  EXPECT_EQ(exr.height, 11);
  std::ofstream(dir_ / "bad.png") << "not a png at all";
  EXPECT_THROW(ReadImageSize(dir_ / "bad.png"), std::runtime_error);
  EXPECT_THAT([&] { ReadImageSize(dir_ / "none.jpg"); }, ThrowsWith<std::runtime_error>("none.jpg: no such file"));
}

}  // namespace
}  // namespace rigsim
