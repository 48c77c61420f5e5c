#include "procedural/textures.h"

#include <algorithm>
#include <cmath>

namespace rigsim::procedural {
// ---------------------------------------------------------------------------------------------
// Texture painting on a float RGB canvas.


float Lattice(int x, int y, uint64_t seed) {
  const uint64_t h = SplitMix64(seed ^ (uint64_t(uint32_t(x)) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(uint32_t(y)) * 0xC2B2AE3D27D4EB4Full));
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
void AddNoise(Canvas& c, uint64_t seed, float amplitude, float coarse_px, float tint) {
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

void FillRect(Canvas& c, float x0, float y0, float x1, float y1, const Vector3f& col, float alpha) {
  const int ax = std::max(0, int(std::lround(x0))), bx = std::min(c.w, int(std::lround(x1)));
  const int ay = std::max(0, int(std::lround(y0))), by = std::min(c.h, int(std::lround(y1)));
  for (int y = ay; y < by; ++y) {
    for (int x = ax; x < bx; ++x) c.Blend(x, y, col, alpha);
  }
}

void FillEllipse(Canvas& c, float cx, float cy, float rx, float ry, const Vector3f& col, float alpha) {
  for (int y = int(cy - ry) - 1; y <= int(cy + ry) + 1; ++y) {
    for (int x = int(cx - rx) - 1; x <= int(cx + rx) + 1; ++x) {
      const float dx = (x - cx) / rx, dy = (y - cy) / ry;
      if (dx * dx + dy * dy <= 1.f) c.Blend(x, y, col, alpha);
    }
  }
}

void Stroke(Canvas& c, float x0, float y0, float x1, float y1, float width, const Vector3f& col, float alpha) {
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

Vector3f RandomColor(Rng& rng, float lo, float hi) {
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

void Window(Canvas& c, Rng& rng, float x0, float y0, float x1, float y1, float ppm, const Vector3f& frame,
            std::vector<Pane>* panes) {
  const float f = std::max(2.f, 0.08f * ppm);
  if (panes != nullptr && x1 - x0 > 2 * f && y1 - y0 > 2 * f) panes->push_back({x0 + f, y0 + f, x1 - f, y1 - f});
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
Canvas PaintFacade(uint64_t seed, float width, float height, float ppm, std::vector<Pane>* panes) {
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
      Window(c, rng, cx - win_w * ppm * 0.5f, bottom - win_h * ppm, cx + win_w * ppm * 0.5f, bottom, ppm, frame, panes);
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
      Window(c, rng, x + 0.4f * ppm + door_w, Y(2.7f), x + unit - 0.2f * ppm, Y(0.5f), ppm, RandomColor(rng, 0.1f, 0.5f), panes);
      if (rng.Chance(0.5f)) {  // lettering on the shop window
        Glyphs(c, rng, x + 0.6f * ppm + door_w, Y(2.2f), 0.25f * ppm, rng.Int(3, 8), Vector3f(0.95f, 0.95f, 0.9f));
      }
    } else {
      Door(c, rng, x + unit * 0.5f - 0.5f * ppm, Y(2.3f), x + unit * 0.5f + 0.5f * ppm, Y(0.05f), ppm);
      Window(c, rng, x + 0.2f * ppm, Y(2.6f), x + unit * 0.5f - 0.8f * ppm, Y(1.0f), ppm, frame, panes);
      Window(c, rng, x + unit * 0.5f + 0.8f * ppm, Y(2.6f), x + unit - 0.2f * ppm, Y(1.0f), ppm, frame, panes);
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

}  // namespace rigsim::procedural

namespace rigsim::procedural {

std::vector<uint8_t> ToRgba8(const Canvas& c, const std::vector<float>& alpha) {
  std::vector<uint8_t> out(size_t(c.w) * c.h * 4);
  for (size_t i = 0; i < size_t(c.w) * c.h; ++i) {
    for (int k = 0; k < 3; ++k) out[4 * i + k] = uint8_t(std::clamp(c.px[3 * i + k], 0.f, 1.f) * 255.f + 0.5f);
    out[4 * i + 3] = uint8_t(std::clamp(i < alpha.size() ? alpha[i] : 1.f, 0.f, 1.f) * 255.f + 0.5f);
  }
  return out;
}

namespace {

void Speckles(Canvas& c, Rng& rng, int n, float r0, float r1, float light, float dark, float alpha) {
  for (int i = 0; i < n; ++i) {
    const float r = rng.Uniform(r0, r1), ex = rng.Uniform(0, float(c.w)), ey = rng.Uniform(0, float(c.h));
    const float tone = rng.Chance(0.5f) ? light : dark;
    FillEllipse(c, ex, ey, r, r, Vector3f::Constant(tone), alpha);
  }
}

void Cracks(Canvas& c, Rng& rng, int n, float ppm, const Vector3f& col) {
  for (int i = 0; i < n; ++i) {
    float x = rng.Uniform(0, float(c.w)), y = rng.Uniform(0, float(c.h)), a = rng.Uniform(0, 2 * kPi);
    for (int k = 0, steps = rng.Int(10, 40); k < steps; ++k) {
      a += rng.Uniform(-0.7f, 0.7f);
      const float nx = x + std::cos(a) * 0.08f * ppm, ny = y + std::sin(a) * 0.08f * ppm;
      Stroke(c, x, y, nx, ny, 1.2f, col, 0.9f);
      x = nx;
      y = ny;
    }
  }
}

}  // namespace

Canvas PaintPaving(uint64_t seed, float width_m, float length_m, float ppm) {
  Rng rng(seed);
  const int w = std::max(8, int(width_m * ppm)), h = std::max(8, int(length_m * ppm));
  const float br = rng.Uniform(0.45f, 0.65f), bg = rng.Uniform(0.42f, 0.6f), bb = rng.Uniform(0.38f, 0.55f);
  const Vector3f base(br, bg, bb);
  Canvas c(w, h, base);
  const float slab = rng.Uniform(0.3f, 0.8f) * ppm, joint = std::max(1.f, 0.012f * ppm);
  int row = 0;
  for (float y = 0; y < h; y += slab, ++row) {
    const float shift = (row % 2) * slab * 0.5f;
    for (float x = -shift; x < w; x += slab) {
      FillRect(c, x + joint, y + joint, x + slab - joint, y + slab - joint, base * rng.Uniform(0.8f, 1.15f));
    }
  }
  AddNoise(c, rng.Fork(), 0.08f, 32, 0.03f);
  Speckles(c, rng, int(width_m * length_m * 20), 0.6f, 2.f, 0.8f, 0.25f, 0.6f);
  Speckles(c, rng, int(width_m * length_m * 80), 0.5f, 1.4f, 0.75f, 0.2f, 0.6f);  // fine grit
  for (int i = 0, n = int(width_m * length_m * 0.3f); i < n; ++i) {  // stains and fallen leaves
    const float r = rng.Uniform(0.05f, 0.3f) * ppm, ex = rng.Uniform(0, float(w)), ey = rng.Uniform(0, float(h));
    const float ry = r * rng.Uniform(0.4f, 1.f);
    const Vector3f col = rng.Chance(0.5f) ? Vector3f(0.35f, 0.33f, 0.3f) : Vector3f(0.55f, 0.4f, 0.15f);
    FillEllipse(c, ex, ey, r, ry, col, 0.5f);
  }
  Cracks(c, rng, int(width_m * length_m * 0.02f) + 1, ppm, base * 0.4f);
  return c;
}

Canvas PaintAsphalt(uint64_t seed, float width_m, float length_m, float ppm) {
  Rng rng(seed);
  const int w = std::max(8, int(width_m * ppm)), h = std::max(8, int(length_m * ppm));
  Canvas c(w, h, Vector3f::Constant(rng.Uniform(0.24f, 0.3f)));
  AddNoise(c, rng.Fork(), 0.1f, 64);
  for (int i = 0, n = rng.Int(2, 6); i < n; ++i) {
    const float x = rng.Uniform(0, float(w)), y = rng.Uniform(0, float(h));
    const float pw = rng.Uniform(0.5f, 2.5f) * ppm, ph = rng.Uniform(0.5f, 3.f) * ppm, tone = rng.Uniform(0.18f, 0.36f);
    FillRect(c, x, y, x + pw, y + ph, Vector3f::Constant(tone), 0.8f);
  }
  Speckles(c, rng, int(width_m * length_m * 25), 0.6f, 2.2f, 0.55f, 0.12f, 0.6f);
  Speckles(c, rng, int(width_m * length_m * 120), 0.5f, 1.5f, 0.5f, 0.1f, 0.7f);  // fine grit
  for (int i = 0, n = rng.Int(1, 4); i < n; ++i) {
    const float ex = rng.Uniform(0, float(w)), ey = rng.Uniform(0, float(h));
    const float rx = rng.Uniform(0.2f, 0.6f) * ppm, ry = rng.Uniform(0.2f, 0.6f) * ppm;
    FillEllipse(c, ex, ey, rx, ry, Vector3f(0.1f, 0.1f, 0.1f), 0.35f);
  }
  Cracks(c, rng, rng.Int(3, 9), ppm, Vector3f(0.06f, 0.06f, 0.06f));
  return c;
}

Canvas PaintGrass(uint64_t seed, float width_m, float length_m, float ppm) {
  Rng rng(seed);
  const int w = std::max(8, int(width_m * ppm)), h = std::max(8, int(length_m * ppm));
  Canvas c(w, h, Vector3f(0.22f, 0.38f, 0.12f));
  AddNoise(c, rng.Fork(), 0.1f, 64, 0.06f);
  for (int i = 0, n = int(width_m * length_m * 60); i < n; ++i) {  // blades and clover
    const float x = rng.Uniform(0, float(w)), y = rng.Uniform(0, float(h)), len = rng.Uniform(1.5f, 5.f);
    const float g = rng.Uniform(0.3f, 0.6f), r = rng.Uniform(0.1f, 0.35f);
    const float dx = rng.Uniform(-1.f, 1.f);
    Stroke(c, x, y, x + dx, y - len, 1.f, Vector3f(r, g, 0.1f), 0.7f);
  }
  for (int i = 0, n = int(width_m * length_m * 0.5f); i < n; ++i) {  // soil patches and flowers
    const float x = rng.Uniform(0, float(w)), y = rng.Uniform(0, float(h));
    if (rng.Chance(0.5f)) {
      const float rx = rng.Uniform(0.05f, 0.3f) * ppm, ry = rng.Uniform(0.05f, 0.3f) * ppm;
      FillEllipse(c, x, y, rx, ry, Vector3f(0.35f, 0.27f, 0.18f), 0.6f);
    } else {
      FillEllipse(c, x, y, 2.f, 2.f, RandomColor(rng, 0.6f, 1.f), 0.9f);
    }
  }
  return c;
}

Canvas PaintPoster(uint64_t seed, int width, int height) {
  Rng rng(seed);
  Canvas c(width, height, RandomColor(rng, 0.5f, 0.95f));
  for (int i = 0; i < 6; ++i) {  // bold shapes
    const float x = rng.Uniform(0, float(width)), y = rng.Uniform(0, float(height));
    const float rx = rng.Uniform(0.05f, 0.25f) * width, ry = rng.Uniform(0.1f, 0.4f) * height;
    const Vector3f col = RandomColor(rng, 0.f, 1.f);
    if (rng.Chance(0.5f)) {
      FillEllipse(c, x, y, rx, ry, col);
    } else {
      FillRect(c, x, y, x + rx, y + ry, col);
    }
  }
  const float line = height * 0.12f;
  for (float y = height * 0.1f; y < height * 0.9f; y += line * 1.6f) {
    const Vector3f ink = RandomColor(rng, 0.f, 0.3f);
    Glyphs(c, rng, width * 0.05f, y, line, std::max(1, int(width * 0.9f / (line * 0.75f))), ink);
  }
  AddNoise(c, rng.Fork(), 0.03f, 16);
  return c;
}

Canvas PaintCarAtlas(uint64_t seed, const Vector3f& paint) {
  Rng rng(seed);
  Canvas c(256, 256, paint);
  FillRect(c, 0, 0, 256, 128, Vector3f(0.1f, 0.12f, 0.15f));
  for (int k = 0; k < 4; ++k) FillRect(c, 8 + k * 62.f, 10, 60 + k * 62.f, 118, Vector3f(0.2f, 0.25f, 0.3f));
  FillRect(c, 192, 128, 256, 256, Vector3f(0.05f, 0.05f, 0.05f));
  FillEllipse(c, 224, 192, 20, 20, Vector3f(0.6f, 0.6f, 0.6f));
  FillRect(c, 10, 150, 40, 165, Vector3f(0.95f, 0.9f, 0.6f));
  FillRect(c, 150, 150, 180, 165, Vector3f(0.8f, 0.1f, 0.1f));
  FillRect(c, 70, 200, 120, 215, Vector3f(0.9f, 0.9f, 0.9f));
  Glyphs(c, rng, 72, 202, 11, 5, Vector3f(0.05f, 0.05f, 0.05f));
  for (int k = 0; k < 12; ++k) {  // dirt, scratches and stickers on the body
    const float x = rng.Uniform(0, 190), y = rng.Uniform(130, 256), r = rng.Uniform(2, 7);
    if (rng.Chance(0.5f)) {
      FillEllipse(c, x, y, r, r * 0.6f, paint * 0.6f, 0.7f);
    } else {
      FillRect(c, x, y, x + 2 * r, y + r, RandomColor(rng), 0.9f);
    }
  }
  AddNoise(c, rng.Fork(), 0.06f, 32);
  return c;
}

Canvas PaintPersonAtlas(uint64_t seed) {
  Rng rng(seed);
  Canvas c(128, 128, RandomColor(rng, 0.1f, 0.9f));
  FillRect(c, 0, 64, 96, 128, RandomColor(rng, 0.05f, 0.5f));
  const float sr = rng.Uniform(0.4f, 0.9f), sg = rng.Uniform(0.3f, 0.7f), sb = rng.Uniform(0.2f, 0.5f);
  FillRect(c, 96, 64, 128, 128, Vector3f(sr, sg, sb));
  for (int k = 0; k < 6; ++k) {
    const float ex = rng.Uniform(0, 128), ey = rng.Uniform(0, 60), rx = rng.Uniform(3, 10), ry = rng.Uniform(3, 10);
    FillEllipse(c, ex, ey, rx, ry, RandomColor(rng), 0.8f);
  }
  AddNoise(c, rng.Fork(), 0.05f, 16);
  return c;
}

Canvas PaintFoliage(uint64_t seed, int size, std::vector<float>* alpha) {
  Rng rng(seed);
  Canvas c(size, size, Vector3f(0.15f, 0.3f, 0.1f));
  alpha->assign(size_t(size) * size, 0.f);
  const float cx = size * 0.5f, cy = size * 0.5f, radius = size * 0.47f;
  for (int i = 0, n = size * 6; i < n; ++i) {  // leaves inside a ragged disc
    const float a = rng.Uniform(0, 2 * kPi), d = radius * std::sqrt(rng.Uniform());
    const float x = cx + d * std::cos(a), y = cy + d * std::sin(a) * 0.9f;
    const float r = rng.Uniform(2.f, 6.f) * size / 256.f + 1.f, angle = rng.Uniform(0, kPi);
    const float lr = rng.Uniform(0.08f, 0.4f), lg = rng.Uniform(0.22f, 0.6f), lb = rng.Uniform(0.04f, 0.2f);
    const Vector3f col(lr, lg, lb);
    const float ca = std::cos(angle), sa = std::sin(angle);
    for (int yy = int(y - r) - 1; yy <= int(y + r) + 1; ++yy) {
      for (int xx = int(x - r) - 1; xx <= int(x + r) + 1; ++xx) {
        if (xx < 0 || yy < 0 || xx >= size || yy >= size) continue;
        const float u = (xx - x) * ca + (yy - y) * sa, v = -(xx - x) * sa + (yy - y) * ca;
        if ((u * u) / (r * r) + (v * v) / (0.25f * r * r) > 1.f) continue;
        c.Blend(xx, yy, col, 1.f);
        (*alpha)[size_t(yy) * size + xx] = 1.f;
      }
    }
  }
  for (int i = 0; i < 4; ++i) {  // twigs
    const float a = rng.Uniform(0, 2 * kPi);
    Stroke(c, cx, cy, cx + radius * 0.8f * std::cos(a), cy + radius * 0.8f * std::sin(a), 2.f, Vector3f(0.3f, 0.22f, 0.15f));
  }
  AddNoise(c, rng.Fork(), 0.05f, 16);
  return c;
}

}  // namespace rigsim::procedural
