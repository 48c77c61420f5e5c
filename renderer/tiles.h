// How Render walks an image: square tiles numbered row by row, one task each, and in each tile
// row batches of pixels whose rays are traced and shaded together.
#pragma once

#include <algorithm>

#include <Eigen/Core>

namespace rigsim {

constexpr int kTileSize = 32;
// A tile row is shaded in batches of pixels of at most this many samples together (at least one
// pixel): a whole row up to 32 spp, and a bounded buffer at any spp.
constexpr int kMaxBatchSamples = 1024;

inline int PixelsPerBatch(int spp) { return std::clamp(kMaxBatchSamples / spp, 1, kTileSize); }

inline int NumTiles(int width, int height) {
  return ((width + kTileSize - 1) / kTileSize) * ((height + kTileSize - 1) / kTileSize);
}

// The top-left pixel of a tile; tiles are numbered row by row.
inline Eigen::Vector2i TileCorner(int tile, int width) {
  const int tiles_x = (width + kTileSize - 1) / kTileSize;
  return Eigen::Vector2i((tile % tiles_x) * kTileSize, (tile / tiles_x) * kTileSize);
}

// Calls f(y, x_begin, x_end) for each batch of the tile at `corner`: row by row, runs of at most
// PixelsPerBatch(spp) pixels, so that a batch's rays and shading records stay in L1.
template <class F>
void ForEachBatch(const Eigen::Vector2i& corner, int width, int height, int spp, F&& f) {
  const int x_end = std::min(width, corner.x() + kTileSize), y_end = std::min(height, corner.y() + kTileSize);
  const int batch_pixels = PixelsPerBatch(spp);
  for (int y = corner.y(); y < y_end; ++y) {
    for (int x = corner.x(); x < x_end; x += batch_pixels) f(y, x, std::min(x_end, x + batch_pixels));
  }
}

}  // namespace rigsim
