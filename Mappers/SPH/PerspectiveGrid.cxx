#include "PerspectiveGrid.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>

namespace raymappers
{
namespace
{
// Beyond this many cells along z the cells get deeper (and hold more samples' worth of
// depth each) so a camera with a tiny near plane cannot make the grid explode.
constexpr int MaxDepthCells = 2048;

/// A particle's range of cells; empty (tz0 > tz1) when it is out of view.
struct CellRange
{
  int tx0, tx1, ty0, ty1, tz0, tz1;
  float zlo, zhi; // depth span of the support, clipped to the view
};
}

bool PerspectiveGrid::build(const SPHParticles& particles,
  const ViewRays& rays,
  const PerspectiveGridParameters& params)
{
  TileSize = std::max(1, params.tileSize);
  const int W = rays.width(), H = rays.height();
  TilesX = (W + TileSize - 1) / TileSize;
  TilesY = (H + TileSize - 1) / TileSize;
  const std::size_t n = particles.size();
  Footprints.resize(n);
  std::vector<CellRange> ranges(n);

  // 1. Each particle's pixel extent and depth span (section 4.1.2, kComputeRelevantCells).
  struct Span
  {
    double lo = std::numeric_limits<double>::infinity();
    double hi = -std::numeric_limits<double>::infinity();
    std::size_t count = 0;
  };
  const Span span = tbb::parallel_reduce(
    tbb::blocked_range<std::size_t>(0, n, 4096),
    Span(),
    [&](const tbb::blocked_range<std::size_t>& r, Span s)
    {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
      {
        CellRange& cr = ranges[i];
        cr.tz0 = 1;
        cr.tz1 = 0; // out of view until proven otherwise
        const SphereFootprint f = rays.footprint(Vec3d(particles.centers[i]), particles.support[i]);
        if (!f.inView)
        {
          continue;
        }
        Footprints[i] = { static_cast<float>(f.x0), static_cast<float>(f.x1), static_cast<float>(f.y0),
          static_cast<float>(f.y1), static_cast<float>(f.zc) };
        cr.tx0 = f.i0 / TileSize;
        cr.tx1 = f.i1 / TileSize;
        cr.ty0 = f.j0 / TileSize;
        cr.ty1 = f.j1 / TileSize;
        cr.tz0 = 0;
        cr.tz1 = 0;
        cr.zlo = static_cast<float>(f.zlo);
        cr.zhi = static_cast<float>(f.zhi);
        s.lo = std::min(s.lo, f.zlo);
        s.hi = std::max(s.hi, f.zhi);
        ++s.count;
      }
      return s;
    },
    [](Span a, const Span& b)
    {
      a.lo = std::min(a.lo, b.lo);
      a.hi = std::max(a.hi, b.hi);
      a.count += b.count;
      return a;
    });
  InView = span.count;
  CellStart.assign(1, 0);
  Refs.clear();
  EmptyRun.clear();
  Steps.cells = 0;
  if (InView == 0 || !(span.lo < span.hi))
  {
    return false;
  }

  // 2. Depth steps (equations 3.2 to 3.9).
  const double lambda = rays.obliquity();
  const double stepFactor = params.stepFactor > 0 ? params.stepFactor : 1.0;
  Steps.logarithmic = rays.isPerspective();
  Steps.zeta0 = span.lo;
  Steps.uniformStep = 0.0;
  Steps.uBreak = 0.0;
  const int S = Steps.samplesPerCell =
    std::clamp(static_cast<int>(std::ceil(TileSize * lambda / stepFactor - 1e-9)), 1, 1024);
  // Pixel-tied step: a cell is TileSize pixels deep (log-depth or depth) and holds S samples.
  double cellDepth = TileSize * rays.pixelSize();
  double extent; // in samples
  if (Steps.logarithmic)
  {
    double uniformDepth = 0.0;
    if (params.fieldStep > 0)
    {
      // Uniform steps of s_f up to where the logarithmic step reaches it (whole cells).
      const double zStar = params.fieldStep / std::expm1(cellDepth / S);
      uniformDepth = std::min(zStar, span.hi) - span.lo;
      if (uniformDepth > 0)
      {
        Steps.uniformStep = params.fieldStep;
        if (uniformDepth / (S * Steps.uniformStep) > MaxDepthCells)
        {
          Steps.uniformStep = uniformDepth / (S * MaxDepthCells);
        }
        Steps.uBreak = S * std::ceil(uniformDepth / (S * Steps.uniformStep) - 1e-9);
      }
    }
    const double logExtent = span.hi > Steps.zetaBreak() ? std::log(span.hi / Steps.zetaBreak()) : 0.0;
    if (logExtent / cellDepth > MaxDepthCells)
    {
      cellDepth = logExtent / MaxDepthCells;
    }
    Steps.delta = cellDepth / S;
    extent = Steps.uBreak + logExtent / Steps.delta;
  }
  else
  {
    Steps.delta = std::max(cellDepth / S, params.fieldStep);
    if ((span.hi - span.lo) / (S * Steps.delta) > MaxDepthCells)
    {
      Steps.delta = (span.hi - span.lo) / (S * MaxDepthCells);
    }
    extent = (span.hi - span.lo) / Steps.delta;
  }
  Steps.cells = std::max(1, static_cast<int>(std::ceil(extent / S - 1e-9)));
  const int totalSamples = Steps.samples();

  // 3. Count the references per cell, then their starts (prefix sum).
  const std::size_t cells = cellCount();
  std::unique_ptr<std::atomic<std::uint32_t>[]> counter(new std::atomic<std::uint32_t>[cells]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 65536),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t c = r.begin(); c != r.end(); ++c)
      {
        counter[c].store(0, std::memory_order_relaxed);
      }
    });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
      {
        CellRange& cr = ranges[i];
        if (cr.tz0 > cr.tz1)
        {
          continue;
        }
        const double u0 = Steps.coordinate(cr.zlo), u1 = Steps.coordinate(cr.zhi);
        cr.tz0 = std::clamp(static_cast<int>(std::floor(u0)), 0, totalSamples - 1) / S;
        cr.tz1 = std::clamp(static_cast<int>(std::floor(u1)), 0, totalSamples - 1) / S;
        for (int ty = cr.ty0; ty <= cr.ty1; ++ty)
        {
          for (int tx = cr.tx0; tx <= cr.tx1; ++tx)
          {
            for (int tz = cr.tz0; tz <= cr.tz1; ++tz)
            {
              counter[cellIndex(tx, ty, tz)].fetch_add(1, std::memory_order_relaxed);
            }
          }
        }
      }
    });
  CellStart.resize(cells + 1);
  std::uint64_t total = 0;
  for (std::size_t c = 0; c < cells; ++c)
  {
    CellStart[c] = static_cast<std::uint32_t>(total);
    total += counter[c].load(std::memory_order_relaxed);
    counter[c].store(CellStart[c], std::memory_order_relaxed); // now the write cursor
  }
  CellStart[cells] = static_cast<std::uint32_t>(total);
  Refs.resize(total);

  // 4. Scatter the particle indices, then order each cell's list by index (the sums over a
  //    cell's particles are then the same for any thread schedule).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
      {
        const CellRange& cr = ranges[i];
        for (int ty = cr.ty0; ty <= cr.ty1 && cr.tz0 <= cr.tz1; ++ty)
        {
          for (int tx = cr.tx0; tx <= cr.tx1; ++tx)
          {
            for (int tz = cr.tz0; tz <= cr.tz1; ++tz)
            {
              const std::uint32_t slot =
                counter[cellIndex(tx, ty, tz)].fetch_add(1, std::memory_order_relaxed);
              Refs[slot] = static_cast<std::uint32_t>(i);
            }
          }
        }
      }
    });
  // 5. Sort each cell's list; the empty successors cache per tile column (section 3.4.3).
  EmptyRun.assign(cells, 0);
  const int columns = TilesX * TilesY;
  tbb::parallel_for(tbb::blocked_range<int>(0, columns, 16),
    [&](const tbb::blocked_range<int>& r)
    {
      for (int col = r.begin(); col != r.end(); ++col)
      {
        const std::size_t base = static_cast<std::size_t>(col) * Steps.cells;
        std::uint32_t run = 0;
        for (int tz = Steps.cells - 1; tz >= 0; --tz)
        {
          const std::size_t c = base + tz;
          const std::uint32_t b = CellStart[c], e = CellStart[c + 1];
          std::sort(Refs.begin() + b, Refs.begin() + e);
          run = b == e ? run + 1 : 0;
          EmptyRun[c] = run;
        }
      }
    });
  return true;
}

std::size_t PerspectiveGrid::memoryBytes() const
{
  return CellStart.size() * sizeof(std::uint32_t) + Refs.size() * sizeof(std::uint32_t) +
    EmptyRun.size() * sizeof(std::uint32_t) + Footprints.size() * sizeof(ParticleFootprint);
}

} // namespace raymappers
