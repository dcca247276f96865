// The sphere glyph kernel against closed-form hits and a brute-force reference renderer
// that tests every sphere at every pixel in double precision.
#include "CameraFixtures.h"
#include "Mappers/CGT/CoherentGridAccelerator.h"
#include "Mappers/CGT/EmbreeSphereAccelerator.h"
#include "SphereReference.h"
#include "Mappers/CGT/SphereRenderer.h"
#include "Mappers/CGT/SphereSet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace raymappers;
using namespace raymappers::test;

TEST(SphereHit, ClosedFormRoots)
{
  // Ray from (0,0,-10) along +z; unit sphere at the origin: hits at t = 9 and 11.
  EXPECT_DOUBLE_EQ(refineSphereHit({ 0, 0, -10 }, { 0, 0, 1 }, { 0, 0, 0 }, 1, 9.001), 9.0);
  EXPECT_DOUBLE_EQ(refineSphereHit({ 0, 0, -10 }, { 0, 0, 1 }, { 0, 0, 0 }, 1, 10.9), 11.0);
  // Offset by 0.6 from the axis: t = 10 -+ sqrt(1 - 0.36) = 10 -+ 0.8.
  EXPECT_NEAR(refineSphereHit({ 0.6, 0, -10 }, { 0, 0, 1 }, { 0, 0, 0 }, 1, 9.3), 9.2, 1e-14);
  // A miss in double keeps the estimate.
  EXPECT_EQ(refineSphereHit({ 2, 0, -10 }, { 0, 0, 1 }, { 0, 0, 0 }, 1, 5.0), 5.0);
}

TEST(SphereHit, SmallSphereFarAwayKeepsItsPrecision)
{
  // A sphere of radius 1e-3 at distance 1e4: |f|^2 - r^2 would lose 14 digits.
  const double d = 1e4, r = 1e-3, off = 0.6e-3;
  const double t = refineSphereHit({ off, 0, 0 }, { 0, 0, 1 }, { 0, 0, d }, r, d);
  EXPECT_NEAR(t, d - std::sqrt(r * r - off * off), 1e-12 * d);
}

namespace
{
struct Scene
{
  SphereSet spheres;
  Mat4 matrix;
};

Scene randomScene(int n, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-4, 4), rad(0.1, 0.9), col(0, 255);
  std::vector<Vec3d> p(n);
  std::vector<double> r(n);
  std::vector<std::uint32_t> c(n);
  for (int i = 0; i < n; ++i)
  {
    p[i] = { pos(rng), pos(rng), pos(rng) };
    r[i] = rad(rng);
    c[i] = packRGBA8(unsigned(col(rng)), unsigned(col(rng)), unsigned(col(rng)), 255);
  }
  Scene s;
  buildSphereSet(
    n,
    Vec3d(0.5, -0.25, 0.1),
    [&](std::size_t i) { return p[i]; },
    [&](std::size_t i) { return r[i]; },
    [&](std::size_t i) { return c[i]; },
    s.spheres);
  s.matrix = multiply(perspective(40, 1.25, 1, 40), lookAt({ 3, 4, 14 }, { 0, 0, 0 }, { 0, 1, 0 }));
  return s;
}

}

TEST(SphereRenderer, MatchesBruteForceReference)
{
  const Scene scene = randomScene(300, 7);
  const RayCamera camera(scene.matrix, 100, 80, scene.spheres.origin);
  EmbreeSphereAccelerator accel;
  accel.build(scene.spheres);
  SphereShading flat; // no lights: the sphere's own colour
  Frame frame;
  RenderStatistics stats;
  renderSpheres({ scene.spheres, accel }, viewOf(camera), { flat, 4, 16 }, frame, stats);
  EXPECT_EQ(stats.counter("rays"), 100 * 80);
  EXPECT_FALSE(stats.effect("shading"));

  int checked = 0, hits = 0;
  const double radius = sceneRadius(scene.spheres);
  for (int j = 0; j < 80; ++j)
  {
    for (int i = 0; i < 100; ++i)
    {
      const Ray ray = camera.pixelRay(i, j);
      const ReferenceHit ref = exactHit(scene.spheres, ray, radius);
      if (ref.bands < 1)
      {
        continue; // within float resolution of a silhouette (grazingBand): either way
      }
      const int id = ref.id;
      const double t = ref.t;
      ++checked;
      const std::size_t k = frame.index(i, j);
      if (id < 0)
      {
        EXPECT_EQ(frame.rgba[4 * k + 3], 0.f) << i << "," << j;
        EXPECT_EQ(frame.depth[k], 1.f);
        continue;
      }
      ++hits;
      ASSERT_EQ(frame.rgba[4 * k + 3], 1.f) << i << "," << j;
      const std::uint32_t c = scene.spheres.colors[static_cast<std::size_t>(id)];
      EXPECT_NEAR(frame.rgba[4 * k], (c & 0xFF) / 255.0, 1e-6) << i << "," << j;
      EXPECT_NEAR(frame.depth[k], camera.depthMap(ray).depthOf(t), 1e-6) << i << "," << j;
    }
  }
  EXPECT_GT(checked, 100 * 80 * 99 / 100);
  EXPECT_GT(hits, 1000);
  EXPECT_EQ(stats.counter("hits") >= hits, true);
}

// A selection pass answers, for every pixel, which input point's sphere is in front: the
// brute-force reference's front sphere, as its input point + 1, at the same window depth,
// on both accelerators. The first input point has a NaN centre and is skipped, so a sphere's
// index in the set is not its point id (the grid's build also sorts the set): writing the
// index would fail here (seen failing with `spheres.sourceIds[id]` replaced by `id`).
TEST(SpherePicking, IdsAreTheInputPointsOfTheFrontSpheres)
{
  Scene scene = randomScene(300, 11);
  SphereSet& spheres = scene.spheres;
  const std::vector<Vec3f> centers = spheres.centers;
  const std::vector<float> radii = spheres.radii;
  buildSphereSet(
    centers.size() + 1,
    spheres.origin,
    [&](std::size_t i)
    {
      return i == 0 ? Vec3d(std::nan(""), 0, 0) : Vec3d(centers[i - 1]) + spheres.origin;
    },
    [&](std::size_t i) { return i == 0 ? 1.0 : double(radii[i - 1]); },
    [&](std::size_t) { return packRGBA8(255, 255, 255, 255); },
    spheres);
  ASSERT_EQ(spheres.skippedNonFinite, 1u);
  const RayCamera camera(scene.matrix, 96, 72, spheres.origin);
  // The grid's build sorts the spheres (sourceIds keep their points): build it first.
  CoherentGridAccelerator grid;
  grid.build(spheres, CoherentGridParameters{});
  EmbreeSphereAccelerator embree;
  embree.build(spheres);
  const double radius = sceneRadius(spheres);
  for (const SphereAccelerator* accel : { static_cast<const SphereAccelerator*>(&embree),
         static_cast<const SphereAccelerator*>(&grid) })
  {
    IdFrame picks;
    RenderStatistics stats;
    pickSpheres({ spheres, *accel }, viewOf(camera), 8, 16, picks, stats);
    ASSERT_EQ(picks.ids.size(), 96u * 72u);
    EXPECT_TRUE(stats.effect("selection_ids"));
    int checked = 0, hits = 0;
    for (int j = 0; j < 72; ++j)
    {
      for (int i = 0; i < 96; ++i)
      {
        const Ray ray = camera.pixelRay(i, j);
        const ReferenceHit ref = exactHit(spheres, ray, radius);
        if (ref.bands < 1)
        {
          continue; // within float resolution of a silhouette
        }
        ++checked;
        const std::size_t k = static_cast<std::size_t>(j) * 96 + static_cast<std::size_t>(i);
        if (ref.id < 0)
        {
          EXPECT_EQ(picks.ids[k], 0u) << i << "," << j;
          EXPECT_EQ(picks.depth[k], 1.f);
          continue;
        }
        ++hits;
        const std::uint32_t point = spheres.sourceIds[static_cast<std::size_t>(ref.id)];
        EXPECT_GE(point, 1u); // the first point is skipped
        EXPECT_EQ(picks.ids[k], point + 1u) << i << "," << j;
        EXPECT_NEAR(picks.depth[k], camera.depthMap(ray).depthOf(ref.t), 1e-6) << i << "," << j;
      }
    }
    EXPECT_GT(checked, 96 * 72 * 99 / 100);
    EXPECT_GT(hits, 1000);
    EXPECT_EQ(stats.counter("rays"), 96 * 72);
  }
}

TEST(SphereRenderer, AnyTileSizeGivesTheSameImage)
{
  const Scene scene = randomScene(500, 11);
  const RayCamera camera(scene.matrix, 77, 51, scene.spheres.origin);
  EmbreeSphereAccelerator accel;
  accel.build(scene.spheres);
  SphereShading shading;
  shading.lights.push_back(Light{});
  shading.material.ambient = 0.1;
  shading.material.specular = 0.4;
  shading.material.specularPower = 20;
  Frame a, b;
  RenderStatistics sa, sb;
  renderSpheres({ scene.spheres, accel }, viewOf(camera), { shading, 4, 4 }, a, sa);
  renderSpheres({ scene.spheres, accel }, viewOf(camera), { shading, 4, 64 }, b, sb);
  EXPECT_EQ(a.rgba, b.rgba);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_TRUE(sa.effect("shading"));
  EXPECT_TRUE(sa.effect("specular"));
}

TEST(SphereRenderer, LambertShadingOfAHeadOnSphere)
{
  // One white sphere, light along -z (travelling towards the sphere from the eye), diffuse
  // only: the centre pixel faces the light (n.l = 1), so its colour is Kd exactly.
  SphereSet s;
  buildSphereSet(
    1,
    Vec3d(),
    [](std::size_t) { return Vec3d(0, 0, 0); },
    [](std::size_t) { return 1.0; },
    [](std::size_t) { return packRGBA8(255, 255, 255, 255); },
    s);
  const RayCamera camera(
    multiply(orthographic(2, 2, 1, 20), lookAt({ 0, 0, 10 }, { 0, 0, 0 }, { 0, 1, 0 })),
    64,
    64,
    {});
  EmbreeSphereAccelerator accel;
  accel.build(s);
  SphereShading shading;
  shading.lights.push_back(Light{});
  shading.material.diffuse = 0.75;
  Frame f;
  RenderStatistics stats;
  renderSpheres({ s, accel }, viewOf(camera), { shading, 4, 32 }, f, stats);
  // pixel (32, 32) has its centre at x = y = 2 * (0.5/32) = 1/32 off the axis
  const double x = 1.0 / 32, nz = std::sqrt(1 - 2 * x * x);
  const std::size_t k = f.index(32, 32);
  EXPECT_NEAR(f.rgba[4 * k], 0.75 * nz, 1e-5);
  // depth of the front point z = nz: view distance 10 - nz, parallel depth (z - n)/(f - n)
  EXPECT_NEAR(f.depth[k], (10 - nz - 1) / 19, 1e-6);
}

TEST(SphereSet, InvalidInputIsDroppedAndCounted)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Vec3d> p = {
    { 0, 0, 0 }, { nan, 0, 0 }, { 1, inf, 0 }, { 2, 0, 0 }, { 3, 0, 0 }, { 4, 0, 0 }, { 5, 0, 0 }
  };
  const std::vector<double> r = { 1, 1, 1, 0, -1, nan, 0.5 };
  SphereSet s;
  buildSphereSet(
    p.size(),
    Vec3d(),
    [&](std::size_t i) { return p[i]; },
    [&](std::size_t i) { return r[i]; },
    [](std::size_t) { return 0u; },
    s);
  EXPECT_EQ(s.size(), 2u);
  EXPECT_EQ(s.skippedNonFinite, 2u);
  EXPECT_EQ(s.skippedBadRadius, 3u);
  EXPECT_FLOAT_EQ(s.maxRadius, 1.f);
}

TEST(SphereRenderer, EmptySetGivesAnEmptyFrame)
{
  SphereSet s;
  EmbreeSphereAccelerator accel;
  accel.build(s);
  const RayCamera camera(
    multiply(perspective(30, 1, 1, 10), lookAt({ 0, 0, 5 }, { 0, 0, 0 }, { 0, 1, 0 })), 16, 16, {});
  Frame f;
  RenderStatistics stats;
  renderSpheres({ s, accel }, viewOf(camera), { SphereShading{}, 4, 8 }, f, stats);
  EXPECT_EQ(f.rgba.size(), 16u * 16u * 4u);
  for (float v : f.rgba)
  {
    EXPECT_EQ(v, 0.f);
  }
  EXPECT_EQ(stats.counter("hits"), 0);
}
