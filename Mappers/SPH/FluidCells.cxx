#include "Mappers/SPH/FluidCells.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>

namespace raymappers
{
namespace
{
struct Bounds
{
  static constexpr double inf = std::numeric_limits<double>::infinity();
  Vec3d lo{ inf, inf, inf };
  Vec3d hi{ -inf, -inf, -inf };
};

/// Spreads the low 21 bits of v to every third bit (Morton interleaving).
std::uint64_t spread3(std::uint64_t v)
{
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

/// The spheres of a coverage test, as structure of arrays (loops over them vectorize).
struct SphereList
{
  std::vector<float> x, y, z, r;
  std::size_t n = 0;

  std::size_t size() const { return n; }
  void clear() { n = 0; }
  void push(float px, float py, float pz, float pr)
  {
    if (n == x.size())
    {
      grow(2 * n + 64);
    }
    x[n] = px;
    y[n] = py;
    z[n] = pz;
    r[n] = pr;
    ++n;
  }
  /// These spheres become those of `in` that meet the ball of radius hd around q.
  void keepMeeting(const SphereList& in, float qx, float qy, float qz, float hd)
  {
    if (x.size() < in.n)
    {
      grow(in.n);
    }
    std::size_t m = 0;
    for (std::size_t k = 0; k < in.n; ++k)
    {
      // Written always, kept when it meets (no branch).
      const float dx = qx - in.x[k], dy = qy - in.y[k], dz = qz - in.z[k], reach = in.r[k] + hd;
      x[m] = in.x[k];
      y[m] = in.y[k];
      z[m] = in.z[k];
      r[m] = in.r[k];
      m += dx * dx + dy * dy + dz * dz < reach * reach ? 1 : 0;
    }
    n = m;
  }
  /// Whether some sphere holds the point q; stops at the first (the cell's own spheres come
  /// first and hold most points).
  bool anyContains(float qx, float qy, float qz) const
  {
    for (std::size_t k = 0; k < n; ++k)
    {
      const float dx = qx - x[k], dy = qy - y[k], dz = qz - z[k];
      if (dx * dx + dy * dy + dz * dz < r[k] * r[k])
      {
        return true;
      }
    }
    return false;
  }
  /// Whether some sphere holds the ball of radius `hd` around q: |q - c| <= r - hd.
  bool anyWithin(float qx, float qy, float qz, float hd) const
  {
    const float* X = x.data();
    const float* Y = y.data();
    const float* Z = z.data();
    const float* R = r.data();
    int found = 0;
#pragma omp simd reduction(| : found)
    for (std::size_t k = 0; k < n; ++k)
    {
      const float dx = qx - X[k], dy = qy - Y[k], dz = qz - Z[k], m = R[k] - hd;
      found |= (m >= 0.f) & (dx * dx + dy * dy + dz * dz <= m * m);
    }
    return found != 0;
  }

private:
  void grow(std::size_t size)
  {
    x.resize(size);
    y.resize(size);
    z.resize(size);
    r.resize(size);
  }
};

/// Whether an axis-aligned cube lies in the union of spheres, proven by containment: a cube of
/// centre q and half side a lies in the sphere B(c, r) iff its farthest corner does, which
/// |q - c| + a sqrt(3) <= r guarantees. A cube no single sphere contains is split into its 8
/// children, down to `Depth` halvings (side s / 16 for a cell of side s; near the points where
/// the union's cover is thinnest, between lattice-like particles of radius = spacing, the margin
/// is 0.13 r, the children's half-diagonal there 0.11 r); the cube is covered when every leaf
/// is. Only the spheres that meet a cube (|q - c| < r + a sqrt(3)) are passed to its children, so
/// the lists shrink as the cubes do. A cube that no sphere meets, or a leaf no single sphere
/// contains, is not proven covered (conservative: the cell counts as not full).
class CoverageTest
{
public:
  static constexpr int Depth = 4;

  /// Starts a cell's test: its block's spheres are gathered with add(), relative to the centre.
  void begin(const Vec3d& centre)
  {
    Centre = centre;
    Levels[Depth].clear();
  }
  void add(const Vec3f& c, float r)
  {
    const Vec3d d = Vec3d(c) - Centre;
    Levels[Depth].push(static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z), r);
  }
  /// Whether the cell (centred at begin's centre, half side a) lies in the spheres' union.
  bool cellCovered(double a)
  {
    // Quick rejection of the cells at the fluid's boundary: one of the 27 points of the
    // 3 x 3 x 3 lattice spanning the box outside every sphere disproves the cover at once.
    const SphereList& all = Levels[Depth];
    const float h = static_cast<float>(a);
    for (int p = 0; p < 27; ++p)
    {
      if (!all.anyContains((p % 3 - 1) * h, ((p / 3) % 3 - 1) * h, (p / 9 - 1) * h))
      {
        return false;
      }
    }
    return covered(0, 0, 0, h, Depth);
  }

private:
  /// Whether the cube of centre q and half side a lies in the union of the spheres of level
  /// `depth`: one of them holds it, or each of its 8 children is covered at the level below.
  bool covered(float qx, float qy, float qz, float a, int depth)
  {
    const float hd = a * 1.7320508f;
    const SphereList& in = Levels[depth];
    if (in.anyWithin(qx, qy, qz, hd))
    {
      return true;
    }
    if (depth == 0)
    {
      return false;
    }
    SphereList& out = Levels[depth - 1];
    const float h = 0.5f * a, chd = 0.5f * hd;
    for (int c = 0; c < 8; ++c)
    {
      const float cx = qx + (c & 1 ? h : -h), cy = qy + (c & 2 ? h : -h), cz = qz + (c & 4 ? h : -h);
      out.keepMeeting(in, cx, cy, cz, chd);
      if (out.size() == 0 || !covered(cx, cy, cz, h, depth - 1))
      {
        return false;
      }
    }
    return true;
  }

  Vec3d Centre;
  SphereList Levels[Depth + 1]; // the spheres meeting the cube of each level (Depth: the block)
};

/// The grid: cells of size s from `origin`, one empty cell of padding on every side (so a
/// cell at the data's border has empty neighbours and is never inner).
struct CellGrid
{
  Vec3d origin;
  double s = 1;
  std::array<long long, 3> dims{ 1, 1, 1 };

  long long index(long long i, long long j, long long k) const
  {
    return (k * dims[1] + j) * dims[0] + i;
  }
  std::array<long long, 3> coordinates(long long c) const
  {
    return { c % dims[0], (c / dims[0]) % dims[1], c / (dims[0] * dims[1]) };
  }
  long long cellOf(const Vec3f& p) const
  {
    const Vec3d q = (Vec3d(p) - origin) * (1.0 / s);
    const auto clampAxis = [&](double v, int a)
    { return std::clamp(static_cast<long long>(std::floor(v)), 1LL, dims[a] - 2); };
    return index(clampAxis(q.x, 0), clampAxis(q.y, 1), clampAxis(q.z, 2));
  }
};

/// The bounding box of the particles' centres.
Bounds centreBounds(const FluidParticles& particles)
{
  return tbb::parallel_reduce(
    tbb::blocked_range<std::size_t>(0, particles.size(), 8192),
    Bounds(),
    [&](const tbb::blocked_range<std::size_t>& r, Bounds acc)
    {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
      {
        const Vec3d p(particles.centers[i]);
        acc.lo = min(acc.lo, p);
        acc.hi = max(acc.hi, p);
      }
      return acc;
    },
    [](Bounds a, const Bounds& c)
    {
      a.lo = min(a.lo, c.lo);
      a.hi = max(a.hi, c.hi);
      return a;
    });
}

/// The grid over the bounds: cells of size max(cellSize, r_max) (cellSize <= 0: 2 r_max) -- at
/// least r_max, which the culling's argument needs -- grown by half until there are no more
/// cells than a few per particle (scattered particles would otherwise ask for an enormous grid
/// of empty cells) and every axis fits a Morton key's 21 bits.
CellGrid chooseCellGrid(const Bounds& b, std::size_t n, double rMax, double cellSize)
{
  CellGrid grid;
  grid.s = std::max(cellSize > 0 ? cellSize : 2.0 * rMax, rMax);
  const Vec3d extent = b.hi - b.lo;
  const double maxCells = std::max(8.0 * static_cast<double>(n), 1.0e6);
  for (;;)
  {
    for (int a = 0; a < 3; ++a)
    {
      grid.dims[a] = static_cast<long long>(std::floor(extent[a] / grid.s)) + 3;
    }
    const double cells = double(grid.dims[0]) * double(grid.dims[1]) * double(grid.dims[2]);
    if (cells <= maxCells && std::max({ grid.dims[0], grid.dims[1], grid.dims[2] }) < (1LL << 21))
    {
      break;
    }
    grid.s *= 1.5;
  }
  grid.origin = b.lo - Vec3d(grid.s, grid.s, grid.s);
  return grid;
}

/// The particles sorted into the cells: cell c holds sorted[start[c] .. start[c + 1]) in
/// index order; `occupied` lists the cells that hold any, in increasing order.
struct CellLists
{
  std::vector<std::uint32_t> start, sorted, occupied;
};

/// Counting sort of the particles by cell: counts, prefix sums, scatter; each cell's list is
/// then put in index order, so the result does not depend on the threads.
CellLists sortIntoCells(const FluidParticles& particles, const CellGrid& grid)
{
  const std::size_t n = particles.size();
  const long long cells = grid.dims[0] * grid.dims[1] * grid.dims[2];
  CellLists lists;
  std::vector<std::uint32_t> cellOf(n);
  std::unique_ptr<std::atomic<std::uint32_t>[]> count(new std::atomic<std::uint32_t>[cells + 1]);
  tbb::parallel_for(tbb::blocked_range<long long>(0, cells + 1, 1 << 16),
    [&](const tbb::blocked_range<long long>& r)
    {
      for (long long c = r.begin(); c != r.end(); ++c)
      {
        count[c].store(0, std::memory_order_relaxed);
      }
    });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
      {
        const long long c = grid.cellOf(particles.centers[i]);
        cellOf[i] = static_cast<std::uint32_t>(c);
        count[c].fetch_add(1, std::memory_order_relaxed);
      }
    });
  std::vector<std::uint32_t>& start = lists.start;
  start.assign(static_cast<std::size_t>(cells) + 1, 0);
  for (long long c = 0; c < cells; ++c)
  {
    const std::uint32_t k = count[c].load(std::memory_order_relaxed);
    start[c + 1] = start[c] + k;
    if (k > 0)
    {
      lists.occupied.push_back(static_cast<std::uint32_t>(c));
    }
    count[c].store(start[c], std::memory_order_relaxed); // now the scatter cursor
  }
  std::vector<std::uint32_t>& sorted = lists.sorted;
  sorted.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
      {
        sorted[count[cellOf[i]].fetch_add(1, std::memory_order_relaxed)] =
          static_cast<std::uint32_t>(i);
      }
    });
  count.reset();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lists.occupied.size(), 1024),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t o = r.begin(); o != r.end(); ++o)
      {
        const std::uint32_t c = lists.occupied[o];
        std::sort(sorted.begin() + start[c], sorted.begin() + start[c + 1]);
      }
    });
  return lists;
}

/// Full cells (1, else 0): the cell's box proven to lie in the union of the spheres of its
/// 3 x 3 x 3 block (CoverageTest).
std::vector<std::uint8_t> findFullCells(const FluidParticles& particles,
  const CellGrid& grid,
  const CellLists& lists)
{
  // The spheres in cell order, so a block's are read from 27 contiguous runs (from the input
  // order every one would be a cache miss).
  const std::size_t n = particles.size();
  std::vector<Vec3f> centre(n);
  std::vector<float> radius(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
      {
        centre[k] = particles.centers[lists.sorted[k]];
        radius[k] = particles.radius[lists.sorted[k]];
      }
    });
  std::vector<std::uint8_t> full(lists.start.size() - 1, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lists.occupied.size(), 256),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      CoverageTest test;
      for (std::size_t o = r.begin(); o != r.end(); ++o)
      {
        const long long c = lists.occupied[o];
        const auto ijk = grid.coordinates(c);
        test.begin(grid.origin + Vec3d(ijk[0] + 0.5, ijk[1] + 0.5, ijk[2] + 0.5) * grid.s);
        for (int d = 0; d < 27; ++d)
        {
          // The cell itself first (d = 0 is e = 13): its particles cover most of it.
          const int e = (d + 13) % 27;
          const long long nb =
            grid.index(ijk[0] + e % 3 - 1, ijk[1] + (e / 3) % 3 - 1, ijk[2] + e / 9 - 1);
          for (std::uint32_t k = lists.start[nb]; k < lists.start[nb + 1]; ++k)
          {
            test.add(centre[k], radius[k]);
          }
        }
        full[static_cast<std::size_t>(c)] = test.cellCovered(0.5 * grid.s) ? 1 : 0;
      }
    });
  return full;
}

/// Inner cells (1, else 0): full with 26 full neighbours (the padding cells are empty, never
/// full).
std::vector<std::uint8_t> findInnerCells(const CellGrid& grid,
  const CellLists& lists,
  const std::vector<std::uint8_t>& full)
{
  std::vector<std::uint8_t> inner(full.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lists.occupied.size(), 1024),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t o = r.begin(); o != r.end(); ++o)
      {
        const long long c = lists.occupied[o];
        if (!full[static_cast<std::size_t>(c)])
        {
          continue;
        }
        const auto ijk = grid.coordinates(c);
        bool all = true;
        for (int d = 0; d < 27 && all; ++d)
        {
          all = full[static_cast<std::size_t>(grid.index(
                  ijk[0] + d % 3 - 1, ijk[1] + (d / 3) % 3 - 1, ijk[2] + d / 9 - 1))] != 0;
        }
        inner[static_cast<std::size_t>(c)] = all ? 1 : 0;
      }
    });
  return inner;
}

/// The kept particles (all but those of inner cells; `inner` empty: all), cell by cell in
/// Morton order of the cells.
void keepBoundaryParticles(const CellGrid& grid,
  const CellLists& lists,
  const std::vector<std::uint8_t>& inner,
  FluidCells& out)
{
  std::vector<std::pair<std::uint64_t, std::uint32_t>> order;
  order.reserve(lists.occupied.size() - out.innerCells);
  for (const std::uint32_t c : lists.occupied)
  {
    if (!inner.empty() && inner[c])
    {
      out.culledParticles += lists.start[c + 1] - lists.start[c];
      continue;
    }
    const auto ijk = grid.coordinates(c);
    order.emplace_back(spread3(static_cast<std::uint64_t>(ijk[0])) |
        spread3(static_cast<std::uint64_t>(ijk[1])) << 1 |
        spread3(static_cast<std::uint64_t>(ijk[2])) << 2,
      c);
  }
  tbb::parallel_sort(order.begin(), order.end());
  out.kept.reserve(lists.sorted.size() - out.culledParticles);
  for (const auto& key : order)
  {
    out.kept.insert(out.kept.end(),
      lists.sorted.begin() + lists.start[key.second],
      lists.sorted.begin() + lists.start[key.second + 1]);
  }
}

/// The full cells merged greedily into few large boxes (a ray crosses each box once, so fewer
/// boxes mean fewer fills per pixel): from each full cell not yet in a box, a run along x,
/// grown into a rectangle along y, then into a box along z, as far as every cell is full and
/// not yet taken (marked 2 once taken).
class BoxMerger
{
public:
  BoxMerger(const CellGrid& cellGrid, std::vector<std::uint8_t>& fullCells)
    : grid(cellGrid)
    , full(fullCells)
  {
  }
  void merge(std::vector<FluidBox>& boxes)
  {
    for (long long k = 1; k + 1 < grid.dims[2]; ++k)
    {
      for (long long j = 1; j + 1 < grid.dims[1]; ++j)
      {
        for (long long i = 1; i + 1 < grid.dims[0]; ++i)
        {
          if (at(i, j, k) == 1)
          {
            boxes.push_back(grow(i, j, k));
          }
        }
      }
    }
  }

private:
  std::uint8_t& at(long long i, long long j, long long k)
  {
    return full[static_cast<std::size_t>(grid.index(i, j, k))];
  }
  /// Whether cells i0..i1 of row (j, k) are full and free.
  bool freeRow(long long i0, long long i1, long long j, long long k)
  {
    for (long long i = i0; i <= i1; ++i)
    {
      if (at(i, j, k) != 1)
      {
        return false;
      }
    }
    return true;
  }
  /// Whether rows j0..j1 of cells i0..i1 in layer k are full and free.
  bool freeRectangle(long long i0, long long i1, long long j0, long long j1, long long k)
  {
    for (long long j = j0; j <= j1; ++j)
    {
      if (!freeRow(i0, i1, j, k))
      {
        return false;
      }
    }
    return true;
  }
  /// The box grown from the free full cell (i, j, k), its cells taken.
  FluidBox grow(long long i, long long j, long long k)
  {
    long long i1 = i, j1 = j, k1 = k;
    while (at(i1 + 1, j, k) == 1)
    {
      ++i1;
    }
    while (freeRow(i, i1, j1 + 1, k))
    {
      ++j1;
    }
    while (freeRectangle(i, i1, j, j1, k1 + 1))
    {
      ++k1;
    }
    for (long long kk = k; kk <= k1; ++kk)
    {
      for (long long jj = j; jj <= j1; ++jj)
      {
        for (long long ii = i; ii <= i1; ++ii)
        {
          at(ii, jj, kk) = 2;
        }
      }
    }
    const Vec3d lo = grid.origin + Vec3d(double(i), double(j), double(k)) * grid.s;
    const Vec3d hi = grid.origin + Vec3d(double(i1 + 1), double(j1 + 1), double(k1 + 1)) * grid.s;
    return { Vec3f(lo), Vec3f(hi) };
  }

  const CellGrid& grid;
  std::vector<std::uint8_t>& full;
};
}

void buildFluidCells(const FluidParticles& particles, double cellSize, bool cull, FluidCells& out)
{
  out = FluidCells();
  if (particles.size() == 0)
  {
    return;
  }
  const CellGrid grid =
    chooseCellGrid(centreBounds(particles), particles.size(), particles.maxRadius, cellSize);
  out.cellSize = grid.s;
  const CellLists lists = sortIntoCells(particles, grid);
  out.occupiedCells = lists.occupied.size();
  if (!cull)
  {
    keepBoundaryParticles(grid, lists, {}, out);
    return;
  }
  std::vector<std::uint8_t> full = findFullCells(particles, grid, lists);
  const std::vector<std::uint8_t> inner = findInnerCells(grid, lists, full);
  for (const std::uint32_t c : lists.occupied)
  {
    out.fullCells += full[c];
    out.innerCells += inner[c];
  }
  keepBoundaryParticles(grid, lists, inner, out);
  BoxMerger(grid, full).merge(out.boxes);
}

} // namespace raymappers
