// Texture sampling, seen in rendered colours: the texture coordinate origin, wrap modes, bilinear
// filtering in linear light, mip mapping and the sampler's minification filter.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "renderer/render_test_scenes.h"
#include "renderer/renderer.h"
#include "renderer/srgb.h"
#include "renderer/texture_sampling.h"

namespace rigsim {
namespace {

TEST(TextureSamplingTest, TexcoordOriginIsTheImageTopLeft) {
  Scene scene;
  // 2 x 2: top row red, bottom row blue; the quad's uv (0, 0) corner is its top-left corner.
  const int tex = AddTexture(scene, 2, 2, {{255, 0, 0, 255}, {255, 0, 0, 255}, {0, 0, 255, 255}, {0, 0, 255, 255}});
  AddFrontQuad(scene, -1, 1, -1, 1, 3, kCar, 1, AddMaterial(scene, {1, 1, 1, 1}, tex));
  const Camera camera = SmallPinhole();
  const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), Opts());
  EXPECT_TRUE(IsRed(ColourAt(view, camera, {0, -0.5, 3})));
  EXPECT_TRUE(IsBlue(ColourAt(view, camera, {0, 0.5, 3})));
}

// A 2 x 1 texture (red | blue) on a quad 3 m ahead spanning x in [-2, 2] and u in [0, 2]: u = 1
// is at x = 0 and each unit of x is half a texture width.
RenderedView RenderRedBlueOverTwoRepeats(const Camera& camera, WrapMode mode, bool nearest) {
  Scene scene;
  const int tex = AddTexture(scene, 2, 1, {{255, 0, 0, 255}, {0, 0, 255, 255}}, mode, nearest);
  AddFrontQuad(scene, -2, 2, -1, 1, 3, kCar, 1, AddMaterial(scene, {1, 1, 1, 1}, tex), 2, 1);
  return Renderer(scene).Render(camera, Rigid3d(), Opts());
}

TEST(TextureSamplingTest, WrapModes) {
  // A 2 x 1 texture (red | blue) over u in [0, 2]: four bands of half a texture-width each.
  struct Case {
    WrapMode mode;
    std::array<bool, 4> red;
  };
  for (const Case& c : {Case{WrapMode::kRepeat, {true, false, true, false}},
                        Case{WrapMode::kClampToEdge, {true, false, false, false}},
                        Case{WrapMode::kMirroredRepeat, {true, false, false, true}}}) {
    const Camera camera = SmallPinhole();
    const RenderedView view = RenderRedBlueOverTwoRepeats(camera, c.mode, /*nearest=*/true);
    for (int band = 0; band < 4; ++band) {
      const auto colour = ColourAt(view, camera, {-1.5 + band, 0, 3});
      EXPECT_TRUE(c.red[band] ? IsRed(colour) : IsBlue(colour))
          << "mode " << int(c.mode) << " band " << band << ": " << colour[0] << " " << colour[1] << " " << colour[2];
    }
  }
}

TEST(TextureSamplingTest, BilinearFilteringWrapsAcrossTheTextureEdgeAsTheSamplerSays) {
  // The same red | blue texture over u in [0, 2], filtered bilinearly. At u = 1 and u = 1.5 a
  // look-up straddles the texture's edge: repeat blends the last texel with the first (purple),
  // clamp holds the edge texel (blue), and mirrored repeat reflects (blue at u = 1; at u = 1.5 it
  // reads u = 0.5, halfway between the texels: purple).
  struct Case {
    WrapMode mode;
    std::array<bool, 2> purple;  // at u = 1 and u = 1.5
  };
  auto is_purple = [](const std::array<int, 3>& c) {
    return c[0] > 30 && c[2] > 30 && std::abs(c[0] - c[2]) < 0.25 * std::max(c[0], c[2]) && c[1] == 0;
  };
  for (const Case& c : {Case{WrapMode::kRepeat, {true, true}}, Case{WrapMode::kClampToEdge, {false, false}},
                        Case{WrapMode::kMirroredRepeat, {false, true}}}) {
    const Camera camera = SmallPinhole();
    const RenderedView view = RenderRedBlueOverTwoRepeats(camera, c.mode, /*nearest=*/false);
    for (int i = 0; i < 2; ++i) {
      const auto colour = ColourAt(view, camera, {0.0 + i, 0, 3});  // u = 1 + i / 2
      EXPECT_TRUE(c.purple[i] ? is_purple(colour) : IsBlue(colour))
          << "mode " << int(c.mode) << " u " << 1 + 0.5 * i << ": " << colour[0] << " " << colour[1] << " " << colour[2];
    }
  }
}

TEST(TextureSamplingTest, BilinearFilteringBlendsTexelCentresInLinearLight) {
  // A 2 x 1 texture, black | white, clamped and magnified over a quad spanning x in [-1, 1] at
  // 3 m: texel centres at u = 0.25 and 0.75, a linear-light blend between them. A half-texel
  // offset, or blending the sRGB codes instead of linear light, moves every mid-tone by tens of
  // codes.
  Scene scene, white;
  AddFrontQuad(scene, -1, 1, -1, 1, 3, kRoad, 1,
               AddMaterial(scene, {1, 1, 1, 1},
                           AddTexture(scene, 2, 1, {{0, 0, 0, 255}, {255, 255, 255, 255}}, WrapMode::kClampToEdge, false)));
  AddFrontQuad(white, -1, 1, -1, 1, 3, kRoad, 1,
               AddMaterial(white, {1, 1, 1, 1}, AddTexture(white, 1, 1, {{255, 255, 255, 255}})));
  const Camera camera = SmallPinhole();
  const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), Opts());
  const RenderedView lit = Renderer(white).Render(camera, Rigid3d(), Opts());
  const int y = 23;
  int mid_tones = 0;
  for (int x = 16; x <= 47; ++x) {  // the quad covers x = 14.8 .. 48.2
    const double u = ((x - 31.5) * 3.0 / 50.0 + 1.0) / 2.0;  // the pixel centre's texture coordinate
    const double weight = std::clamp(2.0 * u - 0.5, 0.0, 1.0);  // of the white texel
    const double light = LinearFromSrgbCode(lit.rgb.at(x, y, 0));  // the quad is evenly lit
    EXPECT_NEAR(view.rgb.at(x, y, 0), SrgbCodeFromLinear(weight * light), 2) << "x " << x << " u " << u;
    mid_tones += weight > 0.1 && weight < 0.9;
  }
  EXPECT_GT(mid_tones, 10);
}

// A 128 x 128 black-and-white checker of 4-texel squares.
std::vector<std::array<uint8_t, 4>> Checker128() {
  std::vector<std::array<uint8_t, 4>> checker;
  for (int y = 0; y < 128; ++y) {
    for (int x = 0; x < 128; ++x) {
      const uint8_t v = ((x / 4 + y / 4) % 2) ? 255 : 0;
      checker.push_back({v, v, v, 255});
    }
  }
  return checker;
}

TEST(TextureSamplingTest, MipMappingAveragesAMinifiedChecker) {
  // A 128 x 128 checker of 4-texel squares seen at about 8.3 texels per pixel: point sampling
  // (or a mip level chosen too fine) gives a black-and-white moire; the right level (3, where a
  // texel covers 2 x 2 squares) gives the checker's mean, as a uniform texture of that mean does.
  const std::vector<std::array<uint8_t, 4>> checker = Checker128();
  const uint8_t mean_srgb = 188;  // sRGB encoding of linear 0.5
  Scene scene, uniform;
  // 0.77 m: a non-integer number of texels per pixel, so point samples do not fall on a pattern
  // that happens to average out.
  AddFrontQuad(scene, -0.4f, 0.37f, -0.4f, 0.37f, 2.5f, kRoad, 1,
               AddMaterial(scene, {1, 1, 1, 1}, AddTexture(scene, 128, 128, checker, WrapMode::kRepeat, false)));
  AddFrontQuad(uniform, -0.4f, 0.37f, -0.4f, 0.37f, 2.5f, kRoad, 1,
               AddMaterial(uniform, {1, 1, 1, 1}, AddTexture(uniform, 1, 1, {{mean_srgb, mean_srgb, mean_srgb, 255}})));
  const Camera camera = SmallPinhole();  // the quad covers 15.4 x 15.4 pixels
  const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), Opts());
  const RenderedView reference = Renderer(uniform).Render(camera, Rigid3d(), Opts());
  int checked = 0;
  for (int y = 18; y <= 29; ++y) {
    for (int x = 26; x <= 37; ++x) {
      ASSERT_EQ(view.label.at(x, y), kRoad);
      EXPECT_NEAR(view.rgb.at(x, y, 0), reference.rgb.at(x, y, 0), 6) << x << "," << y;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 144);
}

// A ramp stays where it is on every mip level, also where a level's size is odd (45 -> 22 ->
// 11 -> 5 -> 2 texels): averaging texel pairs there would stretch the texture away from its corner
// (by 1/44 of it from level 1 on, 1/10 from level 3), so that a feature would move on its surface
// with the distance it is seen from. Where a footprint takes part of a texel, that texel's share
// sits a little off its own centre: within 0.05 of a texel of the level, which the stretch
// exceeds at every level from 1 (0.15 texels at s = 0.3 on level 1).
TEST(TextureSamplingTest, MipLevelsOfOddSizesKeepTheTextureInPlace) {
  constexpr int kWidth = 45;
  Texture ramp;
  ramp.width = kWidth;
  ramp.height = 1;
  for (int x = 0; x < kWidth; ++x) ramp.rgba.insert(ramp.rgba.end(), {uint8_t(5 * x), uint8_t(5 * x), uint8_t(5 * x), 255});
  const MipTexture mip = BuildMipTexture(ramp, TexelEncoding::kLinear);
  ASSERT_GE(mip.levels.size(), 5u);
  for (int level = 0; level <= 4; ++level) {
    for (float s = 0.3f; s <= 0.7f; s += 0.05f) {
      const float value = FirstTexelLinear(SampleTexels(mip, s, 0.5f, float(level)))[0];
      // Where the ramp has this value: texel x (value 5 x / 255) is centred at (x + 0.5) / width.
      const float at = (value * 255.0f / 5.0f + 0.5f) / kWidth;
      EXPECT_NEAR(at * mip.levels[level].width, s * mip.levels[level].width, 0.05f) << "level " << level << " s " << s;
    }
  }
}

TEST(TextureSamplingTest, MinificationFilterOfTheSamplerIsHonoured) {
  // The minified checker of MipMappingAveragesAMinifiedChecker under other glTF minFilters: without
  // mip levels (NEAREST) each pixel is one texel, black or white; LINEAR_MIPMAP_NEAREST reads the
  // nearest level (3), whose texels are the checker's mean.
  const std::vector<std::array<uint8_t, 4>> checker = Checker128();
  auto render = [&](bool min_nearest, MipFilter mip, const std::vector<std::array<uint8_t, 4>>& texels) {
    Scene scene;
    const int size = texels.size() == 1 ? 1 : 128;
    const int tex = AddTexture(scene, size, size, texels, WrapMode::kRepeat, false);
    scene.textures[tex].min_nearest = min_nearest;
    scene.textures[tex].mip = mip;
    AddFrontQuad(scene, -0.4f, 0.37f, -0.4f, 0.37f, 2.5f, kRoad, 1, AddMaterial(scene, {1, 1, 1, 1}, tex));
    return Renderer(scene).Render(SmallPinhole(), Rigid3d(), Opts());
  };
  const RenderedView point = render(true, MipFilter::kNone, checker);
  const RenderedView nearest_level = render(false, MipFilter::kNearest, checker);
  const RenderedView trilinear = render(false, MipFilter::kLinear, checker);
  const RenderedView white_texture = render(false, MipFilter::kLinear, {{255, 255, 255, 255}});
  int black = 0, white = 0;
  for (int y = 18; y <= 29; ++y) {
    for (int x = 26; x <= 37; ++x) {
      const int v = point.rgb.at(x, y, 0);
      black += v == 0;
      white += v == white_texture.rgb.at(x, y, 0);
      EXPECT_NEAR(nearest_level.rgb.at(x, y, 0), trilinear.rgb.at(x, y, 0), 6) << x << "," << y;
    }
  }
  EXPECT_EQ(black + white, 144);  // every pixel is one texel (the mix depends on how the grids beat)
  EXPECT_GT(black, 10);
  EXPECT_GT(white, 10);
}

}  // namespace
}  // namespace rigsim
