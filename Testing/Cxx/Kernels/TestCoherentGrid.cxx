// The coherent grid traversal against a brute-force reference (every sphere at every
// pixel, in double) and against Embree, on random scenes and on the method's hard cases.
#include "CameraFixtures.h"
#include "CoherentGridAccelerator.h"
#include "EmbreeSphereAccelerator.h"
#include "SphereReference.h"
#include "SphereRenderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <string>

using namespace raymappers;
using namespace raymappers::test;

namespace
{
SphereSet makeSet(const std::vector<Vec3d>& p, const std::vector<double>& r, const Vec3d& origin)
{
  SphereSet s;
  buildSphereSet(
    p.size(),
    origin,
    [&](std::size_t i) { return p[i]; },
    [&](std::size_t i) { return r[i]; },
    [](std::size_t i) { return packRGBA8(i % 256, (7 * i) % 256, (13 * i) % 256, 255); },
    s);
  return s;
}

struct Rendered
{
  Frame frame;
  RenderStatistics stats;
};

Rendered renderGrid(SphereSet& s,
  const RayCamera& cam,
  int packet,
  double lambda = 1.0,
  SimdPath simd = SimdPath::Auto)
{
  CoherentGridAccelerator grid;
  grid.setSimdPath(simd);
  CoherentGridParameters params;
  params.lambda = lambda;
  grid.build(s, params);
  Rendered out;
  renderSpheres(s, grid, packet, cam, SphereShading{}, 32, out.frame, out.stats);
  return out;
}

// The brute-force hit of pixel (i, j)'s ray, its normal, and where the renderer starts
// secondary rays (just above the surface); -1 when the ray misses or grazes a sphere.
int referenceHit(const SphereSet& s,
  const RayCamera& cam,
  int i,
  int j,
  Vec3d& hit,
  Vec3d& n,
  Vec3d& start)
{
  const Ray ray = cam.pixelRay(i, j);
  double t, margin;
  const int id = bruteForce(s, ray, t, margin);
  if (id < 0 || margin < 1e-3)
  {
    return -1;
  }
  hit = Vec3d(ray.org) + Vec3d(ray.dir) * t;
  n = normalize(hit - Vec3d(s.centers[static_cast<std::size_t>(id)]));
  start = hit + n * (1e-4 * s.radii[static_cast<std::size_t>(id)]);
  return id;
}

// Renders with the coherent grid (which == 0) or Embree (which == 1).
void renderWith(int which,
  SphereSet& s,
  const RayCamera& cam,
  const SphereShading& shading,
  Frame& f,
  RenderStatistics& stats)
{
  CoherentGridAccelerator grid;
  EmbreeSphereAccelerator bvh;
  if (which == 0)
  {
    grid.build(s, CoherentGridParameters{});
  }
  else
  {
    bvh.build(s);
  }
  const SphereAccelerator& accel = which == 0 ? static_cast<const SphereAccelerator&>(grid) : bvh;
  renderSpheres(s, accel, 8, cam, shading, 16, f, stats);
}

Rendered renderEmbree(const SphereSet& s, const RayCamera& cam)
{
  EmbreeSphereAccelerator bvh;
  bvh.build(s);
  Rendered out;
  renderSpheres(s, bvh, 4, cam, SphereShading{}, 32, out.frame, out.stats);
  return out;
}

// Every pixel whose ray does not graze a sphere: same hit or miss as the brute force, the
// same depth to 1e-5 relative, the colour of the sphere hit.
void expectExact(const SphereSet& s, const RayCamera& cam, const Frame& f, const char* what)
{
  int checked = 0, mismatches = 0;
  for (int j = 0; j < cam.height(); ++j)
  {
    for (int i = 0; i < cam.width(); ++i)
    {
      const Ray ray = cam.pixelRay(i, j);
      double t, margin;
      const int id = bruteForce(s, ray, t, margin);
      if (margin < 1e-4)
      {
        continue;
      }
      ++checked;
      const std::size_t k = f.index(i, j);
      const bool hit = f.rgba[4 * k + 3] > 0;
      if (hit != (id >= 0))
      {
        ++mismatches;
        continue;
      }
      if (id >= 0)
      {
        const double expected = cam.depthMap(ray).depthOf(t);
        if (std::fabs(f.depth[k] - expected) > 1e-5 * std::max(1e-3, expected))
        {
          ++mismatches;
        }
      }
    }
  }
  EXPECT_EQ(mismatches, 0) << what << " (" << checked << " pixels checked)";
  EXPECT_GT(checked, cam.width() * cam.height() / 2) << what;
}

RayCamera perspectiveCamera(const Vec3d& eye,
  const Vec3d& at,
  const Vec3d& origin,
  int w = 96,
  int h = 80,
  double n = 0.5,
  double f = 200)
{
  return RayCamera(
    multiply(perspective(40, double(w) / h, n, f), lookAt(eye, at, { 0, 1, 0 })), w, h, origin);
}

std::vector<Vec3d> randomPoints(int n, double extent, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-extent, extent);
  std::vector<Vec3d> p(n);
  for (auto& q : p)
  {
    q = { u(rng), u(rng), u(rng) };
  }
  return p;
}
}

TEST(CoherentGrid, EverySphereInTheCellOfItsCentre)
{
  const auto p = randomPoints(5000, 10, 3);
  SphereSet s = makeSet(p, std::vector<double>(p.size(), 0.2), {});
  CoherentGrid grid;
  CoherentGridParameters params;
  grid.build(s, params);
  const auto& d = grid.dims();
  const double cells = double(d[0]) * d[1] * d[2];
  EXPECT_GT(cells, 0.5 * p.size());
  EXPECT_LT(cells, 2.5 * p.size());
  std::vector<std::uint32_t> ids = s.sourceIds;
  std::sort(ids.begin(), ids.end());
  for (std::size_t i = 0; i < ids.size(); ++i)
  {
    ASSERT_EQ(ids[i], i); // a permutation of the input
  }
  std::size_t total = 0;
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
      {
        const auto c = grid.cellIndex(i, j, k);
        for (auto id = grid.cellBegin(c); id < grid.cellEnd(c); ++id)
        {
          const auto cell = grid.cellOf(s.centers[id]);
          ASSERT_EQ(cell[0], i);
          ASSERT_EQ(cell[1], j);
          ASSERT_EQ(cell[2], k);
          ++total;
          // the permuted sphere is the input sphere it names
          const Vec3f expected(p[s.sourceIds[id]]);
          ASSERT_EQ(s.centers[id].x, expected.x);
        }
      }
  EXPECT_EQ(total, p.size());
  // grid overhead: one offset per cell and one count per macrocell
  EXPECT_LT(grid.memoryBytes(), 0.5 * p.size() * (sizeof(Vec3f) + 2 * sizeof(float)));
}

// The parallel counting sort keeps the input order inside each cell (so the build is the
// same for any number of threads), on enough spheres that every parallel loop splits, with
// about 20 spheres per cell.
TEST(CoherentGrid, ParallelBuildKeepsInputOrderInsideCells)
{
  const auto p = randomPoints(300000, 10, 5);
  SphereSet s = makeSet(p, std::vector<double>(p.size(), 0.01), {});
  CoherentGrid grid;
  CoherentGridParameters params;
  params.lambda = 0.05;
  grid.build(s, params);
  const auto& d = grid.dims();
  const std::int64_t cells = std::int64_t(d[0]) * d[1] * d[2];
  std::int64_t crowded = 0;
  for (std::int64_t c = 0; c < cells; ++c)
  {
    crowded += grid.cellEnd(c) - grid.cellBegin(c) > 1;
    for (auto id = grid.cellBegin(c); id + 1 < grid.cellEnd(c); ++id)
    {
      ASSERT_LT(s.sourceIds[id], s.sourceIds[id + 1]) << "cell " << c;
    }
  }
  EXPECT_GT(crowded, cells / 2);
  EXPECT_EQ(grid.cellEnd(cells - 1), p.size());
}

TEST(CoherentGrid, MatchesBruteForceForEveryPacketSize)
{
  const auto p = randomPoints(800, 6, 5);
  std::vector<double> r(p.size());
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> ur(0.1, 0.7);
  for (auto& x : r)
  {
    x = ur(rng);
  }
  for (int packet : { 1, 2, 4, 8, 16 })
  {
    SphereSet s = makeSet(p, r, { 0.3, -0.2, 0.1 });
    const RayCamera cam = perspectiveCamera({ 4, 6, 18 }, { 0, 0, 0 }, s.origin);
    const Rendered g = renderGrid(s, cam, packet);
    expectExact(s, cam, g.frame, ("packet " + std::to_string(packet)).c_str());
    if (packet > 1) // a single ray has no frustum to cull with
    {
      EXPECT_GT(g.stats.counter("culled"), 0);
    }
  }
}

namespace
{
// One SIMD path of the ray-sphere tests gives the brute-force image, with packets whose
// active rays are not a multiple of the vector width (padding lanes). A path this CPU (or a
// build without RAYMAPPERS_NATIVE) lacks is reported as skipped, not as passed.
void expectSimdPathMatchesBruteForce(SimdPath path)
{
  if (resolveSimdPath(path) != path)
  {
    GTEST_SKIP() << "this CPU has no " << simdPathName(path) << " path";
  }
  const auto p = randomPoints(1500, 6, 17);
  std::vector<double> r(p.size(), 0.3);
  for (int packet : { 3, 8, 16 })
  {
    SphereSet s = makeSet(p, r, { 0.3, -0.2, 0.1 });
    const RayCamera cam = perspectiveCamera({ 4, 6, 18 }, { 0, 0, 0 }, s.origin, 101, 77);
    const Rendered g = renderGrid(s, cam, packet, 1.0, path);
    expectExact(s,
      cam,
      g.frame,
      (std::string(simdPathName(path)) + " packet " + std::to_string(packet)).c_str());
  }
}
}

TEST(CoherentGrid, PortablePathMatchesBruteForce)
{
  expectSimdPathMatchesBruteForce(SimdPath::Portable);
}

TEST(CoherentGrid, Avx2PathMatchesBruteForce)
{
  expectSimdPathMatchesBruteForce(SimdPath::Avx2);
}

TEST(CoherentGrid, Avx512PathMatchesBruteForce)
{
  expectSimdPathMatchesBruteForce(SimdPath::Avx512);
}

TEST(CoherentGrid, SameImageAsEmbree)
{
  const auto p = randomPoints(2000, 8, 21);
  SphereSet s = makeSet(p, std::vector<double>(p.size(), 0.35), {});
  const RayCamera cam = perspectiveCamera({ -9, 5, 14 }, { 1, 0, 0 }, s.origin, 128, 96);
  const Rendered e = renderEmbree(s, cam);
  const Rendered g = renderGrid(s, cam, 8);
  int differ = 0;
  for (std::size_t k = 0; k < e.frame.depth.size(); ++k)
  {
    differ += (e.frame.rgba[4 * k + 3] > 0) != (g.frame.rgba[4 * k + 3] > 0) ? 1 : 0;
  }
  // only silhouette pixels, where float hit tests of two methods may disagree
  EXPECT_LE(differ, 3);
  EXPECT_EQ(e.stats.counter("rays"), g.stats.counter("rays"));
}

TEST(CoherentGridHardCases, RadiiOverThreeOrdersOfMagnitude)
{
  const auto p = randomPoints(600, 5, 13);
  std::vector<double> r(p.size());
  for (std::size_t i = 0; i < r.size(); ++i)
  {
    r[i] = std::pow(10.0, -3.0 + 3.0 * double(i % 7) / 6.0); // 0.001 .. 1
  }
  SphereSet s = makeSet(p, r, {});
  const RayCamera cam = perspectiveCamera({ 3, 2, 14 }, { 0, 0, 0 }, s.origin);
  expectExact(s, cam, renderGrid(s, cam, 8).frame, "radii 1e-3..1");
}

TEST(CoherentGridHardCases, AllSpheresInOneCell)
{
  const auto p = randomPoints(200, 2, 17);
  SphereSet s = makeSet(p, std::vector<double>(p.size(), 0.3), {});
  const RayCamera cam = perspectiveCamera({ 1, 2, 9 }, { 0, 0, 0 }, s.origin);
  const Rendered g = renderGrid(s, cam, 8, 0.01 / 200.0 * 0.001); // lambda tiny: one cell
  expectExact(s, cam, g.frame, "one cell");
}

TEST(CoherentGridHardCases, CentresOnCellAndMacrocellBoundaries)
{
  // A lattice of 16^3 points with spacing 1: lambda = 1 gives cells of side 1, so every
  // centre lies exactly on cell (and every 6th on macrocell) faces, and on the grid bounds.
  std::vector<Vec3d> p;
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 16; ++i)
        p.push_back({ double(i), double(j), double(k) });
  std::vector<double> r(p.size());
  for (std::size_t i = 0; i < r.size(); ++i)
  {
    r[i] = 0.15 + 0.3 * double(i % 3) / 2.0;
  }
  SphereSet s = makeSet(p, r, { 7.5, 7.5, 7.5 });
  const RayCamera cam = perspectiveCamera({ -6, 22, 30 }, { 7.5, 7.5, 7.5 }, s.origin);
  expectExact(s, cam, renderGrid(s, cam, 8).frame, "lattice on cell faces");
  // Axis-aligned view: rays travel exactly along the cell faces.
  const RayCamera aligned(
    multiply(orthographic(9, 9, 1, 60), lookAt({ 7.5, 7.5, 40 }, { 7.5, 7.5, 0 }, { 0, 1, 0 })),
    90,
    90,
    s.origin);
  expectExact(s, aligned, renderGrid(s, aligned, 8).frame, "lattice, parallel, axis aligned");
}

TEST(CoherentGridHardCases, CoincidentSpheres)
{
  std::vector<Vec3d> p = randomPoints(100, 3, 19);
  const std::vector<Vec3d> copy = p;
  p.insert(p.end(), copy.begin(), copy.end()); // every sphere twice
  SphereSet s = makeSet(p, std::vector<double>(p.size(), 0.4), {});
  const RayCamera cam = perspectiveCamera({ 2, 1, 12 }, { 0, 0, 0 }, s.origin);
  expectExact(s, cam, renderGrid(s, cam, 4).frame, "coincident");
}

TEST(CoherentGridHardCases, SphereContainingTheCamera)
{
  std::vector<Vec3d> p = randomPoints(100, 3, 23);
  p.push_back({ 0, 0, 8 }); // the eye is inside this sphere of radius 2
  std::vector<double> r(p.size(), 0.3);
  r.back() = 2.0;
  SphereSet s = makeSet(p, r, {});
  const RayCamera cam = perspectiveCamera({ 0, 0, 8 }, { 0, 0, 0 }, s.origin, 64, 64, 0.1, 50);
  const Rendered g = renderGrid(s, cam, 8);
  expectExact(s, cam, g.frame, "inside a sphere");
  EXPECT_EQ(g.stats.counter("hits"), 64 * 64); // every ray sees the inside
}

TEST(CoherentGridHardCases, FarFromTheOriginGivesTheSameImage)
{
  const auto p = randomPoints(500, 5, 29);
  std::vector<Vec3d> shifted = p;
  const Vec3d offset{ 1e6, -1e6, 1e6 };
  for (auto& q : shifted)
  {
    q = q + offset;
  }
  SphereSet a = makeSet(p, std::vector<double>(p.size(), 0.3), {});
  SphereSet b = makeSet(shifted, std::vector<double>(p.size(), 0.3), offset);
  const RayCamera ca = perspectiveCamera({ 3, 4, 15 }, { 0, 0, 0 }, a.origin);
  const RayCamera cb = perspectiveCamera(Vec3d(3, 4, 15) + offset, offset, b.origin);
  const Rendered fa = renderGrid(a, ca, 8);
  const Rendered fb = renderGrid(b, cb, 8);
  int differ = 0;
  double worst = 0;
  for (std::size_t k = 0; k < fa.frame.depth.size(); ++k)
  {
    differ += fa.frame.rgba[4 * k + 3] != fb.frame.rgba[4 * k + 3] ? 1 : 0;
    worst = std::max(worst, double(std::fabs(fa.frame.depth[k] - fb.frame.depth[k])));
  }
  EXPECT_LE(differ, 2); // silhouette pixels only
  EXPECT_LT(worst, 1e-5);
}

TEST(CoherentGridHardCases, OneAndZeroParticles)
{
  SphereSet one = makeSet({ { 1, 2, 3 } }, { 0.5 }, { 1, 2, 3 });
  const RayCamera cam = perspectiveCamera({ 1, 2, 8 }, { 1, 2, 3 }, one.origin, 48, 48);
  const Rendered g = renderGrid(one, cam, 8);
  expectExact(one, cam, g.frame, "one particle");
  EXPECT_GT(g.stats.counter("hits"), 0);
  SphereSet none = makeSet({}, {}, {});
  const Rendered z = renderGrid(none, cam, 8);
  EXPECT_EQ(z.stats.counter("hits"), 0);
}

TEST(CoherentGridHardCases, TangentRays)
{
  // Spheres placed so that rays through pixel centres of a parallel view touch them
  // tangentially (centre offset by exactly r from a pixel's ray).
  const RayCamera cam(
    multiply(orthographic(4, 4, 1, 30), lookAt({ 0, 0, 10 }, { 0, 0, 0 }, { 0, 1, 0 })),
    64,
    64,
    {});
  std::vector<Vec3d> p;
  std::vector<double> r;
  for (int i = 0; i < 8; ++i)
  {
    const Ray ray = cam.pixelRay(8 * i + 3, 20);
    p.push_back(Vec3d(ray.org.x + 0.25, ray.org.y, 0.0));
    r.push_back(0.25);
  }
  SphereSet s = makeSet(p, r, {});
  const Rendered g = renderGrid(s, cam, 8);
  const Rendered e = renderEmbree(s, cam);
  expectExact(s, cam, g.frame, "tangent (grid)");
  expectExact(s, cam, e.frame, "tangent (embree)");
}

TEST(ParameterRangeCulling, BothAcceleratorsDrawExactlyTheSpheresInRange)
{
  const auto p = randomPoints(1500, 6, 31);
  // attribute 0: the x coordinate; attribute 1: the index modulo 10
  auto withAttributes = [&](const std::vector<Vec3d>& pts)
  {
    SphereSet s = makeSet(pts, std::vector<double>(pts.size(), 0.3), {});
    setSphereAttributes(
      s, 2, [&](std::uint32_t id, int a) { return a == 0 ? pts[id].x : double(id % 10); });
    return s;
  };
  RangeFilter filter;
  filter.count = 2;
  filter.lo[0] = -2;
  filter.hi[0] = 3;
  filter.lo[1] = 0;
  filter.hi[1] = 6;
  std::vector<Vec3d> kept;
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    if (p[i].x >= -2 && p[i].x <= 3 && double(i % 10) <= 6)
    {
      kept.push_back(p[i]);
    }
  }
  const SphereSet reference = makeSet(kept, std::vector<double>(kept.size(), 0.3), {});
  const RayCamera cam = perspectiveCamera({ 2, 5, 16 }, { 0, 0, 0 }, {});

  SphereSet forGrid = withAttributes(p);
  CoherentGridAccelerator grid;
  grid.build(forGrid, CoherentGridParameters{});
  grid.setRangeFilter(filter);
  Rendered g;
  renderSpheres(forGrid, grid, 8, cam, SphereShading{}, 32, g.frame, g.stats);
  expectExact(reference, cam, g.frame, "grid with ranges");
  EXPECT_TRUE(g.stats.effect("range_culling"));
  EXPECT_GT(g.stats.counter("range_culled"), 0);

  SphereSet forEmbree = withAttributes(p);
  EmbreeSphereAccelerator bvh;
  bvh.build(forEmbree);
  bvh.setRangeFilter(filter);
  Rendered e;
  renderSpheres(forEmbree, bvh, 4, cam, SphereShading{}, 32, e.frame, e.stats);
  expectExact(reference, cam, e.frame, "embree with ranges");

  // No range: nothing culled, the effect is off, and every sphere is drawn again.
  grid.setRangeFilter(RangeFilter{});
  Rendered all;
  renderSpheres(forGrid, grid, 8, cam, SphereShading{}, 32, all.frame, all.stats);
  EXPECT_FALSE(all.stats.effect("range_culling"));
  EXPECT_EQ(all.stats.counter("range_culled"), 0);
  expectExact(forGrid, cam, all.frame, "grid without ranges");
}

TEST(AmbientOcclusion, MatchesBruteForceWithBothAccelerators)
{
  // Spheres packed closely: much of each visible point's hemisphere is blocked nearby.
  const auto p = randomPoints(400, 2.5, 37);
  const std::vector<double> r(p.size(), 0.35);
  const RayCamera cam = perspectiveCamera({ 1, 2, 9 }, { 0, 0, 0 }, {}, 48, 40);
  SphereShading shading; // unlit: the colour is the sphere's, times the unoccluded share
  shading.aoSamples = 16;
  shading.aoRadius = 1.0;
  for (int which = 0; which < 2; ++which)
  {
    SphereSet s = makeSet(p, r, {});
    Frame f;
    RenderStatistics stats;
    renderWith(which, s, cam, shading, f, stats);
    EXPECT_TRUE(stats.effect("ambient_occlusion"));
    EXPECT_EQ(stats.counter("ao_rays"), 16 * stats.counter("hits"));
    int checked = 0, darkened = 0;
    for (int j = 0; j < cam.height(); ++j)
    {
      for (int i = 0; i < cam.width(); ++i)
      {
        Vec3d hit, n, start;
        const int id = referenceHit(s, cam, i, j, hit, n, start);
        if (id < 0)
        {
          continue;
        }
        const std::size_t k = f.index(i, j);
        int occluded = 0;
        bool ambiguous = false;
        for (int a = 0; a < 16; ++a)
        {
          Ray probe;
          probe.org = Vec3f(start);
          probe.dir = Vec3f(aoDirection(n, a, 16, static_cast<std::uint32_t>(k)));
          probe.tnear = 0.f;
          probe.tfar = 1.0f;
          double tp, mp;
          const int blocker = bruteForce(s, probe, tp, mp);
          occluded += blocker >= 0 ? 1 : 0;
          ambiguous = ambiguous || mp < 1e-3 || (blocker >= 0 && std::fabs(tp - 1.0) < 1e-3);
        }
        if (ambiguous)
        {
          continue; // a probe grazes a sphere or ends on one: float and double may differ
        }
        ++checked;
        darkened += occluded > 0 ? 1 : 0;
        const std::uint32_t col = s.colors[static_cast<std::size_t>(id)];
        const double expected = (col & 0xFF) / 255.0 * (1.0 - occluded / 16.0);
        EXPECT_NEAR(f.rgba[4 * k], expected, 1e-5)
          << (which ? "embree" : "grid") << " " << i << "," << j;
      }
    }
    EXPECT_GT(checked, 200);
    EXPECT_GT(darkened, checked / 4); // the scene is dense enough for occlusion to show
  }
}

TEST(AmbientOcclusion, OffCostsNothing)
{
  SphereSet s = makeSet(randomPoints(100, 3, 41), std::vector<double>(100, 0.3), {});
  CoherentGridAccelerator grid;
  grid.build(s, CoherentGridParameters{});
  const RayCamera cam = perspectiveCamera({ 1, 2, 9 }, { 0, 0, 0 }, {}, 32, 32);
  Frame f;
  RenderStatistics stats;
  renderSpheres(s, grid, 8, cam, SphereShading{}, 16, f, stats);
  EXPECT_FALSE(stats.effect("ambient_occlusion"));
  EXPECT_EQ(stats.counter("ao_rays"), 0);
}

TEST(SoftShadows, MatchBruteForceWithBothAccelerators)
{
  // A cloud of spheres over a big "floor" sphere, lit by an area light above: the share
  // of each point's shadow rays that reach the light, brute-forced in double, must be the
  // renderer's.
  std::vector<Vec3d> p = randomPoints(120, 2.0, 43);
  std::vector<double> r(p.size(), 0.3);
  p.push_back({ 0, -30, 0 });
  r.push_back(27.0);
  const RayCamera cam = perspectiveCamera({ 2, 4, 12 }, { 0, -1, 0 }, {}, 48, 40);
  SphereShading shading;
  shading.material.ambient = 0.2;
  shading.material.diffuse = 0.8;
  shading.shadowSide = 3;
  shading.lightCenter = { 1, 8, 2 };
  shading.lightEdgeU = { 2, 0, 0 };
  shading.lightEdgeV = { 0, 0, 2 };
  shading.lightCenterWorld = shading.lightCenter; // identity model transform, origin 0
  for (int which = 0; which < 2; ++which)
  {
    SphereSet s = makeSet(p, r, {});
    Frame f;
    RenderStatistics stats;
    renderWith(which, s, cam, shading, f, stats);
    EXPECT_TRUE(stats.effect("soft_shadows"));
    EXPECT_EQ(stats.counter("shadow_rays"), 9 * stats.counter("hits"));
    int checked = 0, penumbra = 0, umbra = 0;
    for (int j = 0; j < cam.height(); ++j)
    {
      for (int i = 0; i < cam.width(); ++i)
      {
        Vec3d hit, n, start;
        const int id = referenceHit(s, cam, i, j, hit, n, start);
        if (id < 0)
        {
          continue;
        }
        const std::size_t k = f.index(i, j);
        int blocked = 0;
        bool ambiguous = false;
        for (int a = 0; a < 9; ++a)
        {
          const Vec3d q = shadowTarget(shading, a % 3, a / 3, static_cast<std::uint32_t>(k));
          Ray probe;
          probe.org = Vec3f(start);
          probe.dir = Vec3f(normalize(q - start));
          probe.tnear = 0.f;
          probe.tfar = static_cast<float>(length(q - start));
          double tp, mp;
          blocked += bruteForce(s, probe, tp, mp) >= 0 ? 1 : 0;
          ambiguous = ambiguous || mp < 1e-3;
        }
        if (ambiguous)
        {
          continue;
        }
        ++checked;
        penumbra += blocked > 0 && blocked < 9 ? 1 : 0;
        umbra += blocked == 9 ? 1 : 0;
        // unclamped Lambert toward the light's centre, times the visible share
        const std::uint32_t col = s.colors[static_cast<std::size_t>(id)];
        const double base = (col & 0xFF) / 255.0;
        const Vec3d l = normalize(shading.lightCenter - hit);
        const double direct = 0.8 * std::max(0.0, dot(n, l)) * base;
        const double expected = std::min(1.0, 0.2 * base + direct * (1.0 - blocked / 9.0));
        EXPECT_NEAR(f.rgba[4 * k], expected, 1e-5)
          << (which ? "embree" : "grid") << " " << i << "," << j;
      }
    }
    EXPECT_GT(checked, 300);
    EXPECT_GT(penumbra, 10); // the light's size gives soft edges
    EXPECT_GT(umbra, 10);
  }
}

TEST(SoftShadows, OffCostsNothing)
{
  SphereSet s = makeSet(randomPoints(100, 3, 47), std::vector<double>(100, 0.3), {});
  CoherentGridAccelerator grid;
  grid.build(s, CoherentGridParameters{});
  const RayCamera cam = perspectiveCamera({ 1, 2, 9 }, { 0, 0, 0 }, {}, 32, 32);
  Frame f;
  RenderStatistics stats;
  SphereShading lit;
  lit.lights.push_back(Light{});
  renderSpheres(s, grid, 8, cam, lit, 16, f, stats);
  EXPECT_FALSE(stats.effect("soft_shadows"));
  EXPECT_EQ(stats.counter("shadow_rays"), 0);
}
