// Splits a width x height pixel grid into square tiles and runs a function on each tile in
// parallel with TBB. Every pixel belongs to exactly one tile, so any tile size yields the
// same image as long as the per-pixel work does not depend on the tile.
#ifndef RayMappers_TileScheduler_h
#define RayMappers_TileScheduler_h

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace raymappers
{

/// Pixel rectangle [x0, x1) x [y0, y1).
struct Tile
{
  int x0, y0, x1, y1;
};

/// Calls fn(const Tile&) for every tile of `tileSize` x `tileSize` pixels (the last row and
/// column of tiles are clipped to the grid), in parallel.
template<typename Fn>
void forEachTile(int width, int height, int tileSize, Fn&& fn)
{
  if (width <= 0 || height <= 0)
  {
    return;
  }
  tileSize = std::max(1, tileSize);
  const int nx = (width + tileSize - 1) / tileSize;
  const int ny = (height + tileSize - 1) / tileSize;
  tbb::parallel_for(tbb::blocked_range<int>(0, nx * ny, 1),
    [&](const tbb::blocked_range<int>& range)
    {
      for (int t = range.begin(); t != range.end(); ++t)
      {
        const int tx = t % nx;
        const int ty = t / nx;
        const Tile tile{ tx * tileSize,
          ty * tileSize,
          std::min(width, (tx + 1) * tileSize),
          std::min(height, (ty + 1) * tileSize) };
        fn(tile);
      }
    });
}

} // namespace raymappers

#endif
