#include "Mappers/SPH/SpanVoxelizer.h"

#include "Mappers/Common/AvailableMemory.h"

#include "Mappers/SPH/Tallies.h"
#include "Mappers/Common/SimdTarget.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <functional>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <memory>
#include <new>
#include <numeric>
#include <string>
#include <vector>

namespace raymappers
{

RAYMAPPERS_SIMD_VARIANTS(voxelizeFluid)

RAYMAPPERS_SIMD_BEGIN
namespace
{
/// The pixels [x0, x1] x [y0, y1] whose rays can meet a particle (empty when x0 > x1).
struct Footprint
{
  int x0, x1, y0, y1;
};

struct DepthRange
{
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  std::size_t inView = 0;
};

/// The pixels whose rays can meet a box and its depth range clipped to near and far: the
/// bounding rectangle of its corners' projections (the projection of a convex body lies in
/// that of its corners' hull), or the whole image when a corner is at or behind the eye plane.
Footprint boxFootprint(const ViewRays& rays, const FluidBox& b, DepthRange& range)
{
  const int W = rays.width(), H = rays.height();
  double zlo = std::numeric_limits<double>::infinity(), zhi = -zlo;
  double xlo = zlo, xhi = zhi, ylo = zlo, yhi = zhi;
  bool behind = false;
  for (int k = 0; k < 8; ++k)
  {
    const Vec3d p((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z);
    const double z = rays.zetaOf(p);
    zlo = std::min(zlo, z);
    zhi = std::max(zhi, z);
    const std::array<double, 4> c = rays.clip(p);
    if (!(c[3] > 0))
    {
      behind = true;
      continue;
    }
    const double x = (c[0] / c[3] + 1.0) * 0.5 * W, y = (c[1] / c[3] + 1.0) * 0.5 * H;
    xlo = std::min(xlo, x);
    xhi = std::max(xhi, x);
    ylo = std::min(ylo, y);
    yhi = std::max(yhi, y);
  }
  zlo = std::max(zlo, rays.nearZeta());
  zhi = std::min(zhi, rays.farZeta());
  if (!(zlo < zhi))
  {
    return { 1, 0, 1, 0 };
  }
  if (behind)
  {
    xlo = ylo = 0;
    xhi = W;
    yhi = H;
  }
  const Footprint f = { static_cast<int>(std::ceil(std::max(xlo, 0.0) - 0.5)),
    static_cast<int>(std::floor(std::min(xhi, double(W)) - 0.5)),
    static_cast<int>(std::ceil(std::max(ylo, 0.0) - 0.5)),
    static_cast<int>(std::floor(std::min(yhi, double(H)) - 0.5)) };
  if (f.x0 <= f.x1 && f.y0 <= f.y1)
  {
    range.lo = std::min(range.lo, zlo);
    range.hi = std::max(range.hi, zhi);
  }
  return f;
}

/// The ray p(zeta) = A + zeta B inside the box: [z0, z1] (empty when z0 >= z1), by slabs.
inline void rayBox(const Vec3d& A, const Vec3d& B, const FluidBox& b, double& z0, double& z1)
{
  z0 = -std::numeric_limits<double>::infinity();
  z1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
  {
    const double lo = b.lo[a], hi = b.hi[a];
    if (B[a] == 0.0)
    {
      if (A[a] < lo || A[a] > hi)
      {
        z0 = z1;
      }
      continue;
    }
    const double inv = 1.0 / B[a];
    const double t0 = (lo - A[a]) * inv, t1 = (hi - A[a]) * inv;
    z0 = std::max(z0, std::min(t0, t1));
    z1 = std::min(z1, std::max(t0, t1));
  }
}

struct TallyCounters
{
  std::int64_t splatPixels = 0, boxPixels = 0, stoppedSpans = 0, setBitOps = 0, spansFound = 0, spansStored = 0, spansHidden = 0,
               gapsBridged = 0;
};

/// The tallies by their counters' names in the statistics.
constexpr TallyField<TallyCounters> Tallies[] = { { "splat_pixels", &TallyCounters::splatPixels },
  { "box_pixels", &TallyCounters::boxPixels },
  { "stopped_spans", &TallyCounters::stoppedSpans },
  { "set_bit_ops", &TallyCounters::setBitOps },
  { "spans_found", &TallyCounters::spansFound },
  { "spans_stored", &TallyCounters::spansStored },
  { "spans_hidden", &TallyCounters::spansHidden },
  { "gaps_bridged", &TallyCounters::gapsBridged } };

/// Column q (the tile's pixels row by row) of the tile's grid: its words are contiguous.
inline std::uint64_t* columnOf(std::uint64_t* grid, std::size_t q, int words)
{
  return grid + q * words;
}

/// Sets bits [l0, l1] of a column (the tile's grid belongs to one thread: plain stores).
inline std::int64_t setBits(std::uint64_t* column, int l0, int l1)
{
  const int w0 = l0 >> 6, w1 = l1 >> 6;
  const std::uint64_t ones = ~std::uint64_t(0);
  const std::uint64_t first = ones << (l0 & 63);
  const std::uint64_t last = (l1 & 63) == 63 ? ones : (std::uint64_t(1) << ((l1 & 63) + 1)) - 1;
  if (w0 == w1)
  {
    column[w0] |= first & last;
    return 1;
  }
  column[w0] |= first;
  std::fill(column + w0 + 1, column + w1, ones);
  column[w1] |= last;
  return w1 - w0 + 1;
}

inline void setBit(std::uint64_t* column, int l)
{
  column[l >> 6] |= std::uint64_t(1) << (l & 63);
}

/// The first layer >= pos whose bit equals `value` (`words * 64` when none).
inline int nextBit(const std::uint64_t* column, int words, int pos, bool value)
{
  int w = pos >> 6;
  if (w >= words)
  {
    return words * 64;
  }
  std::uint64_t bits = (value ? column[w] : ~column[w]) & (~std::uint64_t(0) << (pos & 63));
  while (bits == 0)
  {
    if (++w == words)
    {
      return words * 64;
    }
    bits = value ? column[w] : ~column[w];
  }
  return (w << 6) + __builtin_ctzll(bits);
}
}

RAYMAPPERS_SIMD_END

#if RAYMAPPERS_SIMD_TARGET == 0 // (the functions outside the variants: once)
std::size_t automaticMemoryBudget()
{
  constexpr std::size_t Least = std::size_t(512) << 20;
  return std::max(Least, availableMemoryBytes() / 2);
}

std::string describeBudgetShortfall(const RenderStatistics& stats)
{
  const auto mb = [](std::int64_t bytes) { return std::to_string((bytes + 1048575) / 1048576); };
  std::string text = "The memory budget of " + mb(stats.counter("memory_budget_bytes")) + " MB" +
    (stats.counter("memory_budget_automatic") ? " (automatic: half the memory available)" : "") +
    " cannot hold this view's voxelization (the tile lists of " + std::to_string(stats.counter("particles_in_view")) +
    " particles in view and a grid of " + std::to_string(stats.counter("layers")) +
    " layers per thread";
  const std::int64_t needed = stats.counter("budget_needed_bytes");
  if (needed > 0)
  {
    return text + " need at least " + mb(needed) + " MB)";
  }
  return text + ": an allocation failed)";
}

std::vector<float> stopDepthsFromWindowDepth(const ViewRays& rays, const float* windowDepth)
{
  const int W = rays.width(), H = rays.height();
  std::vector<float> out(static_cast<std::size_t>(W) * static_cast<std::size_t>(H),
    std::numeric_limits<float>::infinity());
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 16),
    [&](const tbb::blocked_range<int>& r)
    {
      for (int j = r.begin(); j != r.end(); ++j)
      {
        for (int i = 0; i < W; ++i)
        {
          const std::size_t p = static_cast<std::size_t>(j) * W + i;
          const float d = windowDepth[p];
          if (d < 1.f)
          {
            const double z = rays.zetaOfWindowDepth(i + 0.5, j + 0.5, d);
            out[p] = std::isfinite(z) ? static_cast<float>(z) : out[p];
          }
        }
      }
    });
  return out;
}
#endif

RAYMAPPERS_SIMD_BEGIN

namespace
{
const char* const VoxelizerCounters[] = { "angle_millidegrees",
  "boxes_in_view",
  "box_pixels",
  "particles_in_view",
  "layers",
  "words_per_column",
  "tiles",
  "tile_width",
  "tile_height",
  "splat_pixels",
  "stopped_spans",
  "set_bit_ops",
  "spans_found",
  "spans_stored",
  "spans_hidden",
  "gaps_bridged",
  "peak_temporary_bytes",
  "memory_budget_bytes",
  "memory_budget_automatic",
  "budget_exceeded" };

/// What is splatted: the particles (all, or those boundary-cell culling keeps, in its order)
/// and the full cells' boxes, with their footprints (the particles', then the boxes').
struct SplatList
{
  const FluidCells* cells = nullptr;
  std::size_t particles = 0, boxes = 0;
  std::vector<Footprint> footprints;

  std::size_t particleAt(std::size_t k) const { return cells ? std::size_t(cells->kept[k]) : k; }
};

/// The footprints of the list's particles and boxes (sections 3.1, 4.1) and the depth range of
/// those in view; boxesInView counts the boxes in view.
DepthRange projectSplats(const FluidParticles& particles,
  const ViewRays& rays,
  SplatList& list,
  std::size_t& boxesInView)
{
  DepthRange range = tbb::parallel_reduce(
    tbb::blocked_range<std::size_t>(0, list.particles, 4096),
    DepthRange(),
    [&](const tbb::blocked_range<std::size_t>& r, DepthRange d)
    {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
      {
        const std::size_t i = list.particleAt(k);
        const SphereFootprint f = rays.footprint(Vec3d(particles.centers[i]), particles.radius[i]);
        if (!f.inView)
        {
          list.footprints[k] = { 1, 0, 1, 0 };
          continue;
        }
        list.footprints[k] = { f.i0, f.i1, f.j0, f.j1 };
        d.lo = std::min(d.lo, f.zlo);
        d.hi = std::max(d.hi, f.zhi);
        ++d.inView;
      }
      return d;
    },
    [](DepthRange a, const DepthRange& b)
    {
      a.lo = std::min(a.lo, b.lo);
      a.hi = std::max(a.hi, b.hi);
      a.inView += b.inView;
      return a;
    });
  boxesInView = 0;
  for (std::size_t k = 0; k < list.boxes; ++k)
  {
    const Footprint f = boxFootprint(rays, list.cells->boxes[k], range);
    list.footprints[list.particles + k] = f;
    boxesInView += f.x0 <= f.x1 && f.y0 <= f.y1;
  }
  return range;
}

/// The screen's square tiles of `size` pixels (section 3.1) and what each must splat: the
/// indices (into the SplatList) of the particles and boxes whose footprints overlap it,
/// tile t's from items[start[t]] to items[start[t + 1]].
struct TileLists
{
  int size = 0, tilesX = 0, tilesY = 0;
  std::vector<std::size_t> start;
  std::vector<std::uint32_t> items;

  std::size_t tiles() const { return static_cast<std::size_t>(tilesX) * tilesY; }
  /// Calls fn(tile) for each tile footprint f overlaps.
  template<typename Fn>
  void forTilesOf(const Footprint& f, Fn fn) const
  {
    if (f.x0 > f.x1 || f.y0 > f.y1)
    {
      return;
    }
    for (int ty = f.y0 / size; ty <= f.y1 / size; ++ty)
    {
      for (int tx = f.x0 / size; tx <= f.x1 / size; ++tx)
      {
        fn(static_cast<std::size_t>(ty) * tilesX + tx);
      }
    }
  }
};

/// How many (tile, item) entries tiles of `size` pixels would list.
std::size_t tileEntries(const SplatList& list, int size)
{
  return tbb::parallel_reduce(
    tbb::blocked_range<std::size_t>(0, list.footprints.size(), 4096),
    std::size_t(0),
    [&](const tbb::blocked_range<std::size_t>& r, std::size_t n)
    {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
      {
        const Footprint& f = list.footprints[k];
        if (f.x0 <= f.x1 && f.y0 <= f.y1)
        {
          n += static_cast<std::size_t>(f.x1 / size - f.x0 / size + 1) * (f.y1 / size - f.y0 / size + 1);
        }
      }
      return n;
    },
    std::plus<>());
}

/// The lists of tiles of `size` pixels: counted, offset, then filled (in parallel; the order
/// within a tile does not matter, the bits are ORed).
void listTiles(const SplatList& list, int W, int H, int size, TileLists& tl)
{
  tl.size = size;
  tl.tilesX = (W + size - 1) / size;
  tl.tilesY = (H + size - 1) / size;
  std::vector<std::size_t> cursor(tl.tiles() + 1, 0);
  const tbb::blocked_range<std::size_t> all(0, list.footprints.size(), 4096);
  tbb::parallel_for(all,
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
      {
        tl.forTilesOf(list.footprints[k],
          [&](std::size_t t) { __atomic_fetch_add(&cursor[t + 1], 1, __ATOMIC_RELAXED); });
      }
    });
  for (std::size_t t = 0; t < tl.tiles(); ++t)
  {
    cursor[t + 1] += cursor[t];
  }
  tl.start = cursor;
  tl.items.resize(cursor.back());
  tbb::parallel_for(all,
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
      {
        tl.forTilesOf(list.footprints[k],
          [&](std::size_t t)
          {
            tl.items[__atomic_fetch_add(&cursor[t], 1, __ATOMIC_RELAXED)] =
              static_cast<std::uint32_t>(k);
          });
      }
    });
}

/// The voxelization of one tile into its bit grid (one thread's: `size` x `size` columns of
/// `words` words, clear on entry and left clear) and its compression into the spans.
struct TileVoxelizer
{
  const FluidParticles& particles;
  const ViewRays& rays;
  const SplatList& list;
  const VoxelDepthLayers& layers;
  std::uint64_t* grid;    // the tile's columns, `words` words each
  std::uint8_t* touched;  // per column of the tile: a splat wrote it
  const float* stop;      // the stop depths, or null
  int words, W;
  bool shell; // set only the layers of the spheres' surfaces
  float g;    // the gap threshold
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0; // the tile: pixels [x0, x1) x [y0, y1)

  double front() const { return layers.depths.front(); }
  double back() const { return layers.depths.back(); }
  /// Depth z clipped to where pixel (px, j)'s ray ends: the layers' back or opaque geometry.
  double clipToRayEnd(double z, int px, int j) const
  {
    return std::min(
      std::min(z, back()), stop ? double(stop[static_cast<std::size_t>(j) * W + px]) : back());
  }
  /// The tile's column of pixel (px, j), marked as written.
  std::uint64_t* column(int px, int j) const
  {
    const std::size_t q = static_cast<std::size_t>(j - y0) * (x1 - x0) + (px - x0);
    touched[q] = 1;
    return columnOf(grid, q, words);
  }
  void splatParticle(std::size_t k, TallyCounters& t) const;
  void splatBox(std::size_t k, TallyCounters& t) const;
  void splat(const TileLists& tl, std::size_t tile, TallyCounters& t) const;
  void compressColumn(int px, int j, FluidSpans& out, std::vector<float>& staged,
    TallyCounters& t) const;
  void compress(FluidSpans& out, std::vector<float>& staged, TallyCounters& t) const;
};

/// Tiles of at most MaxTileSize pixels a side.
constexpr int MaxTileSize = 64;

/// The chords of the sphere (centre c, r^2) along the centre rays of pixels r0 .. r0 + n - 1
/// of row j (n <= MaxTileSize): z0[k], z1[k] the roots (-b -+ sqrt(disc)) / a of the file
/// comment's quadratic, z0 clipped to the front, where disc > 0 (hit[k]). The lanes of a SIMD
/// loop, with the same operations in the same order as one pixel at a time (the kernels are
/// compiled without contraction): the same floats.
void rowChords(const ViewRays& rays,
  const Vec3d& c,
  double r2,
  int j,
  int r0,
  int n,
  double front,
  double* z0,
  double* z1,
  bool* hit)
{
  const Vec3d A0 = rays.startBase(), Ax = rays.startPerPixelX(), Ay = rays.startPerPixelY();
  const Vec3d B0 = rays.directionBase(), Bx = rays.directionPerPixelX(),
              By = rays.directionPerPixelY();
  const double y = j + 0.5;
#pragma omp simd
  for (int k = 0; k < n; ++k)
  {
    const double x = (r0 + k) + 0.5;
    const double ax = A0.x + Ax.x * x + Ay.x * y - c.x, ay = A0.y + Ax.y * x + Ay.y * y - c.y,
                 az = A0.z + Ax.z * x + Ay.z * y - c.z;
    const double bx = B0.x + Bx.x * x + By.x * y, by = B0.y + Bx.y * x + By.y * y,
                 bz = B0.z + Bx.z * x + By.z * y;
    const double a = bx * bx + by * by + bz * bz, b = ax * bx + ay * by + az * bz;
    const double disc = b * b - a * (ax * ax + ay * ay + az * az - r2);
    const double root = std::sqrt(disc > 0 ? disc : 0.0);
    const double lo = (-b - root) / a;
    z0[k] = lo > front ? lo : front;
    z1[k] = (-b + root) / a;
    hit[k] = disc > 0;
  }
}

/// The pixels px of row j (centre x = px + 0.5) whose centre rays can meet the sphere |p - c|
/// = r, within [i0, i1]: the ray A + zeta B meets it where its discriminant
///   disc(x) = (A.B)^2 - |B|^2 (|A|^2 - r^2)
/// is positive (A relative to c). Along a row either A is fixed (perspective: the eye) and B
/// affine in x, or B is fixed (parallel) and A affine, so disc is a quadratic
/// alpha x^2 + beta x + gamma; where alpha < 0 it is positive between its roots. The interval is
/// widened by a pixel on each side (every pixel in it is still tested exactly), and when
/// alpha >= 0 the whole row is kept. Returns false when no pixel of the row can meet it.
bool rowHitInterval(const ViewRays& rays, const Vec3d& c, double r2, int j, int& i0, int& i1)
{
  const double y = j + 0.5;
  double alpha, beta, gamma;
  if (rays.isPerspective())
  {
    const Vec3d A = rays.startBase() - c, Bj = rays.directionBase() + rays.directionPerPixelY() * y;
    const Vec3d& Bx = rays.directionPerPixelX();
    const double cc = dot(A, A) - r2, ab = dot(A, Bj), ax = dot(A, Bx);
    alpha = ax * ax - cc * dot(Bx, Bx);
    beta = 2.0 * (ab * ax - cc * dot(Bj, Bx));
    gamma = ab * ab - cc * dot(Bj, Bj);
  }
  else
  {
    const Vec3d Aj = rays.startBase() + rays.startPerPixelY() * y - c;
    const Vec3d& Ax = rays.startPerPixelX();
    const Vec3d& B = rays.directionBase();
    const double bb = dot(B, B), ab = dot(Aj, B), xb = dot(Ax, B);
    alpha = xb * xb - bb * dot(Ax, Ax);
    beta = 2.0 * (ab * xb - bb * dot(Aj, Ax));
    gamma = ab * ab - bb * (dot(Aj, Aj) - r2);
  }
  if (!(alpha < 0))
  {
    return true;
  }
  // Roots of alpha x^2 + beta x + gamma; a slightly negative discriminant (rounding at a
  // tangent row) still keeps the pixels around the vertex.
  const double d = beta * beta - 4.0 * alpha * gamma;
  if (d < -1e-9 * (beta * beta + std::abs(4.0 * alpha * gamma)))
  {
    return false;
  }
  const double root = std::sqrt(std::max(d, 0.0));
  const double xa = (-beta + root) / (2.0 * alpha), xb = (-beta - root) / (2.0 * alpha);
  const double lo = std::min(xa, xb) - 0.5 - 1.0, hi = std::max(xa, xb) - 0.5 + 1.0;
  if (!(lo <= hi))
  {
    return true; // NaN: keep the row
  }
  i0 = std::max(i0, static_cast<int>(std::max(std::ceil(lo), -1.0)));
  i1 = std::min(i1, static_cast<int>(std::min(std::floor(hi), 2147483646.0)));
  return i0 <= i1;
}

/// Splat (sections 3.1, 4.1) of the list's particle k into the tile: the chord [zeta_0,
/// zeta_1] of each of its pixels' centre rays through the sphere (clipped to the layers and
/// the stop depth) sets the bits of its layers, or (shell splat, section 4.4) the layers of
/// its ends only.
void TileVoxelizer::splatParticle(std::size_t k, TallyCounters& t) const
{
  const Footprint& fp = list.footprints[k];
  const std::size_t i = list.particleAt(k);
  const int i0 = std::max(fp.x0, x0), i1 = std::min(fp.x1, x1 - 1);
  const int j0 = std::max(fp.y0, y0), j1 = std::min(fp.y1, y1 - 1);
  if (i0 > i1 || j0 > j1)
  {
    return;
  }
  const double dFront = front(), dBack = back();
  const Vec3d c(particles.centers[i]);
  const double r2 = double(particles.radius[i]) * particles.radius[i];
  // Layers of the depths in the sphere from the layer coordinate at its centre: no logarithm
  // per pixel. Logarithmic layers: u(z) = u_c + log(1 + delta) / step with delta = (z - z_c) /
  // z_c, |delta| <= r / z_c, by its cubic Taylor polynomial, off by at most delta^4 / (4 (1 -
  // |delta|)^4 step) layers (the Lagrange remainder), which layerOf corrects against the depth
  // table in as many steps; spheres so large against their depth that this exceeds 4 layers
  // take the exact coordinate. Uniform layers are linear in z: exact.
  const double zc = std::clamp(rays.zetaOf(c), dFront, dBack);
  const double dmax = particles.radius[i] / zc;
  const double d2 = dmax * dmax, e2 = (1.0 - dmax) * (1.0 - dmax);
  const bool cubic = !layers.logarithmic || (dmax < 0.5 && d2 * d2 < 16.0 * layers.step * e2 * e2);
  const double uc = layers.coordinate(zc), perStep = 1.0 / layers.step, perZc = 1.0 / zc;
  const auto coordinate = [&](double z)
  {
    if (!cubic)
    {
      return layers.coordinate(z);
    }
    if (!layers.logarithmic)
    {
      return uc + (z - zc) * perStep;
    }
    const double d = (z - zc) * perZc;
    return uc + d * (1.0 - d * (0.5 - d * (1.0 / 3.0))) * perStep;
  };
  for (int j = j0; j <= j1; ++j)
  {
    int r0 = i0, r1 = i1;
    if (!rowHitInterval(rays, c, r2, j, r0, r1))
    {
      continue;
    }
    double z0s[MaxTileSize], z1s[MaxTileSize];
    bool hits[MaxTileSize];
    rowChords(rays, c, r2, j, r0, r1 - r0 + 1, dFront, z0s, z1s, hits);
    for (int px = r0; px <= r1; ++px)
    {
      if (!hits[px - r0])
      {
        continue;
      }
      const double z0 = z0s[px - r0];
      const double z1 = clipToRayEnd(z1s[px - r0], px, j);
      if (!(z0 < z1))
      {
        continue;
      }
      const int l0 = layers.layerOf(z0, coordinate(z0));
      const int l1 = layers.layerOf(z1, coordinate(z1));
      std::uint64_t* col = column(px, j);
      ++t.splatPixels;
      if (shell)
      {
        setBit(col, l0);
        setBit(col, l1);
        t.setBitOps += 2;
      }
      else
      {
        t.setBitOps += setBits(col, l0, l1);
      }
    }
  }
}

/// Boundary-cell culling's full box k (FluidCells.h): every layer from each pixel ray's entry
/// into the box to its exit (clipped to the layers and the stop depth).
void TileVoxelizer::splatBox(std::size_t k, TallyCounters& t) const
{
  const Footprint& fp = list.footprints[list.particles + k];
  const int i0 = std::max(fp.x0, x0), i1 = std::min(fp.x1, x1 - 1);
  const int j0 = std::max(fp.y0, y0), j1 = std::min(fp.y1, y1 - 1);
  for (int j = j0; j <= j1; ++j)
  {
    for (int px = i0; px <= i1; ++px)
    {
      double z0, z1;
      rayBox(rays.start(px + 0.5, j + 0.5),
        rays.direction(px + 0.5, j + 0.5),
        list.cells->boxes[k],
        z0,
        z1);
      z0 = std::max(z0, front());
      z1 = clipToRayEnd(z1, px, j);
      if (!(z0 < z1))
      {
        continue;
      }
      const int l0 = layers.layerOf(z0, layers.coordinate(z0));
      const int l1 = layers.layerOf(z1, layers.coordinate(z1));
      ++t.boxPixels;
      t.setBitOps += setBits(column(px, j), l0, l1);
    }
  }
}

/// The tile's splat: the particles and full cells' boxes its list holds.
void TileVoxelizer::splat(const TileLists& tl, std::size_t tile, TallyCounters& t) const
{
  for (std::size_t e = tl.start[tile]; e < tl.start[tile + 1]; ++e)
  {
    const std::size_t k = tl.items[e];
    if (k < list.particles)
    {
      splatParticle(k, t);
    }
    else
    {
      splatBox(k - list.particles, t);
    }
  }
}

/// Compression (sections 3.1, 4.3) of pixel (px, j)'s column: its runs of set bits, found word
/// by word, become spans [d_s, d_e], an exit beyond the stop depth moved back to it; a run
/// joins the span before it when the gap between them is shorter than g in world space (gap
/// bridging, sections 3.2, 4.4); beyond S spans the last stored span extends over the rest and
/// keeps the empty space inside it (hiddenEmpty). The spans' depths are appended to the
/// tile's `staged` ones (gatherSpans puts them in place). The column is cleared for the next
/// tile.
void TileVoxelizer::compressColumn(int px, int j, FluidSpans& out, std::vector<float>& staged,
  TallyCounters& t) const
{
  const int L = layers.count, S = out.maxSpans;
  std::uint64_t* column =
    columnOf(grid, static_cast<std::size_t>(j - y0) * (x1 - x0) + (px - x0), words);
  const std::size_t p = out.pixel(px, j);
  const float rayLength = static_cast<float>(length(rays.direction(px + 0.5, j + 0.5)));
  float d[2 * FluidSpans::MaxSpans];
  int stored = 0;
  std::uint32_t found = 0;
  float hidden = 0.f;
  const float stopAt = stop ? stop[p] : std::numeric_limits<float>::infinity();
  int s = nextBit(column, words, 0, true);
  while (s < L)
  {
    const int e = std::min(nextBit(column, words, s, false), L);
    const float entry = static_cast<float>(layers.depths[s]);
    float exit = static_cast<float>(layers.depths[e]);
    if (exit > stopAt)
    {
      // The layer holding the stop depth: the fluid ends at the geometry.
      exit = std::max(entry, stopAt);
      ++t.stoppedSpans;
    }
    if (found > 0 && (entry - d[2 * stored - 1]) * rayLength < g)
    {
      // Bridged: the run extends the last span (its hidden gap stays zero).
      d[2 * stored - 1] = exit;
      ++t.gapsBridged;
    }
    else if (stored < S)
    {
      d[2 * stored] = entry;
      d[2 * stored + 1] = exit;
      ++stored;
      ++found;
    }
    else
    {
      // Beyond S spans: the last stored span extends, its new gap is kept.
      hidden += entry - d[2 * stored - 1];
      d[2 * stored - 1] = exit;
      ++found;
    }
    s = nextBit(column, words, e, true);
  }
  staged.insert(staged.end(), d, d + 2 * stored);
  out.count[p] = static_cast<std::uint8_t>(stored);
  out.found[p] = found;
  out.hiddenEmpty[p] = hidden;
  t.spansFound += found;
  t.spansStored += stored;
  t.spansHidden += found - stored;
  std::fill(column, column + words, std::uint64_t(0)); // clear for the next tile
}

/// The tile's compression: the columns a splat wrote (the others have no span: out.reset
/// cleared them), row by row, their depths staged in that order.
void TileVoxelizer::compress(FluidSpans& out, std::vector<float>& staged, TallyCounters& t) const
{
  for (int j = y0; j < y1; ++j)
  {
    for (int px = x0; px < x1; ++px)
    {
      std::uint8_t& written = touched[static_cast<std::size_t>(j - y0) * (x1 - x0) + (px - x0)];
      if (written)
      {
        compressColumn(px, j, out, staged, t);
        written = 0;
      }
    }
  }
}

/// The depth layers over the particles' depth range (section 4.2: logarithmic in perspective,
/// their angular resolution from the pixel size) and their counters. Returns the 64-bit words
/// of a column's bit mask.
int assignLayers(const ViewRays& rays,
  const VoxelizerParameters& params,
  const DepthRange& range,
  VoxelDepthLayers& layers,
  RenderStatistics& stats)
{
  layers.assign(rays.isPerspective(),
    range.lo,
    range.hi,
    rays.pixelSize(),
    params.angleResolutionDeg,
    params.maxLayers);
  const int words = (layers.count + 63) / 64;
  stats.addCounter("layers", layers.count);
  stats.addCounter("angle_millidegrees",
    static_cast<std::int64_t>(std::lround(1000.0 * layers.angleDeg(rays.pixelSize()))));
  stats.addCounter("words_per_column", words);
  return words;
}

/// Tiles whose grid (with its touched bytes) stays within CacheBytes, so a tile's columns
/// stay in the core's cache while its particles are splatted.
constexpr std::size_t CacheBytes = std::size_t(1) << 20;

/// The tile size: the largest power of two (at most MaxTileSize, the grid within CacheBytes)
/// whose lists, with one grid per thread and the `fixedBytes` already used, fit the budget; 0
/// when none does. `peakBytes` receives the temporary memory it needs (for 0: the least any
/// tile size needs).
int chooseTileSize(const SplatList& list,
  std::size_t columnBytes,
  std::size_t fixedBytes,
  std::size_t budget,
  int threads,
  int W,
  int H,
  std::size_t& peakBytes)
{
  std::size_t least = std::numeric_limits<std::size_t>::max();
  for (int size = MaxTileSize; size >= 1; size /= 2)
  {
    const std::size_t grid = static_cast<std::size_t>(size) * size * (columnBytes + 1);
    if (size > 1 && grid > CacheBytes)
    {
      continue;
    }
    const std::size_t tiles =
      static_cast<std::size_t>((W + size - 1) / size) * ((H + size - 1) / size);
    peakBytes = fixedBytes + tileEntries(list, size) * sizeof(std::uint32_t) +
                (tiles + 1) * sizeof(std::size_t) + threads * grid;
    if (peakBytes <= budget)
    {
      return size;
    }
    least = std::min(least, peakBytes);
  }
  peakBytes = least;
  return 0;
}

/// One thread's tile grid (clear between tiles) and its time in each phase.
struct ThreadGrid
{
  std::vector<std::uint64_t> words;
  std::vector<std::uint8_t> touched;
  double splatMs = 0, compressMs = 0;
};

/// The tiles' staged depths put in place (FluidSpans: pixel p's slots from first[p], the
/// pixels in row order): each row's slot count, their running sum, then the rows' first slots
/// and each tile's depths copied in the order its compression staged them.
void gatherSpans(const TileLists& tl, const std::vector<std::vector<float>>& staged, FluidSpans& out)
{
  const int W = out.width, H = out.height;
  std::vector<std::size_t> rowStart(static_cast<std::size_t>(H) + 1, 0);
  tbb::parallel_for(0, H,
    [&](int j)
    {
      std::size_t slots = 0;
      for (int i = 0; i < W; ++i)
      {
        slots += 2u * out.count[out.pixel(i, j)];
      }
      rowStart[j + 1] = slots;
    });
  std::partial_sum(rowStart.begin(), rowStart.end(), rowStart.begin());
  out.depth.resize(rowStart[H]);
  tbb::parallel_for(0, H,
    [&](int j)
    {
      std::size_t next = rowStart[j];
      for (int i = 0; i < W; ++i)
      {
        const std::size_t p = out.pixel(i, j);
        out.first[p] = next;
        next += 2u * out.count[p];
      }
    });
  tbb::parallel_for(std::size_t(0), tl.tiles(),
    [&](std::size_t tile)
    {
      const float* from = staged[tile].data();
      const int x0 = static_cast<int>(tile % tl.tilesX) * tl.size;
      const int y0 = static_cast<int>(tile / tl.tilesX) * tl.size;
      for (int j = y0; j < std::min(H, y0 + tl.size); ++j)
      {
        for (int i = x0; i < std::min(W, x0 + tl.size); ++i)
        {
          const std::size_t p = out.pixel(i, j);
          std::copy(from, from + 2 * out.count[p], out.depth.begin() + out.first[p]);
          from += 2 * out.count[p];
        }
      }
    });
}

/// The tiles in parallel (section 3.1), each splatted into its thread's grid, then its columns
/// compressed into spans (staged per tile, then gathered in place). Splat and compression
/// alternate per tile: the phases "splat" and "compress" share the loop's time in proportion
/// to the threads' time in each; the gathering is compression's.
void voxelizeTiles(const TileVoxelizer& prototype,
  const TileLists& tl,
  int H,
  FluidSpans& out,
  tbb::combinable<TallyCounters>& tallies,
  RenderStatistics& stats)
{
  const std::size_t columns = static_cast<std::size_t>(tl.size) * tl.size;
  tbb::enumerable_thread_specific<ThreadGrid> grids(
    [&]
    {
      ThreadGrid g;
      g.words.assign(columns * prototype.words, 0);
      g.touched.assign(columns, 0);
      return g;
    });
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::time_point a, Clock::time_point b)
  { return std::chrono::duration<double, std::milli>(b - a).count(); };
  std::vector<std::vector<float>> staged(tl.tiles());
  const Clock::time_point start = Clock::now();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tl.tiles(), 1),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      ThreadGrid& g = grids.local();
      TallyCounters& t = tallies.local();
      for (std::size_t tile = r.begin(); tile != r.end(); ++tile)
      {
        if (tl.start[tile] == tl.start[tile + 1])
        {
          continue;
        }
        TileVoxelizer tv = prototype;
        tv.grid = g.words.data();
        tv.touched = g.touched.data();
        tv.x0 = static_cast<int>(tile % tl.tilesX) * tl.size;
        tv.y0 = static_cast<int>(tile / tl.tilesX) * tl.size;
        tv.x1 = std::min(tv.W, tv.x0 + tl.size);
        tv.y1 = std::min(H, tv.y0 + tl.size);
        const Clock::time_point t0 = Clock::now();
        tv.splat(tl, tile, t);
        const Clock::time_point t1 = Clock::now();
        tv.compress(out, staged[tile], t);
        g.splatMs += ms(t0, t1);
        g.compressMs += ms(t1, Clock::now());
      }
    });
  const Clock::time_point tilesDone = Clock::now();
  gatherSpans(tl, staged, out);
  const double gatherMs = ms(tilesDone, Clock::now());
  const double wall = ms(start, tilesDone);
  double splatMs = 0, compressMs = 0;
  for (const ThreadGrid& g : grids)
  {
    splatMs += g.splatMs;
    compressMs += g.compressMs;
  }
  const double busy = splatMs + compressMs;
  stats.addPhase("splat", busy > 0 ? wall * splatMs / busy : wall);
  stats.addPhase("compress", (busy > 0 ? wall * compressMs / busy : 0.0) + gatherMs);
}

/// The budget cannot hold the tiles' lists and grids: an empty voxelization. `neededBytes`:
/// the least temporary memory the view needs (0: unknown, the allocation failed).
bool budgetExceeded(std::size_t footprintBytes, std::size_t neededBytes, RenderStatistics& stats)
{
  stats.addCounter("budget_exceeded", 1);
  stats.addCounter("budget_needed_bytes", static_cast<std::int64_t>(neededBytes));
  stats.addCounter("peak_temporary_bytes", static_cast<std::int64_t>(footprintBytes));
  return false;
}
}

bool voxelizeFluid(const FluidParticles& particles,
  const ViewRays& rays,
  const VoxelizerParameters& params,
  FluidSpans& out,
  RenderStatistics& stats)
{
  RAYMAPPERS_SIMD_FORWARD(voxelizeFluid, particles, rays, params, out, stats);
  const bool bridging = params.gapThreshold > 0;
  const bool shell = bridging && params.gapThreshold >= 2.0 * particles.maxRadius;
  stats.setEffect("gap_bridging", bridging);
  stats.setEffect("shell_splat", shell);
  for (const char* name : VoxelizerCounters)
  {
    stats.declareCounter(name);
  }
  const int W = rays.width(), H = rays.height();
  out.reset(W, H, std::clamp(params.maxSpans, 1, FluidSpans::MaxSpans));
  const std::size_t budget =
    params.memoryBudget > 0 ? params.memoryBudget : automaticMemoryBudget();
  stats.addCounter("memory_budget_bytes", static_cast<std::int64_t>(budget));
  stats.addCounter("memory_budget_automatic", params.memoryBudget > 0 ? 0 : 1);
  if (particles.size() == 0 || W <= 0 || H <= 0)
  {
    return true;
  }

  SplatList list;
  list.cells = params.cells;
  list.particles = list.cells ? list.cells->kept.size() : particles.size();
  list.boxes = list.cells ? list.cells->boxes.size() : 0;
  list.footprints.resize(list.particles + list.boxes);
  std::size_t boxesInView = 0;
  const DepthRange range = projectSplats(particles, rays, list, boxesInView);
  stats.addCounter("boxes_in_view", static_cast<std::int64_t>(boxesInView));
  stats.addCounter("particles_in_view", static_cast<std::int64_t>(range.inView));
  const std::size_t footprintBytes = list.footprints.capacity() * sizeof(Footprint);
  if (range.inView == 0 && boxesInView == 0)
  {
    stats.addCounter("peak_temporary_bytes", static_cast<std::int64_t>(footprintBytes));
    return true;
  }

  // Layers (section 4.2) and tiles within the budget (section 3.1).
  VoxelDepthLayers& layers = out.layers;
  const int words = assignLayers(rays, params, range, layers, stats);
  const int threads = tbb::this_task_arena::max_concurrency();
  std::size_t peakBytes = footprintBytes;
  const int size = chooseTileSize(list,
    static_cast<std::size_t>(words) * sizeof(std::uint64_t),
    footprintBytes,
    budget,
    threads,
    W,
    H,
    peakBytes);
  if (size == 0)
  {
    return budgetExceeded(footprintBytes, peakBytes, stats);
  }
  TileLists tl;
  tbb::combinable<TallyCounters> tallies;
  try
  {
    listTiles(list, W, H, size, tl);
    stats.addCounter("tiles", static_cast<std::int64_t>(tl.tiles()));
    stats.addCounter("tile_width", size);
    stats.addCounter("tile_height", size);
    stats.addCounter("peak_temporary_bytes", static_cast<std::int64_t>(peakBytes));
    const TileVoxelizer prototype{ particles,
      rays,
      list,
      layers,
      nullptr,
      nullptr,
      params.stopDepth,
      words,
      W,
      shell,
      static_cast<float>(params.gapThreshold) };
    voxelizeTiles(prototype, tl, H, out, tallies, stats);
  }
  catch (const std::bad_alloc&)
  {
    out.reset(W, H, out.maxSpans);
    return budgetExceeded(footprintBytes, 0, stats);
  }
  addTallies(
    Tallies, [&](auto add) { tallies.combine_each(add); }, stats);
  return true;
}

RAYMAPPERS_SIMD_END

} // namespace raymappers
