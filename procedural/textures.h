// Seeded texture painting shared by the procedural scene generators (procedural/presets.h): our own
// random generator and hash (output does not depend on the standard library), a float RGB(A)
// canvas, multi-octave value noise and painters for facades, bricks, windows, doors, posters,
// glyphs, graffiti and plain noisy materials. Textures are never tiled, so every patch differs.
//
// Pixel (0, 0) is the top-left corner of the image; colours are sRGB-encoded values in [0, 1].
// Deterministic: the same seed gives the same pixels. Never draw twice from one Rng within one
// function-argument list or one arithmetic expression: their evaluation order is unspecified and
// differs between compilers (GCC vs Clang).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "common/splitmix64.h"

namespace rigsim::procedural {

using Eigen::Vector2f;
using Eigen::Vector3f;

inline constexpr float kPi = 3.14159265358979f;

// ---------------------------------------------------------------------------------------------
// Randomness: our own generator and hash, so that output does not depend on the standard library.
// Never draw twice from one Rng within one function-argument list or one arithmetic expression:
// their evaluation order is unspecified and differs between compilers (GCC vs Clang).

class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(SplitMix64(seed)) {}
  uint64_t Next() { return SplitMix64(state_++); }
  float Uniform() { return float(Next() >> 40) * (1.0f / 16777216.0f); }
  float Uniform(float a, float b) { return a + (b - a) * Uniform(); }
  int Int(int lo, int hi) { return lo + int(Next() % uint64_t(hi - lo + 1)); }  // inclusive
  bool Chance(float p) { return Uniform() < p; }
  uint64_t Fork() { return Next(); }  // seed for an independent sub-stream

 private:
  uint64_t state_;
};

// ---------------------------------------------------------------------------------------------
// A float RGB canvas (ToRgba8 adds an alpha plane for alpha-masked cards).

struct Canvas {
  int w, h;
  std::vector<float> px;  // rgb, row 0 = top
  Canvas(int width, int height, const Vector3f& fill) : w(width), h(height), px(size_t(width) * height * 3) {
    for (size_t i = 0; i < size_t(w) * h; ++i) {
      px[3 * i] = fill[0];
      px[3 * i + 1] = fill[1];
      px[3 * i + 2] = fill[2];
    }
  }
  void Blend(int x, int y, const Vector3f& c, float a) {
    if (x < 0 || y < 0 || x >= w || y >= h) return;
    float* p = &px[(size_t(y) * w + x) * 3];
    for (int k = 0; k < 3; ++k) p[k] += a * (c[k] - p[k]);
  }
  void Scale(int x, int y, float s) {
    if (x < 0 || y < 0 || x >= w || y >= h) return;
    float* p = &px[(size_t(y) * w + x) * 3];
    for (int k = 0; k < 3; ++k) p[k] *= s;
  }
  std::vector<uint8_t> ToRgb8() const {
    std::vector<uint8_t> out(px.size());
    for (size_t i = 0; i < px.size(); ++i) out[i] = uint8_t(std::clamp(px[i], 0.f, 1.f) * 255.f + 0.5f);
    return out;
  }
};

float Lattice(int x, int y, uint64_t seed);

// Smooth value noise in [0, 1] with unit lattice spacing; not periodic.
float ValueNoise(float x, float y, uint64_t seed);

// Adds multi-octave noise (zero mean, +-amplitude) from `coarse_px` down to 2-pixel features:
// blobs at every scale are what blob and corner detectors respond to. `tint` > 0 varies hue too.
void AddNoise(Canvas& c, uint64_t seed, float amplitude, float coarse_px, float tint = 0.f);

void FillRect(Canvas& c, float x0, float y0, float x1, float y1, const Vector3f& col, float alpha = 1.f);

void FillEllipse(Canvas& c, float cx, float cy, float rx, float ry, const Vector3f& col, float alpha = 1.f);

void Stroke(Canvas& c, float x0, float y0, float x1, float y1, float width, const Vector3f& col, float alpha = 1.f);

Vector3f RandomColor(Rng& rng, float lo = 0.1f, float hi = 0.9f);

// Letter-like shapes: 2-4 strokes between points of a 3x5 grid, like sign lettering.
void Glyphs(Canvas& c, Rng& rng, float x, float y, float height, int count, const Vector3f& col);

// Spray-paint-like curves in saturated colours.
void Graffiti(Canvas& c, Rng& rng, float x, float y, float size);

// A poster or sign board with lettering.
void Board(Canvas& c, Rng& rng, float x0, float y0, float x1, float y1);

void Bricks(Canvas& c, Rng& rng, float ppm, float y_from, float y_to, const Vector3f& base);

// A window's glass, in canvas pixels (x0, y0 the top-left corner): where a generator puts a pane.
struct Pane {
  float x0, y0, x1, y1;
};

// A framed window over [x0, x1] x [y0, y1]; its glass (inside the frame) is appended to `panes`
// when given. Recording draws nothing from `rng`: the pixels are the same either way.
void Window(Canvas& c, Rng& rng, float x0, float y0, float x1, float y1, float ppm, const Vector3f& frame,
            std::vector<Pane>* panes = nullptr);

void Door(Canvas& c, Rng& rng, float x0, float y0, float x1, float y1, float ppm);

// A facade `width` x `height` metres: bricks or plaster, floors of windows, a shop or entrance on
// the ground floor, signs, posters and graffiti. Pixel (0, 0) = top-left seen from the street.
// `panes`, when given, receives the glass of every window and shop window (Window's).
Canvas PaintFacade(uint64_t seed, float width, float height, float ppm, std::vector<Pane>* panes = nullptr);

// Generic noisy material texture (walls, poles, bodies): colour + noise + a few marks.
Canvas PaintPlain(uint64_t seed, int w, int h, const Vector3f& base, float amplitude, int marks);

// RGBA8 pixels of `c` with `alpha` (one value in [0, 1] per pixel).
std::vector<uint8_t> ToRgba8(const Canvas& c, const std::vector<float>& alpha);

// Ground and material painters used by the presets; sizes in metres, `ppm` texels per metre.
// Paving slabs with joints, grit, stains and leaves.
Canvas PaintPaving(uint64_t seed, float width_m, float length_m, float ppm);
// Asphalt: noise, aggregate speckles, repair patches, oil stains, cracks (no markings).
Canvas PaintAsphalt(uint64_t seed, float width_m, float length_m, float ppm);
// Grass and soil (Cityscapes "terrain").
Canvas PaintGrass(uint64_t seed, float width_m, float length_m, float ppm);
// An advertising poster with bold shapes and lettering: the same image is put on objects of
// different classes (a bus side and a wall) as a semantic distractor.
Canvas PaintPoster(uint64_t seed, int width, int height);
// Car atlas: top half cabin windows, bottom-left body paint with lights and plate, bottom-right tyre.
Canvas PaintCarAtlas(uint64_t seed, const Vector3f& paint);
// Person atlas: top half shirt, bottom-left trousers, bottom-right skin.
Canvas PaintPersonAtlas(uint64_t seed);
// Foliage card: leaf clusters on a transparent background; `alpha` receives one value per pixel.
Canvas PaintFoliage(uint64_t seed, int size, std::vector<float>* alpha);

}  // namespace rigsim::procedural
