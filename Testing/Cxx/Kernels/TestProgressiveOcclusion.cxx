// Progressive ambient occlusion (SphereRenderer.h, AoAccumulation): the frames of a still
// view, each tracing the next directions of the same N per hit, end in the one-shot image
// bit for bit; anything that changes the image starts the accumulation again; and the
// grid's local occlusion queries (SphereOcclusion.h) answer as its packet traversal does.
#include "CameraFixtures.h"
#include "Mappers/CGT/CoherentGridAccelerator.h"
#include "Mappers/CGT/EmbreeSphereAccelerator.h"
#include "Mappers/CGT/SphereOcclusion.h"
#include "Mappers/CGT/SphereRenderer.h"
#include "Mappers/CGT/SphereSet.h"

#include <gtest/gtest.h>

#include <cmath>

#include <memory>
#include <random>
#include <string>

using namespace raymappers;
using namespace raymappers::test;

namespace
{
// Spheres packed closely (much of each visible point's hemisphere is blocked nearby), lit.
struct OccludedScene
{
  SphereSet spheres;
  CoherentGridAccelerator grid;
  EmbreeSphereAccelerator bvh;
  SphereShading shading;

  explicit OccludedScene(int which)
    : Which(which)
  {
    std::mt19937 rng(37);
    std::uniform_real_distribution<double> u(-2.5, 2.5);
    std::vector<Vec3d> p(400);
    for (auto& q : p)
    {
      q = { u(rng), u(rng), u(rng) };
    }
    buildSphereSet(
      p.size(),
      Vec3d(0.25, -0.5, 0.125),
      [&](std::size_t i) { return p[i]; },
      [](std::size_t i) { return 0.3 + 0.1 * (i % 3); },
      [](std::size_t i) { return packRGBA8(i % 256, (7 * i) % 256, (13 * i) % 256, 255); },
      spheres);
    if (which == 0)
    {
      grid.build(spheres, CoherentGridParameters{});
    }
    else
    {
      bvh.build(spheres);
    }
    shading.lights.push_back(Light{});
    shading.material.ambient = 0.2;
    shading.material.specular = 0.3;
    shading.material.specularPower = 12;
    shading.aoSamples = 16;
    shading.aoRadius = 1.0;
  }
  const SphereAccelerator& accel() const
  {
    return Which == 0 ? static_cast<const SphereAccelerator&>(grid) : bvh;
  }
  const char* name() const { return Which == 0 ? "grid" : "embree"; }

private:
  int Which;
};

RayCamera cameraAt(const Vec3d& eye, const Vec3d& origin, int w = 64, int h = 48)
{
  return RayCamera(
    multiply(perspective(40, double(w) / h, 0.5, 200), lookAt(eye, { 0, 0, 0 }, { 0, 1, 0 })),
    w,
    h,
    origin);
}

// One frame of the scene with accumulation `acc` (nullptr: none) and budget `budget`.
void renderFrame(const OccludedScene& s,
  const RayCamera& cam,
  const SphereShading& shading,
  int budget,
  AoAccumulation* acc,
  Frame& f,
  RenderStatistics& stats,
  std::uint64_t version = 0)
{
  SphereRenderParameters params{ shading, 8, 16 };
  params.aoSamplesPerFrame = budget;
  params.aoAccumulation = acc;
  params.sceneVersion = version;
  stats.clear();
  renderSpheres({ s.spheres, s.accel() }, viewOf(cam), params, f, stats);
}

Frame oneShot(const OccludedScene& s, const RayCamera& cam, const SphereShading& shading)
{
  Frame f;
  RenderStatistics stats;
  renderFrame(s, cam, shading, 0, nullptr, f, stats);
  EXPECT_EQ(stats.counter("ao_samples_done"), shading.aoSamples);
  EXPECT_EQ(stats.counter("ao_converged"), 1);
  EXPECT_FALSE(stats.effect("ao_progressive"));
  return f;
}

// Renders frames with budget b until converged (at most N + 1), checking the counters of
// each: k1 = min(N, f b) after frame f, converged only at the end; returns the frames taken.
int accumulate(const OccludedScene& s,
  const RayCamera& cam,
  const SphereShading& shading,
  int budget,
  AoAccumulation& acc,
  Frame& f,
  std::uint64_t version = 0)
{
  const int n = shading.aoSamples;
  const int step = std::min(budget, n);
  int frames = 0;
  for (RenderStatistics stats; frames <= n;)
  {
    renderFrame(s, cam, shading, budget, &acc, f, stats, version);
    ++frames;
    const int expected = std::min(n, frames * step);
    EXPECT_TRUE(stats.effect("ao_progressive"));
    EXPECT_EQ(stats.counter("ao_samples_done"), expected) << "frame " << frames;
    EXPECT_EQ(stats.counter("ao_rays"), (expected - (frames - 1) * step) * stats.counter("hits"));
    EXPECT_EQ(stats.counter("ao_converged"), expected == n ? 1 : 0);
    if (expected == n)
    {
      break;
    }
  }
  return frames;
}
}

TEST(ProgressiveOcclusion, FramesOfAStillViewEndInTheOneShotImage)
{
  // N = 16 and N = 7 (a share k / 7 is not exact in binary), budgets 1, 3 (16 = 5 x 3 + 1,
  // 7 = 2 x 3 + 1: a short last frame) and N.
  for (int which = 0; which < 2; ++which)
  {
    OccludedScene s(which);
    const RayCamera cam = cameraAt({ 1, 2, 9 }, s.spheres.origin);
    for (const int n : { 16, 7 })
    {
      s.shading.aoSamples = n;
      const Frame reference = oneShot(s, cam, s.shading);
      for (const int budget : { 1, 3, n })
      {
        AoAccumulation acc;
        Frame f;
        const int frames = accumulate(s, cam, s.shading, budget, acc, f);
        const std::string what =
          std::string(s.name()) + " N " + std::to_string(n) + " budget " + std::to_string(budget);
        EXPECT_EQ(frames, (n + budget - 1) / budget) << what;
        EXPECT_EQ(f.rgba, reference.rgba) << what;
        EXPECT_EQ(f.depth, reference.depth) << what;
        // A converged view is drawn again from the counts: no ray, the same bytes.
        RenderStatistics stats;
        renderFrame(s, cam, s.shading, budget, &acc, f, stats);
        EXPECT_EQ(stats.counter("ao_rays"), 0) << what;
        EXPECT_EQ(stats.counter("ao_converged"), 1) << what;
        EXPECT_EQ(f.rgba, reference.rgba) << what << " again";
      }
    }
  }
}

TEST(ProgressiveOcclusion, AFrameShadesWithTheShareOfTheDirectionsSoFar)
{
  // After the first frame of budget 4, a pixel's colour is its unoccluded colour (AO off)
  // times 1 - (occluded among directions 0..3 of 16) / 4, directions counted here with the
  // accelerator itself.
  const OccludedScene s(0);
  const RayCamera cam = cameraAt({ 1, 2, 9 }, s.spheres.origin);
  SphereShading plainShading = s.shading;
  plainShading.aoSamples = 0;
  const Frame plain = oneShot(s, cam, plainShading);
  AoAccumulation acc;
  Frame f;
  RenderStatistics stats;
  renderFrame(s, cam, s.shading, 4, &acc, f, stats);
  ASSERT_EQ(acc.unoccluded.size(), static_cast<std::size_t>(cam.width() * cam.height()));
  int partial = 0;
  for (std::size_t k = 0; k < acc.unoccluded.size(); ++k)
  {
    if (plain.rgba[4 * k + 3] == 0.f || plain.rgba[4 * k] >= 1.f)
    {
      continue; // no sphere, or a colour clamped to 1 (the share scales it unclamped)
    }
    const int u = acc.unoccluded[k];
    ASSERT_LE(u, 4);
    partial += u > 0 && u < 4 ? 1 : 0;
    const double share = 1.0 - static_cast<double>(4 - u) / 4;
    EXPECT_NEAR(f.rgba[4 * k], plain.rgba[4 * k] * share, 1e-6) << k;
  }
  EXPECT_GT(partial, 50); // the scene is occluded enough for partial shares to show
}

TEST(ProgressiveOcclusion, ChangesStartAgain)
{
  const OccludedScene s(0);
  const RayCamera cam = cameraAt({ 1, 2, 9 }, s.spheres.origin);
  const RayCamera moved = cameraAt({ 1.5, 2, 9 }, s.spheres.origin);
  const RayCamera larger = cameraAt({ 1, 2, 9 }, s.spheres.origin, 80, 60);
  SphereShading relit = s.shading;
  relit.lights[0].direction = normalize(Vec3d(0.3, -0.2, -1));
  SphereShading nearer = s.shading;
  nearer.aoRadius = 0.5;
  struct Change
  {
    const char* what;
    const RayCamera& cam;
    const SphereShading& shading;
    std::uint64_t version;
  };
  for (const Change& c : { Change{ "camera", moved, s.shading, 0 },
         Change{ "window size", larger, s.shading, 0 },
         Change{ "light", cam, relit, 0 },
         Change{ "radius", cam, nearer, 0 },
         Change{ "scene version", cam, s.shading, 1 } })
  {
    AoAccumulation acc;
    Frame f;
    RenderStatistics stats;
    for (int frame = 0; frame < 2; ++frame)
    {
      renderFrame(s, cam, s.shading, 3, &acc, f, stats);
    }
    ASSERT_EQ(stats.counter("ao_samples_done"), 6);
    // The changed frame traces directions 0..2 again, and its accumulation ends in the
    // changed view's one-shot image.
    renderFrame(s, c.cam, c.shading, 3, &acc, f, stats, c.version);
    EXPECT_EQ(stats.counter("ao_samples_done"), 3) << c.what;
    acc.reset();
    accumulate(s, c.cam, c.shading, 3, acc, f, c.version);
    EXPECT_EQ(f.rgba, oneShot(s, c.cam, c.shading).rgba) << c.what;
  }
}

TEST(ProgressiveOcclusion, BudgetAboveTheSamplesIsAllOfThem)
{
  const OccludedScene s(1);
  const RayCamera cam = cameraAt({ 1, 2, 9 }, s.spheres.origin);
  AoAccumulation acc;
  Frame f;
  RenderStatistics stats;
  renderFrame(s, cam, s.shading, 1000, &acc, f, stats);
  EXPECT_EQ(stats.counter("ao_samples_done"), 16);
  EXPECT_EQ(stats.counter("ao_rays"), 16 * stats.counter("hits"));
  EXPECT_EQ(stats.counter("ao_converged"), 1);
  EXPECT_EQ(f.rgba, oneShot(s, cam, s.shading).rgba);
}

TEST(ProgressiveOcclusion, TranslucentSpheresTraceAllDirectionsEveryFrame)
{
  const OccludedScene s(0);
  const RayCamera cam = cameraAt({ 1, 2, 9 }, s.spheres.origin);
  SphereRenderParameters params{ s.shading, 8, 16 };
  params.opacity = 0.5;
  Frame reference;
  RenderStatistics stats;
  renderSpheres({ s.spheres, s.accel() }, viewOf(cam), params, reference, stats);
  AoAccumulation acc;
  params.aoSamplesPerFrame = 2;
  params.aoAccumulation = &acc;
  Frame f;
  stats.clear();
  renderSpheres({ s.spheres, s.accel() }, viewOf(cam), params, f, stats);
  EXPECT_FALSE(stats.effect("ao_progressive"));
  EXPECT_EQ(stats.counter("ao_samples_done"), 16);
  EXPECT_EQ(stats.counter("ao_converged"), 1);
  EXPECT_EQ(f.rgba, reference.rgba);
}

TEST(SphereOcclusion, GridQueriesAnswerAsTheGridTraversal)
{
  // Random short rays from random points among the spheres: blocked exactly when the grid's
  // closest-hit traversal finds a hit, with and without a range filter.
  const OccludedScene s(0);
  const SphereOcclusion occlusion(s.spheres, s.grid);
  ASSERT_TRUE(occlusion.local());
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-3.f, 3.f), len(0.05f, 2.f);
  int blockedRays = 0, rays = 0;
  for (int round = 0; round < 2; ++round)
  {
    RangeFilter filter;
    if (round == 1)
    {
      filter.count = 0; // the spheres have no attributes: the filter is the empty one
    }
    const_cast<CoherentGridAccelerator&>(s.grid).setRangeFilter(filter);
    for (int q = 0; q < 400; ++q)
    {
      RayPacket packet;
      packet.side = 4;
      packet.pixelBlock = false;
      const Vec3f o(u(rng), u(rng), u(rng));
      const float tfar = len(rng);
      const int count = 1 + q % 16;
      for (int a = 0; a < 16; ++a)
      {
        packet.valid[a] = a < count;
        packet.rays[a] = Ray{ o, normalize(Vec3f(u(rng), u(rng), u(rng))), 0.f, tfar };
      }
      PacketHits hits;
      TraversalCounters counters;
      s.grid.intersect(packet, hits, counters);
      bool blocked[MaxPacketRays];
      const int n = occlusion.occluded(packet, count, blocked, counters);
      int expected = 0;
      for (int a = 0; a < count; ++a)
      {
        EXPECT_EQ(blocked[a], hits.prim[a] != NoHit) << q << " lane " << a;
        expected += hits.prim[a] != NoHit ? 1 : 0;
      }
      EXPECT_EQ(n, expected);
      blockedRays += expected;
      rays += count;
    }
  }
  EXPECT_GT(blockedRays, rays / 10);
  EXPECT_LT(blockedRays, rays);
}

TEST(SphereOcclusion, AmbientOcclusionPacketsAnswerAsTheGridTraversal)
{
  // Ambient-occlusion packets (aoDirection, 1 to 16 rays) from just above random points of
  // the surfaces of 6000 random spheres of three radii: blocked exactly when the grid's
  // closest-hit traversal finds a hit, and the query visits no cell outside the box
  // o +- (T + r_max).
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3d> p(6000);
  for (auto& q : p)
  {
    q = Vec3d(u(rng), u(rng), u(rng)) * 2.0;
  }
  SphereSet spheres;
  buildSphereSet(
    p.size(),
    Vec3d(0.5, -0.25, 0.125),
    [&](std::size_t i) { return p[i]; },
    [](std::size_t i) { return 0.1 + 0.02 * (i % 3); },
    [](std::size_t) { return packRGBA8(200, 200, 200, 255); },
    spheres);
  CoherentGridAccelerator accel;
  accel.build(spheres, CoherentGridParameters{});
  const SphereOcclusion occlusion(spheres, accel);
  const CoherentGrid& grid = accel.grid();
  int blockedRays = 0, rays = 0;
  std::int64_t visited = 0, inBoxes = 0;
  for (int q = 0; q < 600; ++q)
  {
    const std::size_t id = rng() % spheres.size();
    const Vec3d n = normalize(Vec3d(u(rng), u(rng), u(rng)));
    const double r = spheres.radii[id];
    const Vec3f o(Vec3d(spheres.centers[id]) + n * (r * (1 + 1e-4)));
    const float T = 0.5f;
    RayPacket packet;
    packet.side = 4;
    packet.pixelBlock = false;
    const int count = 1 + q % 16;
    for (int a = 0; a < 16; ++a)
    {
      packet.valid[a] = a < count;
      packet.rays[a] = Ray{ o, Vec3f(aoDirection(n, a, 16, static_cast<std::uint32_t>(q))), 0.f, T };
    }
    PacketHits hits;
    TraversalCounters counters;
    accel.intersect(packet, hits, counters);
    TraversalCounters queried;
    bool blocked[MaxPacketRays];
    occlusion.occluded(packet, count, blocked, queried);
    for (int a = 0; a < count; ++a)
    {
      EXPECT_EQ(blocked[a], hits.prim[a] != NoHit) << q << " lane " << a;
      blockedRays += hits.prim[a] != NoHit ? 1 : 0;
    }
    rays += count;
    visited += queried.cells;
    const float reach = T + grid.maxRadius();
    const auto lo = grid.cellOf(o - Vec3f(reach, reach, reach));
    const auto hi = grid.cellOf(o + Vec3f(reach, reach, reach));
    inBoxes += std::int64_t(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
  }
  EXPECT_GT(blockedRays, rays / 10);
  EXPECT_LT(blockedRays, rays);
  EXPECT_LE(visited, inBoxes);
}

TEST(AoDirection, TheTableAndTheAngleSumGiveTheDirectFormulasDirections)
{
  // The directions as one formula per ray (radical inverse, shift, tangent frame, lift, one
  // sine and cosine per ray), the form the renderer had before the frame's table of
  // Hammersley points and the per-pixel angle sum: the same unit vectors to rounding (1e-14),
  // and the float directions the rays carry the same in all but a few of the 2000 x 9
  // (measured here: none differs).
  const auto direct = [](const Vec3d& n, int k, int count, std::uint32_t pixel)
  {
    std::uint32_t h = pixel * 0x9E3779B1u;
    h ^= h >> 16;
    h *= 0x85EBCA6Bu;
    h ^= h >> 13;
    const double shift0 = (h & 0xFFFF) / 65536.0, shift1 = (h >> 16) / 65536.0;
    std::uint32_t bits = 0;
    for (int i = 0; i < 32; ++i)
    {
      bits |= ((static_cast<std::uint32_t>(k) >> i) & 1u) << (31 - i);
    }
    double u = (k + 0.5) / count + shift0;
    double v = bits * (1.0 / 4294967296.0) + shift1;
    u -= std::floor(u);
    v -= std::floor(v);
    const double r = std::sqrt(u), phi = 2.0 * M_PI * v;
    const Vec3d a = std::fabs(n.x) > 0.9 ? Vec3d(0, 1, 0) : Vec3d(1, 0, 0);
    const Vec3d t = normalize(cross(a, n));
    const Vec3d b = cross(n, t);
    return normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * std::sqrt(1.0 - u));
  };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  int directions = 0, floatsDiffer = 0;
  for (int q = 0; q < 2000; ++q)
  {
    const Vec3d n = normalize(Vec3d(u(rng), u(rng), u(rng)));
    const auto pixel = static_cast<std::uint32_t>(rng());
    const int count = 1 + q % 256;
    const AoBasis basis = aoBasis(n, pixel);
    for (int k = 0; k < count; k += 1 + count / 8)
    {
      const Vec3d d = direct(n, k, count, pixel);
      const Vec3d e = aoDirectionIn(basis, aoSample(k, count));
      ASSERT_LT(length(d - e), 1e-14) << q << " k " << k;
      const Vec3d g = aoDirection(n, k, count, pixel);
      ASSERT_TRUE(e.x == g.x && e.y == g.y && e.z == g.z) << q << " k " << k;
      const Vec3f df(d), ef(e);
      ++directions;
      floatsDiffer += df.x == ef.x && df.y == ef.y && df.z == ef.z ? 0 : 1;
    }
  }
  EXPECT_LE(floatsDiffer, directions / 1000) << "of " << directions;
}

TEST(SphereOcclusion, EmbreeAnyHitQueriesAnswerAsItsClosestHits)
{
  // rtcOccluded16 against rtcIntersect16 on random short rays among the spheres, packets of
  // 16 and 64 rays (several chunks of 16).
  const OccludedScene s(1);
  const SphereOcclusion occlusion(s.spheres, s.bvh);
  ASSERT_FALSE(occlusion.local());
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> u(-3.f, 3.f), len(0.05f, 2.f);
  int blockedRays = 0, rays = 0;
  for (int q = 0; q < 400; ++q)
  {
    RayPacket packet;
    packet.side = q % 2 ? 8 : 4;
    packet.pixelBlock = false;
    const Vec3f o(u(rng), u(rng), u(rng));
    const float tfar = len(rng);
    const int count = 1 + q % (packet.side * packet.side);
    for (int a = 0; a < packet.side * packet.side; ++a)
    {
      packet.valid[a] = a < count;
      packet.rays[a] = Ray{ o, normalize(Vec3f(u(rng), u(rng), u(rng))), 0.f, tfar };
    }
    PacketHits hits;
    TraversalCounters counters;
    s.bvh.intersect(packet, hits, counters);
    bool blocked[MaxPacketRays];
    const int n = occlusion.occluded(packet, count, blocked, counters);
    int expected = 0;
    for (int a = 0; a < packet.side * packet.side; ++a)
    {
      const bool hit = a < count && hits.prim[a] != NoHit;
      EXPECT_EQ(blocked[a], hit) << q << " lane " << a;
      expected += hit ? 1 : 0;
    }
    EXPECT_EQ(n, expected);
    blockedRays += expected;
    rays += count;
  }
  EXPECT_GT(blockedRays, rays / 10);
  EXPECT_LT(blockedRays, rays);
}
