// The SPH voxelizer (Zirr 2015): tiled voxelization into spans against analytic ray-sphere
// intersections, gap bridging, exact absorption beyond the stored spans, the memory budget,
// and its hard cases.
#include "CameraFixtures.h"
#include "Mappers/SPH/FluidCells.h"
#include "Mappers/SPH/FluidColors.h"
#include "Mappers/SPH/FluidRenderer.h"
#include "Mappers/SPH/SpanVoxelizer.h"
#include "Mappers/SPH/SurfaceLinks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

using namespace raymappers;
using namespace raymappers::test;

namespace
{
struct Sphere
{
  Vec3d c;
  double r;
};

FluidParticles makeParticles(const std::vector<Sphere>& in, const Vec3d& origin = Vec3d())
{
  FluidParticles P;
  buildFluidParticles(
    in.size(),
    origin,
    [&](std::size_t i) { return in[i].c; },
    [&](std::size_t i) { return in[i].r; },
    P);
  return P;
}

ViewRays perspectiveRays(const Vec3d& eye,
  const Vec3d& at,
  int w,
  int h,
  double n = 0.1,
  double f = 100,
  double fovy = 40,
  const Vec3d& origin = Vec3d())
{
  ViewRays rays;
  EXPECT_TRUE(rays.assign(
    multiply(perspective(fovy, double(w) / h, n, f), lookAt(eye, at, { 0, 1, 0 })), w, h, origin));
  return rays;
}

ViewRays orthographicRays(const Vec3d& eye, const Vec3d& at, int w, int h, double hh)
{
  ViewRays rays;
  EXPECT_TRUE(rays.assign(
    multiply(orthographic(hh * w / h, hh, 0.5, 20), lookAt(eye, at, { 0, 1, 0 })), w, h, Vec3d()));
  return rays;
}

/// The depths [z0, z1] where pixel (i, j)'s centre ray is inside the sphere; false if it misses.
bool raySphere(const ViewRays& rays, int i, int j, const Sphere& s, double& z0, double& z1)
{
  const Vec3d A = rays.start(i + 0.5, j + 0.5) - s.c, B = rays.direction(i + 0.5, j + 0.5);
  const double a = dot(B, B), b = dot(A, B), disc = b * b - a * (dot(A, A) - s.r * s.r);
  if (!(disc > 0))
  {
    return false;
  }
  z0 = (-b - std::sqrt(disc)) / a;
  z1 = (-b + std::sqrt(disc)) / a;
  return true;
}

/// Calls fn(i, j, z0, z1, len) for each pixel of a w x h view whose centre ray meets the
/// sphere ([z0, z1] its depths there, len = |B| the ray's length per unit of depth); returns
/// how many pixels it called it for.
template<typename Fn>
int forEachPixelOnSphere(const ViewRays& rays, int w, int h, const Sphere& s, Fn fn)
{
  int count = 0;
  for (int j = 0; j < h; ++j)
  {
    for (int i = 0; i < w; ++i)
    {
      double z0, z1;
      if (raySphere(rays, i, j, s, z0, z1))
      {
        fn(i, j, z0, z1, length(rays.direction(i + 0.5, j + 0.5)));
        ++count;
      }
    }
  }
  return count;
}

/// The depth of the layer holding z.
double layerDepth(const VoxelDepthLayers& L, double z)
{
  const double i = std::floor(L.coordinate(z));
  return L.depth(i + 1) - L.depth(i);
}

/// The union of a ray's intervals in the spheres clipped to [lo, hi]: disjoint intervals of
/// zeta, front to back.
std::vector<std::pair<double, double>> analyticIntervals(const ViewRays& rays,
  int i,
  int j,
  const std::vector<Sphere>& spheres,
  double lo,
  double hi)
{
  std::vector<std::pair<double, double>> iv, out;
  for (const Sphere& s : spheres)
  {
    double z0, z1;
    if (raySphere(rays, i, j, s, z0, z1) && std::max(z0, lo) < std::min(z1, hi))
    {
      iv.emplace_back(std::max(z0, lo), std::min(z1, hi));
    }
  }
  std::sort(iv.begin(), iv.end());
  for (const auto& [x, y] : iv)
  {
    if (out.empty() || x > out.back().second)
    {
      out.emplace_back(x, y);
    }
    else
    {
      out.back().second = std::max(out.back().second, y);
    }
  }
  return out;
}

/// The union of a ray's intervals in the spheres clipped to [lo, hi], total length in zeta.
double analyticThickness(const ViewRays& rays,
  int i,
  int j,
  const std::vector<Sphere>& spheres,
  double lo,
  double hi,
  int* pieces = nullptr)
{
  const auto iv = analyticIntervals(rays, i, j, spheres, lo, hi);
  double total = 0;
  for (const auto& [x, y] : iv)
  {
    total += y - x;
  }
  if (pieces)
  {
    *pieces = static_cast<int>(iv.size());
  }
  return total;
}

/// Slabs of overlapping spheres perpendicular to z (the paper's figure 8): `slabs` lattices
/// of radius-r spheres spaced `spacing` in x and y over [-half, half]^2, `pitch` apart in z.
std::vector<Sphere> slabLattice(int slabs, double r, double spacing, double half, double pitch)
{
  std::vector<Sphere> out;
  const int m = static_cast<int>(std::floor(2 * half / spacing + 1e-9));
  for (int k = 0; k < slabs; ++k)
  {
    for (int a = 0; a <= m; ++a)
    {
      for (int b = 0; b <= m; ++b)
      {
        out.push_back({ { -half + a * spacing, -half + b * spacing, -k * pitch }, r });
      }
    }
  }
  return out;
}

std::size_t pixelIndex(int w, int i, int j)
{
  return static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i);
}

bool voxelize(const std::vector<Sphere>& spheres,
  const ViewRays& rays,
  const VoxelizerParameters& vp,
  FluidSpans& spans,
  RenderStatistics& stats)
{
  stats.clear();
  return voxelizeFluid(makeParticles(spheres), rays, vp, spans, stats);
}
}

TEST(SPHVoxelizer, OneSphereSpansMatchTheAnalyticIntersectionWithinOneLayer)
{
  const Sphere s{ { 0.1, -0.2, 0.3 }, 1.0 };
  for (const bool persp : { true, false })
  {
    const int W = 64, H = 48;
    const ViewRays rays = persp ? perspectiveRays({ 0, 0, 5 }, { 0, 0, 0 }, W, H)
                                : orthographicRays({ 0, 0, 5 }, { 0, 0, 0 }, W, H, 1.5);
    FluidSpans spans;
    RenderStatistics stats;
    ASSERT_TRUE(voxelize({ s }, rays, VoxelizerParameters(), spans, stats));
    EXPECT_GT(stats.counter("layers"), 50);
    EXPECT_NEAR(stats.counter("angle_millidegrees"), 14000, 1); // not capped: 14 degrees reached
    int hits = 0;
    for (int j = 0; j < H; ++j)
    {
      for (int i = 0; i < W; ++i)
      {
        const std::size_t p = spans.pixel(i, j);
        double z0, z1;
        if (!raySphere(rays, i, j, s, z0, z1))
        {
          EXPECT_EQ(spans.count[p], 0) << i << " " << j;
          continue;
        }
        ++hits;
        ASSERT_EQ(spans.count[p], 1) << i << " " << j;
        EXPECT_EQ(spans.found[p], 1u);
        // The covered layers enclose [z0, z1]: entry and exit lie within one layer outside.
        EXPECT_LE(spans.entry(p, 0), z0 + 1e-5);
        EXPECT_LE(z0 - spans.entry(p, 0), layerDepth(spans.layers, z0) + 1e-5) << i << " " << j;
        EXPECT_GE(spans.exit(p, 0), z1 - 1e-5);
        EXPECT_LE(spans.exit(p, 0) - z1, layerDepth(spans.layers, z1) + 1e-5) << i << " " << j;
      }
    }
    EXPECT_GT(hits, 300) << persp;
    EXPECT_EQ(stats.counter("spans_found"), hits);
    // Compressed: only the stored spans take slots (not MaximumSpans per pixel).
    EXPECT_EQ(spans.depth.size(), 2u * hits);
    EXPECT_FALSE(stats.effect("gap_bridging"));
    EXPECT_FALSE(stats.effect("shell_splat"));
  }
}

TEST(SPHVoxelizer, TwoSpheresCloserThanTheGapThresholdMergeFartherDoNot)
{
  const int W = 64, H = 64;
  const ViewRays rays = perspectiveRays({ 0, 0, 6 }, { 0, 0, 0 }, W, H, 0.1, 100, 30);
  const double r = 0.5;
  const auto pair = [&](double gap) {
    return std::vector<Sphere>{ { { 0, 0, r + gap / 2 }, r }, { { 0, 0, -r - gap / 2 }, r } };
  };
  const std::size_t centre = static_cast<std::size_t>(H / 2) * W + W / 2;
  VoxelizerParameters vp;
  vp.gapThreshold = 0.3;
  FluidSpans spans;
  RenderStatistics stats;
  for (const double gap : { 0.2, 0.4 })
  {
    ASSERT_TRUE(voxelize(pair(gap), rays, vp, spans, stats));
    EXPECT_TRUE(stats.effect("gap_bridging"));
    EXPECT_FALSE(stats.effect("shell_splat")); // g < 2 r
    const int expected = gap < vp.gapThreshold ? 1 : 2;
    EXPECT_EQ(spans.count[centre], expected) << gap;
    EXPECT_EQ(stats.counter("gaps_bridged") > 0, expected == 1) << gap;
    double z0, z1, w0, w1;
    ASSERT_TRUE(raySphere(rays, W / 2, H / 2, pair(gap)[0], z0, z1));
    ASSERT_TRUE(raySphere(rays, W / 2, H / 2, pair(gap)[1], w0, w1));
    EXPECT_NEAR(spans.entry(centre, 0), z0, layerDepth(spans.layers, z0) + 1e-5);
    EXPECT_NEAR(spans.exit(centre, expected - 1), w1, layerDepth(spans.layers, w1) + 1e-5);
  }
  // Without bridging the 0.2 gap separates them.
  vp.gapThreshold = 0;
  ASSERT_TRUE(voxelize(pair(0.2), rays, vp, spans, stats));
  EXPECT_EQ(spans.count[centre], 2);
  // g >= 2 r: only the spheres' shells are splatted, and the chords between them are
  // bridged: every pixel that meets the pair has the one span of their union.
  vp.gapThreshold = 1.2;
  ASSERT_TRUE(voxelize(pair(0.2), rays, vp, spans, stats));
  EXPECT_TRUE(stats.effect("shell_splat"));
  EXPECT_EQ(stats.counter("set_bit_ops"), 2 * stats.counter("splat_pixels"));
  int hits = 0;
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const std::size_t p = spans.pixel(i, j);
      double lo = 1e30, hi = -1e30;
      for (const Sphere& s : pair(0.2))
      {
        double z0, z1;
        if (raySphere(rays, i, j, s, z0, z1))
        {
          lo = std::min(lo, z0);
          hi = std::max(hi, z1);
        }
      }
      if (lo > hi)
      {
        EXPECT_EQ(spans.count[p], 0);
        continue;
      }
      ++hits;
      ASSERT_EQ(spans.count[p], 1) << i << " " << j;
      EXPECT_NEAR(spans.entry(p, 0), lo, layerDepth(spans.layers, lo) + 1e-5);
      EXPECT_NEAR(spans.exit(p, 0), hi, layerDepth(spans.layers, hi) + 1e-5);
    }
  }
  EXPECT_GT(hits, 100);
}

TEST(SPHVoxelizer, TwentyFourLayersKeepTheExactThicknessWithSevenSpans)
{
  const int W = 48, H = 48;
  const ViewRays rays = perspectiveRays({ 0, 0, 4 }, { 0, 0, -3 }, W, H, 0.1, 100, 12);
  const std::vector<Sphere> slabs = slabLattice(24, 0.05, 0.06, 0.6, 0.3);
  VoxelizerParameters seven, all;
  all.maxSpans = 63;
  FluidSpans s7, sAll;
  RenderStatistics stats;
  ASSERT_TRUE(voxelize(slabs, rays, all, sAll, stats));
  ASSERT_TRUE(voxelize(slabs, rays, seven, s7, stats));
  EXPECT_GT(stats.counter("spans_hidden"), 0);
  int deep = 0;
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const std::size_t p = s7.pixel(i, j);
      int pieces = 0;
      const double exact = analyticThickness(rays, i, j, slabs, 0, 1e30, &pieces);
      ASSERT_EQ(s7.found[p], static_cast<std::uint32_t>(pieces)) << i << " " << j;
      ASSERT_EQ(sAll.count[p], pieces);
      if (pieces < 24)
      {
        continue;
      }
      ++deep;
      EXPECT_EQ(s7.count[p], 7);
      // Seven stored spans keep the thickness of all 24 (float rounding only) ...
      EXPECT_NEAR(s7.thickness(p), sAll.thickness(p), 1e-5 * sAll.thickness(p));
      // ... which is the analytic one up to one layer at each end of each span.
      double slack = 0;
      for (int k = 0; k < sAll.count[p]; ++k)
      {
        slack += layerDepth(sAll.layers, sAll.entry(p, k)) +
                 layerDepth(sAll.layers, sAll.exit(p, k) * 0.99999);
      }
      EXPECT_NEAR(s7.thickness(p), exact, slack) << i << " " << j;
    }
  }
  EXPECT_GT(deep, W * H / 4);
}

TEST(SPHVoxelizer, TilesShrinkToRespectTheMemoryBudgetWithTheSameSpans)
{
  const int W = 64, H = 48;
  const ViewRays rays = perspectiveRays({ 0, 0, 5 }, { 0, 0, 0 }, W, H);
  const std::vector<Sphere> spheres = { { { 0, 0, 0 }, 1.0 }, { { 0.5, 0.3, -1.5 }, 0.8 } };
  VoxelizerParameters vp;
  vp.angleResolutionDeg = 0.05; // asks for more than 16384 layers: capped
  FluidSpans whole, tiled;
  RenderStatistics stats;
  ASSERT_TRUE(voxelize(spheres, rays, vp, whole, stats));
  EXPECT_EQ(stats.counter("layers"), 16384);
  // 2 KB columns: tiles of 16 x 16 keep a thread's grid within the cache (1 MB).
  const std::int64_t size = stats.counter("tile_width");
  EXPECT_EQ(size, 16);
  EXPECT_EQ(stats.counter("tile_height"), size);
  EXPECT_EQ(stats.counter("tiles"), (W / 16) * (H / 16));
  const std::int64_t full = stats.counter("peak_temporary_bytes");
  EXPECT_GE(full, 16 * 16 * 16384 / 8); // at least one thread's grid
  // The default budget is automatic, at least 512 MB, and the voxelizer takes only its need.
  EXPECT_EQ(vp.memoryBudget, 0u);
  EXPECT_EQ(stats.counter("memory_budget_automatic"), 1);
  EXPECT_GE(stats.counter("memory_budget_bytes"), std::int64_t(512) << 20);
  EXPECT_LE(full, stats.counter("memory_budget_bytes"));
  // A third of that budget: smaller tiles, the same spans.
  vp.memoryBudget = static_cast<std::size_t>(full / 3);
  stats.clear();
  ASSERT_TRUE(voxelize(spheres, rays, vp, tiled, stats));
  EXPECT_LT(stats.counter("tile_width"), size);
  EXPECT_GT(stats.counter("tiles"), (W / 16) * (H / 16));
  EXPECT_LE(stats.counter("peak_temporary_bytes"), static_cast<std::int64_t>(vp.memoryBudget));
  EXPECT_EQ(stats.counter("memory_budget_bytes"), static_cast<std::int64_t>(vp.memoryBudget));
  EXPECT_EQ(stats.counter("memory_budget_automatic"), 0);
  EXPECT_EQ(tiled.count, whole.count);
  EXPECT_EQ(tiled.depth, whole.depth);
  // Below one column's bits the voxelization refuses instead of exceeding the budget.
  vp.memoryBudget = 1000;
  FluidSpans none;
  stats.clear();
  EXPECT_FALSE(voxelize(spheres, rays, vp, none, stats));
  EXPECT_EQ(stats.counter("budget_exceeded"), 1);
  EXPECT_LE(stats.counter("peak_temporary_bytes"), 1000);
  // The need it reports is the least any tile size takes: a byte less refuses, that budget
  // voxelizes, with the same spans.
  const std::int64_t needed = stats.counter("budget_needed_bytes");
  EXPECT_GT(needed, 1000);
  vp.memoryBudget = static_cast<std::size_t>(needed - 1);
  stats.clear();
  EXPECT_FALSE(voxelize(spheres, rays, vp, none, stats));
  EXPECT_EQ(stats.counter("budget_needed_bytes"), needed);
  vp.memoryBudget = static_cast<std::size_t>(needed);
  stats.clear();
  ASSERT_TRUE(voxelize(spheres, rays, vp, tiled, stats));
  EXPECT_EQ(stats.counter("peak_temporary_bytes"), needed);
  EXPECT_EQ(tiled.count, whole.count);
  EXPECT_EQ(tiled.depth, whole.depth);
}

TEST(SPHVoxelizer, NearPlaneCuttingASphereStartsItsSpansAtTheNearPlane)
{
  const int W = 48, H = 48;
  const double nearZ = 4.6;
  const ViewRays rays = perspectiveRays({ 0, 0, 5 }, { 0, 0, 0 }, W, H, nearZ, 100, 40);
  const Sphere s{ { 0, 0, 0 }, 1.0 };
  FluidSpans spans;
  RenderStatistics stats;
  ASSERT_TRUE(voxelize({ s }, rays, VoxelizerParameters(), spans, stats));
  EXPECT_NEAR(spans.layers.d0, nearZ, 1e-9);
  int cut = 0;
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const std::size_t p = spans.pixel(i, j);
      double z0, z1;
      if (!raySphere(rays, i, j, s, z0, z1) || z1 <= nearZ)
      {
        EXPECT_EQ(spans.count[p], 0);
        continue;
      }
      ASSERT_EQ(spans.count[p], 1);
      if (z0 < nearZ)
      {
        ++cut;
        EXPECT_FLOAT_EQ(spans.entry(p, 0), static_cast<float>(nearZ));
      }
      EXPECT_NEAR(spans.exit(p, 0), z1, layerDepth(spans.layers, z1) + 1e-5);
    }
  }
  EXPECT_GT(cut, 100);
}

TEST(SPHVoxelizer, CameraInsideTheFluidSeesItFromTheNearPlaneOnEveryPixel)
{
  const int W = 40, H = 30;
  const ViewRays rays = perspectiveRays({ 0.2, 0.1, 0.3 }, { 0, 0, -3 }, W, H, 0.05, 50, 60);
  const std::vector<Sphere> fluid = { { { 0, 0, 0 }, 2.0 }, { { 0, 0, -3.5 }, 0.5 } };
  FluidSpans spans;
  RenderStatistics stats;
  ASSERT_TRUE(voxelize(fluid, rays, VoxelizerParameters(), spans, stats));
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const std::size_t p = spans.pixel(i, j);
      double z0, z1;
      ASSERT_TRUE(raySphere(rays, i, j, fluid[0], z0, z1));
      ASSERT_GE(spans.count[p], 1);
      EXPECT_FLOAT_EQ(spans.entry(p, 0), 0.05f);
      EXPECT_NEAR(spans.exit(p, 0), z1, layerDepth(spans.layers, z1) + 1e-5);
      int pieces = 0;
      const double exact = analyticThickness(rays, i, j, fluid, 0.05, 50, &pieces);
      EXPECT_EQ(spans.count[p], pieces);
      EXPECT_TRUE(std::isfinite(spans.thickness(p)));
      EXPECT_NEAR(spans.thickness(p), exact, 4 * layerDepth(spans.layers, 3.0));
    }
  }
}

TEST(SPHVoxelizer, EmptyInputAndParticlesOutOfViewGiveNoSpans)
{
  const ViewRays rays = perspectiveRays({ 0, 0, 5 }, { 0, 0, 0 }, 32, 32);
  FluidSpans spans;
  RenderStatistics stats;
  ASSERT_TRUE(voxelize({}, rays, VoxelizerParameters(), spans, stats));
  EXPECT_EQ(spans.count.size(), 32u * 32u);
  EXPECT_EQ(std::count(spans.count.begin(), spans.count.end(), 0), 32 * 32);
  // Behind the eye and far off to the side.
  ASSERT_TRUE(voxelize(
    { { { 0, 0, 9 }, 1 }, { { 40, 0, 0 }, 1 } }, rays, VoxelizerParameters(), spans, stats));
  EXPECT_EQ(stats.counter("particles_in_view"), 0);
  EXPECT_EQ(std::count(spans.count.begin(), spans.count.end(), 0), 32 * 32);
}

TEST(SPHVoxelizer, OpaqueGeometryStopDepthEndsTheSpansThere)
{
  // A plane z = 0.2 (window depths from the rays' own matrix) through a sphere of radius 1
  // at the origin, seen from z = 5: where the ray meets the sphere before the plane the
  // span runs from the analytic entry to the plane exactly; behind it there is no fluid.
  const int W = 48, H = 48;
  const ViewRays rays = perspectiveRays({ 0, 0, 5 }, { 0, 0, 0 }, W, H);
  const Sphere s{ { 0, 0, 0 }, 1.0 };
  std::vector<float> window(static_cast<std::size_t>(W) * H);
  std::vector<double> planeZeta(window.size());
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const Vec3d A = rays.start(i + 0.5, j + 0.5), B = rays.direction(i + 0.5, j + 0.5);
      const double zeta = (0.2 - A.z) / B.z; // where the ray meets z = 0.2
      const std::array<double, 4> c = rays.clip(A + B * zeta);
      window[pixelIndex(W, i, j)] = static_cast<float>(0.5 * (c[2] / c[3] + 1.0));
      planeZeta[pixelIndex(W, i, j)] = zeta;
    }
  }
  const std::vector<float> stop = stopDepthsFromWindowDepth(rays, window.data());
  VoxelizerParameters vp;
  vp.stopDepth = stop.data();
  FluidSpans spans;
  RenderStatistics stats;
  ASSERT_TRUE(voxelize({ s }, rays, vp, spans, stats));
  int cut = 0;
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const std::size_t p = spans.pixel(i, j);
      ASSERT_NEAR(stop[p], planeZeta[p], 1e-3 * planeZeta[p]);
      double z0, z1;
      if (!raySphere(rays, i, j, s, z0, z1) || z0 >= stop[p])
      {
        EXPECT_EQ(spans.count[p], 0) << i << " " << j;
        continue;
      }
      ASSERT_EQ(spans.count[p], 1) << i << " " << j;
      EXPECT_NEAR(spans.entry(p, 0), z0, layerDepth(spans.layers, z0) + 1e-5);
      ++cut;
      EXPECT_FLOAT_EQ(spans.exit(p, 0), stop[p]) << i << " " << j;
    }
  }
  EXPECT_GT(cut, 300);
  EXPECT_EQ(stats.counter("stopped_spans"), cut) << stats.summary();
  // Without geometry (window depth 1 everywhere) nothing is stopped.
  std::fill(window.begin(), window.end(), 1.f);
  const std::vector<float> none = stopDepthsFromWindowDepth(rays, window.data());
  vp.stopDepth = none.data();
  FluidSpans free;
  ASSERT_TRUE(voxelize({ s }, rays, vp, free, stats));
  EXPECT_EQ(stats.counter("stopped_spans"), 0);
  FluidSpans plain;
  ASSERT_TRUE(voxelize({ s }, rays, VoxelizerParameters(), plain, stats));
  EXPECT_EQ(free.depth, plain.depth);
}

TEST(SPHVoxelizer, NonFinitePositionsAndBadRadiiAreSkippedAndCounted)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Sphere> clean = { { { 0, 0, 0 }, 1.0 }, { { 0.8, 0.2, -1 }, 0.5 } };
  std::vector<Sphere> dirty = { { { nan, 0, 0 }, 1.0 },
    clean[0],
    { { 0, inf, 0 }, 1.0 },
    { { 0, 0, 0 }, -1.0 },
    clean[1],
    { { 0, 0, nan }, 0.5 },
    { { 0, 0, 0 }, nan } };
  const FluidParticles P = makeParticles(dirty);
  EXPECT_EQ(P.size(), 2u);
  EXPECT_EQ(P.skippedNonFinite, 3u);
  EXPECT_EQ(P.skippedBadRadius, 2u);
  const ViewRays rays = perspectiveRays({ 0, 0, 5 }, { 0, 0, 0 }, 32, 32);
  FluidSpans a, b;
  RenderStatistics stats;
  ASSERT_TRUE(voxelizeFluid(P, rays, VoxelizerParameters(), a, stats));
  ASSERT_TRUE(voxelize(clean, rays, VoxelizerParameters(), b, stats));
  EXPECT_EQ(a.count, b.count);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_GT(
    std::count_if(a.count.begin(), a.count.end(), [](std::uint8_t c) { return c > 0; }), 50);
}

namespace
{
std::uint8_t linkOf(const FluidSpans& s, std::size_t p, int slot, int dir)
{
  return static_cast<std::uint8_t>(s.links[s.slot(p, slot)] >> (8 * dir));
}

/// Mean and max angle (degrees) between the entry normals and the analytic sphere normals at
/// the pixels whose 3 x 3 neighbourhood all meets the sphere, where the surface faces the eye
/// by at least minCos.
std::pair<double, double> entryNormalError(const FluidSpans& spans,
  const ViewRays& rays,
  const Sphere& s,
  double minCos,
  int& tested)
{
  double sum = 0, worst = 0;
  tested = 0;
  for (int j = 1; j + 1 < spans.height; ++j)
  {
    for (int i = 1; i + 1 < spans.width; ++i)
    {
      bool interior = true;
      double z0 = 0, z1 = 0;
      for (int b = -1; b <= 1; ++b)
      {
        for (int a = -1; a <= 1; ++a)
        {
          interior = interior && raySphere(rays, i + a, j + b, s, z0, z1);
        }
      }
      if (!interior || !raySphere(rays, i, j, s, z0, z1))
      {
        continue;
      }
      const std::size_t p = spans.pixel(i, j);
      const Vec3d exact = normalize(rays.pointAt(i + 0.5, j + 0.5, z0) - s.c);
      if (-dot(exact, normalize(rays.direction(i + 0.5, j + 0.5))) < minCos)
      {
        continue;
      }
      const Vec3f n = decodeNormal(spans.normals[spans.slot(p, 0)]);
      const double angle = std::acos(std::clamp(dot(Vec3d(n), exact), -1.0, 1.0)) * 180 / M_PI;
      sum += angle;
      worst = std::max(worst, angle);
      ++tested;
      // The exit normal faces out of the fluid, along the ray.
      EXPECT_GT(
        dot(Vec3d(decodeNormal(spans.normals[spans.slot(p, 1)])), rays.direction(i + 0.5, j + 0.5)),
        0);
    }
  }
  return { tested ? sum / tested : 0.0, worst };
}
}

TEST(SPHVoxelizer, SurfaceConnectionLinksOverlappingSpansAndBubbleWalls)
{
  // Three pixels in a row: a bubble (two spans) beside one span spanning it, beside a span
  // that overlaps nothing.
  FluidSpans s;
  s.reset(3, 1, 7);
  const auto put = [&](int i, std::vector<std::pair<float, float>> v)
  {
    const std::size_t p = s.pixel(i, 0); // (called in pixel order: appended)
    s.count[p] = static_cast<std::uint8_t>(v.size());
    s.first[p] = s.depth.size();
    for (const auto& span : v)
    {
      s.depth.push_back(span.first);
      s.depth.push_back(span.second);
    }
  };
  put(0, { { 1, 2 }, { 3, 4 } });
  put(1, { { 0.5f, 5 } });
  put(2, { { 10, 11 } });
  RenderStatistics stats;
  connectSurfaces(s, stats);
  const std::uint8_t Own = FluidSpans::OwnColumn;
  // Pixel 0 towards +x: both entries reach the same neighbour span, so the inner entry
  // links to the preceding exit and the inner exit to the next entry (the bubble's walls).
  EXPECT_EQ(linkOf(s, 0, 0, 0), 0);
  EXPECT_EQ(linkOf(s, 0, 1, 0), Own | 2);
  EXPECT_EQ(linkOf(s, 0, 2, 0), Own | 1);
  EXPECT_EQ(linkOf(s, 0, 3, 0), 1);
  // Towards -x (beyond the image) and +-y: boundary spans, entry and exit linked.
  for (const int dir : { 1, 2, 3 })
  {
    EXPECT_EQ(linkOf(s, 0, 0, dir), Own | 1);
    EXPECT_EQ(linkOf(s, 0, 1, dir), Own | 0);
    EXPECT_EQ(linkOf(s, 0, 2, dir), Own | 3);
    EXPECT_EQ(linkOf(s, 0, 3, dir), Own | 2);
  }
  // Pixel 1 towards -x: its entry to the first entry, its exit to the last exit.
  EXPECT_EQ(linkOf(s, 1, 0, 1), 0);
  EXPECT_EQ(linkOf(s, 1, 1, 1), 3);
  // Pixel 1 towards +x and pixel 2 towards -x: no overlap.
  EXPECT_EQ(linkOf(s, 1, 0, 0), Own | 1);
  EXPECT_EQ(linkOf(s, 1, 1, 0), Own | 0);
  EXPECT_EQ(linkOf(s, 2, 0, 1), Own | 1);
  EXPECT_EQ(linkOf(s, 2, 1, 1), Own | 0);
  EXPECT_EQ(stats.counter("links_neighbour"), 4);
  // Own-column links: pixel 0: 2 bubble walls + 3 x 4 boundary; pixel 1: 3 x 2; pixel 2: 4 x 2.
  EXPECT_EQ(stats.counter("links_own"), 14 + 6 + 8);
}

TEST(SPHVoxelizer, SobelNormalsAlongTheLinksFollowTheSphereAndSmoothingImprovesThem)
{
  const Sphere s{ { 0, 0, 0 }, 1.0 };
  const int W = 96, H = 96;
  const ViewRays rays = perspectiveRays({ 0, 0, 4 }, { 0, 0, 0 }, W, H, 0.1, 100, 40);
  FluidSpans spans;
  RenderStatistics stats;
  ASSERT_TRUE(voxelize({ s }, rays, VoxelizerParameters(), spans, stats));
  connectSurfaces(spans, stats);
  SurfaceNeighbourhoods nbh;
  findNeighbourhoods(spans, nbh, stats);
  const std::vector<float> raw = spans.depth;
  smoothSurfaces(spans, nbh, rays, 0.0, 20, stats);
  EXPECT_FALSE(stats.effect("smoothing"));
  EXPECT_EQ(stats.counter("filter_iterations"), 0);
  EXPECT_EQ(stats.counter("filtered_points"), 0);
  EXPECT_EQ(spans.depth, raw);
  computeNormals(spans, nbh, rays, stats);
  int tested = 0;
  const auto [mean0, worst0] = entryNormalError(spans, rays, s, 0.0, tested);
  const auto [front0, frontWorst0] = entryNormalError(spans, rays, s, 0.5, tested);
  EXPECT_GT(tested, 1000);
  // Unsmoothed (measured 1.5 degrees mean, 4.2 at most): the 14 degree angle resolution.
  EXPECT_LT(mean0, 3.0);
  EXPECT_LT(worst0, 8.0);

  // Radius 0.1: about 2.5 pixels at the sphere's front (sigma zeta = 0.0114 * 3).
  stats.clear();
  smoothSurfaces(spans, nbh, rays, 0.1, 20, stats);
  EXPECT_TRUE(stats.effect("smoothing"));
  EXPECT_EQ(stats.counter("filter_iterations"),
    static_cast<std::int64_t>(std::ceil(0.1 / (rays.pixelSize() * spans.layers.d0))));
  EXPECT_GT(stats.counter("filtered_points"), 2000);
  computeNormals(spans, nbh, rays, stats);
  const auto [mean1, worst1] = entryNormalError(spans, rays, s, 0.0, tested);
  const auto [front1, frontWorst1] = entryNormalError(spans, rays, s, 0.5, tested);
  // Smoothing removes the layers' steps where the surface faces the eye (measured 0.45
  // degrees mean, 1.1 at most) and flattens towards the silhouette, less on the whole.
  EXPECT_LT(front1, 0.5 * front0);
  EXPECT_LT(frontWorst1, 0.5 * frontWorst0);
  EXPECT_LT(mean1, mean0);
  EXPECT_LT(worst1, 20.0);
  for (std::size_t p = 0; p < spans.count.size(); ++p)
  {
    if (spans.count[p])
    {
      EXPECT_LE(spans.entry(p, 0), spans.exit(p, 0));
    }
  }
}

namespace
{
FluidRenderParameters litFluid()
{
  FluidRenderParameters fp;
  fp.material.ambient = 0.1;
  fp.material.diffuse = 0.7;
  fp.material.specular = 0.4;
  fp.material.specularPower = 20;
  Light light;
  light.direction = normalize(Vec3d(-0.3, -0.4, -1));
  fp.lights = { light };
  return fp;
}

/// The brightest colour the lights allow: ambient + diffuse + specular at full strength.
Vec3d lightBound(const FluidRenderParameters& fp)
{
  Vec3d b = fp.color * fp.material.ambient;
  for (const Light& l : fp.lights)
  {
    b +=
      l.color * (fp.color * fp.material.diffuse + fp.material.specularColor * fp.material.specular);
  }
  return b;
}

bool frameFinite(const Frame& f)
{
  return std::all_of(f.rgba.begin(), f.rgba.end(), [](float v) { return std::isfinite(v); }) &&
         std::all_of(f.depth.begin(), f.depth.end(), [](float v) { return std::isfinite(v); });
}
}

TEST(SPHVoxelizer, TranslucencyThroughTwentyFourLayersIsExactBeerLambertWithSevenSpans)
{
  const int W = 48, H = 48;
  const ViewRays rays = perspectiveRays({ 0, 0, 4 }, { 0, 0, -3 }, W, H, 0.1, 100, 12);
  const std::vector<Sphere> slabs = slabLattice(24, 0.05, 0.06, 0.6, 0.3);
  const FluidParticles P = makeParticles(slabs);
  FluidRenderParameters fp = litFluid();
  fp.density = 0.4;
  FluidSpans spans;
  Frame seven, all;
  RenderStatistics stats;
  ASSERT_TRUE(renderFluid({ P, spans }, viewOf(rays), fp, seven, stats));
  EXPECT_GT(stats.counter("spans_hidden"), 0);
  EXPECT_TRUE(stats.effect("translucency"));
  EXPECT_FALSE(stats.effect("refraction"));
  EXPECT_FALSE(stats.effect("ambient_occlusion"));
  EXPECT_FALSE(stats.effect("smoothing"));
  EXPECT_EQ(stats.counter("refraction_paths"), 0);
  EXPECT_EQ(stats.counter("march_columns"), 0);
  EXPECT_EQ(stats.counter("ao_samples"), 0);
  EXPECT_EQ(stats.counter("filtered_points"), 0);
  EXPECT_EQ(stats.phase("refract"), 0.0);
  EXPECT_EQ(stats.phase("ao"), 0.0);
  EXPECT_EQ(stats.counter("translucent_pixels"), stats.counter("shaded_pixels"));
  fp.voxelizer.maxSpans = 63;
  FluidSpans allSpans;
  stats.clear();
  ASSERT_TRUE(renderFluid({ P, allSpans }, viewOf(rays), fp, all, stats));
  EXPECT_EQ(stats.counter("spans_hidden"), 0);
  const Vec3d kappa = fp.absorptionColor * fp.density;
  int deep = 0;
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const std::size_t p = spans.pixel(i, j);
      int pieces = 0;
      const double len = length(rays.direction(i + 0.5, j + 0.5));
      const double exact = analyticThickness(rays, i, j, slabs, 0, 1e30, &pieces) * len;
      const double alpha7 = seven.rgba[4 * p + 3], alphaAll = all.rgba[4 * p + 3];
      const double beer =
        1 -
        (std::exp(-kappa.x * exact) + std::exp(-kappa.y * exact) + std::exp(-kappa.z * exact)) / 3;
      // Seven stored spans absorb as all of them do ...
      EXPECT_NEAR(alpha7, alphaAll, 2e-6) << i << " " << j;
      // ... and as Beer-Lambert over the analytic thickness, up to one layer at each end of
      // each span (the slope of the absorption is at most kappa_max).
      double slack = 0;
      for (int k = 0; k < allSpans.count[p]; ++k)
      {
        slack += layerDepth(allSpans.layers, allSpans.entry(p, k)) +
                 layerDepth(allSpans.layers, allSpans.exit(p, k) * 0.99999);
      }
      EXPECT_NEAR(alpha7, beer, kappa.x * slack * len + 1e-6) << i << " " << j;
      if (pieces >= 24)
      {
        ++deep;
        EXPECT_GT(alpha7, 0.25);
      }
    }
  }
  EXPECT_GT(deep, W * H / 4);

  // Off the view axis a ray's world length is |B| times its depth range: a sphere in the
  // corner of a wide view.
  const Sphere corner{ { 1.4, 1.0, 0 }, 0.9 };
  const ViewRays wide = perspectiveRays({ 0, 0, 3 }, { 0, 0, 0 }, W, H, 0.1, 100, 90);
  Frame frame;
  ASSERT_TRUE(renderFluid({ makeParticles({ corner }), allSpans }, viewOf(wide), fp, frame, stats));
  const int tested = forEachPixelOnSphere(wide, W, H, corner,
    [&](int i, int j, double z0, double z1, double len)
    {
      const double chord = (z1 - z0) * len;
      const double beer =
        1 -
        (std::exp(-kappa.x * chord) + std::exp(-kappa.y * chord) + std::exp(-kappa.z * chord)) / 3;
      const double slack =
        (layerDepth(allSpans.layers, z0) + layerDepth(allSpans.layers, z1)) * len;
      EXPECT_NEAR(frame.rgba[4 * frame.index(i, j) + 3], beer, kappa.x * slack + 1e-6)
        << i << " " << j;
    });
  EXPECT_GT(tested, 100);
}

TEST(SPHVoxelizer, OpaqueFrontSurfaceIsLitWithTheSphereNormalAtItsDepth)
{
  const Sphere s{ { 0, 0, 0 }, 1.0 };
  const int W = 64, H = 64;
  const ViewRays rays = perspectiveRays({ 0, 0, 4 }, { 0, 0, 0 }, W, H, 0.5, 20, 40);
  FluidRenderParameters fp = litFluid();
  fp.translucency = false;
  fp.material.specular = 0; // the diffuse term: its error is the normal's (a few degrees)
  FluidSpans spans;
  Frame frame;
  RenderStatistics stats;
  ASSERT_TRUE(renderFluid({ makeParticles({ s }), spans }, viewOf(rays), fp, frame, stats));
  double sumError = 0, maxError = 0;
  EXPECT_FALSE(stats.effect("translucency"));
  EXPECT_EQ(stats.counter("translucent_pixels"), 0);
  int tested = 0;
  for (int j = 1; j + 1 < H; ++j)
  {
    for (int i = 1; i + 1 < W; ++i)
    {
      const std::size_t p = frame.index(i, j);
      double z0, z1;
      if (!raySphere(rays, i, j, s, z0, z1))
      {
        EXPECT_EQ(frame.rgba[4 * p + 3], 0.f);
        EXPECT_EQ(frame.depth[p], 1.f);
        continue;
      }
      EXPECT_EQ(frame.rgba[4 * p + 3], 1.f);
      const Vec3d x = rays.pointAt(i + 0.5, j + 0.5, z0);
      const Vec3d n = normalize(x - s.c);
      const Vec3d d = normalize(rays.direction(i + 0.5, j + 0.5));
      if (-dot(n, d) < 0.5)
      {
        continue; // near the silhouette the normal's error grows
      }
      ++tested;
      const Vec3d ref = shadeParts(fp.lights, fp.material, fp.color, x, n, -d).total();
      for (int c = 0; c < 3; ++c)
      {
        const double e = std::abs(frame.rgba[4 * p + c] - ref[c]);
        sumError += e;
        maxError = std::max(maxError, e);
      }
      const std::array<double, 4> c = rays.clip(x);
      const double windowDepth = 0.5 * (c[2] / c[3] + 1);
      const std::array<double, 4> c1 =
        rays.clip(rays.pointAt(i + 0.5, j + 0.5, z0 - layerDepth(spans.layers, z0)));
      EXPECT_NEAR(frame.depth[p], windowDepth, windowDepth - 0.5 * (c1[2] / c1[3] + 1) + 1e-6);
    }
  }
  EXPECT_GT(tested, 1000);
  EXPECT_LT(sumError / (3 * tested), 0.01);
  EXPECT_LT(maxError, 0.05);
}

namespace
{
/// Three slabs of overlapping spheres and a ball: refracted paths through them meet many
/// surfaces, inside and outside the fluid.
std::vector<Sphere> slabsAndBall()
{
  std::vector<Sphere> fluid = slabLattice(3, 0.08, 0.07, 1.0, 0.07);
  fluid.push_back({ { 0.3, 0.6, 0.2 }, 0.4 });
  return fluid;
}
}

TEST(SPHVoxelizer, RefractionAndTotalInternalReflectionNeverCreateEnergy)
{
  // A slab of fluid seen at grazing angles, and a sphere: dense and weakly absorbing, so
  // paths bounce inside many times.
  const std::vector<Sphere> fluid = slabsAndBall();
  const int W = 64, H = 48;
  const ViewRays rays = perspectiveRays({ 0.2, 0.5, 3.0 }, { 0, 0, -1 }, W, H, 0.1, 50, 50);
  const ViewRays parallel = orthographicRays({ 0.2, 0.5, 3.0 }, { 0, 0, -1 }, W, H, 1.2);
  FluidRenderParameters fp = litFluid();
  fp.density = 0.05;
  fp.bounces = 12;
  fp.smoothingRadius = 0.02;
  const Vec3d bound = lightBound(fp);
  const FluidParticles P = makeParticles(fluid);
  for (const auto& [eta, view] : { std::pair{ 1.33, &rays }, { 2.4, &rays }, { 2.4, &parallel } })
  {
    fp.refractiveIndex = eta;
    FluidSpans spans;
    Frame frame;
    RenderStatistics stats;
    ASSERT_TRUE(renderFluid({ P, spans }, viewOf(*view), fp, frame, stats));
    EXPECT_TRUE(stats.effect("refraction"));
    EXPECT_EQ(stats.counter("refraction_paths"), stats.counter("shaded_pixels"));
    EXPECT_GT(stats.counter("tir_events"), 0) << eta;
    EXPECT_GT(stats.counter("march_columns"), stats.counter("shaded_pixels"));
    EXPECT_GT(stats.phase("refract"), 0.0);
    EXPECT_EQ(stats.phase("render"), 0.0);
    ASSERT_TRUE(frameFinite(frame));
    for (std::size_t p = 0; p < frame.depth.size(); ++p)
    {
      const float* c = &frame.rgba[4 * p];
      EXPECT_LE(c[0], bound.x + 1e-6) << p;
      EXPECT_LE(c[1], bound.y + 1e-6) << p;
      EXPECT_LE(c[2], bound.z + 1e-6) << p;
      EXPECT_GE(std::min({ c[0], c[1], c[2] }), 0.f);
      EXPECT_GE(c[3], 0.f);
      EXPECT_LE(c[3], 1.f + 1e-6);
    }
  }
  // An index of 1, or an opaque surface, marches nothing.
  for (const bool translucent : { true, false })
  {
    fp.refractiveIndex = translucent ? 1.0 : 1.33;
    fp.translucency = translucent;
    FluidSpans spans;
    Frame frame;
    RenderStatistics stats;
    ASSERT_TRUE(renderFluid({ P, spans }, viewOf(rays), fp, frame, stats));
    EXPECT_FALSE(stats.effect("refraction"));
    EXPECT_EQ(stats.counter("march_columns"), 0);
    EXPECT_EQ(stats.counter("surface_events"), 0);
    EXPECT_EQ(stats.phase("refract"), 0.0);
  }
}

TEST(SPHVoxelizer, MarchTileSkippingFindsTheSameSurfacesAsColumnByColumn)
{
  // Slabs, a bubble-like hollow sphere pair and a ball, at an index and absorption that send
  // paths through many surfaces inside and outside; perspective and parallel views.
  std::vector<Sphere> fluid = slabsAndBall();
  fluid.push_back({ { -0.5, -0.4, 0.5 }, 0.25 });
  const FluidParticles P = makeParticles(fluid);
  FluidRenderParameters fp = litFluid();
  fp.refractiveIndex = 1.33;
  fp.density = 0.3;
  fp.bounces = 8;
  const int W = 160, H = 120;
  const ViewRays rays = perspectiveRays({ 0.6, 0.9, 2.5 }, { 0, 0, -1 }, W, H, 0.1, 50, 50);
  const ViewRays parallel = orthographicRays({ 0.2, 0.5, 3.0 }, { 0, 0, -1 }, W, H, 1.2);
  for (const ViewRays* view : { &rays, &parallel })
  {
    Frame skipped, columns;
    RenderStatistics withSkips, without;
    FluidSpans spans;
    ASSERT_TRUE(renderFluid({ P, spans }, viewOf(*view), fp, skipped, withSkips));
    fp.marchTileSkipping = false;
    ASSERT_TRUE(renderFluid({ P, spans }, viewOf(*view), fp, columns, without));
    fp.marchTileSkipping = true;
    EXPECT_GT(withSkips.counter("march_tile_skips"), 0);
    EXPECT_EQ(without.counter("march_tile_skips"), 0);
    EXPECT_LT(withSkips.counter("march_columns"), without.counter("march_columns"));
    EXPECT_EQ(withSkips.counter("surface_events"), without.counter("surface_events"));
    std::size_t differing = 0;
    double maxDiff = 0;
    for (std::size_t k = 0; k < skipped.rgba.size(); ++k)
    {
      const double d = std::abs(double(skipped.rgba[k]) - columns.rgba[k]);
      maxDiff = std::max(maxDiff, d);
      differing += d > 1e-6;
    }
    std::cout << "tile skipping: " << withSkips.counter("march_columns") << " steps ("
              << withSkips.counter("march_tile_skips") << " tiles) against "
              << without.counter("march_columns") << "; " << differing
              << " channels differ, max " << maxDiff << "\n";
    EXPECT_EQ(differing, 0u);
  }
}

TEST(SPHVoxelizer, AmbientOcclusionDarkensOnlyWhereFluidIsNearAndCostsNothingWhenOff)
{
  // Two spheres side by side: the crevice between them is occluded, their front centres not.
  const std::vector<Sphere> pair = { { { -0.5, 0, 0 }, 0.5 }, { { 0.5, 0, 0 }, 0.5 } };
  const int W = 96, H = 48;
  const ViewRays rays = perspectiveRays({ 0, 0, 4 }, { 0, 0, 0 }, W, H, 0.5, 20, 25);
  FluidRenderParameters fp = litFluid();
  fp.translucency = false;
  fp.aoRadius = 0.3;
  fp.aoSamples = 32;
  const FluidParticles P = makeParticles(pair);
  FluidSpans spans;
  Frame off, on;
  RenderStatistics stats;
  ASSERT_TRUE(renderFluid({ P, spans }, viewOf(rays), fp, off, stats));
  EXPECT_FALSE(stats.effect("ambient_occlusion"));
  EXPECT_EQ(stats.counter("ao_samples"), 0);
  EXPECT_EQ(stats.phase("ao"), 0.0);
  fp.ambientOcclusion = true;
  stats.clear();
  ASSERT_TRUE(renderFluid({ P, spans }, viewOf(rays), fp, on, stats));
  EXPECT_TRUE(stats.effect("ambient_occlusion"));
  EXPECT_EQ(stats.counter("ao_samples"), 32 * stats.counter("shaded_pixels"));
  // The pixel of each sphere's front centre, and one just beside the contact.
  const auto pixelOf = [&](const Vec3d& x)
  {
    const std::array<double, 4> c = rays.clip(x);
    const int i = static_cast<int>((c[0] / c[3] + 1) * 0.5 * W),
              j = static_cast<int>((c[1] / c[3] + 1) * 0.5 * H);
    return static_cast<std::size_t>(j) * W + i;
  };
  // A convex sphere does not occlude itself: the outer halves, farther than aoRadius from
  // the other sphere, are unchanged.
  int outer = 0;
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      double z0, z1;
      for (const Sphere& s : pair)
      {
        if (raySphere(rays, i, j, s, z0, z1) &&
            std::abs(rays.pointAt(i + 0.5, j + 0.5, z0).x) > 0.5)
        {
          const std::size_t p = static_cast<std::size_t>(j) * W + i;
          EXPECT_FLOAT_EQ(on.rgba[4 * p], off.rgba[4 * p]) << i << " " << j;
          ++outer;
        }
      }
    }
  }
  EXPECT_GT(outer, 500);
  const std::size_t crevice = pixelOf({ -0.08, 0, 0.3 });
  ASSERT_EQ(on.rgba[4 * crevice + 3], 1.f);
  EXPECT_LT(on.rgba[4 * crevice], 0.85 * off.rgba[4 * crevice]);
  for (std::size_t p = 0; p < on.depth.size(); ++p)
  {
    EXPECT_LE(on.rgba[4 * p], off.rgba[4 * p] + 1e-6);
  }
}

TEST(SPHVoxelizer, RenderingHardCasesEmptyInsideAndNonFinite)
{
  FluidRenderParameters fp = litFluid();
  fp.refractiveIndex = 1.33;
  fp.ambientOcclusion = true;
  FluidSpans spans;
  Frame frame;
  RenderStatistics stats;
  // Empty input: an empty frame at the far plane.
  const ViewRays rays = perspectiveRays({ 0, 0, 5 }, { 0, 0, 0 }, 32, 24);
  ASSERT_TRUE(renderFluid({ makeParticles({}), spans }, viewOf(rays), fp, frame, stats));
  EXPECT_TRUE(std::all_of(frame.rgba.begin(), frame.rgba.end(), [](float v) { return v == 0.f; }));
  EXPECT_TRUE(
    std::all_of(frame.depth.begin(), frame.depth.end(), [](float v) { return v == 1.f; }));
  EXPECT_EQ(stats.counter("shaded_pixels"), 0);
  // The camera inside the fluid: every pixel sees fluid, nothing is NaN.
  const ViewRays inside = perspectiveRays({ 0.2, 0.1, 0.3 }, { 0, 0, -3 }, 32, 24, 0.05, 50, 60);
  stats.clear();
  ASSERT_TRUE(renderFluid({ makeParticles({ { { 0, 0, 0 }, 2.0 }, { { 0, 0, -3.5 }, 0.5 } }), spans }, viewOf(inside), fp, frame, stats));
  ASSERT_TRUE(frameFinite(frame));
  EXPECT_EQ(stats.counter("shaded_pixels"), 32 * 24);
  for (std::size_t p = 0; p < frame.depth.size(); ++p)
  {
    EXPECT_GT(frame.rgba[4 * p + 3], 0.f);
    EXPECT_LT(frame.depth[p], 1.f);
  }
  // Non-finite positions: skipped, counted, the rest rendered.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  stats.clear();
  ASSERT_TRUE(
    renderFluid({ makeParticles({ { { nan, 0, 0 }, 1 }, { { 0, 0, 0 }, 1 }, { { 0, nan, 0 }, 1 } }), spans }, viewOf(rays), fp, frame, stats));
  EXPECT_EQ(stats.counter("particles_skipped"), 2);
  EXPECT_GT(stats.counter("shaded_pixels"), 50);
  EXPECT_TRUE(frameFinite(frame));
}

namespace
{
/// A block of nx x ny x nz particles at spacing d (radius r) centred on the origin, without
/// those whose centre lies within `hole` of `holeCentre` (a bubble).
std::vector<Sphere> lattice(int nx,
  int ny,
  int nz,
  double d,
  double r,
  const Vec3d& holeCentre = Vec3d(),
  double hole = 0)
{
  std::vector<Sphere> out;
  for (int k = 0; k < nz; ++k)
  {
    for (int j = 0; j < ny; ++j)
    {
      for (int i = 0; i < nx; ++i)
      {
        const Vec3d c((i - 0.5 * (nx - 1)) * d, (j - 0.5 * (ny - 1)) * d, (k - 0.5 * (nz - 1)) * d);
        if (length(c - holeCentre) >= hole)
        {
          out.push_back({ c, r });
        }
      }
    }
  }
  return out;
}

/// Voxelizes with and without boundary-cell culling and expects the same spans, pixel by pixel
/// and slot by slot (the union of spheres is the same, so are its layers).
void expectCullingKeepsTheSpans(const FluidParticles& P, const ViewRays& rays, const char* what)
{
  FluidCells cells;
  buildFluidCells(P, 0, true, cells);
  VoxelizerParameters culled;
  culled.cells = &cells;
  FluidSpans a, b;
  RenderStatistics sa, sb;
  ASSERT_TRUE(voxelizeFluid(P, rays, VoxelizerParameters(), a, sa));
  ASSERT_TRUE(voxelizeFluid(P, rays, culled, b, sb));
  ASSERT_EQ(a.layers.count, b.layers.count) << what;
  EXPECT_LT(sb.counter("particles_in_view"), sa.counter("particles_in_view")) << what;
  EXPECT_GT(sb.counter("boxes_in_view"), 0) << what;
  int differing = 0;
  for (std::size_t p = 0; p < a.count.size(); ++p)
  {
    bool same = a.count[p] == b.count[p] && a.found[p] == b.found[p];
    for (int s = 0; same && s < 2 * a.count[p]; ++s)
    {
      same = a.depth[a.slot(p, 0) + s] == b.depth[b.slot(p, 0) + s];
    }
    differing += same ? 0 : 1;
  }
  EXPECT_EQ(differing, 0) << what;
  EXPECT_GT(sa.counter("spans_found"), 100) << what;
}
}

TEST(SPHVoxelizer, BoundaryCullingDropsInnerParticlesAndKeepsEverySpan)
{
  // Radius = spacing: the spheres cover the block, the inner cells are full.
  const std::vector<Sphere> block = lattice(24, 20, 16, 0.1, 0.1);
  const FluidParticles P = makeParticles(block);
  FluidCells cells;
  buildFluidCells(P, 0, true, cells);
  EXPECT_DOUBLE_EQ(cells.cellSize, 2 * 0.1f);
  EXPECT_GT(cells.innerCells, 0u);
  EXPECT_GT(cells.culledParticles, block.size() / 4);
  EXPECT_EQ(cells.kept.size() + cells.culledParticles, block.size());
  expectCullingKeepsTheSpans(P, perspectiveRays({ 3, 2, 4 }, { 0, 0, 0 }, 96, 72), "oblique");
  expectCullingKeepsTheSpans(P, orthographicRays({ 0, 1, 5 }, { 0, 0, 0 }, 96, 72, 1.5), "parallel");
  // The camera inside the block: the near plane cuts spheres and boxes alike.
  expectCullingKeepsTheSpans(
    P, perspectiveRays({ 0.03, 0.02, 0.1 }, { 1, 0.3, -2 }, 64, 48, 0.05, 50, 60), "inside");
}

TEST(SPHVoxelizer, BoundaryCullingKeepsABubbleInsideTheFluid)
{
  // A hole of radius 0.45 around the centre: the spheres leave a bubble of radius ~0.35, seen
  // through the fluid as a second span on the central pixels.
  const FluidParticles P = makeParticles(lattice(24, 24, 24, 0.1, 0.1, { 0, 0, 0 }, 0.45));
  FluidCells cells;
  buildFluidCells(P, 0, true, cells);
  EXPECT_GT(cells.culledParticles, 0u);
  const ViewRays rays = perspectiveRays({ 0.2, 0.3, 5 }, { 0, 0, 0 }, 64, 64);
  expectCullingKeepsTheSpans(P, rays, "bubble");
  FluidSpans spans;
  RenderStatistics stats;
  VoxelizerParameters vp;
  vp.cells = &cells;
  ASSERT_TRUE(voxelizeFluid(P, rays, vp, spans, stats));
  EXPECT_EQ(spans.count[spans.pixel(32, 32)], 2);
}

TEST(SPHVoxelizer, FluidCellsWithoutCullingKeepEveryParticleOnce)
{
  const std::vector<Sphere> block = lattice(10, 9, 8, 0.1, 0.1);
  const FluidParticles P = makeParticles(block);
  FluidCells cells;
  buildFluidCells(P, 0, false, cells);
  EXPECT_TRUE(cells.boxes.empty());
  EXPECT_EQ(cells.culledParticles, 0u);
  std::vector<std::uint32_t> sorted = cells.kept;
  std::sort(sorted.begin(), sorted.end());
  ASSERT_EQ(sorted.size(), block.size());
  for (std::size_t i = 0; i < sorted.size(); ++i)
  {
    ASSERT_EQ(sorted[i], i);
  }
}

TEST(SPHVoxelizer, SparseOrScatteredParticlesAreNotCulled)
{
  // Spheres of radius spacing / 3: they do not cover the cells, nothing is full.
  const FluidParticles sparse = makeParticles(lattice(12, 12, 12, 0.3, 0.1));
  FluidCells cells;
  buildFluidCells(sparse, 0, true, cells);
  EXPECT_EQ(cells.fullCells, 0u);
  EXPECT_EQ(cells.kept.size(), sparse.size());
  EXPECT_TRUE(cells.boxes.empty());
  // One particle a million units away: the grid stays a few cells per particle (larger
  // cells), and the culled voxelization still equals the plain one.
  std::vector<Sphere> far = lattice(16, 16, 16, 0.1, 0.1);
  far.push_back({ { 1e6, 0, 0 }, 0.1 });
  const FluidParticles P = makeParticles(far);
  buildFluidCells(P, 0, true, cells);
  EXPECT_GT(cells.cellSize, 0.2);
  EXPECT_EQ(cells.kept.size() + cells.culledParticles, far.size());
}

namespace
{
/// The layer of the depth table holding z (clamped to the layers).
int layerHolding(const VoxelDepthLayers& L, double z)
{
  const int l =
    static_cast<int>(std::upper_bound(L.depths.begin(), L.depths.end(), z) - L.depths.begin()) - 1;
  return std::clamp(l, 0, L.count - 1);
}

/// Pixel (i, j)'s spans against the union of its ray's intervals in the spheres (clipped to
/// the layers' range [lo, hi]): the voxelization covers, per interval, the layers from the
/// one holding its entry to the one holding its exit, and layers that touch make one span;
/// so the spans are the intervals merged where their layers touch, each entry at most one
/// layer before its interval's entry, each exit at most one layer after. Where an interval's
/// end lies within 1e-6 (relative) of a layer boundary, float and double may take either
/// layer: such a pixel is not checked and `ambiguous` counts it. Returns the analytic
/// spans.
std::vector<std::pair<double, double>> expectSpansOfUnion(const FluidSpans& spans,
  const ViewRays& rays,
  int i,
  int j,
  const std::vector<Sphere>& spheres,
  double lo,
  double hi,
  int& ambiguous)
{
  const VoxelDepthLayers& L = spans.layers;
  std::vector<std::pair<double, double>> merged;
  int lastLayer = -2;
  for (const auto& [a, b] : analyticIntervals(rays, i, j, spheres, lo, hi))
  {
    for (const double z : { a, b })
    {
      if (layerHolding(L, z * (1 - 1e-6)) != layerHolding(L, z * (1 + 1e-6)))
      {
        ++ambiguous;
        return {};
      }
    }
    if (layerHolding(L, a) <= lastLayer + 1)
    {
      merged.back().second = b;
    }
    else
    {
      merged.emplace_back(a, b);
    }
    lastLayer = layerHolding(L, b);
  }
  const std::size_t p = spans.pixel(i, j);
  EXPECT_EQ(spans.found[p], merged.size()) << i << " " << j;
  EXPECT_EQ(spans.count[p], std::min<std::size_t>(merged.size(), spans.maxSpans)) << i << " " << j;
  for (int k = 0; k < std::min<int>(spans.count[p], static_cast<int>(merged.size())); ++k)
  {
    const double a = merged[k].first, b = merged[k].second;
    EXPECT_LE(spans.entry(p, k), a + 1e-6 * a) << i << " " << j << " span " << k;
    EXPECT_LE(a - spans.entry(p, k), layerDepth(L, a) + 1e-6 * a) << i << " " << j << " span " << k;
    EXPECT_GE(spans.exit(p, k), b - 1e-6 * b) << i << " " << j << " span " << k;
    EXPECT_LE(spans.exit(p, k) - b, layerDepth(L, b) + 1e-6 * b) << i << " " << j << " span " << k;
  }
  return merged;
}
}

// A sheet one particle thick (spheres of radius 0.04 at spacing 0.05 in the plane z = 0,
// overlapping into a sheet without holes: a point of the plane is at most 0.035 from a
// centre), seen obliquely and almost edge-on: where a ray crosses the sheet it meets a few
// spheres in turn, their union along the ray one piece or several with gaps between them.
// Every pixel's spans are the analytic ones (expectSpansOfUnion), up to 63 stored.
TEST(SPHVoxelizer, SheetOneParticleThick)
{
  std::vector<Sphere> sheet;
  for (int a = -10; a <= 10; ++a)
  {
    for (int b = -10; b <= 10; ++b)
    {
      sheet.push_back({ { 0.05 * a, 0.05 * b, 0.0 }, 0.04 });
    }
  }
  VoxelizerParameters vp;
  vp.maxSpans = 63;
  for (const Vec3d& eye : { Vec3d(0.8, 0.6, 1.5), Vec3d(0.3, 2.0, 0.12) })
  {
    const int W = 48, H = 48;
    const ViewRays rays = perspectiveRays(eye, { 0, 0, 0 }, W, H, 0.1, 100, 40);
    FluidSpans spans;
    RenderStatistics stats;
    ASSERT_TRUE(voxelize(sheet, rays, vp, spans, stats));
    int crossing = 0, several = 0, ambiguous = 0;
    for (int j = 0; j < H; ++j)
    {
      for (int i = 0; i < W; ++i)
      {
        const auto merged = expectSpansOfUnion(spans,
          rays,
          i,
          j,
          sheet,
          spans.layers.depths.front(),
          spans.layers.depths.back(),
          ambiguous);
        crossing += !merged.empty();
        several += merged.size() > 1;
      }
    }
    std::printf("sheet from (%g, %g, %g): %d pixels cross it, %d in several spans, %d ambiguous\n",
      eye.x,
      eye.y,
      eye.z,
      crossing,
      several,
      ambiguous);
    EXPECT_GT(crossing, 150);
    EXPECT_LE(ambiguous, W * H / 100);
  }
}

// A bubble: a spherical shell of 600 particles (radius 0.08, on a sphere of radius 0.5,
// spaced about 0.07: the wall has no holes) around empty space. The central pixels' rays
// cross the front wall, the bubble and the back wall: two spans, the first ending at the
// wall's inner surface, the second starting at the far wall's; every pixel's spans are the
// analytic ones. Rendered translucent, a central pixel's opacity is 1 - mean_c
// exp(-kappa_c l) with l the walls' thickness along its ray, within the layers at the
// spans' ends.
TEST(SPHVoxelizer, BubbleIsASpanPerWall)
{
  const double R = 0.5, r = 0.08;
  std::vector<Sphere> shell;
  const int n = 600;
  for (int k = 0; k < n; ++k)
  {
    const double z = 1 - (2 * k + 1.0) / n, rho = std::sqrt(1 - z * z);
    const double phi = 2.39996323 * k;
    shell.push_back({ Vec3d(rho * std::cos(phi), rho * std::sin(phi), z) * R, r });
  }
  const int W = 48, H = 48;
  const ViewRays rays = perspectiveRays({ 0.3, 0.4, 2.5 }, { 0, 0, 0 }, W, H, 0.1, 100, 40);
  FluidSpans spans;
  RenderStatistics stats;
  ASSERT_TRUE(voxelize(shell, rays, VoxelizerParameters(), spans, stats));
  int central = 0, ambiguous = 0;
  const double lo = spans.layers.depths.front(), hi = spans.layers.depths.back();
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const int before = ambiguous;
      const auto merged = expectSpansOfUnion(spans, rays, i, j, shell, lo, hi, ambiguous);
      const Vec3d a = rays.start(i + 0.5, j + 0.5), b = normalize(rays.direction(i + 0.5, j + 0.5));
      if (ambiguous == before && length(a - b * dot(a, b)) < 0.3) // well inside the bubble
      {
        ++central;
        EXPECT_EQ(merged.size(), 2u) << i << " " << j;
        EXPECT_EQ(spans.count[spans.pixel(i, j)], 2) << i << " " << j;
      }
    }
  }
  std::printf("bubble: %d central pixels with two spans, %d ambiguous\n", central, ambiguous);
  EXPECT_GT(central, 100);
  EXPECT_LE(ambiguous, W * H / 100);

  FluidRenderParameters fp = litFluid();
  Frame frame;
  stats.clear();
  ASSERT_TRUE(renderFluid({ makeParticles(shell), spans }, viewOf(rays), fp, frame, stats));
  EXPECT_TRUE(frameFinite(frame));
  int checked = 0;
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const Vec3d a = rays.start(i + 0.5, j + 0.5), b = rays.direction(i + 0.5, j + 0.5);
      if (length(a - normalize(b) * dot(a, normalize(b))) >= 0.3)
      {
        continue;
      }
      const int before = ambiguous;
      const auto merged = expectSpansOfUnion(spans, rays, i, j, shell, lo, hi, ambiguous);
      if (ambiguous != before)
      {
        continue;
      }
      double l = 0, slack = 0;
      for (const auto& [x, y] : analyticIntervals(rays, i, j, shell, lo, hi))
      {
        l += y - x;
      }
      for (const auto& [x, y] : merged)
      {
        slack += layerDepth(spans.layers, x) + layerDepth(spans.layers, y);
      }
      auto alpha = [&](double thickness)
      {
        double t = 0;
        for (int c = 0; c < 3; ++c)
        {
          t += std::exp(-fp.density * fp.absorptionColor[c] * thickness * length(b)) / 3;
        }
        return 1 - t;
      };
      const double A = frame.rgba[4 * frame.index(i, j) + 3];
      EXPECT_GE(A, alpha(l - slack) - 1e-6) << i << " " << j;
      EXPECT_LE(A, alpha(l + slack) + 1e-6) << i << " " << j;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

// The camera inside a block of 16^3 overlapping particles (radius = spacing 0.1: every
// point of the block is covered), the near plane 0.05 in front of the eye cutting spheres:
// every pixel's first span starts at the near plane, and all spans are the analytic ones;
// rendered with refraction and ambient occlusion, no NaN, and every pixel sees the fluid
// at the near plane (window depth 0).
TEST(SPHVoxelizer, CameraInsideAParticleFluid)
{
  const std::vector<Sphere> block = lattice(16, 16, 16, 0.1, 0.1);
  const int W = 40, H = 30;
  const double nearZ = 0.05;
  const ViewRays rays = perspectiveRays({ 0.03, 0.02, 0.1 }, { 1, 0.3, -2 }, W, H, nearZ, 50, 60);
  FluidSpans spans;
  RenderStatistics stats;
  ASSERT_TRUE(voxelize(block, rays, VoxelizerParameters(), spans, stats));
  EXPECT_NEAR(spans.layers.d0, nearZ, 1e-9);
  int ambiguous = 0;
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const std::size_t p = spans.pixel(i, j);
      ASSERT_GE(spans.count[p], 1);
      EXPECT_FLOAT_EQ(spans.entry(p, 0), static_cast<float>(nearZ)) << i << " " << j;
      expectSpansOfUnion(spans, rays, i, j, block, nearZ, spans.layers.depths.back(), ambiguous);
    }
  }
  std::printf("camera inside: %d of %d pixels ambiguous\n", ambiguous, W * H);
  EXPECT_LE(ambiguous, W * H / 100);
  FluidRenderParameters fp = litFluid();
  fp.refractiveIndex = 1.33;
  fp.ambientOcclusion = true;
  Frame frame;
  stats.clear();
  ASSERT_TRUE(renderFluid({ makeParticles(block), spans }, viewOf(rays), fp, frame, stats));
  EXPECT_TRUE(frameFinite(frame));
  for (std::size_t p = 0; p < frame.depth.size(); ++p)
  {
    EXPECT_GT(frame.rgba[4 * p + 3], 0.f);
    EXPECT_LT(frame.depth[p], 1e-6f);
  }
}

namespace
{
/// A material that shows the surface colour unlit (ambient 1, no diffuse or specular): the
/// frame's colour is the medium's model alone.
FluidRenderParameters unlitFluid()
{
  FluidRenderParameters fp = litFluid();
  fp.material = Material{ 1.0, 0.0, 0.0 };
  fp.color = { 1.0, 0.9, 0.8 };
  return fp;
}
}

TEST(SPHVoxelizer, TranslucentColourIsTheLightAGreyScatteringSlabSendsBack)
{
  // One sphere: along each pixel's chord l the medium absorbs kappa_c and scatters the grey
  // sigma = min_k kappa_k of the lit colour C back, so the pixel is the integral of
  // sigma C_c exp(-kappa_c t) over [0, l] (summed here with the midpoint rule, not the closed
  // form the renderer uses), its alpha 1 - mean_c exp(-kappa_c l).
  const Sphere s{ { 0, 0, 0 }, 1.0 };
  const int W = 48, H = 48;
  const ViewRays rays = perspectiveRays({ 0, 0, 4 }, { 0, 0, 0 }, W, H, 0.5, 20, 40);
  FluidRenderParameters fp = unlitFluid();
  for (const double density : { 0.3, 3.0 })
  {
    fp.density = density;
    const Vec3d kappa = fp.absorptionColor * density;
    const double sigma = std::min({ kappa.x, kappa.y, kappa.z });
    FluidSpans spans;
    Frame frame;
    RenderStatistics stats;
    ASSERT_TRUE(renderFluid({ makeParticles({ s }), spans }, viewOf(rays), fp, frame, stats));
    const int tested = forEachPixelOnSphere(rays, W, H, s,
      [&](int i, int j, double z0, double z1, double len)
      {
        const double chord = (z1 - z0) * len;
        // The voxelized chord is within a layer of the exact one at each end.
        const double slack = (layerDepth(spans.layers, z0) + layerDepth(spans.layers, z1)) * len;
        const float* px = &frame.rgba[4 * frame.index(i, j)];
        for (int c = 0; c < 3; ++c)
        {
          double sum = 0;
          const int steps = 2000;
          for (int k = 0; k < steps; ++k)
          {
            sum += sigma * fp.color[c] * std::exp(-kappa[c] * chord * (k + 0.5) / steps);
          }
          const double expected = sum * chord / steps;
          EXPECT_NEAR(px[c], expected, sigma * slack + 1e-4) << i << " " << j << " " << c;
        }
      });
    EXPECT_GT(tested, 300);
  }
  // Seen through 2 radii of water at the default absorption (0.8, 0.35, 0.15) per unit and
  // density 3, white light comes back blue (the channel water absorbs least), not orange.
  fp.color = { 1, 1, 1 };
  FluidSpans spans;
  Frame frame;
  RenderStatistics stats;
  ASSERT_TRUE(renderFluid({ makeParticles({ s }), spans }, viewOf(rays), fp, frame, stats));
  const float* centre = &frame.rgba[4 * frame.index(W / 2, H / 2)];
  EXPECT_GT(centre[2], 1.5f * centre[1]);
  EXPECT_GT(centre[1], 1.5f * centre[0]);
  // Grey absorption: the albedo is 1 and the body is C (1 - T), white here: its alpha.
  fp.absorptionColor = { 0.5, 0.5, 0.5 };
  ASSERT_TRUE(renderFluid({ makeParticles({ s }), spans }, viewOf(rays), fp, frame, stats));
  const double alpha = frame.rgba[4 * frame.index(W / 2, H / 2) + 3];
  EXPECT_GT(alpha, 0.9);
  for (int c = 0; c < 3; ++c)
  {
    EXPECT_NEAR(frame.rgba[4 * frame.index(W / 2, H / 2) + c], alpha, 1e-6) << c;
  }
}

TEST(SPHVoxelizer, ParticleColoursAreTheNormalizedKernelAverageAtTheFrontSurface)
{
  // A block of particles, red for x < 0 and blue beyond, drawn opaque and unlit: each pixel
  // shows the colour at its front surface point p, against a brute-force reference that
  // intersects every sphere and sums every particle's Wendland C2 weight
  // (1 - q)^4 (1 + 4q), q = |p - x_i| / (2 r_i) (the same r for all here).
  std::vector<Sphere> block;
  const double spacing = 0.1, r = 0.1;
  for (int a = -6; a < 6; ++a)
    for (int b = -3; b <= 3; ++b)
      for (int c = -3; c <= 3; ++c)
        block.push_back({ { (a + 0.5) * spacing, b * spacing, c * spacing }, r });
  const FluidParticles P = makeParticles(block);
  FluidColors colors;
  buildFluidColors(
    P,
    [&](std::uint32_t id) { return block[id].c.x < 0 ? Vec3d(1, 0, 0) : Vec3d(0, 0, 1); },
    colors);
  FluidRenderParameters fp = unlitFluid();
  fp.translucency = false;
  fp.colors = &colors;
  fp.colorParticles = &P;
  const int W = 96, H = 64;
  const ViewRays rays = perspectiveRays({ 0.1, 0.2, 3 }, { 0, 0, 0 }, W, H, 0.5, 20, 30);
  FluidSpans spans;
  Frame frame;
  RenderStatistics stats;
  ASSERT_TRUE(renderFluid({ P, spans }, viewOf(rays), fp, frame, stats));
  EXPECT_TRUE(stats.effect("particle_colors"));
  EXPECT_GT(stats.counter("color_samples"), stats.counter("shaded_pixels"));
  int tested = 0, red = 0, blue = 0;
  double maxError = 0;
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const auto iv = analyticIntervals(rays, i, j, block, 0, 1e30);
      if (iv.empty() || frame.rgba[4 * frame.index(i, j) + 3] == 0.f)
      {
        continue;
      }
      const Vec3d p = rays.pointAt(i + 0.5, j + 0.5, iv.front().first);
      Vec3d sum;
      double weights = 0;
      for (const Sphere& s : block)
      {
        const double q = length(p - s.c) / (2 * s.r);
        const double w = q < 1 ? std::pow(1 - q, 4) * (1 + 4 * q) : 0.0;
        sum += (s.c.x < 0 ? Vec3d(1, 0, 0) : Vec3d(0, 0, 1)) * w;
        weights += w;
      }
      const Vec3d ref = sum * (1 / weights);
      const float* px = &frame.rgba[4 * frame.index(i, j)];
      for (int c = 0; c < 3; ++c)
      {
        maxError = std::max(maxError, std::abs(px[c] - ref[c]));
      }
      ++tested;
      red += px[0] > 0.99f && p.x < -0.25;
      blue += px[2] > 0.99f && p.x > 0.25;
    }
  }
  EXPECT_GT(tested, 1000);
  EXPECT_GT(red, 200);
  EXPECT_GT(blue, 200);
  // The front point is the voxel layer's, within a layer of the exact one.
  EXPECT_LT(maxError, 0.05);
  // Without colours nothing is looked up.
  fp.colors = nullptr;
  stats.clear();
  ASSERT_TRUE(renderFluid({ P, spans }, viewOf(rays), fp, frame, stats));
  EXPECT_FALSE(stats.effect("particle_colors"));
  EXPECT_EQ(stats.counter("color_samples"), 0);
}
