#include "Mappers/SPH/PerspectiveGrid.h"

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

/// The depth range of the supports in view and how many particles are in view.
struct DepthSpan
{
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  std::size_t count = 0;
};

/// Each particle's pixel extent, its range of tiles and its depth span (section 4.1.2,
/// kComputeRelevantCells; the cells along z follow once the depth steps are known), and the
/// depth range of all of them.
DepthSpan projectParticles(const SPHParticles& particles,
  const ViewRays& rays,
  int tileSize,
  std::vector<ParticleFootprint>& footprints,
  std::vector<CellRange>& ranges)
{
  return tbb::parallel_reduce(
    tbb::blocked_range<std::size_t>(0, particles.size(), 4096),
    DepthSpan(),
    [&](const tbb::blocked_range<std::size_t>& r, DepthSpan s)
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
        footprints[i] = { static_cast<float>(f.x0),
          static_cast<float>(f.x1),
          static_cast<float>(f.y0),
          static_cast<float>(f.y1),
          static_cast<float>(f.zc) };
        cr.tx0 = f.i0 / tileSize;
        cr.tx1 = f.i1 / tileSize;
        cr.ty0 = f.j0 / tileSize;
        cr.ty1 = f.j1 / tileSize;
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
    [](DepthSpan a, const DepthSpan& b)
    {
      a.lo = std::min(a.lo, b.lo);
      a.hi = std::max(a.hi, b.hi);
      a.count += b.count;
      return a;
    });
}

/// Perspective depth steps reaching [span.lo, span.hi] for cells of log-depth cellDepth
/// holding S samples: uniform steps of the field step s_f up to the break zeta_b, the first
/// multiple of s_f at or beyond zeta* = s_f / (e^delta - 1) (where the logarithmic step
/// reaches s_f), then logarithmic steps of delta = cellDepth / S (equation 3.5). The step
/// boundaries lie on a lattice fixed by the view alone: the depths m s_f (m integer) before
/// the break, zeta_b e^(k delta) beyond it (zeta_b = 1 without a field step); zeta_0 is the
/// last boundary at or before span.lo. So two sets of particles seen by one camera (the
/// regions of a distributed render) are sampled at the same depths. Returns the extent in
/// samples. Beyond MaxDepthCells cells the steps lengthen, off the lattice.
double logarithmicSteps(const DepthSpan& span,
  double fieldStep,
  double cellDepth,
  DepthSteps& steps)
{
  const int S = steps.samplesPerCell;
  steps.delta = cellDepth / S;
  steps.zetaBreak = 1.0; // without a field step the log lattice is e^(n delta)
  if (fieldStep > 0)
  {
    const double mBreak = std::ceil(1.0 / std::expm1(steps.delta) - 1e-9);
    steps.zetaBreak = mBreak * fieldStep;
    if (span.lo < steps.zetaBreak)
    {
      steps.firstStep = std::floor(span.lo / fieldStep);
      steps.uniformStep = fieldStep;
      steps.uBreak = mBreak - steps.firstStep;
      const double uniformDepth = std::min(steps.zetaBreak, span.hi) - steps.zeta(0);
      if (uniformDepth / (S * fieldStep) > MaxDepthCells)
      {
        // Off the lattice: longer steps from the front.
        steps.zetaBase = steps.zeta(0);
        steps.firstStep = 0;
        steps.uniformStep = uniformDepth / (S * MaxDepthCells);
        steps.uBreak = static_cast<double>(S) * MaxDepthCells;
        steps.zetaBreak = steps.zetaBase + steps.uBreak * steps.uniformStep;
      }
    }
  }
  if (steps.uniformStep == 0)
  {
    steps.firstLogStep = std::floor(std::log(span.lo / steps.zetaBreak) / steps.delta);
  }
  const double front = steps.zeta(steps.uBreak); // where the log part begins
  const double logExtent = span.hi > front ? std::log(span.hi / front) : 0.0;
  if (logExtent / cellDepth > MaxDepthCells)
  {
    // Off the lattice: deeper cells from where the log part begins.
    steps.zetaBreak = front;
    steps.firstLogStep = 0;
    steps.delta = logExtent / MaxDepthCells / S;
  }
  return steps.coordinate(span.hi);
}

/// Parallel depth steps (section 3.4.1, "a fixed sampling rate"): uniform steps of the longer of
/// cellDepth / S and the field step, their boundaries at its multiples (a lattice fixed by the
/// view, as above). Returns the extent in samples.
double uniformSteps(const DepthSpan& span, double fieldStep, double cellDepth, DepthSteps& steps)
{
  const int S = steps.samplesPerCell;
  steps.delta = std::max(cellDepth / S, fieldStep);
  steps.firstStep = std::floor(span.lo / steps.delta);
  if ((span.hi - steps.zeta(0)) / (S * steps.delta) > MaxDepthCells)
  {
    // Off the lattice: longer steps from the front.
    steps.zetaBase = span.lo;
    steps.firstStep = 0;
    steps.delta = (span.hi - span.lo) / (S * MaxDepthCells);
  }
  return steps.coordinate(span.hi);
}

/// The depth steps (section 3.3, equations 3.2 to 3.9): S = ceil(tileSize lambda / stepFactor)
/// samples per cell (lambda the obliquity, equation 3.4), a cell tileSize pixels deep (in
/// log-depth, or depth for parallel views), as many cells as reach past the particles' back;
/// beyond MaxDepthCells cells the cells deepen.
DepthSteps depthSteps(const ViewRays& rays,
  const PerspectiveGridParameters& params,
  int tileSize,
  const DepthSpan& span)
{
  const double lambda = rays.obliquity();
  const double stepFactor = params.stepFactor > 0 ? params.stepFactor : 1.0;
  DepthSteps steps;
  steps.logarithmic = rays.isPerspective();
  steps.zetaNear = rays.nearZeta();
  const int S = steps.samplesPerCell =
    std::clamp(static_cast<int>(std::ceil(tileSize * lambda / stepFactor - 1e-9)), 1, 1024);
  // Pixel-tied step: a cell is tileSize pixels deep (log-depth or depth) and holds S samples.
  const double cellDepth = tileSize * rays.pixelSize();
  const double extent = steps.logarithmic
                          ? logarithmicSteps(span, params.fieldStep, cellDepth, steps)
                          : uniformSteps(span, params.fieldStep, cellDepth, steps);
  steps.cells = std::max(1, static_cast<int>(std::ceil(extent / S - 1e-9)));
  return steps;
}

/// Calls fn(cell) for every cell of the range (x, y and z).
template<typename Fn>
void forEachCell(const PerspectiveGrid& grid, const CellRange& cr, Fn fn)
{
  for (int ty = cr.ty0; ty <= cr.ty1; ++ty)
  {
    for (int tx = cr.tx0; tx <= cr.tx1; ++tx)
    {
      for (int tz = cr.tz0; tz <= cr.tz1; ++tz)
      {
        fn(grid.cellIndex(tx, ty, tz));
      }
    }
  }
}

/// The map from particles to cells, counted (section 3.4.2): each particle's range of cells
/// along z (the sample coordinates of its depth span, equation 3.7), then one count per
/// cell of its range.
void countReferences(const PerspectiveGrid& grid,
  std::vector<CellRange>& ranges,
  std::atomic<std::uint32_t>* counter)
{
  const DepthSteps& steps = grid.steps();
  const int S = steps.samplesPerCell, totalSamples = steps.samples();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid.cellCount(), 65536),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t c = r.begin(); c != r.end(); ++c)
      {
        counter[c].store(0, std::memory_order_relaxed);
      }
    });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ranges.size(), 4096),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
      {
        CellRange& cr = ranges[i];
        if (cr.tz0 > cr.tz1)
        {
          continue;
        }
        const double u0 = steps.coordinate(cr.zlo), u1 = steps.coordinate(cr.zhi);
        cr.tz0 = std::clamp(static_cast<int>(std::floor(u0)), 0, totalSamples - 1) / S;
        cr.tz1 = std::clamp(static_cast<int>(std::floor(u1)), 0, totalSamples - 1) / S;
        forEachCell(
          grid, cr, [&](std::size_t c) { counter[c].fetch_add(1, std::memory_order_relaxed); });
      }
    });
}

/// The cells' starts in the map (prefix sum of the counts); the counters become the cells'
/// write cursors. Returns the number of references.
std::uint64_t cellStarts(std::atomic<std::uint32_t>* counter,
  std::size_t cells,
  std::vector<std::uint32_t>& start)
{
  start.resize(cells + 1);
  std::uint64_t total = 0;
  for (std::size_t c = 0; c < cells; ++c)
  {
    start[c] = static_cast<std::uint32_t>(total);
    total += counter[c].load(std::memory_order_relaxed);
    counter[c].store(start[c], std::memory_order_relaxed); // now the write cursor
  }
  start[cells] = static_cast<std::uint32_t>(total);
  return total;
}

/// Scatters the particle indices into their cells' lists.
void scatterReferences(const PerspectiveGrid& grid,
  const std::vector<CellRange>& ranges,
  std::atomic<std::uint32_t>* counter,
  std::vector<std::uint32_t>& refs)
{
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ranges.size(), 4096),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
      {
        const CellRange& cr = ranges[i];
        if (cr.tz0 > cr.tz1)
        {
          continue;
        }
        forEachCell(grid,
          cr,
          [&](std::size_t c) {
            refs[counter[c].fetch_add(1, std::memory_order_relaxed)] =
              static_cast<std::uint32_t>(i);
          });
      }
    });
}
}

bool PerspectiveGrid::build(const SPHParticles& particles,
  const ViewRays& rays,
  const PerspectiveGridParameters& params)
{
  TileSize = std::max(1, params.tileSize);
  TilesX = (rays.width() + TileSize - 1) / TileSize;
  TilesY = (rays.height() + TileSize - 1) / TileSize;
  Footprints.resize(particles.size());
  std::vector<CellRange> ranges(particles.size());
  const DepthSpan span = projectParticles(particles, rays, TileSize, Footprints, ranges);
  InView = span.count;
  CellStart.assign(1, 0);
  Refs.clear();
  EmptyRun.clear();
  Steps.cells = 0;
  if (InView == 0 || !(span.lo < span.hi))
  {
    return false;
  }
  Steps = depthSteps(rays, params, TileSize, span);
  const std::size_t cells = cellCount();
  std::unique_ptr<std::atomic<std::uint32_t>[]> counter(new std::atomic<std::uint32_t>[cells]);
  countReferences(*this, ranges, counter.get());
  Refs.resize(cellStarts(counter.get(), cells, CellStart));
  scatterReferences(*this, ranges, counter.get(), Refs);
  sortCellsAndCountEmptyRuns();
  return true;
}

/// Orders each cell's list by particle index (the sums over a cell's particles are then the
/// same for any thread schedule) and fills the empty successors cache (section 3.4.3) per
/// tile column, back to front.
void PerspectiveGrid::sortCellsAndCountEmptyRuns()
{
  EmptyRun.assign(cellCount(), 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, TilesX * TilesY, 16),
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
}

std::size_t PerspectiveGrid::memoryBytes() const
{
  return CellStart.size() * sizeof(std::uint32_t) + Refs.size() * sizeof(std::uint32_t) +
    EmptyRun.size() * sizeof(std::uint32_t) + Footprints.size() * sizeof(ParticleFootprint);
}

} // namespace raymappers
