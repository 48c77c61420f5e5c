#include "gltf/gltf_loader.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "gltf/gltf_test_support.h"

namespace rigsim::gltf_test {
namespace {

TEST(GltfLoader, DecodesBaseColorTextureAndSampler) {
  const TempDir dir;
  // 3x2 image with known pixels, written as PNG (lossless) next to the file and as a data URI.
  cv::Mat bgr(2, 3, CV_8UC3);
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 3; ++x) bgr.at<cv::Vec3b>(y, x) = cv::Vec3b(uchar(10 * x), uchar(100 + y), uchar(200 + x + y));  // B G R
  }
  ASSERT_TRUE(cv::imwrite((dir / "tex.png").string(), bgr));
  std::vector<uint8_t> png;
  ASSERT_TRUE(cv::imencode(".png", bgr, png));
  GltfBuilder g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int uv = g.Accessor<uint8_t>({0, 255, 255, 255, 0, 0, 0, 0}, kGltfUByte, "VEC2", 3, /*normalized=*/true);
  g.doc["images"] = json::array({{{"uri", "tex.png"}}, {{"uri", DataUri("image/png", png)}}});
  g.doc["samplers"] = json::array({{{"magFilter", 9728}, {"minFilter", 9984}, {"wrapS", 33071}, {"wrapT", 33648}}});
  g.doc["textures"] = json::array({{{"source", 0}, {"sampler", 0}}, {{"source", 1}}});
  g.doc["materials"] = json::array({
      {{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1, 1}}, {"baseColorTexture", {{"index", 0}}}}},
       {"alphaMode", "MASK"}, {"alphaCutoff", 0.3}, {"doubleSided", true}},
      {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}, {"alphaMode", "BLEND"}}});
  g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}}, -1, 4, 0);
  g.Mesh({{"POSITION", pos}}, -1, 4, 1);
  g.Node({{"mesh", 0}});
  g.Node({{"mesh", 1}});
  g.Scene({0, 1});
  const auto path = g.Write(dir, "textured");
  const Scene s = LoadGltf(path);
  ASSERT_EQ(s.textures.size(), 2u);
  ASSERT_EQ(s.materials.size(), 2u);
  for (const Texture& t : s.textures) {
    ASSERT_EQ(t.width, 3);
    ASSERT_EQ(t.height, 2);
    for (int y = 0; y < 2; ++y) {
      for (int x = 0; x < 3; ++x) {
        const uint8_t* p = &t.rgba[(y * 3 + x) * 4];
        EXPECT_EQ(p[0], 200 + x + y);
        EXPECT_EQ(p[1], 100 + y);
        EXPECT_EQ(p[2], 10 * x);
        EXPECT_EQ(p[3], 255);
      }
    }
  }
  EXPECT_TRUE(s.textures[0].nearest);
  EXPECT_TRUE(s.textures[0].min_nearest);  // NEAREST_MIPMAP_NEAREST
  EXPECT_EQ(s.textures[0].mip, MipFilter::kNearest);
  EXPECT_EQ(s.textures[0].wrap_s, WrapMode::kClampToEdge);
  EXPECT_EQ(s.textures[0].wrap_t, WrapMode::kMirroredRepeat);
  EXPECT_FALSE(s.textures[1].nearest);  // no sampler: linear, trilinear when minified
  EXPECT_FALSE(s.textures[1].min_nearest);
  EXPECT_EQ(s.textures[1].mip, MipFilter::kLinear);
  EXPECT_EQ(s.textures[1].wrap_s, WrapMode::kRepeat);
  const Material& m = s.materials[0];
  EXPECT_EQ(m.base_color_texture, 0);
  EXPECT_TRUE(m.base_color_factor.isApprox(Eigen::Vector4f(0.5f, 0.25f, 1, 1)));
  EXPECT_EQ(m.alpha_mode, AlphaMode::kMask);
  EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.3f);
  EXPECT_TRUE(m.double_sided);
  EXPECT_EQ(s.materials[1].base_color_texture, 1);
  EXPECT_EQ(s.materials[1].alpha_mode, AlphaMode::kBlend);
  // Normalized unsigned-byte texcoords.
  ASSERT_EQ(s.meshes[0].texcoords.size(), 3u);
  EXPECT_TRUE(s.meshes[0].texcoords[0].isApprox(Eigen::Vector2f(0, 1)));
  EXPECT_TRUE(s.meshes[0].texcoords[1].isApprox(Eigen::Vector2f(1, 1)));

  // A missing image file is an error that names it.
  std::filesystem::remove(dir / "tex.png");
  ExpectLoadFails(path, "tex.png");
}

// EXT_texture_webp: the texture's WebP image replaces its (here absent) PNG fallback. Lossless
// pixels arrive exactly; lossy and lossless WebP headers give the size that the pixel limit checks.
TEST(GltfLoader, WebpTexturesThroughTheirExtension) {
  const TempDir dir;
  cv::Mat bgra(2, 3, CV_8UC4);
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 3; ++x) bgra.at<cv::Vec4b>(y, x) = cv::Vec4b(uint8_t(10 * x), uint8_t(50 + y), 200, uint8_t(255 - 40 * x));
  }
  std::vector<uint8_t> lossless, lossy, lossy_alpha;  // VP8L, VP8 and VP8X first chunks
  ASSERT_TRUE(cv::imencode(".webp", bgra, lossless, {cv::IMWRITE_WEBP_QUALITY, 101}));
  ASSERT_TRUE(cv::imencode(".webp", bgra, lossy_alpha, {cv::IMWRITE_WEBP_QUALITY, 80}));
  cv::Mat bgr(2, 3, CV_8UC3, cv::Scalar(30, 60, 90));
  ASSERT_TRUE(cv::imencode(".webp", bgr, lossy, {cv::IMWRITE_WEBP_QUALITY, 80}));
  for (const std::vector<uint8_t>* webp : {&lossless, &lossy, &lossy_alpha}) {
    GltfBuilder g;
    const int pos = g.Positions(kUnitQuad);
    const int uv = g.Accessor<float>({0, 0, 1, 0, 1, 1, 0, 1}, kGltfFloat, "VEC2", 4);
    g.doc["extensionsUsed"] = {"EXT_texture_webp"};
    g.doc["extensionsRequired"] = {"EXT_texture_webp"};
    const std::string name = webp == &lossless ? "lossless" : webp == &lossy ? "lossy" : "lossy_alpha";
    EXPECT_EQ(std::string(webp->begin() + 12, webp->begin() + 16), webp == &lossless ? "VP8L" : webp == &lossy ? "VP8 " : "VP8X");
    std::ofstream(dir / (name + ".webp"), std::ios::binary).write(reinterpret_cast<const char*>(webp->data()), std::streamsize(webp->size()));
    g.doc["images"] = json::array({{{"uri", name + ".webp"}}});
    g.doc["textures"] = json::array({{{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}}});
    g.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    g.Node({{"mesh", g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}}, -1, 6, 0)}});
    g.Scene({0});
    const auto path = g.Write(dir, name);
    const Scene s = LoadGltf(path);
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_EQ(s.materials[0].base_color_texture, 0);
    EXPECT_EQ(s.textures[0].width, 3);
    EXPECT_EQ(s.textures[0].height, 2);
    EXPECT_FALSE(HasWarning(s, "webp"));
    if (webp == &lossless) {
      for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 3; ++x) {
          const uint8_t* t = &s.textures[0].rgba[(size_t(y) * 3 + x) * 4];
          const cv::Vec4b& b = bgra.at<cv::Vec4b>(y, x);
          EXPECT_EQ((std::array<int, 4>{t[0], t[1], t[2], t[3]}), (std::array<int, 4>{b[2], b[1], b[0], b[3]})) << x << "," << y;
        }
      }
    }
    GltfLoadOptions small;
    small.max_image_pixels = 5;
    ExpectLoadFails(path, small, "image 0 is 3x2 pixels, more than the limit of 5");
  }
}

TEST(GltfLoader, ImagesAreCheckedBeforeDecoding) {
  const TempDir dir;
  // Only a PNG's IHDR, claiming 70000 x 70000 pixels (18 GiB as RGBA); a BMP (stb would decode it,
  // glTF does not allow it); a real 3 x 2 JPEG, under a limit of 5 pixels and then the default.
  const std::vector<uint8_t> huge_png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                                         0, 1, 0x11, 0x70, 0, 1, 0x11, 0x70, 8, 6, 0, 0, 0, 0, 0, 0, 0};
  // The largest size a PNG header can state (2^32 - 1 each way).
  std::vector<uint8_t> widest_png = huge_png;
  for (int i = 16; i < 24; ++i) widest_png[i] = 0xFF;
  std::vector<uint8_t> bmp(64, 0);
  bmp[0] = 'B';
  bmp[1] = 'M';
  std::vector<uint8_t> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", cv::Mat(2, 3, CV_8UC3, cv::Scalar(40, 80, 120)), jpeg));
  struct Case {
    const std::vector<uint8_t>* bytes;
    uint64_t max_pixels;
    std::string error;  // empty: loads
  };
  const uint64_t default_limit = GltfLoadOptions{}.max_image_pixels;
  for (const Case& c : {Case{&huge_png, default_limit, "image 0 is 70000x70000 pixels, more than the limit"},
                        Case{&bmp, default_limit, "image 0 is not a PNG, JPEG or WebP image"},
                        Case{&widest_png, default_limit, "image 0 is 4294967295x4294967295 pixels, more than the limit"},
                        Case{&jpeg, 5, "image 0 is 3x2 pixels, more than the limit of 5"}, Case{&jpeg, default_limit, ""}}) {
    GltfBuilder g;  // the image is the base colour of the triangle's material
    const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    g.doc["images"] = json::array({{{"uri", DataUri("image/png", *c.bytes)}}});
    g.doc["textures"] = json::array({{{"source", 0}}});
    g.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    g.Mesh({{"POSITION", pos}}, -1, 4, 0);
    g.Node({{"mesh", 0}});
    g.Scene({0});
    const auto path = g.Write(dir, "image");
    GltfLoadOptions options;
    options.max_image_pixels = c.max_pixels;
    if (c.error.empty()) {
      EXPECT_NO_THROW(LoadGltf(path, options));
      continue;
    }
    ExpectLoadFails(path, options, c.error);
  }
}

// A texture whose optional extension (in extensionsUsed, not extensionsRequired) points at an
// image rigsim cannot decode falls back to its PNG `source` (glTF 2.0, "Extensions"): the other
// image is skipped with one warning naming it. An image no texture uses is skipped the same way
// when it is too large; used, either is refused (ImagesAreCheckedBeforeDecoding).
TEST(GltfLoader, ImagesNoUsedTextureSamplesAreSkippedWhenRigsimCannotDecodeThem) {
  const TempDir dir;
  std::vector<uint8_t> ktx2 = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
  ktx2.resize(80, 0);  // the KTX2 identifier and a (fake) header
  std::vector<uint8_t> dds = {'D', 'D', 'S', ' ', 0x7C, 0, 0, 0};
  dds.resize(128, 0);
  for (const auto& [extension, bytes] : {std::pair{"KHR_texture_basisu", ktx2}, std::pair{"MSFT_texture_dds", dds}}) {
    const std::string file = std::string(extension) + ".image";  // tinygltf takes only PNG and JPEG data URIs
    std::ofstream(dir / file, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    GltfBuilder g;
    const GltfBuilder::TwoSets quad = g.QuadWithTwoTexcoordSets();
    g.doc["extensionsUsed"] = {extension};
    g.doc["images"] = json::array({{{"uri", TinyPngUri()}}, {{"uri", file}}});
    g.doc["textures"] = json::array({{{"source", 0}, {"extensions", {{extension, {{"source", 1}}}}}}});
    g.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    g.Node({{"mesh", g.Mesh({{"POSITION", quad.pos}, {"TEXCOORD_0", quad.uv0}}, -1, 6, 0)}});
    g.Scene({0});
    const Scene s = LoadGltf(g.Write(dir, extension));
    ASSERT_EQ(s.textures.size(), 1u) << extension;
    EXPECT_EQ(s.materials[0].base_color_texture, 0);
    EXPECT_EQ(s.textures[0].width, 2);  // the PNG
    EXPECT_EQ(std::count_if(s.warnings.begin(), s.warnings.end(),
                            [](const std::string& w) { return w.find("image 1") != std::string::npos; }), 1) << extension;
    EXPECT_TRUE(HasWarning(s, "image 1 is not a PNG, JPEG or WebP image (the formats glTF 2.0 and EXT_texture_webp allow); "
                              "no texture rigsim uses samples it, so it is skipped")) << extension;
  }
  // An image over the pixel limit that no texture uses.
  GltfBuilder g;
  g.doc["images"] = json::array({{{"uri", TinyPngUri()}}});
  g.Node({{"mesh", g.Mesh({{"POSITION", g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}})}});
  g.Scene({0});
  GltfLoadOptions small;
  small.max_image_pixels = 3;
  const Scene s = LoadGltf(g.Write(dir, "unused_large"), small);
  EXPECT_TRUE(HasWarning(s, "image 0 is 2x2 pixels, more than the limit of 3 (GltfLoadOptions::max_image_pixels); "
                            "no texture rigsim uses samples it"));
}

}  // namespace
}  // namespace rigsim::gltf_test
