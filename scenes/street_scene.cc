#include "scenes/street_scene.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "scenes/scene_builder.h"

namespace rigsim {
namespace {

using Eigen::Vector2f;
using Eigen::Vector3f;

constexpr float kPi = 3.14159265358979f;
constexpr float kStreetHalfLength = 60.f;
constexpr float kRoadHalfWidth = 5.f;
constexpr float kFacadeX = 9.f;
constexpr float kCurbHeight = 0.15f;
constexpr float kNearPpm = 72.f;  // texels per metre on surfaces near the origin
constexpr float kFarPpm = 40.f;   // further away, where they cover fewer pixels

// ---------------------------------------------------------------------------------------------
// Randomness: our own generator and hash, so that output does not depend on the standard library.
// Never draw twice from one Rng within one function-argument list or one arithmetic expression:
// their evaluation order is unspecified and differs between compilers (GCC vs Clang).

uint64_t Mix(uint64_t z) {  // splitmix64 finaliser
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(Mix(seed)) {}
  uint64_t Next() { return Mix(state_++); }
  float Uniform() { return float(Next() >> 40) * (1.0f / 16777216.0f); }
  float Uniform(float a, float b) { return a + (b - a) * Uniform(); }
  int Int(int lo, int hi) { return lo + int(Next() % uint64_t(hi - lo + 1)); }  // inclusive
  bool Chance(float p) { return Uniform() < p; }
  uint64_t Fork() { return Next(); }  // seed for an independent sub-stream

 private:
  uint64_t state_;
};

// ---------------------------------------------------------------------------------------------
// Texture painting on a float RGB canvas.

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

float Lattice(int x, int y, uint64_t seed) {
  const uint64_t h = Mix(seed ^ (uint64_t(uint32_t(x)) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(uint32_t(y)) * 0xC2B2AE3D27D4EB4Full));
  return float(h >> 40) * (1.0f / 16777216.0f);
}

// Smooth value noise in [0, 1] with unit lattice spacing; not periodic.
float ValueNoise(float x, float y, uint64_t seed) {
  const float fx = std::floor(x), fy = std::floor(y);
  const int ix = int(fx), iy = int(fy);
  float tx = x - fx, ty = y - fy;
  tx = tx * tx * (3 - 2 * tx);
  ty = ty * ty * (3 - 2 * ty);
  const float a = Lattice(ix, iy, seed), b = Lattice(ix + 1, iy, seed);
  const float c = Lattice(ix, iy + 1, seed), d = Lattice(ix + 1, iy + 1, seed);
  return (a + (b - a) * tx) + ((c + (d - c) * tx) - (a + (b - a) * tx)) * ty;
}

// Adds multi-octave noise (zero mean, +-amplitude) from `coarse_px` down to 2-pixel features:
// blobs at every scale are what blob and corner detectors respond to. `tint` > 0 varies hue too.
void AddNoise(Canvas& c, uint64_t seed, float amplitude, float coarse_px, float tint = 0.f) {
  std::vector<float> scales;
  for (float s = coarse_px; s >= 2.f; s *= 0.5f) scales.push_back(s);
  for (int y = 0; y < c.h; ++y) {
    for (int x = 0; x < c.w; ++x) {
      float v = 0, amp = 1, norm = 0, hue = 0;
      for (size_t o = 0; o < scales.size(); ++o) {
        v += amp * (ValueNoise(x / scales[o], y / scales[o], seed + o) - 0.5f);
        norm += amp;
        amp *= 0.7f;
      }
      if (tint > 0) hue = ValueNoise(x / coarse_px, y / coarse_px, seed + 99) - 0.5f;
      v = v / norm * 2 * amplitude;
      float* p = &c.px[(size_t(y) * c.w + x) * 3];
      p[0] += v + tint * hue;
      p[1] += v;
      p[2] += v - tint * hue;
    }
  }
}

void FillRect(Canvas& c, float x0, float y0, float x1, float y1, const Vector3f& col, float alpha = 1.f) {
  const int ax = std::max(0, int(std::lround(x0))), bx = std::min(c.w, int(std::lround(x1)));
  const int ay = std::max(0, int(std::lround(y0))), by = std::min(c.h, int(std::lround(y1)));
  for (int y = ay; y < by; ++y) {
    for (int x = ax; x < bx; ++x) c.Blend(x, y, col, alpha);
  }
}

void FillEllipse(Canvas& c, float cx, float cy, float rx, float ry, const Vector3f& col, float alpha = 1.f) {
  for (int y = int(cy - ry) - 1; y <= int(cy + ry) + 1; ++y) {
    for (int x = int(cx - rx) - 1; x <= int(cx + rx) + 1; ++x) {
      const float dx = (x - cx) / rx, dy = (y - cy) / ry;
      if (dx * dx + dy * dy <= 1.f) c.Blend(x, y, col, alpha);
    }
  }
}

void Stroke(Canvas& c, float x0, float y0, float x1, float y1, float width, const Vector3f& col, float alpha = 1.f) {
  const float len = std::hypot(x1 - x0, y1 - y0);
  const float r = std::max(0.5f, width * 0.5f);
  const int minx = int(std::min(x0, x1) - r) - 1, maxx = int(std::max(x0, x1) + r) + 1;
  const int miny = int(std::min(y0, y1) - r) - 1, maxy = int(std::max(y0, y1) + r) + 1;
  for (int y = miny; y <= maxy; ++y) {
    for (int x = minx; x <= maxx; ++x) {
      float t = len > 0 ? ((x - x0) * (x1 - x0) + (y - y0) * (y1 - y0)) / (len * len) : 0.f;
      t = std::clamp(t, 0.f, 1.f);
      const float d = std::hypot(x - (x0 + t * (x1 - x0)), y - (y0 + t * (y1 - y0)));
      if (d <= r) c.Blend(x, y, col, alpha);
    }
  }
}

Vector3f RandomColor(Rng& rng, float lo = 0.1f, float hi = 0.9f) {
  const float r = rng.Uniform(lo, hi), g = rng.Uniform(lo, hi), b = rng.Uniform(lo, hi);
  return Vector3f(r, g, b);
}

// Letter-like shapes: 2-4 strokes between points of a 3x5 grid, like sign lettering.
void Glyphs(Canvas& c, Rng& rng, float x, float y, float height, int count, const Vector3f& col) {
  const float cell = height / 4.f, width = std::max(1.f, height * 0.12f);
  for (int g = 0; g < count; ++g) {
    const int strokes = rng.Int(2, 4);
    for (int s = 0; s < strokes; ++s) {
      const float ax = x + float(rng.Int(0, 2)) * cell;
      const float ay = y + float(rng.Int(0, 4)) * cell;
      const float bx = x + float(rng.Int(0, 2)) * cell;
      const float by = y + float(rng.Int(0, 4)) * cell;
      Stroke(c, ax, ay, bx, by, width, col);
    }
    if (rng.Chance(0.3f)) FillEllipse(c, x + cell, y + 2 * cell, cell * 0.8f, cell * 0.8f, col);
    x += 3 * cell;
  }
}

// Spray-paint-like curves in saturated colours.
void Graffiti(Canvas& c, Rng& rng, float x, float y, float size) {
  const Vector3f col = RandomColor(rng, 0.f, 1.f);
  const int strokes = rng.Int(3, 7);
  float px = x, py = y;
  for (int s = 0; s < strokes; ++s) {
    float angle = rng.Uniform(0, 2 * kPi);
    for (int k = 0; k < 8; ++k) {
      angle += rng.Uniform(-0.6f, 0.6f);
      const float nx = std::clamp(px + std::cos(angle) * size * 0.1f, x - size, x + size);
      const float ny = std::clamp(py + std::sin(angle) * size * 0.1f, y - size * 0.5f, y + size * 0.5f);
      Stroke(c, px, py, nx, ny, size * 0.06f, col, 0.85f);
      px = nx;
      py = ny;
    }
  }
  if (rng.Chance(0.6f)) {
    const int n = rng.Int(2, 4);
    const Vector3f col2 = RandomColor(rng, 0.f, 1.f);
    Glyphs(c, rng, x - size * 0.5f, y - size * 0.2f, size * 0.35f, n, col2);
  }
}

// A poster or sign board with lettering.
void Board(Canvas& c, Rng& rng, float x0, float y0, float x1, float y1) {
  FillRect(c, x0, y0, x1, y1, RandomColor(rng));
  const float h = y1 - y0;
  const int n = std::max(1, int((x1 - x0) / (h * 0.6f)) - 1);
  Glyphs(c, rng, x0 + h * 0.2f, y0 + h * 0.25f, h * 0.5f, std::min(n, 12), RandomColor(rng, 0.f, 1.f));
  Stroke(c, x0, y0, x1, y0, 2, Vector3f(0.1f, 0.1f, 0.1f));
  Stroke(c, x0, y1, x1, y1, 2, Vector3f(0.1f, 0.1f, 0.1f));
}

void Bricks(Canvas& c, Rng& rng, float ppm, float y_from, float y_to, const Vector3f& base) {
  const float bw = 0.25f * ppm, bh = 0.075f * ppm, mortar = std::max(1.f, 0.012f * ppm);
  const Vector3f mortar_col(0.72f, 0.70f, 0.66f);
  FillRect(c, 0, y_from, float(c.w), y_to, mortar_col);
  int row = 0;
  for (float y = y_from; y < y_to; y += bh, ++row) {
    const float shift = (row % 2) * bw * 0.5f;
    for (float x = -shift; x < c.w; x += bw) {
      const float j = rng.Uniform(-0.12f, 0.12f);
      const float jr = rng.Uniform(-0.03f, 0.03f), jb = rng.Uniform(-0.03f, 0.03f);
      const Vector3f col = (base + Vector3f(j + jr, j, j + jb)).cwiseMax(0.f);
      FillRect(c, x + mortar * 0.5f, y + mortar * 0.5f, x + bw - mortar * 0.5f, std::min(y + bh - mortar * 0.5f, y_to), col);
    }
  }
}

void Window(Canvas& c, Rng& rng, float x0, float y0, float x1, float y1, float ppm, const Vector3f& frame) {
  const float f = std::max(2.f, 0.08f * ppm);
  FillRect(c, x0 - f * 0.5f, y1, x1 + f * 0.5f, y1 + f * 0.8f, Vector3f(0.8f, 0.78f, 0.74f));  // sill
  FillRect(c, x0, y0, x1, y1, frame);
  // Glass: dark with a vertical reflection gradient, random curtains and a reflected blob.
  const float gr = rng.Uniform(0.05f, 0.15f), gg = rng.Uniform(0.08f, 0.18f), gb = rng.Uniform(0.12f, 0.25f);
  const Vector3f glass(gr, gg, gb);
  for (int y = int(y0 + f); y < int(y1 - f); ++y) {
    const float t = (y - y0) / std::max(1.f, y1 - y0);
    for (int x = int(x0 + f); x < int(x1 - f); ++x) c.Blend(x, y, glass * (1.4f - 0.6f * t), 1.f);
  }
  if (rng.Chance(0.6f)) {
    const Vector3f cur = RandomColor(rng, 0.4f, 0.95f);
    const float cw = (x1 - x0) * rng.Uniform(0.15f, 0.45f);
    FillRect(c, x0 + f, y0 + f, x0 + f + cw, y1 - f, cur, 0.9f);
    if (rng.Chance(0.5f)) FillRect(c, x1 - f - cw, y0 + f, x1 - f, y1 - f, cur, 0.9f);
  }
  if (rng.Chance(0.5f)) {
    const float ex = rng.Uniform(x0, x1), ey = rng.Uniform(y0, y1);
    FillEllipse(c, ex, ey, (x1 - x0) * 0.2f, (y1 - y0) * 0.1f, Vector3f(0.7f, 0.75f, 0.8f), 0.35f);
  }
  // Mullions: a cross, or a single vertical bar.
  const float mx = (x0 + x1) * 0.5f;
  FillRect(c, mx - f * 0.4f, y0, mx + f * 0.4f, y1, frame);
  if (rng.Chance(0.6f)) {
    const float my = y0 + (y1 - y0) * rng.Uniform(0.25f, 0.4f);
    FillRect(c, x0, my - f * 0.4f, x1, my + f * 0.4f, frame);
  }
}

void Door(Canvas& c, Rng& rng, float x0, float y0, float x1, float y1, float ppm) {
  const Vector3f wood = RandomColor(rng, 0.1f, 0.5f);
  FillRect(c, x0 - 0.1f * ppm, y0 - 0.1f * ppm, x1 + 0.1f * ppm, y1, Vector3f(0.85f, 0.83f, 0.8f));
  FillRect(c, x0, y0, x1, y1, wood);
  const float m = 0.1f * ppm;
  const float mid = (y0 + y1) * 0.45f;
  FillRect(c, x0 + m, y0 + m, x1 - m, mid - m * 0.5f, wood * 0.7f);
  FillRect(c, x0 + m, mid + m * 0.5f, x1 - m, y1 - m, wood * 0.7f);
  FillEllipse(c, x1 - 1.5f * m, (y0 + y1) * 0.55f, 0.03f * ppm + 1, 0.03f * ppm + 1, Vector3f(0.85f, 0.75f, 0.3f));
  if (rng.Chance(0.5f)) FillRect(c, x0 + m, y0 - 0.5f * ppm, x1 - m, y0 - 0.15f * ppm, Vector3f(0.12f, 0.14f, 0.2f));  // transom
}

// A facade `width` x `height` metres: bricks or plaster, floors of windows, a shop or entrance on
// the ground floor, signs, posters and graffiti. Pixel (0, 0) = top-left seen from the street.
Canvas PaintFacade(uint64_t seed, float width, float height, float ppm) {
  Rng rng(seed);
  const int w = std::max(8, int(width * ppm)), h = std::max(8, int(height * ppm));
  const bool brick = rng.Chance(0.55f);
  Vector3f base = RandomColor(rng, 0.45f, 0.9f);
  if (brick) {
    const float br = rng.Uniform(0.45f, 0.7f), bg = rng.Uniform(0.2f, 0.35f), bb = rng.Uniform(0.12f, 0.25f);
    base = Vector3f(br, bg, bb);
  }
  Canvas c(w, h, base);
  auto Y = [&](float metres_above_ground) { return h - metres_above_ground * ppm; };  // to pixel row
  if (brick) Bricks(c, rng, ppm, 0, float(h), base);
  AddNoise(c, rng.Fork(), brick ? 0.06f : 0.09f, 48, 0.03f);
  // Plaster stains and repaired patches.
  if (!brick) {
    for (int i = 0, n = int(width * height * 0.05f); i < n; ++i) {
      const float x = rng.Uniform(0, float(w)), y = rng.Uniform(0, float(h));
      const float pw = rng.Uniform(0.3f, 1.5f) * ppm, ph = rng.Uniform(0.2f, 1.f) * ppm, tone = rng.Uniform(0.85f, 1.1f);
      FillRect(c, x, y, x + pw, y + ph, base * tone, 0.6f);
    }
  }
  if (!brick) {
    // Quoins at both corners and hairline cracks: plaster alone is too smooth for detectors.
    const Vector3f stone = base * rng.Uniform(0.75f, 0.9f);
    for (float y = 0.4f * ppm; y < h; y += 0.6f * ppm) {
      const float len = (int(y / (0.6f * ppm)) % 2 ? 0.5f : 0.8f) * ppm;
      FillRect(c, 0, y, len, y + 0.55f * ppm, stone);
      FillRect(c, float(w) - len, y, float(w), y + 0.55f * ppm, stone);
    }
    for (int i = 0, n = int(width * height * 0.04f); i < n; ++i) {
      float x = rng.Uniform(0, float(w)), y = rng.Uniform(0, float(h)), a = rng.Uniform(0, 2 * kPi);
      for (int k = 0, steps = rng.Int(5, 20); k < steps; ++k) {
        a += rng.Uniform(-0.8f, 0.8f);
        const float nx = x + std::cos(a) * 0.06f * ppm, ny = y + std::sin(a) * 0.06f * ppm;
        Stroke(c, x, y, nx, ny, 1.f, base * 0.55f, 0.8f);
        x = nx;
        y = ny;
      }
    }
  }
  // Cornice and floor bands.
  const Vector3f trim = RandomColor(rng, 0.6f, 0.95f);
  FillRect(c, 0, 0, float(w), 0.35f * ppm, trim);
  Stroke(c, 0, 0.35f * ppm, float(w), 0.35f * ppm, 2, trim * 0.5f);
  const float ground = 4.f, floor_h = rng.Uniform(3.0f, 3.5f);
  FillRect(c, 0, Y(ground), float(w), Y(ground) + 0.25f * ppm, trim);

  // Upper floors: a regular grid of windows with per-window variation.
  const float pitch = rng.Uniform(2.4f, 3.4f), win_w = rng.Uniform(0.9f, 1.4f), win_h = rng.Uniform(1.3f, 1.8f);
  const Vector3f frame = rng.Chance(0.5f) ? Vector3f(0.92f, 0.92f, 0.9f) : RandomColor(rng, 0.15f, 0.6f);
  const int cols = std::max(1, int(width / pitch));
  const float margin = (width - cols * pitch) * 0.5f;
  for (float fy = ground; fy + floor_h < height - 0.3f; fy += floor_h) {
    for (int k = 0; k < cols; ++k) {
      const float cx = (margin + (k + 0.5f) * pitch) * ppm;
      const float bottom = Y(fy + 0.9f);
      Window(c, rng, cx - win_w * ppm * 0.5f, bottom - win_h * ppm, cx + win_w * ppm * 0.5f, bottom, ppm, frame);
      if (rng.Chance(0.15f)) {  // a balcony rail or flower box
        FillRect(c, cx - win_w * ppm * 0.6f, bottom, cx + win_w * ppm * 0.6f, bottom + 0.3f * ppm, RandomColor(rng, 0.1f, 0.6f));
        for (float x = cx - win_w * ppm * 0.6f; x < cx + win_w * ppm * 0.6f; x += 0.12f * ppm) {
          Stroke(c, x, bottom, x, bottom + 0.3f * ppm, 1.5f, Vector3f(0.1f, 0.1f, 0.1f));
        }
      }
    }
  }

  // Ground floor: shop fronts with a sign band, or an entrance with small windows.
  float x = rng.Uniform(0.3f, 1.0f) * ppm;
  while (x < w - 1.5f * ppm) {
    const float unit = std::min(rng.Uniform(3.f, 6.f) * ppm, w - x - 0.3f * ppm);
    if (unit < 1.5f * ppm) break;
    if (rng.Chance(0.6f)) {
      Board(c, rng, x, Y(3.75f), x + unit, Y(3.1f));
      const float door_w = 1.1f * ppm;
      Door(c, rng, x + 0.2f * ppm, Y(2.4f), x + 0.2f * ppm + door_w, Y(0.05f), ppm);
      Window(c, rng, x + 0.4f * ppm + door_w, Y(2.7f), x + unit - 0.2f * ppm, Y(0.5f), ppm, RandomColor(rng, 0.1f, 0.5f));
      if (rng.Chance(0.5f)) {  // lettering on the shop window
        Glyphs(c, rng, x + 0.6f * ppm + door_w, Y(2.2f), 0.25f * ppm, rng.Int(3, 8), Vector3f(0.95f, 0.95f, 0.9f));
      }
    } else {
      Door(c, rng, x + unit * 0.5f - 0.5f * ppm, Y(2.3f), x + unit * 0.5f + 0.5f * ppm, Y(0.05f), ppm);
      Window(c, rng, x + 0.2f * ppm, Y(2.6f), x + unit * 0.5f - 0.8f * ppm, Y(1.0f), ppm, frame);
      Window(c, rng, x + unit * 0.5f + 0.8f * ppm, Y(2.6f), x + unit - 0.2f * ppm, Y(1.0f), ppm, frame);
      if (rng.Chance(0.7f)) {  // house number plate
        FillRect(c, x + unit * 0.5f + 0.6f * ppm, Y(2.2f), x + unit * 0.5f + 0.85f * ppm, Y(2.0f), Vector3f(0.1f, 0.2f, 0.6f));
        Glyphs(c, rng, x + unit * 0.5f + 0.63f * ppm, Y(2.17f), 0.13f * ppm, 1, Vector3f(1, 1, 1));
      }
    }
    x += unit + rng.Uniform(0.2f, 0.8f) * ppm;
  }
  // Posters, graffiti, a drainpipe and the grime line at the bottom.
  for (int i = 0, n = rng.Int(0, 3); i < n; ++i) {
    const float px = rng.Uniform(0, float(w) - 1.0f * ppm), py = Y(rng.Uniform(1.0f, 2.2f));
    const float pw = rng.Uniform(0.4f, 0.8f) * ppm, ph = rng.Uniform(0.5f, 0.9f) * ppm;
    Board(c, rng, px, py, px + pw, py + ph);
  }
  for (int i = 0, n = rng.Chance(0.6f) ? rng.Int(1, 3) : 0; i < n; ++i) {
    const float gx = rng.Uniform(0, float(w)), gy = Y(rng.Uniform(0.5f, 1.6f)), gs = rng.Uniform(0.6f, 1.5f) * ppm;
    Graffiti(c, rng, gx, gy, gs);
  }
  const float pipe = rng.Uniform(0.2f, 0.6f) * ppm;
  FillRect(c, pipe, 0.35f * ppm, pipe + 0.1f * ppm, float(h), Vector3f(0.35f, 0.35f, 0.38f));
  for (float y = 0.35f * ppm; y < h; y += 2.f * ppm) FillRect(c, pipe - 2, y, pipe + 0.1f * ppm + 2, y + 0.05f * ppm + 1, Vector3f(0.2f, 0.2f, 0.2f));
  for (int y = int(Y(0.6f)); y < h; ++y) {
    const float t = (y - Y(0.6f)) / (0.6f * ppm);
    for (int xx = 0; xx < w; ++xx) c.Scale(xx, y, 1.f - 0.3f * t * ValueNoise(xx / 6.f, y / 6.f, seed + 7));
  }
  return c;
}

// Asphalt for the road segment x in [-5, 5], z in [z0, z0 + len]; texture u along +x, v along +z.
Canvas PaintRoad(uint64_t seed, float z0, float len, float ppm) {
  Rng rng(seed);
  const float width = 2 * kRoadHalfWidth;
  const int w = int(width * ppm), h = int(len * ppm);
  Canvas c(w, h, Vector3f(0.27f, 0.27f, 0.28f));
  auto U = [&](float x) { return (x + kRoadHalfWidth) * ppm; };
  auto V = [&](float z) { return (z - z0) * ppm; };
  AddNoise(c, rng.Fork(), 0.07f, 64);
  // Repair patches with sharp edges and their own grain.
  for (int i = 0, n = rng.Int(2, 6); i < n; ++i) {
    const float x = rng.Uniform(0, float(w)), y = rng.Uniform(0, float(h));
    const float pw = rng.Uniform(0.5f, 2.5f) * ppm, ph = rng.Uniform(0.5f, 3.f) * ppm, tone = rng.Uniform(0.18f, 0.36f);
    FillRect(c, x, y, x + pw, y + ph, Vector3f::Constant(tone), 0.8f);
  }
  // Aggregate: light and dark speckles at a few sizes.
  for (int i = 0, n = int(width * len * 25); i < n; ++i) {
    const float r = rng.Uniform(0.6f, 2.2f), ex = rng.Uniform(0, float(w)), ey = rng.Uniform(0, float(h));
    const float tone = rng.Chance(0.5f) ? 0.55f : 0.12f;
    FillEllipse(c, ex, ey, r, r, Vector3f::Constant(tone), 0.6f);
  }
  // Oil stains.
  for (int i = 0, n = rng.Int(1, 4); i < n; ++i) {
    const float ex = rng.Uniform(0, float(w)), ey = rng.Uniform(0, float(h));
    const float rx = rng.Uniform(0.2f, 0.6f) * ppm, ry = rng.Uniform(0.2f, 0.6f) * ppm;
    FillEllipse(c, ex, ey, rx, ry, Vector3f(0.1f, 0.1f, 0.1f), 0.35f);
  }
  // Lane markings in world coordinates, so that they continue across segments.
  const Vector3f paint(0.9f, 0.9f, 0.86f);
  auto Worn = [&](float x0, float y0, float x1, float y1) {
    for (int y = std::max(0, int(y0)); y < std::min(h, int(y1)); ++y) {
      for (int x = std::max(0, int(x0)); x < std::min(w, int(x1)); ++x) {
        const float wear = ValueNoise(x / 5.f, y / 5.f, seed + 11);
        if (wear > 0.25f) c.Blend(x, y, paint, 0.9f);
      }
    }
  };
  for (float z = std::floor(z0 / 9.f) * 9.f; z < z0 + len; z += 9.f) Worn(U(-0.06f), V(z), U(0.06f), V(z + 3.f));  // centre dashes
  Worn(U(-4.7f), 0, U(-4.58f), float(h));
  Worn(U(4.58f), 0, U(4.7f), float(h));
  // A zebra crossing near z = 8 m.
  if (z0 <= 9.f && z0 + len >= 6.f) {
    for (float x = -4.2f; x < 4.2f; x += 1.0f) Worn(U(x), V(6.f), U(x + 0.5f), V(9.f));
  }
  // Cracks: thin random walks.
  for (int i = 0, n = rng.Int(3, 9); i < n; ++i) {
    float x = rng.Uniform(0, float(w)), y = rng.Uniform(0, float(h)), a = rng.Uniform(0, 2 * kPi);
    for (int k = 0, steps = rng.Int(10, 40); k < steps; ++k) {
      a += rng.Uniform(-0.7f, 0.7f);
      const float nx = x + std::cos(a) * 0.08f * ppm, ny = y + std::sin(a) * 0.08f * ppm;
      Stroke(c, x, y, nx, ny, 1.2f, Vector3f(0.06f, 0.06f, 0.06f), 0.9f);
      x = nx;
      y = ny;
    }
  }
  // Manhole covers: a ring and a grid of bosses.
  for (int i = 0, n = rng.Chance(0.7f) ? rng.Int(1, 2) : 0; i < n; ++i) {
    const float cx = rng.Uniform(1.f, width - 1.f) * ppm, cy = rng.Uniform(1.f, len - 1.f) * ppm, r = 0.32f * ppm;
    FillEllipse(c, cx, cy, r, r, Vector3f(0.2f, 0.19f, 0.18f));
    FillEllipse(c, cx, cy, r * 0.88f, r * 0.88f, Vector3f(0.33f, 0.31f, 0.29f));
    for (float gy = -r * 0.7f; gy <= r * 0.7f; gy += 0.07f * ppm) {
      for (float gx = -r * 0.7f; gx <= r * 0.7f; gx += 0.07f * ppm) {
        if (gx * gx + gy * gy < r * r * 0.6f) FillEllipse(c, cx + gx, cy + gy, 0.015f * ppm + 0.5f, 0.015f * ppm + 0.5f, Vector3f(0.15f, 0.15f, 0.14f));
      }
    }
  }
  return c;
}

// Paving for a sidewalk strip 4 m wide (u across, starting at the curb) by `len` m (v along z).
Canvas PaintSidewalk(uint64_t seed, float len, float ppm) {
  Rng rng(seed);
  const float width = kFacadeX - kRoadHalfWidth;
  const int w = int(width * ppm), h = int(len * ppm);
  const Vector3f base = Vector3f::Constant(rng.Uniform(0.5f, 0.62f));
  Canvas c(w, h, base);
  const float slab = rng.Uniform(0.4f, 0.6f) * ppm, joint = std::max(1.f, 0.01f * ppm);
  for (float y = 0; y < h; y += slab) {
    for (float x = 0.3f * ppm; x < w; x += slab) {
      FillRect(c, x + joint, y + joint, x + slab - joint, y + slab - joint, base * rng.Uniform(0.85f, 1.12f));
      if (rng.Chance(0.05f)) {  // cracked slab
        const float ya = y + rng.Uniform(0, slab), yb = y + rng.Uniform(0, slab);
        Stroke(c, x, ya, x + slab, yb, 1.2f, base * 0.4f);
      }
    }
  }
  // Curb stones along the road edge (u = 0).
  for (float y = 0; y < h; y += 0.8f * ppm) FillRect(c, 0, y + joint, 0.3f * ppm - joint, y + 0.8f * ppm - joint, Vector3f::Constant(rng.Uniform(0.62f, 0.75f)));
  AddNoise(c, rng.Fork(), 0.08f, 32);
  for (int i = 0, n = int(width * len * 20); i < n; ++i) {  // grit: small light and dark speckles
    const float r = rng.Uniform(0.6f, 2.f), ex = rng.Uniform(0, float(w)), ey = rng.Uniform(0, float(h));
    const float tone = rng.Chance(0.5f) ? 0.8f : 0.25f;
    FillEllipse(c, ex, ey, r, r, Vector3f::Constant(tone), 0.6f);
  }
  for (int i = 0, n = int(width * len * 0.3f); i < n; ++i) {  // water stains and fallen leaves
    const float r = rng.Uniform(0.05f, 0.3f) * ppm, ex = rng.Uniform(0, float(w)), ey = rng.Uniform(0, float(h));
    const float ry = r * rng.Uniform(0.4f, 1.f);
    const Vector3f col = rng.Chance(0.5f) ? Vector3f(0.35f, 0.33f, 0.3f) : Vector3f(0.55f, 0.4f, 0.15f);
    FillEllipse(c, ex, ey, r, ry, col, 0.5f);
  }
  for (int i = 0, n = int(width * len * 3); i < n; ++i) {  // gum and stains
    const float r = rng.Uniform(0.8f, 0.04f * ppm), ex = rng.Uniform(0, float(w)), ey = rng.Uniform(0, float(h));
    const float tone = rng.Uniform(0.15f, 0.35f);
    FillEllipse(c, ex, ey, r, r, Vector3f::Constant(tone), 0.7f);
  }
  if (rng.Chance(0.4f)) {
    const float gx = rng.Uniform(0, float(w)), gy = rng.Uniform(0, float(h));
    Graffiti(c, rng, gx, gy, 0.8f * ppm);
  }
  return c;
}

// Generic noisy material texture (walls, poles, bodies): colour + noise + a few marks.
Canvas PaintPlain(uint64_t seed, int w, int h, const Vector3f& base, float amplitude, int marks) {
  Rng rng(seed);
  Canvas c(w, h, base);
  AddNoise(c, rng.Fork(), amplitude, std::max(4.f, std::min(w, h) / 4.f), 0.02f);
  for (int i = 0; i < marks; ++i) {
    const float r = rng.Uniform(1.f, std::max(2.f, std::min(w, h) / 16.f));
    const float ex = rng.Uniform(0, float(w)), ey = rng.Uniform(0, float(h)), ry = r * rng.Uniform(0.5f, 1.5f);
    const float tone = rng.Uniform(0.5f, 1.3f);
    FillEllipse(c, ex, ey, r, ry, base * tone, 0.7f);
  }
  return c;
}

// ---------------------------------------------------------------------------------------------
// Geometry helpers. Quads are given by their top-left corner and the full right and down edges
// as seen from the front; the front normal is right x up, triangles counter-clockwise from it.

struct UvRect {
  float u0 = 0, v0 = 0, u1 = 1, v1 = 1;
};

void AddQuad(MeshData& m, const Vector3f& tl, const Vector3f& right, const Vector3f& down, const UvRect& uv = {}) {
  const uint32_t b = uint32_t(m.positions.size());
  const Vector3f n = right.cross(-down).normalized();
  m.positions.insert(m.positions.end(), {tl, tl + right, tl + down, tl + right + down});
  m.normals.insert(m.normals.end(), {n, n, n, n});
  m.texcoords.insert(m.texcoords.end(), {Vector2f(uv.u0, uv.v0), Vector2f(uv.u1, uv.v0), Vector2f(uv.u0, uv.v1), Vector2f(uv.u1, uv.v1)});
  m.indices.insert(m.indices.end(), {b, b + 2, b + 3, b, b + 3, b + 1});
}

// Axis-aligned box; every face shows `uv` of the texture.
void AddBox(MeshData& m, const Vector3f& lo, const Vector3f& hi, const UvRect& uv = {}) {
  const Vector3f d = hi - lo;
  AddQuad(m, Vector3f(hi.x(), hi.y(), hi.z()), Vector3f(0, 0, -d.z()), Vector3f(0, -d.y(), 0), uv);  // +x
  AddQuad(m, Vector3f(lo.x(), hi.y(), lo.z()), Vector3f(0, 0, d.z()), Vector3f(0, -d.y(), 0), uv);   // -x
  AddQuad(m, Vector3f(lo.x(), hi.y(), hi.z()), Vector3f(d.x(), 0, 0), Vector3f(0, -d.y(), 0), uv);   // +z
  AddQuad(m, Vector3f(hi.x(), hi.y(), lo.z()), Vector3f(-d.x(), 0, 0), Vector3f(0, -d.y(), 0), uv);  // -z
  AddQuad(m, Vector3f(lo.x(), hi.y(), lo.z()), Vector3f(d.x(), 0, 0), Vector3f(0, 0, d.z()), uv);    // +y
  AddQuad(m, Vector3f(lo.x(), lo.y(), hi.z()), Vector3f(d.x(), 0, 0), Vector3f(0, 0, -d.z()), uv);   // -y
}

// Vertical cylinder (with a top cap) standing on `base`.
void AddCylinder(MeshData& m, const Vector3f& base, float radius, float height, int segments, const UvRect& uv = {}) {
  for (int i = 0; i < segments; ++i) {
    const float a0 = 2 * kPi * i / segments, a1 = 2 * kPi * (i + 1) / segments;
    const Vector3f p0 = base + Vector3f(radius * std::sin(a0), height, radius * std::cos(a0));
    const Vector3f p1 = base + Vector3f(radius * std::sin(a1), height, radius * std::cos(a1));
    const float u0 = uv.u0 + (uv.u1 - uv.u0) * i / segments, u1 = uv.u0 + (uv.u1 - uv.u0) * (i + 1) / segments;
    AddQuad(m, p0, p1 - p0, Vector3f(0, -height, 0), {u0, uv.v0, u1, uv.v1});
    const uint32_t b = uint32_t(m.positions.size());
    const Vector3f top = base + Vector3f(0, height, 0);
    m.positions.insert(m.positions.end(), {top, p0, p1});
    m.normals.insert(m.normals.end(), 3, Vector3f(0, 1, 0));
    m.texcoords.insert(m.texcoords.end(), {Vector2f(uv.u0, uv.v0), Vector2f(u0, uv.v0), Vector2f(u1, uv.v0)});
    m.indices.insert(m.indices.end(), {b, b + 1, b + 2});
  }
}

// Sphere-like blob with radial noise (tree crowns, heads).
void AddBlob(MeshData& m, const Vector3f& centre, const Vector3f& radii, float bumpiness, uint64_t seed, const UvRect& uv = {}) {
  const int stacks = 10, slices = 16;
  const uint32_t b = uint32_t(m.positions.size());
  for (int i = 0; i <= stacks; ++i) {
    const float th = kPi * i / stacks;
    for (int j = 0; j <= slices; ++j) {
      const float ph = 2 * kPi * j / slices;
      const Vector3f dir(std::sin(th) * std::sin(ph), std::cos(th), std::sin(th) * std::cos(ph));
      const float r = 1.f + bumpiness * (ValueNoise(float(j % slices) * 0.7f, float(i) * 0.7f, seed) - 0.5f);
      m.positions.push_back(centre + r * dir.cwiseProduct(radii));
      m.normals.push_back(dir);
      m.texcoords.emplace_back(uv.u0 + (uv.u1 - uv.u0) * j / slices, uv.v0 + (uv.v1 - uv.v0) * i / stacks);
    }
  }
  for (int i = 0; i < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      const uint32_t tl = b + i * (slices + 1) + j, tr = tl + 1, bl = tl + slices + 1, br = bl + 1;
      if (i > 0) m.indices.insert(m.indices.end(), {tl, bl, br});
      if (i < stacks - 1) m.indices.insert(m.indices.end(), {tl, br, tr});
    }
  }
}

Eigen::Matrix4d Placement(float x, float z, float yaw) {
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  t.translate(Eigen::Vector3d(x, 0, z));
  t.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()));
  return t.matrix();
}

// ---------------------------------------------------------------------------------------------

class StreetGenerator {
 public:
  explicit StreetGenerator(uint64_t seed) : rng_(seed) {}

  SceneBuilder Build() {
    Road();
    Sidewalks();
    Buildings();
    EndBuildings();
    Lamps();
    Signs();
    Railing();
    Cars();
    People();
    Trees();
    return std::move(b_);
  }

 private:
  int Material(const std::string& name, const Canvas& c) {
    const int tex = b_.AddTexture(name, c.w, c.h, 3, c.ToRgb8());
    return b_.AddMaterial(name, Eigen::Vector4f::Ones(), tex);
  }
  static float PpmAt(float z_near) { return std::abs(z_near) < 25.f ? kNearPpm : kFarPpm; }
  static float NearestAbs(float z0, float z1) { return (z0 <= 0 && z1 >= 0) ? 0.f : std::min(std::abs(z0), std::abs(z1)); }

  void Road() {
    for (float z0 = -kStreetHalfLength; z0 < kStreetHalfLength; z0 += 10.f) {
      const float ppm = NearestAbs(z0, z0 + 10) < 25.f ? 64.f : 32.f;
      const int mat = Material("road_" + std::to_string(int(z0)), PaintRoad(rng_.Fork(), z0, 10.f, ppm));
      MeshData m;
      // Seen from above: u along +x, v along +z, normal +y.
      AddQuad(m, Vector3f(-kRoadHalfWidth, 0, z0), Vector3f(2 * kRoadHalfWidth, 0, 0), Vector3f(0, 0, 10.f));
      b_.AddNode("road_" + std::to_string(int(z0)), "road", std::move(m), mat);
    }
  }

  void Sidewalks() {
    const float width = kFacadeX - kRoadHalfWidth;
    for (int side = -1; side <= 1; side += 2) {
      for (float z0 = -kStreetHalfLength; z0 < kStreetHalfLength; z0 += 10.f) {
        const float ppm = NearestAbs(z0, z0 + 10) < 25.f ? 64.f : 32.f;
        const std::string name = std::string(side < 0 ? "sidewalk_left_" : "sidewalk_right_") + std::to_string(int(z0));
        const int mat = Material(name, PaintSidewalk(rng_.Fork(), 10.f, ppm));
        MeshData m;
        const float curb = side * kRoadHalfWidth;
        // Top: u from the curb outwards (texture column 0 = curb stones), v along +z.
        if (side > 0) {
          AddQuad(m, Vector3f(curb, kCurbHeight, z0), Vector3f(width, 0, 0), Vector3f(0, 0, 10.f));
        } else {
          AddQuad(m, Vector3f(curb, kCurbHeight, z0 + 10.f), Vector3f(-width, 0, 0), Vector3f(0, 0, -10.f), {0, 1, 1, 0});
        }
        // Curb face towards the road, showing the curb-stone column of the texture.
        const UvRect curb_uv{0, 0, 0.05f, 1};
        if (side > 0) {
          AddQuad(m, Vector3f(curb, kCurbHeight, z0), Vector3f(0, 0, 10.f), Vector3f(0, -kCurbHeight, 0), curb_uv);
        } else {
          AddQuad(m, Vector3f(curb, kCurbHeight, z0 + 10.f), Vector3f(0, 0, -10.f), Vector3f(0, -kCurbHeight, 0), curb_uv);
        }
        b_.AddNode(name, "sidewalk", std::move(m), mat);
      }
    }
  }

  // One building as a box whose street-facing side carries its own facade texture.
  // `front_x` is the facade plane, `side` = +1 for the right (+x) side of the street.
  void Building(const std::string& name, int side, float front_x, float z0, float z1, float height) {
    const float ppm = PpmAt(NearestAbs(z0, z1));
    const float width = z1 - z0;
    const int facade = Material(name + "_facade", PaintFacade(rng_.Fork(), width, height, ppm));
    const uint64_t sides_seed = rng_.Fork();
    const Vector3f sides_color = RandomColor(rng_, 0.4f, 0.8f);
    const int sides = Material(name + "_sides", PaintPlain(sides_seed, 256, 256, sides_color, 0.08f, 30));
    const float depth = 10.f;
    MeshData front, rest;
    if (side > 0) {  // facade at x = front_x facing -x: right = +z
      AddQuad(front, Vector3f(front_x, height, z0), Vector3f(0, 0, width), Vector3f(0, -height, 0));
      AddBox(rest, Vector3f(front_x + 0.001f, 0, z0), Vector3f(front_x + depth, height, z1));
    } else {  // facade at x = -front_x facing +x: right = -z
      AddQuad(front, Vector3f(-front_x, height, z1), Vector3f(0, 0, -width), Vector3f(0, -height, 0));
      AddBox(rest, Vector3f(-front_x - depth, 0, z0), Vector3f(-front_x - 0.001f, height, z1));
    }
    // One node (one instance) with two primitives: the facade and the plain body behind it.
    std::vector<MeshPart> parts;
    parts.push_back({std::move(front), facade});
    parts.push_back({std::move(rest), sides});
    b_.AddNode(name, "building", std::move(parts));
  }

  void Buildings() {
    for (int side = -1; side <= 1; side += 2) {
      // Slots of random width along the street; one interior slot is an alley closed by a wall.
      std::vector<std::pair<float, float>> slots;
      for (float z = -kStreetHalfLength; z < kStreetHalfLength - 0.5f;) {
        float w = rng_.Uniform(8.f, 16.f);
        if (kStreetHalfLength - (z + w) < 6.f) w = kStreetHalfLength - z;
        slots.emplace_back(z, z + w);
        z += w;
      }
      const int alley = rng_.Int(1, int(slots.size()) - 2);
      for (size_t i = 0; i < slots.size(); ++i) {
        const auto [z0, z1] = slots[i];
        const std::string name = std::string(side < 0 ? "building_left_" : "building_right_") + std::to_string(i);
        if (int(i) == alley) {
          Building(name + "_rear", side, kFacadeX + 8.f, z0, z1, rng_.Uniform(10.f, 16.f));
          Wall(name + "_wall", side, z0, z1);
        } else {
          Building(name, side, kFacadeX, z0, z1, rng_.Uniform(8.f, 18.f));
        }
      }
    }
  }

  void Wall(const std::string& name, int side, float z0, float z1) {
    const float h = 2.4f, t = 0.3f, len = z1 - z0;
    const float ppm = PpmAt(NearestAbs(z0, z1));
    Canvas c(int(len * ppm), int(h * ppm), RandomColor(rng_, 0.45f, 0.65f));
    Rng rng(rng_.Fork());
    AddNoise(c, rng.Fork(), 0.1f, 32);
    for (float x = 0; x < c.w; x += 2.f * ppm) Stroke(c, x, 0, x, float(c.h), 2, Vector3f(0.2f, 0.2f, 0.2f));  // panel joints
    for (int i = 0, n = rng.Int(2, 4); i < n; ++i) {
      const float gx = rng.Uniform(0, float(c.w)), gy = rng.Uniform(0.3f, 0.7f) * c.h, gs = rng.Uniform(0.6f, 1.2f) * ppm;
      Graffiti(c, rng, gx, gy, gs);
    }
    const int mat = Material(name, c);
    MeshData m;
    const float x0 = side * kFacadeX;
    AddBox(m, Vector3f(std::min(x0, x0 + side * t), 0, z0), Vector3f(std::max(x0, x0 + side * t), h, z1));
    b_.AddNode(name, "wall", std::move(m), mat);
  }

  void EndBuildings() {
    for (int end = -1; end <= 1; end += 2) {
      const std::string name = end < 0 ? "building_end_south" : "building_end_north";
      const float height = rng_.Uniform(12.f, 18.f), width = 2 * kFacadeX;
      const int facade = Material(name + "_facade", PaintFacade(rng_.Fork(), width, height, kFarPpm));
      MeshData front;
      const float z = end * kStreetHalfLength;
      if (end > 0) {  // at +z facing -z: right = -x
        AddQuad(front, Vector3f(kFacadeX, height, z), Vector3f(-width, 0, 0), Vector3f(0, -height, 0));
      } else {
        AddQuad(front, Vector3f(-kFacadeX, height, z), Vector3f(width, 0, 0), Vector3f(0, -height, 0));
      }
      b_.AddNode(name, "building", std::move(front), facade);
    }
  }

  void Lamps() {
    const int mat = Material("lamp_metal", PaintPlain(rng_.Fork(), 64, 512, Vector3f(0.3f, 0.32f, 0.3f), 0.08f, 40));
    int k = 0;
    for (float z = -52.f; z <= 52.f; z += 13.f, ++k) {
      const int side = (k % 2) ? 1 : -1;
      MeshData m;
      AddCylinder(m, Vector3f(0, 0, 0), 0.09f, 6.f, 10);
      AddBox(m, Vector3f(-1.2f, 5.85f, -0.05f), Vector3f(0, 5.95f, 0.05f));  // arm over the road
      AddBox(m, Vector3f(-1.5f, 5.75f, -0.15f), Vector3f(-1.0f, 5.95f, 0.15f));  // lamp head
      b_.AddNode("lamp_" + std::to_string(k), "pole", std::move(m), mat, Placement(side * (kRoadHalfWidth + 0.4f), z, side > 0 ? 0.f : kPi));
    }
  }

  void Signs() {
    const int pole_mat = Material("sign_pole", PaintPlain(rng_.Fork(), 32, 256, Vector3f(0.55f, 0.57f, 0.6f), 0.06f, 10));
    const float zs[] = {-30.f, -11.f, 14.f, 33.f};
    for (int i = 0; i < 4; ++i) {
      const int side = (i % 2) ? -1 : 1;
      Rng rng(rng_.Fork());
      // Sign face: a red-bordered disc, a blue square or a warning triangle, with a glyph.
      Canvas c(128, 128, Vector3f(0.8f, 0.8f, 0.8f));
      const int kind = rng.Int(0, 2);
      if (kind == 0) {
        FillEllipse(c, 64, 64, 62, 62, Vector3f(0.8f, 0.05f, 0.05f));
        FillEllipse(c, 64, 64, 48, 48, Vector3f(0.95f, 0.95f, 0.95f));
      } else if (kind == 1) {
        FillRect(c, 2, 2, 126, 126, Vector3f(0.1f, 0.25f, 0.7f));
        FillRect(c, 10, 10, 118, 118, Vector3f(0.15f, 0.35f, 0.8f));
      } else {
        for (int y = 4; y < 124; ++y) {
          const float half = (y - 4) * 0.52f;
          for (int x = int(64 - half); x <= int(64 + half); ++x) c.Blend(x, y, (half - std::abs(x - 64.f) < 9 || y > 114) ? Vector3f(0.8f, 0.05f, 0.05f) : Vector3f(0.97f, 0.9f, 0.2f), 1);
        }
      }
      Glyphs(c, rng, 40, 44, 36, 2, Vector3f(0.05f, 0.05f, 0.05f));
      AddNoise(c, rng.Fork(), 0.04f, 16);
      const int face = Material("traffic_sign_" + std::to_string(i), c);
      MeshData pole, plate;
      AddCylinder(pole, Vector3f(0, 0, 0), 0.04f, 2.9f, 8);
      AddBox(plate, Vector3f(-0.35f, 2.2f, -0.12f), Vector3f(0.35f, 2.9f, -0.09f));
      const Eigen::Matrix4d place = Placement(side * (kRoadHalfWidth + 0.5f), zs[i], rng.Uniform(-0.3f, 0.3f) + (side > 0 ? 0.f : kPi));
      b_.AddNode("sign_pole_" + std::to_string(i), "pole", std::move(pole), pole_mat, place);
      b_.AddNode("traffic_sign_" + std::to_string(i), "traffic sign", std::move(plate), face, place);
    }
  }

  void Railing() {
    const int mat = Material("railing", PaintPlain(rng_.Fork(), 64, 64, Vector3f(0.2f, 0.3f, 0.25f), 0.1f, 8));
    MeshData m;
    for (float z = 0; z <= 6.01f; z += 1.5f) AddBox(m, Vector3f(-0.03f, 0, z - 0.03f), Vector3f(0.03f, 1.0f, z + 0.03f));
    AddBox(m, Vector3f(-0.025f, 0.95f, 0), Vector3f(0.025f, 1.0f, 6.f));
    AddBox(m, Vector3f(-0.025f, 0.5f, 0), Vector3f(0.025f, 0.54f, 6.f));
    b_.AddNode("fence_0", "fence", std::move(m), mat, Placement(-(kRoadHalfWidth + 0.25f), 3.f, 0.f) * Eigen::Affine3d(Eigen::Translation3d(0, kCurbHeight, 0)).matrix());
  }

  void Cars() {
    const float zs[] = {-38.f, -21.f, -9.f, 11.5f, 24.f, 41.f};
    for (int i = 0; i < 5; ++i) {
      Rng rng(rng_.Fork());
      const int side = (i % 2) ? -1 : 1;
      const float z = zs[i + (i >= 3 ? 1 : 0)] + rng.Uniform(-1.5f, 1.5f);
      // Atlas: top half cabin (windows), bottom-left body paint, bottom-right tyres.
      const Vector3f paint = RandomColor(rng, 0.05f, 0.9f);
      Canvas c(256, 256, paint);
      FillRect(c, 0, 0, 256, 128, Vector3f(0.1f, 0.12f, 0.15f));
      for (int k = 0; k < 4; ++k) FillRect(c, 8 + k * 62.f, 10, 60 + k * 62.f, 118, Vector3f(0.2f, 0.25f, 0.3f));  // window panes
      FillRect(c, 192, 128, 256, 256, Vector3f(0.05f, 0.05f, 0.05f));
      FillEllipse(c, 224, 192, 20, 20, Vector3f(0.6f, 0.6f, 0.6f));  // hub
      FillRect(c, 10, 150, 40, 165, Vector3f(0.95f, 0.9f, 0.6f));    // lights
      FillRect(c, 150, 150, 180, 165, Vector3f(0.8f, 0.1f, 0.1f));
      FillRect(c, 70, 200, 120, 215, Vector3f(0.9f, 0.9f, 0.9f));    // number plate
      Glyphs(c, rng, 72, 202, 11, 5, Vector3f(0.05f, 0.05f, 0.05f));
      AddNoise(c, rng.Fork(), 0.05f, 32);
      const int mat = Material("car_" + std::to_string(i), c);
      MeshData m;
      const UvRect body{0, 0.5f, 0.75f, 1}, cabin{0, 0, 1, 0.5f}, tyre{0.75f, 0.5f, 1, 1};
      const float len = rng.Uniform(3.8f, 4.6f), wid = rng.Uniform(1.7f, 1.9f);
      AddBox(m, Vector3f(-wid / 2, 0.3f, -len / 2), Vector3f(wid / 2, 1.0f, len / 2), body);
      AddBox(m, Vector3f(-wid / 2 + 0.1f, 1.0f, -len / 2 + 0.7f), Vector3f(wid / 2 - 0.1f, rng.Uniform(1.45f, 1.7f), len / 2 - 1.0f), cabin);
      for (int wx = -1; wx <= 1; wx += 2) {
        for (int wz = -1; wz <= 1; wz += 2) {
          AddBox(m, Vector3f(wx * wid / 2 - 0.12f, 0, wz * (len / 2 - 0.75f) - 0.33f), Vector3f(wx * wid / 2 + 0.12f, 0.66f, wz * (len / 2 - 0.75f) + 0.33f), tyre);
        }
      }
      float yaw = rng.Uniform(-0.05f, 0.05f);
      if (rng.Chance(0.5f)) yaw += kPi;
      b_.AddNode("car_" + std::to_string(i), "car", std::move(m), mat, Placement(side * (kRoadHalfWidth - 1.1f), z, yaw));
    }
  }

  void People() {
    const float spots[][2] = {{6.5f, -16.f}, {-7.2f, -5.5f}, {7.6f, 7.f}, {-6.3f, 19.f}};
    for (int i = 0; i < 4; ++i) {
      Rng rng(rng_.Fork());
      // Atlas: top half shirt, bottom-left trousers, bottom-right skin/hair.
      Canvas c(128, 128, RandomColor(rng, 0.1f, 0.9f));
      FillRect(c, 0, 64, 96, 128, RandomColor(rng, 0.05f, 0.5f));
      const float sr = rng.Uniform(0.4f, 0.9f), sg = rng.Uniform(0.3f, 0.7f), sb = rng.Uniform(0.2f, 0.5f);
      FillRect(c, 96, 64, 128, 128, Vector3f(sr, sg, sb));
      for (int k = 0; k < 6; ++k) {  // print pattern on the shirt
        const float ex = rng.Uniform(0, 128), ey = rng.Uniform(0, 60), rx = rng.Uniform(3, 10), ry = rng.Uniform(3, 10);
        FillEllipse(c, ex, ey, rx, ry, RandomColor(rng), 0.8f);
      }
      AddNoise(c, rng.Fork(), 0.05f, 16);
      const int mat = Material("person_" + std::to_string(i), c);
      const UvRect shirt{0, 0, 1, 0.5f}, trousers{0, 0.5f, 0.75f, 1}, skin{0.75f, 0.5f, 1, 1};
      const float s = rng.Uniform(0.9f, 1.08f);  // body scale
      MeshData m;
      AddBox(m, s * Vector3f(-0.2f, 0, -0.1f), s * Vector3f(-0.03f, 0.85f, 0.1f), trousers);
      AddBox(m, s * Vector3f(0.03f, 0, -0.1f), s * Vector3f(0.2f, 0.85f, 0.1f), trousers);
      AddBox(m, s * Vector3f(-0.23f, 0.85f, -0.12f), s * Vector3f(0.23f, 1.5f, 0.12f), shirt);
      AddBox(m, s * Vector3f(-0.32f, 0.8f, -0.06f), s * Vector3f(-0.23f, 1.45f, 0.06f), shirt);
      AddBox(m, s * Vector3f(0.23f, 0.8f, -0.06f), s * Vector3f(0.32f, 1.45f, 0.06f), shirt);
      AddBlob(m, s * Vector3f(0, 1.63f, 0), s * Vector3f(0.1f, 0.12f, 0.11f), 0.05f, rng.Fork(), skin);
      Eigen::Matrix4d place = Placement(spots[i][0], spots[i][1], rng.Uniform(0, 2 * kPi));
      place(1, 3) = kCurbHeight;  // standing on the sidewalk
      b_.AddNode("person_" + std::to_string(i), "person", std::move(m), mat, place);
    }
  }

  void Trees() {
    const float spots[][2] = {{-7.5f, -27.f}, {7.5f, -34.f}, {-7.5f, 27.f}, {7.5f, 21.f}};
    for (int i = 0; i < 4; ++i) {
      Rng rng(rng_.Fork());
      // Atlas: left quarter bark, the rest leaves.
      Canvas c(256, 256, Vector3f(0.16f, 0.32f, 0.1f));
      FillRect(c, 0, 0, 64, 256, Vector3f(0.3f, 0.22f, 0.15f));
      AddNoise(c, rng.Fork(), 0.1f, 32, 0.05f);
      for (int k = 0; k < 400; ++k) {
        const float x = rng.Uniform(64, 256), y = rng.Uniform(0, 256), r = rng.Uniform(1.5f, 5.f);
        const float lr = rng.Uniform(0.1f, 0.4f), lg = rng.Uniform(0.25f, 0.55f), lb = rng.Uniform(0.05f, 0.2f);
        FillEllipse(c, x, y, r, r * 0.6f, Vector3f(lr, lg, lb), 0.8f);
      }
      const int mat = Material("tree_" + std::to_string(i), c);
      const UvRect bark{0, 0, 0.25f, 1}, leaves{0.25f, 0, 1, 1};
      MeshData m;
      const float trunk_h = rng.Uniform(2.8f, 3.6f);
      AddCylinder(m, Vector3f(0, 0, 0), 0.15f, trunk_h + 0.5f, 9, bark);
      for (int k = 0, n = rng.Int(3, 5); k < n; ++k) {
        const float r = rng.Uniform(1.1f, 1.7f);
        const float cx = rng.Uniform(-0.7f, 0.7f), cy = trunk_h + rng.Uniform(0.6f, 1.8f), cz = rng.Uniform(-0.7f, 0.7f);
        AddBlob(m, Vector3f(cx, cy, cz), Vector3f(r, r * 0.85f, r), 0.35f, rng.Fork(), leaves);
      }
      Eigen::Matrix4d place = Placement(spots[i][0], spots[i][1], rng.Uniform(0, 2 * kPi));
      place(1, 3) = kCurbHeight;
      b_.AddNode("tree_" + std::to_string(i), "vegetation", std::move(m), mat, place);
    }
  }

  Rng rng_;
  SceneBuilder b_;
};

}  // namespace

std::vector<uint8_t> StreetSceneGlb(uint64_t seed) { return StreetGenerator(seed).Build().ToGlb(); }

void WriteStreetScene(const std::filesystem::path& glb_path, uint64_t seed) { StreetGenerator(seed).Build().WriteGlb(glb_path); }

}  // namespace rigsim
