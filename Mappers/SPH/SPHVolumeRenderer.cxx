#include "SPHVolumeRenderer.h"

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

struct Counters
{
  std::int64_t bundles = 0, cellsVisited = 0, cellsLeaped = 0, samples = 0, kernelEvaluations = 0,
               weightSums = 0, gradientEvaluations = 0, shaded = 0, contour = 0, terminated = 0;
  void addTo(Counters& o) const
  {
    o.bundles += bundles;
    o.cellsVisited += cellsVisited;
    o.cellsLeaped += cellsLeaped;
    o.samples += samples;
    o.kernelEvaluations += kernelEvaluations;
    o.weightSums += weightSums;
    o.gradientEvaluations += gradientEvaluations;
    o.shaded += shaded;
    o.contour += contour;
    o.terminated += terminated;
  }
};

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
  // The region's depths: a ray owns the samples with zEnter <= z < zExit (RegionBox.h).
  std::vector<float> zEnter, zExit;
  std::vector<float> r, g, b, a;
  std::vector<unsigned char> done;
  std::vector<int> activeInRow;
  int active = 0;
};

/// Adds every particle of a cell to the buffered samples of the bundle's rays within its
/// support. zs[k]: the slab's sample depths without jitter (all rays share them); with
/// jitter each ray's sample sits at zb[k] + j (zb[k + 1] - zb[k]), j its offset. A particle visits, per buffered
/// sample its depth span reaches, the rows of its footprint whose line at that depth meets
/// its support (the discriminant of |P0 + i V|^2 = H^2, a quadratic in the pixel column i),
/// and evaluates each such row in whole SIMD chunks of Lanes columns (the cache rows are
/// padded, lanes outside the support add 0), which is cheaper than exact short spans with
/// scalar remainders.
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
  const std::size_t plane = static_cast<std::size_t>(bundle.th) * bundle.stride;
  const Vec3f Ax = bundle.startPerX, Bx = bundle.dirPerX;
  std::int64_t evaluations = 0;
  for (const std::uint32_t* ref = refBegin; ref != refEnd; ++ref)
  {
    const std::uint32_t i = *ref;
    const ParticleFootprint& fp = grid.footprints()[i];
    const Vec3f p = particles.centers[i];
    const float H = particles.support[i];
    const float H2 = H * H, invH2 = 1.f / H2;
    const float cW = static_cast<float>(norm / (double(H) * H * H));
    const float qvW = particles.qv[i] * cW, vW = particles.v[i] * cW;
    const float qvG = qvW * invH2; // grad W = c/H^5 shape'(q)/q (x - x_i)
    const int jlo = std::max(bundle.y0, static_cast<int>(std::ceil(fp.y0 - 0.5f)));
    const int jhi = std::min(bundle.y1 - 1, static_cast<int>(std::floor(fp.y1 - 0.5f)));
    const int ilo = std::max(bundle.x0, static_cast<int>(std::ceil(fp.x0 - 0.5f)));
    const int ihi = std::min(bundle.x1 - 1, static_cast<int>(std::floor(fp.x1 - 0.5f)));
    if (jlo > jhi || ilo > ihi)
    {
      continue;
    }
    // The chunks of Lanes columns (relative to the tile) that hold the footprint.
    const int c0 = (ilo - bundle.x0) / Lanes * Lanes, c1 = ihi - bundle.x0;
    for (int k = 0; k < slab; ++k)
    {
      if (!Jitter && !(std::abs(zs[k] - fp.zeta) < H))
      {
        continue;
      }
      if (Jitter && (zb[k] > fp.zeta + H || zb[k + 1] < fp.zeta - H))
      {
        continue;
      }
      const std::size_t sampleOffset = static_cast<std::size_t>(k) * plane;
      for (int j = jlo; j <= jhi; ++j)
      {
        const int row = j - bundle.y0;
        if (bundle.activeInRow[row] == 0)
        {
          continue;
        }
        // The row's rays at depth z: x(i) - x_p = P0 + i V for pixel column i.
        const Vec3f rs = bundle.rowStart[row] - p, rd = bundle.rowDir[row];
        const float z = zs[k];
        const Vec3f P0 = rs + rd * z, V = Ax + Bx * z;
        if (!Jitter)
        {
          const float qa = dot(V, V), qb = dot(P0, V), qc = dot(P0, P0) - H2;
          if (!(qb * qb - qa * qc > 0.f))
          {
            continue; // the row's plane misses the support at this depth
          }
        }
        const std::size_t rowOffset = sampleOffset + static_cast<std::size_t>(row) * bundle.stride;
        float* A = cache.A.data() + rowOffset;
        float* B = Weights ? cache.B.data() + rowOffset : nullptr;
        float* Gx = Gradient ? cache.Gx.data() + rowOffset : nullptr;
        float* Gy = Gradient ? cache.Gy.data() + rowOffset : nullptr;
        float* Gz = Gradient ? cache.Gz.data() + rowOffset : nullptr;
        const float* jl = bundle.jitter.data() + static_cast<std::size_t>(row) * bundle.stride;
        const float zk = zb[k], zstep = zb[k + 1] - zb[k];
        for (int base = c0; base <= c1; base += Lanes)
        {
          evaluations += Lanes;
          const float fb = static_cast<float>(bundle.x0 + base);
          // Plain floats in the loop (no struct temporaries), so it runs in SIMD lanes.
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
      }
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
}

double referenceWeightSum(SPHKernel kernel, double volume, double support, int neighbours)
{
  return neighbours * volume * kernelValue(kernel, 0.5 * support, support);
}

void renderSPH(const SPHParticles& particles,
  const ViewRays& rays,
  const SPHRenderParameters& params,
  const TransferFunctionTable& table,
  const float* opaqueDepth,
  PerspectiveGrid& grid,
  Frame& frame,
  RenderStatistics& stats)
{
  const bool normalized = params.normalization == SPHNormalization::Normalized;
  const bool weights = normalized || params.contour;
  stats.setEffect("normalization", normalized);
  stats.setEffect("gradient_shading", params.shade);
  stats.setEffect("contour_shading", params.contour);
  stats.setEffect("jitter", params.jitter);
  stats.setEffect("early_termination", params.terminationOpacity < 1.0);
  stats.setEffect("opaque_geometry", opaqueDepth != nullptr);
  for (const char* name : { "particles_in_view", "grid_cells", "depth_cells", "samples_per_cell",
         "grid_references", "grid_bytes", "bundles", "cells_visited", "cells_leaped", "samples",
         "kernel_evaluations", "weight_sums", "gradient_evaluations", "shaded_samples",
         "contour_samples", "terminated_rays" })
  {
    stats.declareCounter(name);
  }
  frame.resize(rays.width(), rays.height());
  if (particles.size() == 0 || table.empty())
  {
    return;
  }
  PerspectiveGridParameters gp;
  gp.tileSize = params.tileSize;
  gp.stepFactor = params.stepFactor;
  gp.fieldStep = params.samplesPerSupport > 0 ? particles.minSupport / params.samplesPerSupport : 0.0;
  bool any;
  {
    ScopedPhase phase(stats, "grid");
    any = grid.build(particles, rays, gp);
  }
  stats.addCounter("particles_in_view", static_cast<std::int64_t>(grid.particlesInView()));
  if (!any)
  {
    return;
  }
  const DepthSteps& steps = grid.steps();
  stats.addCounter("grid_cells", static_cast<std::int64_t>(grid.cellCount()));
  stats.addCounter("depth_cells", steps.cells);
  stats.addCounter("samples_per_cell", steps.samplesPerCell);
  stats.addCounter("grid_references", static_cast<std::int64_t>(grid.refs().size()));
  stats.addCounter("grid_bytes", static_cast<std::int64_t>(grid.memoryBytes()));

  ScopedPhase phase(stats, "raycast");
  const ExtinctionTable tf(table);
  const int S = steps.samplesPerCell;
  const int D = params.slabDepth > 0 ? std::min(params.slabDepth, S) : S;
  const DepositFn depositFn = pickDeposit(params.kernel, weights, params.shade, params.jitter);
  const float wMax = static_cast<float>(params.referenceWeightSum > 0 ? params.referenceWeightSum : 1.0);
  const float threshold = static_cast<float>(params.terminationOpacity);
  const float contourTau = static_cast<float>(
    -std::log1p(-std::clamp(params.contourOpacity, 0.0, 1.0 - 1e-7)) / table.unitDistance());
  const float minQ = particles.minQ, maxQ = particles.maxQ;
  const int T = grid.tileSize();
  const bool regionBounded = params.region.bounded();
  const int tilesX = grid.tilesX(), tiles = grid.tilesX() * grid.tilesY();
  const Vec3d origin = particles.origin;
  std::vector<Counters> perTile(tiles);

  tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1),
    [&](const tbb::blocked_range<int>& range)
    {
      thread_local Bundle bundle;
      thread_local SlabCache cache;
      for (int t = range.begin(); t != range.end(); ++t)
      {
        Counters& counters = perTile[t];
        const int tx = t % tilesX, ty = t / tilesX;
        Bundle& bd = bundle;
        bd.x0 = tx * T;
        bd.y0 = ty * T;
        bd.x1 = std::min(rays.width(), bd.x0 + T);
        bd.y1 = std::min(rays.height(), bd.y0 + T);
        bd.tw = bd.x1 - bd.x0;
        bd.th = bd.y1 - bd.y0;
        const int R = bd.tw * bd.th;
        bd.stride = (bd.tw + Lanes - 1) / Lanes * Lanes;
        const std::size_t P = static_cast<std::size_t>(bd.th) * bd.stride; // a cache plane
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
        bd.jitter.assign(P, 0.5f);
        bd.r.assign(R, 0.f);
        bd.g.assign(R, 0.f);
        bd.b.assign(R, 0.f);
        bd.a.assign(R, 0.f);
        bd.done.assign(R, 0);
        bd.activeInRow.assign(bd.th, bd.tw);
        bd.active = R;
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
                    rays.direction(px + 0.5, py + 0.5), particles.origin, z0, z1))
              {
                bd.zEnter[r] = static_cast<float>(z0);
                bd.zExit[r] = static_cast<float>(z1);
              }
              else
              {
                bd.zExit[r] = -Infinity;
              }
            }
            // The sample sits at the fraction j of its step: the midpoint, or the pixel's
            // jitter offset.
            bd.jitter[static_cast<std::size_t>(row) * bd.stride + col] =
              params.jitter ? sphJitterOffset(px, py) : 0.5f;
          }
        }
        ++counters.bundles;
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
          // Rays that end at opaque geometry before this cell are finished.
          const float zCell = static_cast<float>(steps.zeta(static_cast<double>(tz) * S));
          for (int r = 0; r < R; ++r)
          {
            if (!bd.done[r] && std::min(bd.zStop[r], bd.zExit[r]) <= zCell)
            {
              bd.done[r] = 1;
              --bd.activeInRow[r / bd.tw];
              --bd.active;
            }
          }
          if (bd.active == 0)
          {
            break;
          }
          ++counters.cellsVisited;
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
            cache.clear(static_cast<std::size_t>(slab) * P, weights, params.shade);
            depositFn(particles, grid, refBegin, refEnd, zs.data(), zb.data(), slab, bd, cache, counters);

            // Classification, shading and compositing of the slab, front to back.
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
                  bd.done[r] = 1;
                  --bd.activeInRow[r / bd.tw];
                  --bd.active;
                  continue;
                }
                if (z < bd.zEnter[r])
                {
                  continue; // the previous region's sample
                }
                const float a = A[ci];
                const float w = weights ? B[ci] : 0.f;
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
                  continue;
                }
                ++counters.samples;
                const float len = (std::min(zb[k + 1], bd.zStop[r]) - zb[k]) * bd.dirLength[r];
                float cr = 0, cg = 0, cb = 0, alpha = 0;
                if (hasValue)
                {
                  const ExtinctionTable::Entry e = tf.lookup(value);
                  alpha = -std::expm1(-e.tau * len);
                  cr = e.r;
                  cg = e.g;
                  cb = e.b;
                  if (params.shade && alpha > 0.f)
                  {
                    const std::size_t g = static_cast<std::size_t>(k) * P + ci;
                    const Vec3d grad(cache.Gx[g], cache.Gy[g], cache.Gz[g]);
                    const double glen = length(grad);
                    if (glen > 0 && std::isfinite(glen))
                    {
                      // Normal = -grad A / |grad A| (equation 3.23), in world space,
                      // turned to face the viewer (two-sided lighting).
                      const double px = bd.x0 + col + 0.5, py = bd.y0 + row + 0.5;
                      const Vec3d dirModel = rays.direction(px, py);
                      const Vec3d pModel = rays.pointAt(px, py, z) + origin;
                      Vec3d n = normalize(transformVector(params.normalToWorld, 3, grad * (-1.0 / glen)));
                      const Vec3d dirWorld = normalize(transformVector(params.modelToWorld, 4, dirModel));
                      if (dot(n, dirWorld) > 0)
                      {
                        n = -n;
                      }
                      const Vec3d s = shade(params.lights, params.material, Vec3d(cr, cg, cb),
                        transformPoint(params.modelToWorld, pModel), n, -dirWorld);
                      cr = static_cast<float>(std::clamp(s.x, 0.0, 1.0));
                      cg = static_cast<float>(std::clamp(s.y, 0.0, 1.0));
                      cb = static_cast<float>(std::clamp(s.z, 0.0, 1.0));
                      ++counters.shaded;
                    }
                  }
                }
                // Premultiplied contribution (3.31 to 3.33).
                float pr = alpha * cr, pg = alpha * cg, pb = alpha * cb;
                if (contour)
                {
                  const float I = std::clamp(1.f - w / wMax, 0.f, 1.f);
                  const float ac = -std::expm1(-contourTau * I * len);
                  pr += ac * static_cast<float>(params.contourColor[0]);
                  pg += ac * static_cast<float>(params.contourColor[1]);
                  pb += ac * static_cast<float>(params.contourColor[2]);
                  alpha = std::min(1.f, alpha + ac);
                  ++counters.contour;
                }
                const float tr = 1.f - bd.a[r];
                bd.r[r] += tr * pr;
                bd.g[r] += tr * pg;
                bd.b[r] += tr * pb;
                bd.a[r] += tr * alpha;
                if (bd.a[r] >= threshold)
                {
                  bd.done[r] = 1;
                  --bd.activeInRow[r / bd.tw];
                  --bd.active;
                  ++counters.terminated;
                }
              }
            }
          }
        }
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
    });
  Counters total;
  for (const Counters& c : perTile)
  {
    c.addTo(total);
  }
  stats.addCounter("bundles", total.bundles);
  stats.addCounter("cells_visited", total.cellsVisited);
  stats.addCounter("cells_leaped", total.cellsLeaped);
  stats.addCounter("samples", total.samples);
  stats.addCounter("kernel_evaluations", total.kernelEvaluations);
  stats.addCounter("weight_sums", total.weightSums);
  stats.addCounter("gradient_evaluations", total.gradientEvaluations);
  stats.addCounter("shaded_samples", total.shaded);
  stats.addCounter("contour_samples", total.contour);
  stats.addCounter("terminated_rays", total.terminated);
}

} // namespace raymappers
