// The coherent grid traversal against a brute-force reference (every sphere at every
// pixel, in double) and against Embree, on random scenes and on the method's hard cases.
#include "CameraFixtures.h"
#include "Mappers/CGT/CoherentGridAccelerator.h"
#include "Mappers/CGT/EmbreeSphereAccelerator.h"
#include "Mappers/CGT/RaySphereLanes.h"
#include "Mappers/CGT/SphereRenderer.h"
#include "SphereReference.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <iostream>
#include <limits>
#include <memory>
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
  renderSpheres({ s, grid }, viewOf(cam), { SphereShading{}, packet, 32 }, out.frame, out.stats);
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
  renderSpheres({ s, accel }, viewOf(cam), { shading, 8, 16 }, f, stats);
}

Rendered renderEmbree(const SphereSet& s, const RayCamera& cam)
{
  EmbreeSphereAccelerator bvh;
  bvh.build(s);
  Rendered out;
  renderSpheres({ s, bvh }, viewOf(cam), { SphereShading{}, 4, 32 }, out.frame, out.stats);
  return out;
}

// Every pixel: the same hit or miss as the brute force, the same depth to 1e-5 relative,
// except the pixels whose ray passes within the float band of a silhouette (grazingBand,
// where float arithmetic may legitimately decide either way); those must be rare.
void expectExact(const SphereSet& s, const RayCamera& cam, const Frame& f, const char* what)
{
  const double scene = sceneRadius(s);
  int checked = 0, mismatches = 0, grazing = 0;
  for (int j = 0; j < cam.height(); ++j)
  {
    for (int i = 0; i < cam.width(); ++i)
    {
      const Ray ray = cam.pixelRay(i, j);
      const ReferenceHit ref = exactHit(s, ray, scene);
      if (ref.bands < 1)
      {
        ++grazing;
        continue;
      }
      ++checked;
      const std::size_t k = f.index(i, j);
      const bool hit = f.rgba[4 * k + 3] > 0;
      if (hit != (ref.id >= 0))
      {
        ++mismatches;
        continue;
      }
      if (ref.id >= 0)
      {
        const double expected = cam.depthMap(ray).depthOf(ref.t);
        if (std::fabs(f.depth[k] - expected) > 1e-5 * std::max(1e-3, expected))
        {
          ++mismatches;
        }
      }
    }
  }
  EXPECT_EQ(mismatches, 0) << what << " (" << checked << " pixels checked)";
  EXPECT_LE(grazing, cam.width() * cam.height() / 100) << what;
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

std::vector<double> randomRadii(std::size_t n, double lo, double hi, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<double> r(n);
  for (auto& x : r)
  {
    x = u(rng);
  }
  return r;
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
  params.lambda = 1.0; // about one cell per sphere
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

// Far more z layers than the placement's slabs (about 256 runs of x rows): a slab holds
// many layers, and the spheres of a line along z still land in their own cells, in input
// order.
TEST(CoherentGrid, SlabsOfSeveralLayersPlaceEverySphere)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3d> p(60000);
  for (auto& q : p)
  {
    q = { 1e-4 * u(rng), 1e-4 * u(rng), 100.0 * u(rng) };
  }
  SphereSet s = makeSet(p, std::vector<double>(p.size(), 1e-3), {});
  CoherentGrid grid;
  grid.build(s, CoherentGridParameters());
  const auto& d = grid.dims();
  ASSERT_GT(d[2], 2 * 4096);
  std::size_t total = 0;
  for (int k = 0; k < d[2]; ++k)
  {
    const auto c = grid.cellIndex(0, 0, k);
    ASSERT_EQ(grid.cellBegin(c), total) << "layer " << k;
    for (auto id = grid.cellBegin(c); id < grid.cellEnd(c); ++id, ++total)
    {
      ASSERT_EQ(grid.cellOf(s.centers[id])[2], k);
      ASSERT_EQ(s.centers[id].z, Vec3f(p[s.sourceIds[id]]).z);
      if (id + 1 < grid.cellEnd(c))
      {
        ASSERT_LT(s.sourceIds[id], s.sourceIds[id + 1]);
      }
    }
  }
  EXPECT_EQ(total, p.size());
}

TEST(CoherentGrid, MatchesBruteForceForEveryPacketSize)
{
  const auto p = randomPoints(800, 6, 5);
  const std::vector<double> r = randomRadii(p.size(), 0.1, 0.7, 9);
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

// The ordered test (RayPacket::ordered) on 16 equal rays down the axis of coincident spheres
// of indices 7, 3, 9, met in that order: of the tie at t the lowest index wins, and from
// (t, tieFrom = 4) on the next one is 7, then 9, then none (a near root at tNear keeps it).
template<typename Lanes>
void expectOrderedTies()
{
  RayLanes L;
  for (int i = 0; i < 16; ++i)
  {
    L.ox[i] = L.oy[i] = 0.f;
    L.oz[i] = 10.f;
    L.dx[i] = L.dy[i] = 0.f;
    L.dz[i] = -1.f;
    L.tNear[i] = 0.f;
    L.tieFrom[i] = 0;
  }
  auto query = [&](std::uint32_t from, float tNear)
  {
    for (int i = 0; i < 16; ++i)
    {
      L.tNear[i] = tNear;
      L.tieFrom[i] = from;
      L.tBest[i] = 100.f;
      L.prim[i] = NoHit;
    }
    for (const std::uint32_t id : { 7u, 3u, 9u })
    {
      Lanes::template intersect<true>(L, 16, 0.f, 0.f, 0.f, 0.16f, id);
    }
    for (int i = 1; i < 16; ++i)
    {
      EXPECT_EQ(L.prim[i], L.prim[0]);
      EXPECT_EQ(L.tBest[i], L.tBest[0]);
    }
    return L.prim[0];
  };
  EXPECT_EQ(query(0, 0.f), 3u);
  const float t = L.tBest[0];
  EXPECT_FLOAT_EQ(t, 9.6f);
  EXPECT_EQ(query(4, t), 7u);
  EXPECT_EQ(query(8, t), 9u);
  EXPECT_EQ(query(10, t), NoHit);
  // Just past the near roots: the far roots' tie, again to the lowest index.
  EXPECT_EQ(query(0, std::nextafter(t, 1e30f)), 3u);
  EXPECT_FLOAT_EQ(L.tBest[0], 10.4f);
}

TEST(RaySphereLanes, OrderedTiesGoToTheLowestIndexOnEveryPath)
{
  expectOrderedTies<PortableLanes>();
#ifdef RAYMAPPERS_X86_SIMD
  if (resolveSimdPath(SimdPath::Avx2) == SimdPath::Avx2)
  {
    expectOrderedTies<Avx2Lanes>();
  }
  if (resolveSimdPath(SimdPath::Avx512) == SimdPath::Avx512)
  {
    expectOrderedTies<Avx512Lanes>();
  }
#endif
}

// Packets whose rays share no axis along which they all move the same way (rays from one
// point in every direction, as soft shadows toward a large light or secondary rays of a
// concave spot send), and packets where only one ray turns: each ray is then traversed on
// its own axis, and every lane must find the reference's closest hit (the lanes the grid
// would otherwise walk the wrong way along the chosen axis lose their hits).
TEST(CoherentGrid, PacketsWithoutACommonAxisMatchBruteForce)
{
  const auto p = randomPoints(3000, 10, 77);
  SphereSet s = makeSet(p, randomRadii(p.size(), 0.05, 0.5, 31), {});
  CoherentGridAccelerator grid;
  grid.build(s, CoherentGridParameters());
  int compared = 0, hit = 0;
  for (int side : { 2, 4, 8 })
  {
    for (int turned = 0; turned < 2; ++turned)
    {
      RayPacket packet;
      packet.side = side;
      packet.pixelBlock = false;
      const int n = side * side;
      const Vec3f o(0.5f, -0.25f, 0.75f);
      for (int a = 0; a < n; ++a)
      {
        // turned 0: directions over the whole sphere (golden spiral); 1: all near +x but
        // the last, which points back along -x.
        Vec3d d;
        if (turned == 0)
        {
          const double z = 1.0 - 2.0 * (a + 0.5) / n, phi = 2.399963229728653 * a;
          d = Vec3d(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z);
        }
        else
        {
          d = a + 1 < n ? Vec3d(1.0, 0.02 * (a % side), 0.03 * (a / side)) : Vec3d(-1, 0.1, 0.2);
        }
        packet.valid[a] = true;
        packet.rays[a] = Ray{ o, Vec3f(normalize(d)), 0.f, 40.f };
      }
      PacketHits hits;
      TraversalCounters counters;
      grid.intersect(packet, hits, counters);
      for (int a = 0; a < n; ++a)
      {
        const ReferenceHit ref = exactHit(s, packet.rays[a], 10.0);
        if (ref.bands < 1)
        {
          continue; // a grazed sphere before the hit: float may decide either way
        }
        ++compared;
        hit += ref.id >= 0 ? 1 : 0;
        const int got = hits.prim[a] == NoHit ? -1 : static_cast<int>(hits.prim[a]);
        EXPECT_EQ(got, ref.id) << "side " << side << ", turned " << turned << ", ray " << a;
      }
    }
  }
  EXPECT_GT(compared, 120);
  EXPECT_GT(hit, compared / 3); // most rays meet a sphere: the comparison sees hits
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

namespace
{
// Every pixel whose ray passes no sphere's silhouette within 1e-3 of that sphere's radius
// (where float and double decide alike at any scale, unlike grazingBand, which is absolute
// and so too wide for spheres much smaller than the scene): the same hit or miss as the
// brute force and the same depth to 1e-5 relative. Returns how many pixels hit.
int expectBruteForce(const SphereSet& s, const RayCamera& cam, const Frame& f, const char* what)
{
  int hits = 0, mismatches = 0, skipped = 0;
  for (int j = 0; j < cam.height(); ++j)
  {
    for (int i = 0; i < cam.width(); ++i)
    {
      const Ray ray = cam.pixelRay(i, j);
      double t, margin;
      const int id = bruteForce(s, ray, t, margin);
      if (margin < 1e-3)
      {
        ++skipped;
        continue;
      }
      const std::size_t k = f.index(i, j);
      if ((f.rgba[4 * k + 3] > 0) != (id >= 0))
      {
        ++mismatches;
        continue;
      }
      if (id >= 0)
      {
        ++hits;
        const double expected = cam.depthMap(ray).depthOf(t);
        mismatches += std::fabs(f.depth[k] - expected) > 1e-5 * std::max(1e-3, expected) ? 1 : 0;
      }
    }
  }
  EXPECT_EQ(mismatches, 0) << what;
  EXPECT_LE(skipped, cam.width() * cam.height() / 20) << what;
  return hits;
}

// n spheres uniformly in the cube of side `side` centred at c.
std::vector<Vec3d> cube(int n, const Vec3d& c, double side, unsigned seed)
{
  std::vector<Vec3d> p = randomPoints(n, 0.5 * side, seed);
  for (auto& q : p)
  {
    q = q + c;
  }
  return p;
}
}

// The hard cases of clustered data (the grid's cells follow the bounds of the centres, so
// these decide its resolution): every centre in one point, a cluster a millionth of the
// domain's size, a single far outlier.
TEST(CoherentGridHardCases, AllParticlesInOnePoint)
{
  const Vec3d point{ 0.25, -0.5, 1.0 };
  const std::vector<Vec3d> p(1000, point);
  std::vector<double> r(p.size());
  for (std::size_t i = 0; i < r.size(); ++i)
  {
    r[i] = 0.1 + 0.4 * double(i % 10) / 9.0; // concentric shells of 0.1 to 0.5
  }
  r[r.size() / 2] = 0.6; // the outermost shell once, in the middle of its cell's spheres
  SphereSet s = makeSet(p, r, {});
  const RayCamera cam = perspectiveCamera(point + Vec3d(0.3, 0.2, 3), point, s.origin, 64, 64);
  EXPECT_GT(expectBruteForce(s, cam, renderGrid(s, cam, 8).frame, "one point"), 64 * 64 / 20);
  EXPECT_GT(expectBruteForce(s, cam, renderEmbree(s, cam).frame, "one point, Embree"), 0);
}

TEST(CoherentGridHardCases, ClusterOfAMillionthOfTheDomain)
{
  // 2000 spheres across a domain of side 2 and 1000 in a cube of side 2e-6 (radius 1e-7, so
  // they touch), the cluster at the set's origin so its float coordinates resolve it.
  const Vec3d centre{ 0.2, 0.1, -0.3 };
  std::vector<Vec3d> p = cube(2000, { 0, 0, 0 }, 2.0, 31);
  std::vector<double> r(p.size(), 0.03);
  const std::vector<Vec3d> cluster = cube(1000, centre, 2e-6, 37);
  p.insert(p.end(), cluster.begin(), cluster.end());
  r.resize(p.size(), 1e-7);
  SphereSet s = makeSet(p, r, centre);
  const RayCamera far = perspectiveCamera({ 3, 2, 5 }, { 0, 0, 0 }, s.origin);
  EXPECT_GT(expectBruteForce(s, far, renderGrid(s, far, 8).frame, "cluster, far"), 0);
  // Up close: the cluster fills the view from 1e-5 away.
  const RayCamera close =
    perspectiveCamera(centre + Vec3d(2e-6, 1e-6, 1e-5), centre, s.origin, 64, 64, 2e-6, 5);
  EXPECT_GT(
    expectBruteForce(s, close, renderGrid(s, close, 8).frame, "cluster, close"), 64 * 64 / 10);
}

TEST(CoherentGridHardCases, FlatLayerOneCellThick)
{
  // 20,000 spheres in the plane z = 0 (a 2D crystal, as the LAMMPS crack): the grid is one
  // cell thick, so the placement's slabs and the macrocells split it along y only. Every
  // sphere in its cell, input order inside cells, and the image of the grid against the
  // brute force, seen at an angle.
  std::mt19937 rng(43);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3d> p(20000);
  for (auto& q : p)
  {
    q = { 3.0 * u(rng), 2.0 * u(rng), 0.0 };
  }
  SphereSet s = makeSet(p, std::vector<double>(p.size(), 0.008), {});
  CoherentGrid grid;
  grid.build(s, CoherentGridParameters());
  const auto& d = grid.dims();
  ASSERT_EQ(d[2], 1);
  ASSERT_GT(d[1], 64);
  std::size_t total = 0;
  for (int j = 0; j < d[1]; ++j)
    for (int i = 0; i < d[0]; ++i)
    {
      const auto c = grid.cellIndex(i, j, 0);
      ASSERT_EQ(grid.cellBegin(c), total) << "cell " << i << ", " << j;
      for (auto id = grid.cellBegin(c); id < grid.cellEnd(c); ++id, ++total)
      {
        const auto cell = grid.cellOf(s.centers[id]);
        ASSERT_EQ(cell[0], i);
        ASSERT_EQ(cell[1], j);
        ASSERT_EQ(s.centers[id].x, Vec3f(p[s.sourceIds[id]]).x);
        if (id + 1 < grid.cellEnd(c))
        {
          ASSERT_LT(s.sourceIds[id], s.sourceIds[id + 1]);
        }
      }
    }
  EXPECT_EQ(total, p.size());
  SphereSet t = makeSet(p, std::vector<double>(p.size(), 0.008), {});
  const RayCamera cam = perspectiveCamera({ 2.2, -1.0, 1.6 }, { 1.5, 1.0, 0 }, t.origin, 64, 64);
  EXPECT_GT(expectBruteForce(t, cam, renderGrid(t, cam, 8).frame, "flat layer"), 64 * 64 / 10);
}

TEST(CoherentGridHardCases, SingleFarOutlier)
{
  // 2000 spheres in a cube of side 2 and one 1e5 away: the centres' bounds, and so the
  // grid, stretch over the outlier.
  std::vector<Vec3d> p = cube(2000, { 0, 0, 0 }, 2.0, 41);
  p.push_back({ 1e5, 3, -2 });
  SphereSet s = makeSet(p, std::vector<double>(p.size(), 0.05), {});
  const RayCamera cam = perspectiveCamera({ 2, 1.5, 4 }, { 0, 0, 0 }, s.origin, 64, 64);
  EXPECT_GT(expectBruteForce(s, cam, renderGrid(s, cam, 8).frame, "outlier"), 64 * 64 / 10);
}

// The occupancy statistic behind the mapper's automatic choice of accelerator: the spheres
// of leaves (cells without a nested grid, and subcells) holding more than a limit, checked
// against counts known from the construction.
TEST(CoherentGridHardCases, CrowdedLeavesCountTheSpheresNoCellSeparates)
{
  auto crowded = [](SphereSet& s, std::uint32_t limit)
  {
    CoherentGrid grid;
    grid.build(s, CoherentGridParameters());
    return grid.spheresInLeavesAbove(limit);
  };
  // 1500 spheres in one point and 800 in another: only the first leaf is above 1024, and
  // "above" is strict.
  std::vector<Vec3d> p(1500, Vec3d{ 0.1, 0.2, 0.3 });
  p.insert(p.end(), 800, Vec3d{ 0.9, -0.4, 0.3 });
  SphereSet points = makeSet(p, std::vector<double>(p.size(), 0.05), {});
  EXPECT_EQ(crowded(points, 1024), 1500u);
  EXPECT_EQ(crowded(points, 1499), 1500u);
  EXPECT_EQ(crowded(points, 1500), 0u);
  EXPECT_EQ(crowded(points, 799), 2300u);
  // A dense cluster of small spheres in a wide domain: its top-level cells (side about 0.1)
  // hold hundreds each, but their nested grids separate them (a count of cells rather than
  // leaves finds them). One level only: a cluster ten times smaller than a cell would stay
  // in a few subcells.
  std::vector<Vec3d> q = cube(2000, { 0, 0, 0 }, 2.0, 43);
  const std::vector<Vec3d> dense = cube(5000, { 0.3, 0.3, 0.3 }, 0.1, 47);
  q.insert(q.end(), dense.begin(), dense.end());
  std::vector<double> r(2000, 0.01);
  r.resize(q.size(), 1e-4);
  SphereSet separable = makeSet(q, r, {});
  EXPECT_EQ(crowded(separable, 1024), 0u);
  // The same cluster a thousand times smaller than its spheres' radius: no subcell may be
  // smaller than half a radius, so one leaf keeps the whole cluster.
  const std::vector<Vec3d> tight = cube(3000, { 0.3, 0.3, 0.3 }, 2e-6, 53);
  q.resize(2000);
  q.insert(q.end(), tight.begin(), tight.end());
  r.assign(2000, 0.01);
  r.resize(q.size(), 1e-3);
  SphereSet inseparable = makeSet(q, r, {});
  EXPECT_EQ(crowded(inseparable, 1024), 3000u);
  // Uniform spheres: no leaf comes near the limit.
  const std::vector<Vec3d> u = randomPoints(20000, 1.0, 59);
  SphereSet uniform = makeSet(u, std::vector<double>(u.size(), 0.01), {});
  EXPECT_EQ(crowded(uniform, 64), 0u);
}

TEST(CoherentGridHardCases, NestedCellWithANearerSphereBehindItsFrontLayer)
{
  // A crowded cell (a closed sheet of small spheres inside a sparse frame of eight) is nested;
  // bigger spheres centred just behind the sheet bulge in front of it. A ray that hits the
  // sheet first in its sub-slice must still find the bigger sphere of a later sub-slice: the
  // nested walk may stop only once hits lie before the next sub-slice minus the cell's
  // largest radius.
  std::vector<Vec3d> p;
  std::vector<double> r;
  for (int i = 0; i < 8; ++i)
  {
    p.push_back({ i & 1 ? 5.0 : -5.0, i & 2 ? 5.0 : -5.0, i & 4 ? 5.0 : -5.0 });
    r.push_back(0.01);
  }
  for (int j = 0; j < 50; ++j)
    for (int i = 0; i < 50; ++i)
    {
      p.push_back({ 0.01 + 0.02 * i, 0.01 + 0.02 * j, 0.5 });
      r.push_back(0.015); // overlapping: the sheet is closed
    }
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 5; ++i)
    {
      p.push_back({ 0.1 + 0.2 * i, 0.1 + 0.2 * j, 0.42 }); // front surface at 0.52
      r.push_back(0.1);
    }
  SphereSet s = makeSet(p, r, { 0.5, 0.5, 0.5 });
  {
    SphereSet copy = s;
    CoherentGridAccelerator grid;
    grid.build(copy, CoherentGridParameters{});
    EXPECT_GT(grid.grid().nestedCellCount(), 0u);
  }
  const RayCamera cam = perspectiveCamera({ 0.5, 0.5, 2.5 }, { 0.5, 0.5, 0.5 }, s.origin, 96, 96);
  EXPECT_GT(expectBruteForce(s, cam, renderGrid(s, cam, 8).frame, "sheet"), 96 * 96 / 10);
}

namespace
{
// The closest hits of every pixel's ray of `cam`, traced in side x side blocks of pixels.
struct Traced
{
  std::vector<std::uint32_t> prim;
  std::vector<float> t;
};

Traced traceAll(const SphereAccelerator& accel, const RayCamera& cam, int side)
{
  const int w = cam.width(), h = cam.height();
  Traced out;
  out.prim.assign(static_cast<std::size_t>(w) * h, NoHit);
  out.t.assign(out.prim.size(), 0.f);
  RayPacket packet;
  packet.side = side;
  PacketHits hits;
  TraversalCounters counters;
  for (int by = 0; by < h; by += side)
  {
    for (int bx = 0; bx < w; bx += side)
    {
      for (int k = 0; k < side * side; ++k)
      {
        const int i = bx + k % side, j = by + k / side;
        packet.valid[k] = i < w && j < h;
        if (packet.valid[k])
        {
          packet.rays[k] = cam.pixelRay(i, j);
        }
      }
      accel.intersect(packet, hits, counters);
      for (int k = 0; k < side * side; ++k)
      {
        if (packet.valid[k])
        {
          const std::size_t p = static_cast<std::size_t>(by + k / side) * w + bx + k % side;
          out.prim[p] = hits.prim[k];
          out.t[p] = hits.t[k];
        }
      }
    }
  }
  return out;
}

// One accelerator of the grazing cases: the coherent grid on one SIMD path with lambda
// cells per sphere (1, or 64 so that r_max spans cells), or Embree (lambda 0). It keeps
// its accelerator from scene to scene (an Embree device per scene would dominate).
class Tracer
{
public:
  Tracer(SimdPath simd, double lambda)
    : Lambda(lambda)
    , Name(lambda > 0 ? std::string("grid ") + simdPathName(simd) + " lambda " +
                          std::to_string(static_cast<int>(lambda))
                      : std::string("embree"))
  {
    Grid.setSimdPath(simd);
  }
  const std::string& name() const { return Name; }
  /// Builds over `s` (the grid permutes it: hits and t, not ids, are compared).
  const SphereAccelerator& build(SphereSet& s)
  {
    if (Lambda > 0)
    {
      CoherentGridParameters params;
      params.lambda = Lambda;
      Grid.build(s, params);
      return Grid;
    }
    Bvh.build(s);
    return Bvh;
  }

private:
  double Lambda;
  std::string Name;
  CoherentGridAccelerator Grid;
  EmbreeSphereAccelerator Bvh;
};

// Every SIMD path of the grid this CPU has, each with lambda 1 and 64, and Embree.
std::vector<std::unique_ptr<Tracer>> allTracers()
{
  std::vector<std::unique_ptr<Tracer>> out;
  for (const SimdPath path : { SimdPath::Portable, SimdPath::Avx2, SimdPath::Avx512 })
  {
    if (resolveSimdPath(path) != path)
    {
      std::cout << "this CPU has no " << simdPathName(path)
                << " path (its CoherentGrid.*PathMatchesBruteForce test reports the skip)\n";
      continue;
    }
    for (const double lambda : { 1.0, 64.0 })
    {
      out.push_back(std::make_unique<Tracer>(path, lambda));
    }
  }
  out.push_back(std::make_unique<Tracer>(SimdPath::Auto, 0.0));
  return out;
}

// How far a ray is from grazing: the power of ten nearest to |d - r| / r, 1 (1e-1) to 7
// (1e-7), 8 for 3e-8 and below (tangent up to rounding).
int grazingDecade(double relative)
{
  return relative > 0 ? std::clamp(static_cast<int>(std::lround(-std::log10(relative))), 1, 8) : 8;
}

// Per decade of |d - r| / r: the grazing rays, those in the float band, and those whose
// float hit or miss differs from the exact one.
struct GrazingTally
{
  int rays[9] = {}, inBand[9] = {}, differ[9] = {};
  void print(const std::string& what) const
  {
    std::cout << what << ", |d - r| / r ~ 1e-1 ... 1e-7, 0: rays/in band/differ:";
    for (int e = 1; e <= 8; ++e)
    {
      std::cout << " " << rays[e] << "/" << inBand[e] << "/" << differ[e];
    }
    std::cout << "\n";
  }
};

// The exact hit of every pixel's ray (exactHit), row by row.
std::vector<ReferenceHit> exactHits(const SphereSet& s, const RayCamera& cam)
{
  const double scene = sceneRadius(s);
  std::vector<ReferenceHit> ref;
  for (int j = 0; j < cam.height(); ++j)
  {
    for (int i = 0; i < cam.width(); ++i)
    {
      ref.push_back(exactHit(s, cam.pixelRay(i, j), scene));
    }
  }
  return ref;
}

// A lit frame and the traced hits of `s` seen by `cam` through one tracer, checked against
// the exact hits `ref` (exactHits): no NaN or Inf in colour, depth and t; the frame's
// coverage is the traced hits; hit or miss as the exact one outside the float band (bands
// >= 1); a hit's float t within the stated tolerance. `grazing[p]` >= 0 marks a pixel to
// tally by how close it comes to grazing (its |d - r| / r).
void expectGrazingAgreement(Tracer& tracer,
  SphereSet s,
  const RayCamera& cam,
  int side,
  const std::vector<ReferenceHit>& ref,
  const std::vector<double>& grazing,
  GrazingTally& tally)
{
  const SphereAccelerator& accel = tracer.build(s);
  SphereShading lit;
  lit.lights.push_back(Light{});
  lit.material.ambient = 0.1;
  lit.material.specular = 0.5;
  lit.material.specularPower = 20;
  Frame frame;
  RenderStatistics stats;
  renderSpheres({ s, accel }, viewOf(cam), { lit, side, 32 }, frame, stats);
  const Traced traced = traceAll(accel, cam, side);
  int nonFinite = 0, renderDiffers = 0, outside = 0, tOff = 0;
  for (std::size_t p = 0; p < ref.size(); ++p)
  {
    const bool hit = traced.prim[p] != NoHit;
    for (int c = 0; c < 4; ++c)
    {
      nonFinite += !std::isfinite(frame.rgba[4 * p + c]);
    }
    nonFinite += !std::isfinite(frame.depth[p]) + !std::isfinite(traced.t[p]);
    renderDiffers += hit != (frame.rgba[4 * p + 3] > 0);
    const bool exact = ref[p].id >= 0;
    if (grazing[p] >= 0)
    {
      const int e = grazingDecade(grazing[p]);
      ++tally.rays[e];
      tally.inBand[e] += ref[p].bands < 1;
      tally.differ[e] += hit != exact;
    }
    if (hit != exact)
    {
      outside += ref[p].bands >= 1;
    }
    else if (hit && std::fabs(traced.t[p] - ref[p].t) > ref[p].tTolerance)
    {
      ++tOff;
    }
  }
  EXPECT_EQ(nonFinite, 0) << tracer.name();
  EXPECT_EQ(renderDiffers, 0) << tracer.name();
  EXPECT_EQ(outside, 0) << tracer.name() << " packet " << side;
  EXPECT_EQ(tOff, 0) << tracer.name() << " packet " << side;
}

// Signed offsets eps of the grazing rays: d = r (1 + eps), eps = +-1e-1 ... +-1e-7 and 0.
std::vector<double> grazingOffsets()
{
  std::vector<double> out;
  for (int e = 1; e <= 7; ++e)
  {
    out.push_back(std::pow(10.0, -e));
    out.push_back(-std::pow(10.0, -e));
  }
  out.push_back(0.0);
  return out;
}
}

// Rays grazing a sphere at d = r (1 + eps) where float arithmetic is exact: parallel rays
// along -z at dyadic x (or y), a sphere of radius 1/4 at the origin. Then f = o - c, b and
// p = f - b d are exact, r^2 = 1/16 is a float and rounding |p|^2 = x^2 keeps its order
// against it, and the packet's side planes (x or y = const) are exact: the grid must decide
// every ray exactly as the double reference does, the tangent ones (d = r) included (a
// hit: the test is closed, disc >= 0), on every SIMD path; Embree within the float band.
// Each ray sits in a corner, on an edge or inside its 8 x 8 packet (the others 1 apart, far
// from the sphere), the offset along +-x or +-y.
TEST(CoherentGridHardCases, GrazingRaysExactInExactArithmetic)
{
  const double r = 0.25;
  const SphereSet sphere = makeSet({ { 0, 0, 0 } }, { r }, {});
  const int lanes[] = { 0, 7, 63, 3, 24, 36, 45 }; // corners, edges, interior
  for (auto& tracer : allTracers())
  {
    SphereSet s = sphere;
    const SphereAccelerator& accel = tracer->build(s);
    const bool embree = tracer->name() == "embree";
    GrazingTally tally;
    int wrong = 0, outside = 0;
    for (const double eps : grazingOffsets())
    {
      for (const int lane : lanes)
      {
        for (int axis = 0; axis < 4; ++axis)
        {
          // The grazing ray at (x, y) = +-(r (1 + eps)) along x or y, rounded to float.
          const float off = static_cast<float>((axis < 2 ? 1 : -1) * r * (1 + eps));
          const float gx = axis % 2 == 0 ? off : 0.f, gy = axis % 2 == 0 ? 0.f : off;
          RayPacket packet;
          packet.side = 8;
          for (int k = 0; k < 64; ++k)
          {
            packet.valid[k] = true;
            Ray& ray = packet.rays[k];
            ray.org = Vec3f(gx + float(k % 8 - lane % 8), gy + float(k / 8 - lane / 8), 4.f);
            ray.dir = Vec3f(0.f, 0.f, -1.f);
            ray.tnear = 0.f;
            ray.tfar = 20.f;
          }
          PacketHits hits;
          TraversalCounters counters;
          accel.intersect(packet, hits, counters);
          for (int k = 0; k < 64; ++k)
          {
            const ReferenceHit ref = exactHit(s, packet.rays[k], sceneRadius(s));
            const bool hit = hits.prim[k] != NoHit;
            wrong += hit != (ref.id >= 0);
            outside += hit != (ref.id >= 0) && ref.bands >= 1;
            if (k == lane)
            {
              const double d = std::hypot(double(gx), double(gy));
              const int e = grazingDecade(std::fabs(d - r) / r);
              ++tally.rays[e];
              tally.inBand[e] += ref.bands < 1;
              tally.differ[e] += hit != (d <= r);
            }
          }
        }
      }
    }
    tally.print("exact arithmetic, " + tracer->name());
    // Embree's arithmetic is its own (a reciprocal of |d|^2, its own boxes): only the band
    // holds for it.
    EXPECT_EQ(embree ? outside : wrong, 0) << tracer->name();
    EXPECT_GT(tally.rays[8], 0); // tangent rays were tested
  }
}

// Grazing rays in general position: a sphere at the origin whose radius puts the ray of a
// chosen pixel of an oblique perspective view at d = r (1 + eps) (eps = +-1e-1 ... +-1e-7,
// 0: tangent in double, up to the radius's rounding to float), for pixels in corners, on
// edges and inside the 8 x 8 packets. Every pixel of each frame is checked
// (expectGrazingAgreement): outside the float band, at most 6e-5 r here (grazingBand with
// |o| ~ 2.7, S = r from 0.16 to 1.2), hit and miss are exact; inside it they are tallied.
// Then the same on 1024 spheres beside every second pixel's ray of a larger view, where the
// band is wider (many small spheres: S ~ 300 r, a band of 1.6e-3 r).
TEST(CoherentGridHardCases, GrazingRaysMatchDoubleReference)
{
  auto tracers = allTracers();
  const RayCamera cam = perspectiveCamera({ 1.2, 0.9, 2.4 }, { 0.1, 0, 0 }, {}, 16, 16, 0.1, 20);
  const int pixels[][2] = {
    { 0, 0 }, { 7, 3 }, { 8, 8 }, { 15, 12 }, { 3, 7 }, { 12, 0 }, { 4, 4 }, { 11, 15 }
  };
  std::vector<GrazingTally> tallies(tracers.size());
  double widestBand = 0; // relative to r
  for (const auto& px : pixels)
  {
    const Ray ray = cam.pixelRay(px[0], px[1]);
    const Vec3d o(ray.org), d(ray.dir);
    const double dist = length(o - d * dot(o, d)); // the ray's distance from the origin
    for (const double eps : grazingOffsets())
    {
      SphereSet s = makeSet({ { 0, 0, 0 } }, { dist / (1 + eps) }, {});
      widestBand = std::max(widestBand, grazingBand(ray, sceneRadius(s), s.radii[0]) / s.radii[0]);
      std::vector<double> grazing(16 * 16, -1.0);
      grazing[static_cast<std::size_t>(px[1]) * 16 + px[0]] =
        std::fabs(dist - s.radii[0]) / s.radii[0];
      const std::vector<ReferenceHit> ref = exactHits(s, cam);
      for (std::size_t k = 0; k < tracers.size(); ++k)
      {
        expectGrazingAgreement(*tracers[k], s, cam, 8, ref, grazing, tallies[k]);
      }
    }
  }
  std::cout << "one sphere: float band up to " << widestBand << " r\n";
  EXPECT_LT(widestBand, 1e-4); // so every ray with |d - r| >= 1e-4 r was asserted exact
  for (std::size_t k = 0; k < tracers.size(); ++k)
  {
    tallies[k].print("one sphere, " + tracers[k]->name());
  }

  // Many spheres: one beside the ray of every second pixel (in x and y) of a 64 x 64 view,
  // at t = 3 along it, offset perpendicularly in a direction turning by the golden angle,
  // radius a third of the pixel spacing there (so no other ray comes near it).
  const RayCamera wide = perspectiveCamera({ 1.2, 0.9, 2.4 }, { 0.1, 0, 0 }, {}, 64, 64, 0.1, 20);
  std::vector<Vec3d> centres;
  std::vector<double> radii;
  const std::vector<double> offsets = grazingOffsets();
  for (int j = 0; j < 64; j += 2)
  {
    for (int i = 0; i < 64; i += 2)
    {
      const Ray ray = wide.pixelRay(i, j);
      const Vec3d o(ray.org), d(ray.dir);
      const double spacing = length(
        Vec3d(wide.pixelRay(i + 1, j).org) - o + (Vec3d(wide.pixelRay(i + 1, j).dir) - d) * 3.0);
      const double r = spacing / 3;
      const Vec3d e1 = normalize(cross(d, Vec3d(0, 1, 0))), e2 = cross(d, e1);
      const double angle = 2.39996323 * double(centres.size());
      const double eps = offsets[centres.size() % offsets.size()];
      centres.push_back(
        o + d * 3.0 + (e1 * std::cos(angle) + e2 * std::sin(angle)) * (r * (1 + eps)));
      radii.push_back(r);
    }
  }
  SphereSet many = makeSet(centres, radii, {});
  // The grazing pixels' actual |d - r| / r on the float data (the others: -1).
  std::vector<double> grazing(64 * 64, -1.0);
  for (std::size_t n = 0; n < many.size(); ++n)
  {
    const int i = 2 * static_cast<int>(n % 32), j = 2 * static_cast<int>(n / 32);
    const Ray ray = wide.pixelRay(i, j);
    const Vec3d f = Vec3d(ray.org) - Vec3d(many.centers[n]), d(ray.dir);
    const double dist = length(f - d * dot(f, d));
    grazing[static_cast<std::size_t>(j) * 64 + i] = std::fabs(dist - many.radii[n]) / many.radii[n];
  }
  const std::vector<ReferenceHit> ref = exactHits(many, wide);
  for (auto& tracer : tracers)
  {
    for (const int side : { 1, 8, 16 })
    {
      GrazingTally tally;
      expectGrazingAgreement(*tracer, many, wide, side, ref, grazing, tally);
      if (side == 8)
      {
        tally.print("1024 spheres, " + tracer->name());
      }
    }
  }
}

// A picture full of silhouettes (2000 overlapping spheres), no pixel skipped: every pixel is
// tallied by how close its ray comes to grazing any sphere, and outside the float band the
// hit or miss must be exact (expectGrazingAgreement). The pixels inside the band are few:
// a sphere at distance D puts about 4 pi r band (f / D)^2 pixel centres within its band (f
// the focal length in pixels), summed below over all spheres (a bound: the band counts only
// spheres in front of the hit); the float decisions that differ from the exact ones can
// only be among them.
TEST(CoherentGridHardCases, SilhouettesWithoutSkipping)
{
  const auto p = randomPoints(2000, 8, 21);
  SphereSet s = makeSet(p, std::vector<double>(p.size(), 0.35), {});
  const Vec3d eye(-9, 5, 14);
  const RayCamera cam = perspectiveCamera(eye, { 1, 0, 0 }, s.origin, 128, 96);
  const std::vector<ReferenceHit> ref = exactHits(s, cam);
  std::vector<double> margin;
  int inBand = 0;
  for (const ReferenceHit& h : ref)
  {
    margin.push_back(h.margin);
    inBand += h.bands < 1;
  }
  const double focal = 96 / (2 * std::tan(20 * M_PI / 180));
  const double scene = sceneRadius(s);
  double expected = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
  {
    const double D = length(Vec3d(s.centers[i]) - eye), r = s.radii[i];
    const double band = 48 * FloatRoundoff * (length(eye) + scene + r);
    expected += 4 * M_PI * r * band * (focal / D) * (focal / D);
  }
  std::cout << "pixels in the float band: " << inBand << " (expected " << expected << ")\n";
  EXPECT_LE(inBand, 3 + 4 * expected);
  for (auto& tracer : allTracers())
  {
    GrazingTally tally;
    expectGrazingAgreement(*tracer, s, cam, 8, ref, margin, tally);
    tally.print("2000 spheres, every pixel, " + tracer->name());
    int differ = 0;
    for (int e = 1; e <= 8; ++e)
    {
      differ += tally.differ[e];
    }
    EXPECT_LE(differ, inBand) << tracer->name();
  }
}

// Spheres smaller than a pixel's footprint (radii 0.05 to 0.5 of the pixel spacing at their
// depth): each pixel's hit or miss is the exact one outside the float band, with every
// accelerator. A sphere that lies between pixel centres is missed, legitimately: the
// pixel centres the silhouettes cover (counted with multiplicity, hidden or not) number
// the sum of their areas in pixels, pi (r f / D)^2 / cos^3(theta) for a sphere at
// distance D and angle theta off the view axis (f the focal length in pixels), each
// covering at most one centre.
TEST(CoherentGridHardCases, SubPixelRadiiMatchDoubleReference)
{
  const Vec3d eye(3, 4, 9), at(0, 0, 0);
  const int W = 96, H = 80;
  const RayCamera cam = perspectiveCamera(eye, at, {}, W, H);
  const double focal = H / (2 * std::tan(20 * M_PI / 180));
  const auto p = randomPoints(2000, 2, 53);
  std::mt19937 rng(59);
  std::uniform_real_distribution<double> fraction(0.05, 0.5);
  std::vector<double> r;
  double expected = 0, variance = 0;
  for (const Vec3d& c : p)
  {
    const double D = length(c - eye);
    const double cosTheta = dot(c - eye, normalize(at - eye)) / D;
    r.push_back(fraction(rng) * D / focal);
    const double covered = M_PI * std::pow(r.back() * focal / D, 2) / std::pow(cosTheta, 3);
    expected += covered;
    variance += covered * (1 - covered);
  }
  SphereSet s = makeSet(p, r, {});
  const std::vector<ReferenceHit> ref = exactHits(s, cam);
  std::vector<double> margin;
  int covered = 0, seen = 0;
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const ReferenceHit& h = ref[static_cast<std::size_t>(j) * W + i];
      margin.push_back(h.margin);
      seen += h.id >= 0;
      const Ray ray = cam.pixelRay(i, j);
      for (const Vec3d& c : p)
      {
        const Vec3d f = Vec3d(ray.org) - c;
        covered += length(f - Vec3d(ray.dir) * dot(f, Vec3d(ray.dir))) <= r[&c - p.data()];
      }
    }
  }
  std::cout << "sub-pixel spheres: " << seen << " pixels hit, " << covered
            << " pixel centres covered, " << expected << " +- " << std::sqrt(variance)
            << " expected from the silhouettes' areas\n";
  EXPECT_LT(std::fabs(covered - expected), 5 * std::sqrt(variance));
  EXPECT_LT(covered, 0.1 * p.size() * 4); // most spheres are missed by every pixel's ray
  for (auto& tracer : allTracers())
  {
    GrazingTally tally;
    expectGrazingAgreement(*tracer, s, cam, 8, ref, margin, tally);
    tally.print("2000 sub-pixel spheres, " + tracer->name());
  }
}

namespace
{
// Spheres with a zero radius exactly on pixel rays of an axis-aligned parallel view (if one
// were kept, the ray through its centre would meet it, disc = 0, and its normal (p - c) / r
// would be 0 / 0), every third input point, among 300 ordinary spheres.
struct ZeroRadiusScene
{
  std::vector<Vec3d> points;
  std::vector<double> radii;
  std::vector<std::uint32_t> colors; // the ordinary spheres' colours, alike in both sets
};

ZeroRadiusScene zeroRadiusScene(const RayCamera& cam, bool withZeros)
{
  const auto p = randomPoints(300, 3, 61);
  ZeroRadiusScene out;
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    if (withZeros && i % 2 == 0)
    {
      const Ray ray = cam.pixelRay(static_cast<int>(7 * i % 64), static_cast<int>(11 * i % 64));
      out.points.push_back({ ray.org.x, ray.org.y, p[i].z + 4 });
      out.radii.push_back(0.0);
      out.colors.push_back(packRGBA8(255, 0, 255, 255));
    }
    out.points.push_back(p[i]);
    out.radii.push_back(0.15 + 0.2 * double(i % 5) / 4);
    out.colors.push_back(packRGBA8(i % 256, (7 * i) % 256, (13 * i) % 256, 255));
  }
  return out;
}
}

// Zero radii mixed in: skipped and counted while the set is built, never hit, no NaN in a
// lit picture, and the rest unchanged: bit for bit the picture of the set without them,
// with each accelerator.
TEST(CoherentGridHardCases, ZeroRadiiMixedInAreSkipped)
{
  const RayCamera cam(
    multiply(orthographic(4, 4, 1, 30), lookAt({ 0, 0, 10 }, { 0, 0, 0 }, { 0, 1, 0 })),
    64,
    64,
    {});
  ASSERT_EQ(cam.pixelRay(5, 9).dir.x, 0.f); // the rays are exactly along -z
  ASSERT_EQ(cam.pixelRay(5, 9).dir.y, 0.f);
  SphereShading lit;
  lit.lights.push_back(Light{});
  lit.material.ambient = 0.1;
  lit.material.specular = 0.4;
  lit.material.specularPower = 10;
  auto build = [&](const ZeroRadiusScene& z)
  {
    SphereSet s;
    buildSphereSet(
      z.points.size(),
      Vec3d(),
      [&](std::size_t i) { return z.points[i]; },
      [&](std::size_t i) { return z.radii[i]; },
      [&](std::size_t i) { return z.colors[i]; },
      s);
    return s;
  };
  const ZeroRadiusScene mixed = zeroRadiusScene(cam, true), plain = zeroRadiusScene(cam, false);
  for (auto& tracer : allTracers())
  {
    SphereSet a = build(mixed), b = build(plain);
    EXPECT_EQ(a.skippedBadRadius, 150u);
    EXPECT_EQ(a.size(), b.size());
    Frame fa, fb;
    RenderStatistics sa, sb;
    renderSpheres({ a, tracer->build(a) }, viewOf(cam), { lit, 8, 32 }, fa, sa);
    renderSpheres({ b, tracer->build(b) }, viewOf(cam), { lit, 8, 32 }, fb, sb);
    EXPECT_TRUE(
      std::all_of(fa.rgba.begin(), fa.rgba.end(), [](float v) { return std::isfinite(v); }))
      << tracer->name();
    EXPECT_EQ(fa.rgba, fb.rgba) << tracer->name();
    EXPECT_EQ(fa.depth, fb.depth) << tracer->name();
    EXPECT_GT(sa.counter("hits"), 500) << tracer->name();
  }
}

namespace
{
// Milliseconds of building the grid over `s` and tracing `cam`, with the traversal's
// counters. The work runs on this thread alone (an arena of one thread) and is timed by the
// thread's CPU clock, so other processes on the machine do not enter the time (wall time
// on a loaded machine varied tenfold from run to run).
struct Timed
{
  double ms;
  std::int64_t cells, tests;
};

Timed buildAndTrace(SphereSet s, const RayCamera& cam)
{
  Timed out{};
  tbb::task_arena serial(1);
  serial.execute(
    [&]()
    {
      timespec t0, t1;
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
      CoherentGridAccelerator grid;
      grid.build(s, CoherentGridParameters{});
      Frame f;
      RenderStatistics stats;
      renderSpheres({ s, grid }, viewOf(cam), { SphereShading{}, 8, 32 }, f, stats);
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
      out = { (t1.tv_sec - t0.tv_sec) * 1e3 + (t1.tv_nsec - t0.tv_nsec) * 1e-6,
        stats.counter("cells"),
        stats.counter("sphere_tests") };
    });
  return out;
}

double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
}

// Radii spread over six decades, 1e-8 to 1e-2 (log-uniform), in a unit box of 20000 centres.
// The grid's cells come from the count (about one per sphere: cells of 0.037), not from the
// radii; r_max = 1e-2 grows every packet's cell range by r_max sqrt(1 + slope^2) (0.27 cells)
// on each side. Checked: every pixel exact outside the float band with every accelerator;
// then the time of building and tracing against the same centres with equal radii: 1e-5
// (the geometric mean: as with the spread, nearly every ray crosses the whole box) and
// 1.9e-3 (the rms radius: the same cross-section, so as many rays stop early). An 8 x 8
// packet spans w ~ 3.1 cells here, so against equal radii of 1e-5 the enlargement visits
// ((w + 1 + 2 * 0.27) / (w + 1))^2 ~ 1.28 times the cells (an exact count), and the tests
// it adds are mostly culled by the frustum; and against equal radii of r_max = 1e-2 (the
// same cell ranges; they hide much of the box, cross-section 6.3 views against 0.23, so
// their rays stop sooner). The times are medians of 9 interleaved runs of each, on one
// thread's CPU clock; their ratio is the one time-related check the issue asks for (< 2x;
// medians measured 1.05 to 1.3 over nine runs, single runs 0.65 to 1.5).
TEST(CoherentGridHardCases, RadiiOverSixDecades)
{
  std::mt19937 rng(71);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Vec3d> p(20000);
  std::vector<double> spread(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    p[i] = { unit(rng), unit(rng), unit(rng) };
    spread[i] = std::pow(10.0, -8 + 6 * unit(rng));
  }
  const Vec3d centre(0.5, 0.5, 0.5), eye(1.6, 1.3, 2.4);
  {
    SphereSet s = makeSet(p, spread, centre);
    CoherentGrid grid;
    CoherentGridParameters params;
    params.lambda = 1.0; // about one cell per sphere
    grid.build(s, params);
    const auto& d = grid.dims();
    EXPECT_GT(double(d[0]) * d[1] * d[2], 0.5 * p.size());
    EXPECT_LT(double(d[0]) * d[1] * d[2], 2.5 * p.size());
  }
  SphereSet s = makeSet(p, spread, centre);
  const RayCamera small = perspectiveCamera(eye, centre, centre, 32, 32, 0.1, 20);
  const std::vector<ReferenceHit> ref = exactHits(s, small);
  std::vector<double> margin;
  int hits = 0;
  for (const ReferenceHit& h : ref)
  {
    margin.push_back(h.margin);
    hits += h.id >= 0;
  }
  EXPECT_GT(hits, 20); // the large spheres are seen
  for (auto& tracer : allTracers())
  {
    GrazingTally tally;
    expectGrazingAgreement(*tracer, s, small, 8, ref, margin, tally);
  }

  const RayCamera cam = perspectiveCamera(eye, centre, centre, 128, 128, 0.1, 20);
  const double rms = std::sqrt((1e-4 - 1e-16) / (2 * std::log(1e6)));
  for (const double equal : { 1e-5, rms, 1e-2 })
  {
    const SphereSet a = makeSet(p, spread, centre);
    const SphereSet b = makeSet(p, std::vector<double>(p.size(), equal), centre);
    std::vector<double> ta, tb, ratios;
    Timed wa{}, wb{};
    for (int k = 0; k < 9; ++k)
    {
      wa = buildAndTrace(a, cam);
      wb = buildAndTrace(b, cam);
      ta.push_back(wa.ms);
      tb.push_back(wb.ms);
      ratios.push_back(wa.ms / wb.ms);
    }
    std::sort(ratios.begin(), ratios.end());
    std::cout << "radii 1e-8..1e-2 against equal radii " << equal << ": " << median(ta) << " ms / "
              << median(tb) << " ms = " << median(ta) / median(tb) << " (single runs " << ratios[0]
              << " to " << ratios[8] << "); cells " << wa.cells << " / " << wb.cells
              << ", sphere tests " << wa.tests << " / " << wb.tests << "\n";
    EXPECT_LT(median(ta), 2 * median(tb)) << "equal radii " << equal;
    if (equal == 1e-5)
    {
      EXPECT_LT(wa.cells, 1.4 * wb.cells);
      EXPECT_LT(wa.tests, 2 * wb.tests);
    }
  }
}

namespace
{
// The byte colour of a pixel of an unlit frame.
std::array<int, 3> pixelColour(const Frame& f, std::size_t p)
{
  return { static_cast<int>(std::lround(f.rgba[4 * p] * 255)),
    static_cast<int>(std::lround(f.rgba[4 * p + 1] * 255)),
    static_cast<int>(std::lround(f.rgba[4 * p + 2] * 255)) };
}
}

// Crowds in one grid cell: 200,000 spheres with one centre (all of radius 0.5, or radii
// 0.5 to 0.9 with one largest), and 200,000 centres in a box of side 1e-4 (radius 0.5).
// Coincident: the front sphere wins: with one centre the picture is the largest sphere's
// alone (for identical spheres any of them: its colour is one of the set's). In the box,
// the union's front against the brute force over all spheres, on every 8th pixel. Every
// crowd makes one cell: the cell is never smaller than the largest radius, or each
// packet would walk the whole grid of cells much smaller than the spheres. (10 million
// spheres take seconds per frame, each packet testing every sphere: measured, not run
// here.)
TEST(CoherentGridHardCases, ManySpheresInOneCell)
{
  const std::size_t n = 200000;
  const RayCamera cam = perspectiveCamera({ 0.5, 0.4, 3 }, { 0, 0, 0 }, {}, 32, 32, 0.1, 20);
  for (const int crowd : { 0, 1, 2 })
  {
    std::vector<Vec3d> p(n);
    std::vector<double> r(n, 0.5);
    for (std::size_t i = 0; i < n; ++i)
    {
      const std::uint32_t h = static_cast<std::uint32_t>(i) * 2654435761u;
      if (crowd == 1)
      {
        r[i] = 0.5 + 0.4 * double(h % 100000) / 100000; // at most 0.899996
      }
      if (crowd == 2)
      {
        p[i] = Vec3d((h & 1023) / 1023.0, ((h >> 10) & 1023) / 1023.0, (h >> 20) / 4095.0) * 1e-4;
      }
    }
    if (crowd == 1)
    {
      r[n / 3] = 0.9; // the largest, unique
    }
    SphereSet s = makeSet(p, r, {});
    const SphereSet original = s;
    CoherentGridAccelerator grid;
    grid.build(s, CoherentGridParameters{});
    EXPECT_EQ(grid.grid().dims(), (std::array<int, 3>{ 1, 1, 1 })) << "crowd " << crowd;
    Frame f;
    RenderStatistics stats;
    renderSpheres({ s, grid }, viewOf(cam), { SphereShading{}, 8, 32 }, f, stats);
    const SphereSet front =
      crowd == 1 ? makeSet({ p[n / 3] }, { 0.9 }, {}) : makeSet({ p[0] }, { 0.5 }, {});
    int wrong = 0, checked = 0;
    for (int j = 0; j < 32; ++j)
    {
      for (int i = 0; i < 32; ++i)
      {
        const std::size_t k = f.index(i, j);
        if (crowd == 2 && k % 8 != 0)
        {
          continue;
        }
        const Ray ray = cam.pixelRay(i, j);
        const ReferenceHit ref = exactHit(crowd == 2 ? original : front, ray, 1.0);
        const bool hit = f.rgba[4 * k + 3] > 0;
        ++checked;
        if (ref.bands < 1)
        {
          continue;
        }
        if (hit != (ref.id >= 0))
        {
          ++wrong;
          continue;
        }
        if (!hit)
        {
          continue;
        }
        wrong += std::fabs(f.depth[k] - cam.depthMap(ray).depthOf(ref.t)) > 1e-6;
        const auto c = pixelColour(f, k);
        if (crowd == 1)
        {
          wrong += c[0] != int(n / 3 % 256); // the largest sphere's colour
        }
        else if (crowd == 0)
        {
          wrong += c[1] != 7 * c[0] % 256 || c[2] != 13 * c[0] % 256; // one of the set's
        }
      }
    }
    EXPECT_EQ(wrong, 0) << "crowd " << crowd;
    EXPECT_GT(stats.counter("hits"), 100) << "crowd " << crowd;
    EXPECT_GT(checked, 100) << "crowd " << crowd;
  }
}

// Overlapping spheres (radius 0.1, centres 0.037 apart) whose cells stop at the floor of
// the largest radius, so r_max spans one cell, seen along the box's diagonal: the rays'
// slopes in U and V are near 1, and the sphere-center method must grow each packet's cell
// range by r_max sqrt(1 + slope^2), 1.4 cells (a sphere whose centre is 1 to 1.4 cells off
// a ray in the centre's slice is hit by it). Every pixel exact outside the float band,
// for every accelerator and packet size.
TEST(CoherentGridHardCases, CrowdedSpheresSeenAlongTheDiagonal)
{
  std::mt19937 rng(73);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Vec3d> p(20000);
  for (auto& q : p)
  {
    q = { unit(rng), unit(rng), unit(rng) };
  }
  const Vec3d centre(0.5, 0.5, 0.5);
  const RayCamera cam = perspectiveCamera({ 2.2, 2.3, 2.1 }, centre, centre, 48, 48, 0.1, 20);
  SphereSet s = makeSet(p, std::vector<double>(p.size(), 0.1), centre);
  CoherentGrid grid;
  CoherentGridParameters params;
  params.lambda = 1.0; // cells of side 0.0368 by lambda, so the floor decides
  grid.build(s, params);
  EXPECT_FLOAT_EQ(grid.cellSize(), 0.1f); // at the floor: r_max spans one cell
  const std::vector<ReferenceHit> ref = exactHits(s, cam);
  std::vector<double> margin;
  for (const ReferenceHit& h : ref)
  {
    margin.push_back(h.margin);
  }
  for (auto& tracer : allTracers())
  {
    for (const int side : { 1, 8, 16 })
    {
      GrazingTally tally;
      expectGrazingAgreement(*tracer, s, cam, side, ref, margin, tally);
    }
  }
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
  renderSpheres({ forGrid, grid }, viewOf(cam), { SphereShading{}, 8, 32 }, g.frame, g.stats);
  expectExact(reference, cam, g.frame, "grid with ranges");
  EXPECT_TRUE(g.stats.effect("range_culling"));
  EXPECT_GT(g.stats.counter("range_culled"), 0);

  SphereSet forEmbree = withAttributes(p);
  EmbreeSphereAccelerator bvh;
  bvh.build(forEmbree);
  bvh.setRangeFilter(filter);
  Rendered e;
  renderSpheres({ forEmbree, bvh }, viewOf(cam), { SphereShading{}, 4, 32 }, e.frame, e.stats);
  expectExact(reference, cam, e.frame, "embree with ranges");

  // No range: nothing culled, the effect is off, and every sphere is drawn again.
  grid.setRangeFilter(RangeFilter{});
  Rendered all;
  renderSpheres({ forGrid, grid }, viewOf(cam), { SphereShading{}, 8, 32 }, all.frame, all.stats);
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
  renderSpheres({ s, grid }, viewOf(cam), { SphereShading{}, 8, 16 }, f, stats);
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
  renderSpheres({ s, grid }, viewOf(cam), { lit, 8, 16 }, f, stats);
  EXPECT_FALSE(stats.effect("soft_shadows"));
  EXPECT_EQ(stats.counter("shadow_rays"), 0);
}
