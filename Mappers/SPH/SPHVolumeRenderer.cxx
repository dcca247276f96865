#include "Mappers/SPH/SPHVolumeRenderer.h"

#include "Mappers/SPH/Tallies.h"
#include "Mappers/Common/SimdTarget.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>

namespace raymappers
{
namespace
{
constexpr float Infinity = std::numeric_limits<float>::infinity();

}

#if RAYMAPPERS_SIMD_TARGET == 0 // (the functions outside the variants: once)
/// Offset in [0, 1) of a pixel's samples under stochastic jittering: a fixed 32 x 32
/// pattern of hashed values (section 4.1.2: "read from a 2D array with 32 x 32 entries").
float sphJitterOffset(int px, int py)
{
  std::uint32_t h = static_cast<std::uint32_t>(px & 31) | (static_cast<std::uint32_t>(py & 31) << 5);
  h ^= h >> 16;
  h *= 0x7feb352dU;
  h ^= h >> 15;
  h *= 0x846ca68bU;
  h ^= h >> 16;
  return static_cast<float>(h >> 8) * (1.f / 16777216.f);
}
#endif

RAYMAPPERS_SIMD_VARIANTS(renderSPH)

RAYMAPPERS_SIMD_BEGIN

namespace
{
/// The transfer function as colour and extinction tau = -ln(1 - alpha)/unitDistance, so a
/// segment of length l has opacity 1 - exp(-tau l) (equation 3.27 without a pow per sample).
class ExtinctionTable
{
public:
  explicit ExtinctionTable(const TransferFunctionTable& tf)
  {
    const int n = std::max(2, tf.size());
    Lo = tf.rangeMin();
    const double hi = tf.rangeMax();
    Scale = hi > Lo ? (n - 1) / (hi - Lo) : 0.0;
    Entries.resize(n);
    for (int k = 0; k < n; ++k)
    {
      const auto c = tf.lookup(Lo + (hi > Lo ? k / Scale : 0.0));
      const double a = std::clamp(static_cast<double>(c[3]), 0.0, 1.0 - 1e-7);
      Entries[k] = { c[0], c[1], c[2], static_cast<float>(-std::log1p(-a) / tf.unitDistance()) };
    }
  }
  struct Entry
  {
    float r, g, b, tau;
  };
  Entry lookup(float v) const
  {
    const int n = static_cast<int>(Entries.size());
    const double x = std::clamp((v - Lo) * Scale, 0.0, static_cast<double>(n - 1));
    const int k = std::min(static_cast<int>(x), n - 2);
    const float f = static_cast<float>(x - k);
    const Entry& a = Entries[k];
    const Entry& b = Entries[k + 1];
    return { a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b),
      a.tau + f * (b.tau - a.tau) };
  }

private:
  std::vector<Entry> Entries;
  double Lo = 0, Scale = 0;
};

/// What the bundles count (see BundleCounters).
struct Counters
{
  std::int64_t bundles = 0, cellsVisited = 0, cellsLeaped = 0, samples = 0, kernelEvaluations = 0,
               weightSums = 0, gradientEvaluations = 0, shaded = 0, contour = 0, terminated = 0;
};

/// The bundles' counters by their names in the statistics.
constexpr TallyField<Counters> BundleCounters[] = { { "bundles", &Counters::bundles },
  { "cells_visited", &Counters::cellsVisited },
  { "cells_leaped", &Counters::cellsLeaped },
  { "samples", &Counters::samples },
  { "kernel_evaluations", &Counters::kernelEvaluations },
  { "weight_sums", &Counters::weightSums },
  { "gradient_evaluations", &Counters::gradientEvaluations },
  { "shaded_samples", &Counters::shaded },
  { "contour_samples", &Counters::contour },
  { "terminated_rays", &Counters::terminated } };

/// The slab cache of one bundle: per buffered sample and ray the sums A, B and grad A
/// (B and grad A only when an effect needs them).
struct SlabCache
{
  std::vector<float> A, B, Gx, Gy, Gz;
  void clear(std::size_t n, bool weights, bool gradient)
  {
    A.assign(n, 0.f);
    if (weights)
    {
      B.assign(n, 0.f);
    }
    if (gradient)
    {
      Gx.assign(n, 0.f);
      Gy.assign(n, 0.f);
      Gz.assign(n, 0.f);
    }
  }
};

// Columns evaluated together in the deposit loop (one AVX-512 or two AVX2 vectors); the
// slab cache's rows are padded to a multiple of it.
constexpr int Lanes = 16;

/// A bundle of rays (a tile) and what they have gathered so far. Per-ray arrays are indexed
/// row * tw + col; the slab cache and the jitter factors row * stride + col.
struct Bundle
{
  int x0, y0, x1, y1, tw, th, stride;
  std::vector<Vec3f> rowStart, rowDir; // A and B at pixel column 0 of each row (centre 0.5)
  Vec3f startPerX, dirPerX;
  std::vector<float> dirLength, zStop, jitter;
  // The region's depths: a ray owns the samples with zEnter <= z < zExit (RegionBox.h), in
  // double: a sample's depth is the same float on every region (on the lattice of
  // PerspectiveGrid.h), while the box's depths differ with each region's float origin by
  // rounding, which in float would give a sample near a face to both regions or neither.
  std::vector<double> zEnter, zExit;
  std::vector<float> r, g, b, a;
  std::vector<unsigned char> done;
  std::vector<int> activeInRow;
  int active = 0;

  int rays() const { return tw * th; }
  /// A cache plane: one sample of every ray, rows padded to the stride.
  std::size_t plane() const { return static_cast<std::size_t>(th) * stride; }
  /// The ray takes no more samples.
  void retire(int ray)
  {
    done[ray] = 1;
    --activeInRow[ray / tw];
    --active;
  }
};

/// Particle i's kernel in the deposit: its centre, support H and the factors of its
/// contributions q_i V_i W, V_i W (W = c / H^3 shape(q^2)) and q_i V_i grad W
/// (grad W = c / H^5 shape'(q) / q (x - x_i)).
struct ParticleKernel
{
  Vec3f p;
  float H, H2, invH2, qvW, vW, qvG;

  ParticleKernel(const SPHParticles& particles, std::uint32_t i, double norm)
    : p(particles.centers[i])
    , H(particles.support[i])
  {
    H2 = H * H;
    invH2 = 1.f / H2;
    const float cW = static_cast<float>(norm / (double(H) * H * H));
    qvW = particles.qv[i] * cW;
    vW = particles.v[i] * cW;
    qvG = qvW * invH2;
  }
};

/// The slab cache's rows of one buffered sample and bundle row (null where an effect is off).
struct CacheRow
{
  float *A, *B, *Gx, *Gy, *Gz;
};

/// A bundle row's rays relative to a particle: x(i) - x_p = rs + Ax i + (rd + Bx i) z at pixel
/// column i and depth z; P0 + V i at the slab sample's shared depth.
struct RowRays
{
  Vec3f rs, rd, Ax, Bx, P0, V;
};

/// One chunk of Lanes columns of a bundle row: adds the particle's kernel at each column's
/// sample, at the shared depth (P0 + V i) or, with jitter, at the column's own depth
/// zk + j zstep (j from jl). Lanes outside the support add 0. Plain floats in the loop (no
/// struct temporaries), so it runs in SIMD lanes.
template<SPHKernel K, bool Weights, bool Gradient, bool Jitter>
inline void depositChunk(const ParticleKernel& pk,
  const RowRays& rays,
  const float* jl,
  float zk,
  float zstep,
  int base,
  float fb,
  const CacheRow& row)
{
  float* A = row.A;
  float* B = row.B;
  float* Gx = row.Gx;
  float* Gy = row.Gy;
  float* Gz = row.Gz;
  const float invH2 = pk.invH2, qvW = pk.qvW, vW = pk.vW, qvG = pk.qvG;
  const Vec3f rs = rays.rs, rd = rays.rd, Ax = rays.Ax, Bx = rays.Bx, P0 = rays.P0, V = rays.V;
#pragma omp simd
  for (int l = 0; l < Lanes; ++l)
  {
    const int c = base + l;
    const float fi = fb + static_cast<float>(l);
    float dx, dy, dz;
    if (Jitter)
    {
      const float zj = zk + jl[c] * zstep;
      dx = rs.x + Ax.x * fi + (rd.x + Bx.x * fi) * zj;
      dy = rs.y + Ax.y * fi + (rd.y + Bx.y * fi) * zj;
      dz = rs.z + Ax.z * fi + (rd.z + Bx.z * fi) * zj;
    }
    else
    {
      dx = P0.x + V.x * fi;
      dy = P0.y + V.y * fi;
      dz = P0.z + V.z * fi;
    }
    const float q2 = (dx * dx + dy * dy + dz * dz) * invH2;
    const bool inside = q2 < 1.f;
    const float qc2 = inside ? q2 : 0.f;
    const float w = inside ? kernelShape<K>(qc2) : 0.f;
    A[c] += qvW * w;
    if (Weights)
    {
      B[c] += vW * w;
    }
    if (Gradient)
    {
      const float gs = inside ? qvG * kernelShapeDerivativeOverQ<K>(qc2) : 0.f;
      Gx[c] += gs * dx;
      Gy[c] += gs * dy;
      Gz[c] += gs * dz;
    }
  }
}

/// The rows and Lanes chunks of a bundle that a particle's footprint covers: rows jlo..jhi
/// (pixel rows whose centres lie in it) and the chunks starting at columns c0, c0 + Lanes, ...
/// up to c1 (relative to the tile).
struct CoveredRows
{
  int jlo, jhi, c0, c1;
  bool empty; // no pixel centre of the bundle lies in the footprint

  CoveredRows(const ParticleFootprint& fp, const Bundle& bundle)
  {
    jlo = std::max(bundle.y0, static_cast<int>(std::ceil(fp.y0 - 0.5f)));
    jhi = std::min(bundle.y1 - 1, static_cast<int>(std::floor(fp.y1 - 0.5f)));
    const int ilo = std::max(bundle.x0, static_cast<int>(std::ceil(fp.x0 - 0.5f)));
    const int ihi = std::min(bundle.x1 - 1, static_cast<int>(std::floor(fp.x1 - 0.5f)));
    empty = jlo > jhi || ilo > ihi;
    c0 = (ilo - bundle.x0) / Lanes * Lanes;
    c1 = ihi - bundle.x0;
  }
};

/// Adds a particle to buffered sample k of the covered rows: the rows whose line at the
/// sample's depth zs[k] meets its support (the discriminant of |P0 + i V|^2 = H^2, a quadratic
/// in the pixel column i; with jitter every covered row), in whole chunks of Lanes columns.
template<SPHKernel K, bool Weights, bool Gradient, bool Jitter>
void depositSample(const ParticleKernel& pk,
  const CoveredRows& rows,
  int k,
  const float* zs,
  const float* zb,
  const Bundle& bundle,
  SlabCache& cache,
  std::int64_t& evaluations)
{
  const Vec3f Ax = bundle.startPerX, Bx = bundle.dirPerX;
  const std::size_t sampleOffset = static_cast<std::size_t>(k) * bundle.plane();
  for (int j = rows.jlo; j <= rows.jhi; ++j)
  {
    const int row = j - bundle.y0;
    if (bundle.activeInRow[row] == 0)
    {
      continue;
    }
    // The row's rays at depth z: x(i) - x_p = P0 + i V for pixel column i.
    const Vec3f rs = bundle.rowStart[row] - pk.p, rd = bundle.rowDir[row];
    const float z = zs[k];
    const RowRays rays{ rs, rd, Ax, Bx, rs + rd * z, Ax + Bx * z };
    if (!Jitter)
    {
      const float qa = dot(rays.V, rays.V), qb = dot(rays.P0, rays.V),
                  qc = dot(rays.P0, rays.P0) - pk.H2;
      if (!(qb * qb - qa * qc > 0.f))
      {
        continue; // the row's plane misses the support at this depth
      }
    }
    const std::size_t rowOffset = sampleOffset + static_cast<std::size_t>(row) * bundle.stride;
    const CacheRow cacheRow{ cache.A.data() + rowOffset,
      Weights ? cache.B.data() + rowOffset : nullptr,
      Gradient ? cache.Gx.data() + rowOffset : nullptr,
      Gradient ? cache.Gy.data() + rowOffset : nullptr,
      Gradient ? cache.Gz.data() + rowOffset : nullptr };
    const float* jl = bundle.jitter.data() + static_cast<std::size_t>(row) * bundle.stride;
    const float zk = zb[k], zstep = zb[k + 1] - zb[k];
    for (int base = rows.c0; base <= rows.c1; base += Lanes)
    {
      evaluations += Lanes;
      depositChunk<K, Weights, Gradient, Jitter>(
        pk, rays, jl, zk, zstep, base, static_cast<float>(bundle.x0 + base), cacheRow);
    }
  }
}

/// The slab cache's sampling (section 3.6.2, Listing 3.2): adds every particle of a cell to
/// the buffered samples of the bundle's rays within its support. zs[k]: the slab's sample
/// depths without jitter (all rays share them); with jitter each ray's sample sits at
/// zb[k] + j (zb[k + 1] - zb[k]), j its offset. A particle visits the buffered samples its
/// depth span reaches and there the rows of its footprint, each in whole SIMD chunks of Lanes
/// columns (the cache rows are padded, lanes outside the support add 0), which is cheaper
/// than exact short spans with scalar remainders.
template<SPHKernel K, bool Weights, bool Gradient, bool Jitter>
void deposit(const SPHParticles& particles,
  const PerspectiveGrid& grid,
  const std::uint32_t* refBegin,
  const std::uint32_t* refEnd,
  const float* zs,
  const float* zb,
  int slab,
  const Bundle& bundle,
  SlabCache& cache,
  Counters& counters)
{
  const double norm = kernelNormalization(K);
  std::int64_t evaluations = 0;
  for (const std::uint32_t* ref = refBegin; ref != refEnd; ++ref)
  {
    const ParticleFootprint& fp = grid.footprints()[*ref];
    const ParticleKernel pk(particles, *ref, norm);
    const CoveredRows rows(fp, bundle);
    if (rows.empty)
    {
      continue;
    }
    for (int k = 0; k < slab; ++k)
    {
      if (!Jitter && !(std::abs(zs[k] - fp.zeta) < pk.H))
      {
        continue;
      }
      if (Jitter && (zb[k] > fp.zeta + pk.H || zb[k + 1] < fp.zeta - pk.H))
      {
        continue;
      }
      depositSample<K, Weights, Gradient, Jitter>(
        pk, rows, k, zs, zb, bundle, cache, evaluations);
    }
  }
  counters.kernelEvaluations += evaluations;
  if (Weights)
  {
    counters.weightSums += evaluations;
  }
  if (Gradient)
  {
    counters.gradientEvaluations += evaluations;
  }
}

using DepositFn = void (*)(const SPHParticles&,
  const PerspectiveGrid&,
  const std::uint32_t*,
  const std::uint32_t*,
  const float*,
  const float*,
  int,
  const Bundle&,
  SlabCache&,
  Counters&);

template<SPHKernel K>
DepositFn pickDeposit(bool weights, bool gradient, bool jitter)
{
  const int key = (weights ? 4 : 0) | (gradient ? 2 : 0) | (jitter ? 1 : 0);
  switch (key)
  {
    case 0: return &deposit<K, false, false, false>;
    case 1: return &deposit<K, false, false, true>;
    case 2: return &deposit<K, false, true, false>;
    case 3: return &deposit<K, false, true, true>;
    case 4: return &deposit<K, true, false, false>;
    case 5: return &deposit<K, true, false, true>;
    case 6: return &deposit<K, true, true, false>;
    default: return &deposit<K, true, true, true>;
  }
}

DepositFn pickDeposit(SPHKernel kernel, bool weights, bool gradient, bool jitter)
{
  switch (kernel)
  {
    case SPHKernel::Poly6: return pickDeposit<SPHKernel::Poly6>(weights, gradient, jitter);
    case SPHKernel::CubicSpline: return pickDeposit<SPHKernel::CubicSpline>(weights, gradient, jitter);
    default: return pickDeposit<SPHKernel::WendlandC2>(weights, gradient, jitter);
  }
}

Vec3d transformPoint(const double* M, const Vec3d& p)
{
  return { M[0] * p.x + M[1] * p.y + M[2] * p.z + M[3], M[4] * p.x + M[5] * p.y + M[6] * p.z + M[7],
    M[8] * p.x + M[9] * p.y + M[10] * p.z + M[11] };
}
Vec3d transformVector(const double* M, int stride, const Vec3d& v)
{
  return { M[0] * v.x + M[1] * v.y + M[2] * v.z,
    M[stride] * v.x + M[stride + 1] * v.y + M[stride + 2] * v.z,
    M[2 * stride] * v.x + M[2 * stride + 1] * v.y + M[2 * stride + 2] * v.z };
}

/// The counters of a frame (declared whether or not it has anything to draw).
const char* const SPHCounters[] = { "particles_in_view",
  "grid_cells",
  "depth_cells",
  "samples_per_cell",
  "grid_references",
  "grid_bytes",
  "bundles",
  "cells_visited",
  "cells_leaped",
  "samples",
  "kernel_evaluations",
  "weight_sums",
  "gradient_evaluations",
  "shaded_samples",
  "contour_samples",
  "terminated_rays" };

/// The effects the frame plans (the field's normalization, the shading, jitter, early
/// termination, opaque geometry) and the counters it fills.
void declareStatistics(const SPHRenderParameters& params, bool opaque, RenderStatistics& stats)
{
  stats.setEffect("normalization", params.normalization == SPHNormalization::Normalized);
  stats.setEffect("gradient_shading", params.shade);
  stats.setEffect("contour_shading", params.contour);
  stats.setEffect("jitter", params.jitter);
  stats.setEffect("early_termination", params.terminationOpacity < 1.0);
  stats.setEffect("opaque_geometry", opaque);
  for (const char* name : SPHCounters)
  {
    stats.declareCounter(name);
  }
}

/// The perspective grid of the view (section 3.4, phase grid) and its counters; false when no
/// particle is in view.
bool buildGrid(const SPHParticles& particles,
  const ViewRays& rays,
  const SPHRenderParameters& params,
  PerspectiveGrid& grid,
  RenderStatistics& stats)
{
  PerspectiveGridParameters gp;
  gp.tileSize = params.tileSize;
  gp.stepFactor = params.stepFactor;
  const double support = params.smallestSupport > 0 ? params.smallestSupport : particles.minSupport;
  gp.fieldStep = params.samplesPerSupport > 0 ? support / params.samplesPerSupport : 0.0;
  bool any;
  {
    ScopedPhase phase(stats, "grid");
    any = grid.build(particles, rays, gp);
  }
  stats.addCounter("particles_in_view", static_cast<std::int64_t>(grid.particlesInView()));
  if (!any)
  {
    return false;
  }
  const DepthSteps& steps = grid.steps();
  stats.addCounter("grid_cells", static_cast<std::int64_t>(grid.cellCount()));
  stats.addCounter("depth_cells", steps.cells);
  stats.addCounter("samples_per_cell", steps.samplesPerCell);
  stats.addCounter("grid_references", static_cast<std::int64_t>(grid.refs().size()));
  stats.addCounter("grid_bytes", static_cast<std::int64_t>(grid.memoryBytes()));
  return true;
}

/// A sample's colour and opacity (premultiplied once classified).
struct SampleColour
{
  float r = 0, g = 0, b = 0, alpha = 0;
};

/// Where a sample is: ray r of the bundle (at row, col), its slab cache entry g, its depth z
/// in its step [z0, z1).
struct SampleSite
{
  int r, row, col;
  std::size_t g;
  float z, z0, z1;
};

/// What the ray casting of a frame shares between its bundles, and the phases of a bundle.
struct Raycast
{
  Raycast(const SPHParticles& sph,
    const ViewRays& view,
    const SPHRenderParameters& p,
    const TransferFunctionTable& table,
    const float* depth,
    const PerspectiveGrid& g)
    : particles(sph)
    , rays(view)
    , params(p)
    , grid(g)
    , opaqueDepth(depth)
    , tf(table)
  {
    normalized = params.normalization == SPHNormalization::Normalized;
    weights = normalized || params.contour;
    S = grid.steps().samplesPerCell;
    D = params.slabDepth > 0 ? std::min(params.slabDepth, S) : S;
    depositFn = pickDeposit(params.kernel, weights, params.shade, params.jitter);
    wMax = static_cast<float>(params.referenceWeightSum > 0 ? params.referenceWeightSum : 1.0);
    threshold = static_cast<float>(params.terminationOpacity);
    contourTau = static_cast<float>(
      -std::log1p(-std::clamp(params.contourOpacity, 0.0, 1.0 - 1e-7)) / table.unitDistance());
    minQ = particles.minQ;
    maxQ = particles.maxQ;
  }

  void castBundle(int t, Bundle& bd, SlabCache& cache, Counters& counters) const;
  void frameBundle(int tx, int ty, Bundle& bd) const;
  void limitRays(Bundle& bd) const;
  void sampleCell(int tz,
    std::size_t c,
    Bundle& bd,
    SlabCache& cache,
    std::vector<float>& zb,
    std::vector<float>& zs,
    Counters& counters) const;
  void compositeSlab(const SlabCache& cache,
    const float* zb,
    int slab,
    Bundle& bd,
    Counters& counters) const;
  bool shadeSample(const SlabCache& cache,
    const SampleSite& s,
    const Bundle& bd,
    SampleColour& colour) const;
  bool classifySample(const SlabCache& cache,
    const SampleSite& s,
    float a,
    float w,
    const Bundle& bd,
    Counters& counters,
    SampleColour& out) const;

  const SPHParticles& particles;
  const ViewRays& rays;
  const SPHRenderParameters& params;
  const PerspectiveGrid& grid;
  const float* opaqueDepth;
  ExtinctionTable tf;
  DepositFn depositFn;
  bool normalized, weights;
  int S, D; // samples per cell and per slab
  float wMax, threshold, contourTau, minQ, maxQ;
};

/// Ray setup of tile (tx, ty)'s bundle (sections 3.6.1, 4.1.2): its pixels, the rays of its
/// rows (a ray's point at depth z is A + z B, linear in the pixel column), and nothing
/// gathered yet.
void Raycast::frameBundle(int tx, int ty, Bundle& bd) const
{
  const int T = grid.tileSize();
  bd.x0 = tx * T;
  bd.y0 = ty * T;
  bd.x1 = std::min(rays.width(), bd.x0 + T);
  bd.y1 = std::min(rays.height(), bd.y0 + T);
  bd.tw = bd.x1 - bd.x0;
  bd.th = bd.y1 - bd.y0;
  const int R = bd.rays();
  bd.stride = (bd.tw + Lanes - 1) / Lanes * Lanes;
  bd.rowStart.resize(bd.th);
  bd.rowDir.resize(bd.th);
  bd.startPerX = Vec3f(rays.startPerPixelX());
  bd.dirPerX = Vec3f(rays.directionPerPixelX());
  for (int row = 0; row < bd.th; ++row)
  {
    const double py = bd.y0 + row + 0.5;
    bd.rowStart[row] = Vec3f(rays.start(0.5, py));
    bd.rowDir[row] = Vec3f(rays.direction(0.5, py));
  }
  bd.dirLength.resize(R);
  bd.zStop.resize(R);
  bd.zEnter.assign(R, -Infinity);
  bd.zExit.assign(R, Infinity);
  bd.jitter.assign(bd.plane(), 0.5f);
  bd.r.assign(R, 0.f);
  bd.g.assign(R, 0.f);
  bd.b.assign(R, 0.f);
  bd.a.assign(R, 0.f);
  bd.done.assign(R, 0);
  bd.activeInRow.assign(bd.th, bd.tw);
  bd.active = R;
}

/// Where each ray of the bundle ends and where its samples sit: |B| (a step's length per unit
/// of depth), the depth of opaque geometry, the region's depths (RegionBox.h) and the
/// fraction j of its steps (the midpoint, or the pixel's jitter offset, section 3.2.2).
void Raycast::limitRays(Bundle& bd) const
{
  const bool regionBounded = params.region.bounded();
  for (int row = 0; row < bd.th; ++row)
  {
    for (int col = 0; col < bd.tw; ++col)
    {
      const int r = row * bd.tw + col;
      const int px = bd.x0 + col, py = bd.y0 + row;
      bd.dirLength[r] = static_cast<float>(length(rays.direction(px + 0.5, py + 0.5)));
      float zStop = Infinity;
      if (opaqueDepth)
      {
        const float d = opaqueDepth[static_cast<std::size_t>(py) * rays.width() + px];
        if (d < 1.f)
        {
          zStop = static_cast<float>(rays.zetaOfWindowDepth(px + 0.5, py + 0.5, d));
        }
      }
      bd.zStop[r] = zStop;
      if (regionBounded)
      {
        double z0 = -Infinity, z1 = Infinity;
        if (params.region.clip(rays.start(px + 0.5, py + 0.5),
              rays.direction(px + 0.5, py + 0.5),
              particles.origin,
              z0,
              z1))
        {
          bd.zEnter[r] = z0;
          bd.zExit[r] = z1;
        }
        else
        {
          bd.zExit[r] = -Infinity;
        }
      }
      bd.jitter[static_cast<std::size_t>(row) * bd.stride + col] =
        params.jitter ? sphJitterOffset(px, py) : 0.5f;
    }
  }
}

/// The ray bundle of tile t walks its column of cells front to back (section 3.6.1, Listing
/// 4.4), leaping over runs of empty cells with the empty successors cache (section 3.4.3);
/// rays that end at opaque geometry or leave the region before a cell are retired, the
/// others sample the cell. The gathered colours go to the frame afterwards.
void Raycast::castBundle(int t, Bundle& bd, SlabCache& cache, Counters& counters) const
{
  const int tx = t % grid.tilesX(), ty = t / grid.tilesX();
  frameBundle(tx, ty, bd);
  limitRays(bd);
  ++counters.bundles;
  const int R = bd.rays();
  const DepthSteps& steps = grid.steps();
  std::vector<float> zb(D + 1), zs(D);
  for (int tz = 0; tz < steps.cells && bd.active > 0; ++tz)
  {
    const std::size_t c = grid.cellIndex(tx, ty, tz);
    if (const std::uint32_t run = grid.emptyRun(c))
    {
      counters.cellsLeaped += run;
      tz += static_cast<int>(run) - 1;
      continue;
    }
    const float zCell = static_cast<float>(steps.zeta(static_cast<double>(tz) * S));
    for (int r = 0; r < R; ++r)
    {
      if (!bd.done[r] && std::min<double>(bd.zStop[r], bd.zExit[r]) <= zCell)
      {
        bd.retire(r);
      }
    }
    if (bd.active == 0)
    {
      break;
    }
    ++counters.cellsVisited;
    sampleCell(tz, c, bd, cache, zb, zs, counters);
  }
}

/// A cell's samples, slab by slab (section 3.6.2): the slab's depths (section 3.3: the steps
/// zb and their midpoints zs), the particles' contributions gathered into the slab cache,
/// then classification, shading and compositing of the slab.
void Raycast::sampleCell(int tz,
  std::size_t c,
  Bundle& bd,
  SlabCache& cache,
  std::vector<float>& zb,
  std::vector<float>& zs,
  Counters& counters) const
{
  const DepthSteps& steps = grid.steps();
  const std::uint32_t* refBegin = grid.refs().data() + grid.cellStart(c);
  const std::uint32_t* refEnd = grid.refs().data() + grid.cellStart(c + 1);
  for (int s0 = 0; s0 < S && bd.active > 0; s0 += D)
  {
    const int slab = std::min(D, S - s0);
    const double k0 = static_cast<double>(tz) * S + s0;
    for (int k = 0; k <= slab; ++k)
    {
      zb[k] = static_cast<float>(steps.zeta(k0 + k));
    }
    for (int k = 0; k < slab; ++k)
    {
      zs[k] = 0.5f * (zb[k] + zb[k + 1]);
    }
    cache.clear(static_cast<std::size_t>(slab) * bd.plane(), weights, params.shade);
    depositFn(particles, grid, refBegin, refEnd, zs.data(), zb.data(), slab, bd, cache, counters);
    compositeSlab(cache, zb.data(), slab, bd, counters);
  }
}

/// Gradient shading (section 3.7.1) of sample s: the normal -grad A / |grad A| (equation
/// 3.23) in world space, turned to face the viewer (two-sided lighting), lights the colour
/// (Lambert + Phong, Lighting.h). False (colour unchanged) where the gradient vanishes.
bool Raycast::shadeSample(const SlabCache& cache,
  const SampleSite& s,
  const Bundle& bd,
  SampleColour& colour) const
{
  const Vec3d grad(cache.Gx[s.g], cache.Gy[s.g], cache.Gz[s.g]);
  const double glen = length(grad);
  if (!(glen > 0 && std::isfinite(glen)))
  {
    return false;
  }
  const double px = bd.x0 + s.col + 0.5, py = bd.y0 + s.row + 0.5;
  const Vec3d dirModel = rays.direction(px, py);
  const Vec3d pModel = rays.pointAt(px, py, s.z) + particles.origin;
  Vec3d n = normalize(transformVector(params.normalToWorld, 3, grad * (-1.0 / glen)));
  const Vec3d dirWorld = normalize(transformVector(params.modelToWorld, 4, dirModel));
  if (dot(n, dirWorld) > 0)
  {
    n = -n;
  }
  const Vec3d lit = shadeParts(params.lights,
    params.material,
    Vec3d(colour.r, colour.g, colour.b),
    transformPoint(params.modelToWorld, pModel),
    n,
    -dirWorld).total();
  colour.r = static_cast<float>(std::clamp(lit.x, 0.0, 1.0));
  colour.g = static_cast<float>(std::clamp(lit.y, 0.0, 1.0));
  colour.b = static_cast<float>(std::clamp(lit.z, 0.0, 1.0));
  return true;
}

/// Classification and shading of sample s with sums A = a and B = w: its value (section 3.5,
/// equations 3.14 to 3.16: normalized a / w, empty where w vanishes and clamped to the
/// particles' range against rounding; unnormalized a, pseudo-normalized a / w_max, empty
/// where a = 0); its segment of length l = (zeta_{k+1} - zeta_k) |B| (clipped at opaque
/// geometry) has opacity 1 - exp(-tau l) (opacity correction, equation 3.27); the contour
/// (section 3.7.2) adds I = clamp(1 - w / w_max, 0, 1) times its colour and opacity (3.24 to
/// 3.26). The premultiplied contribution (3.31 to 3.33) goes to `out`; false for an empty
/// sample.
bool Raycast::classifySample(const SlabCache& cache,
  const SampleSite& s,
  float a,
  float w,
  const Bundle& bd,
  Counters& counters,
  SampleColour& out) const
{
  float value;
  bool hasValue;
  if (normalized)
  {
    hasValue = w > std::numeric_limits<float>::min();
    value = hasValue ? std::clamp(a / w, minQ, maxQ) : 0.f;
  }
  else
  {
    hasValue = a != 0.f;
    value = params.normalization == SPHNormalization::PseudoNormalized ? a / wMax : a;
  }
  const bool contour = params.contour && w > 0.f;
  if (!hasValue && !contour)
  {
    return false;
  }
  ++counters.samples;
  const float len = (std::min(s.z1, bd.zStop[s.r]) - s.z0) * bd.dirLength[s.r];
  SampleColour colour;
  if (hasValue)
  {
    const ExtinctionTable::Entry e = tf.lookup(value);
    colour = { e.r, e.g, e.b, -std::expm1(-e.tau * len) };
    if (params.shade && colour.alpha > 0.f && shadeSample(cache, s, bd, colour))
    {
      ++counters.shaded;
    }
  }
  out = { colour.alpha * colour.r, colour.alpha * colour.g, colour.alpha * colour.b, colour.alpha };
  if (contour)
  {
    const float I = std::clamp(1.f - w / wMax, 0.f, 1.f);
    const float ac = -std::expm1(-contourTau * I * len);
    out.r += ac * static_cast<float>(params.contourColor[0]);
    out.g += ac * static_cast<float>(params.contourColor[1]);
    out.b += ac * static_cast<float>(params.contourColor[2]);
    out.alpha = std::min(1.f, out.alpha + ac);
    ++counters.contour;
  }
  return true;
}

/// Classification, shading and compositing of the slab's samples, front to back: a ray's
/// samples up to where it ends (opaque geometry, the region) and from where its region
/// starts; each premultiplied contribution composited front to back (equations 3.29, 3.30)
/// until the ray's opacity reaches the termination threshold (early ray termination, section
/// 4.1.3).
void Raycast::compositeSlab(const SlabCache& cache,
  const float* zb,
  int slab,
  Bundle& bd,
  Counters& counters) const
{
  const std::size_t P = bd.plane();
  const int R = bd.rays();
  for (int k = 0; k < slab; ++k)
  {
    const float* A = cache.A.data() + static_cast<std::size_t>(k) * P;
    const float* B = weights ? cache.B.data() + static_cast<std::size_t>(k) * P : nullptr;
    for (int r = 0; r < R; ++r)
    {
      if (bd.done[r])
      {
        continue;
      }
      const int row = r / bd.tw, col = r - row * bd.tw;
      const std::size_t ci = static_cast<std::size_t>(row) * bd.stride + col;
      const float z = zb[k] + bd.jitter[ci] * (zb[k + 1] - zb[k]);
      if (z >= bd.zStop[r] || z >= bd.zExit[r])
      {
        bd.retire(r);
        continue;
      }
      if (z < bd.zEnter[r])
      {
        continue; // the previous region's sample
      }
      const SampleSite site{ r, row, col, static_cast<std::size_t>(k) * P + ci, z, zb[k], zb[k + 1] };
      SampleColour c;
      if (!classifySample(cache, site, A[ci], weights ? B[ci] : 0.f, bd, counters, c))
      {
        continue;
      }
      const float tr = 1.f - bd.a[r];
      bd.r[r] += tr * c.r;
      bd.g[r] += tr * c.g;
      bd.b[r] += tr * c.b;
      bd.a[r] += tr * c.alpha;
      if (bd.a[r] >= threshold)
      {
        bd.retire(r);
        ++counters.terminated;
      }
    }
  }
}

/// Writes the bundle's premultiplied colours into the frame.
void writeBundle(const Bundle& bd, Frame& frame)
{
  for (int row = 0; row < bd.th; ++row)
  {
    for (int col = 0; col < bd.tw; ++col)
    {
      const int r = row * bd.tw + col;
      float* out = &frame.rgba[4 * frame.index(bd.x0 + col, bd.y0 + row)];
      out[0] = bd.r[r];
      out[1] = bd.g[r];
      out[2] = bd.b[r];
      out[3] = bd.a[r];
    }
  }
}
}

RAYMAPPERS_SIMD_END

#if RAYMAPPERS_SIMD_TARGET == 0
double referenceWeightSum(SPHKernel kernel, double volume, double support, int neighbours)
{
  return neighbours * volume * kernelValue(kernel, 0.5 * support, support);
}
#endif

RAYMAPPERS_SIMD_BEGIN


void renderSPH(const SPHScene& scene,
  const View& view,
  const SPHRenderParameters& params,
  Frame& frame,
  RenderStatistics& stats)
{
  RAYMAPPERS_SIMD_FORWARD(renderSPH, scene, view, params, frame, stats);
  const SPHParticles& particles = scene.particles;
  const TransferFunctionTable& table = scene.table;
  PerspectiveGrid& grid = scene.grid;
  const ViewRays& rays = view.depthRays();
  const float* opaqueDepth = view.opaqueDepth();
  declareStatistics(params, opaqueDepth != nullptr, stats);
  frame.resize(rays.width(), rays.height());
  if (particles.size() == 0 || table.empty() || !buildGrid(particles, rays, params, grid, stats))
  {
    return;
  }
  ScopedPhase phase(stats, "raycast");
  const Raycast raycast(particles, rays, params, table, opaqueDepth, grid);
  std::vector<Counters> perTile(static_cast<std::size_t>(grid.tilesX()) * grid.tilesY());
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(perTile.size()), 1),
    [&](const tbb::blocked_range<int>& range)
    {
      thread_local Bundle bundle;
      thread_local SlabCache cache;
      for (int t = range.begin(); t != range.end(); ++t)
      {
        raycast.castBundle(t, bundle, cache, perTile[t]);
        writeBundle(bundle, frame);
      }
    });
  addTallies(
    BundleCounters, [&](auto add) { std::for_each(perTile.begin(), perTile.end(), add); }, stats);
}

RAYMAPPERS_SIMD_END

} // namespace raymappers
