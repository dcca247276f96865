// Translucent spheres: the front-to-back composite of the sphere renderer against closed
// forms. Unlit spheres on the view axis of a parallel camera whose pixels all cross every
// sphere, so each pixel's composite is the sum over the spheres in depth order,
//   C = sum_k a_k c_k prod_{j < k} (1 - a_j),   A = 1 - prod_k (1 - a_k),
// on both accelerators.
#include "CameraFixtures.h"
#include "RegionFixtures.h"
#include "Mappers/CGT/CoherentGridAccelerator.h"
#include "Mappers/CGT/EmbreeSphereAccelerator.h"
#include "Mappers/CGT/SphereRenderer.h"
#include "Mappers/CGT/SphereSet.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

using namespace raymappers;
using namespace raymappers::test;

namespace
{
// A sphere of the column: centre z on the view axis, radius, colour and opacity.
struct ColumnSphere
{
  double z, radius;
  unsigned r, g, b;
  double opacity;
};

constexpr int Pixels = 8; // an 8 x 8 frame over 0.2 x 0.2: every ray crosses every sphere

// The parallel camera looking down -z from z = 10 at a 0.2 x 0.2 window.
RayCamera columnCamera()
{
  return RayCamera(multiply(orthographic(0.1, 0.1, 1, 40), lookAt({ 0, 0, 10 }, { 0, 0, 0 }, { 0, 1, 0 })),
    Pixels, Pixels, {});
}

// The spheres in the given input order; per-sphere opacities when `ownOpacities`.
SphereSet columnSet(const std::vector<ColumnSphere>& column, bool ownOpacities)
{
  SphereSet s;
  buildSphereSet(
    column.size(), Vec3d(), [&](std::size_t i) { return Vec3d(0, 0, column[i].z); },
    [&](std::size_t i) { return column[i].radius; },
    [&](std::size_t i) { return packRGBA8(column[i].r, column[i].g, column[i].b, 255); }, s);
  if (ownOpacities)
  {
    setSphereOpacities(s, [&](std::uint32_t id) { return column[id].opacity; });
  }
  return s;
}

// The closed form of the header over the spheres sorted front (largest z) to back.
std::array<double, 4> columnComposite(std::vector<ColumnSphere> column, double opacity, bool own)
{
  std::sort(column.begin(), column.end(),
    [](const ColumnSphere& a, const ColumnSphere& b) { return a.z > b.z; });
  std::array<double, 4> c{ 0, 0, 0, 0 };
  double transmitted = 1.0;
  for (const ColumnSphere& s : column)
  {
    const double a = opacity * (own ? s.opacity : 1.0);
    c[0] += transmitted * a * s.r / 255.0;
    c[1] += transmitted * a * s.g / 255.0;
    c[2] += transmitted * a * s.b / 255.0;
    transmitted *= 1.0 - a;
  }
  c[3] = 1.0 - transmitted;
  return c;
}

struct Rendered
{
  Frame frame;
  RenderStatistics stats;
};

// The column rendered with global `opacity` through the grid or Embree, optionally
// stopped at a window depth, its primary rays seeing only `region`.
Rendered renderColumn(const std::vector<ColumnSphere>& column,
  double opacity,
  bool ownOpacities,
  bool grid,
  const float* opaqueDepth = nullptr,
  const RegionBox& region = {})
{
  SphereSet spheres = columnSet(column, ownOpacities);
  CoherentGridAccelerator gridAccel;
  EmbreeSphereAccelerator embree;
  if (grid)
  {
    gridAccel.build(spheres, CoherentGridParameters{});
  }
  else
  {
    embree.build(spheres);
  }
  const SphereAccelerator& accel =
    grid ? static_cast<const SphereAccelerator&>(gridAccel) : embree;
  SphereRenderParameters params;
  params.opacity = opacity;
  params.packetSide = 4;
  Rendered out;
  renderSpheres({ spheres, accel, region }, viewOf(columnCamera(), opaqueDepth), params,
    out.frame, out.stats);
  return out;
}

void expectEveryPixel(const Frame& frame, const std::array<double, 4>& expected, double tolerance)
{
  for (int k = 0; k < Pixels * Pixels; ++k)
  {
    for (int c = 0; c < 4; ++c)
    {
      ASSERT_NEAR(frame.rgba[4 * k + c], expected[c], tolerance) << "pixel " << k << " channel " << c;
    }
  }
}

// N equal spheres of radius 0.4, 1 apart along z.
std::vector<ColumnSphere> equalColumn(int n)
{
  std::vector<ColumnSphere> column;
  for (int i = 0; i < n; ++i)
  {
    column.push_back({ -1.0 * i, 0.4, 200, 100, 50, 1.0 });
  }
  return column;
}
}

class TranslucentSpheres : public ::testing::TestWithParam<bool>
{
};

TEST_P(TranslucentSpheres, EqualSpheresGiveOneMinusTheTransmittedPower)
{
  // N spheres of opacity a: A = 1 - (1 - a)^N, C = c A (one colour).
  const int n = 5;
  const double a = 0.3;
  const Rendered r = renderColumn(equalColumn(n), a, false, GetParam());
  const double alpha = 1.0 - std::pow(1.0 - a, n);
  expectEveryPixel(r.frame, { alpha * 200 / 255.0, alpha * 100 / 255.0, alpha * 50 / 255.0, alpha },
    1e-6);
  EXPECT_TRUE(r.stats.effect("translucency"));
  EXPECT_EQ(r.stats.counter("translucent_layers"), Pixels * Pixels * n);
  EXPECT_EQ(r.stats.counter("translucent_terminated"), 0);
}

TEST_P(TranslucentSpheres, OwnOpacitiesAndColoursCompositeInDepthOrderWhateverTheInputOrder)
{
  // Different colours and opacities, given back to front, front to back and mixed: the
  // composite is the depth-ordered closed form, and the same bytes for every input order.
  std::vector<ColumnSphere> column = { { -3, 0.45, 255, 0, 0, 0.6 }, { -1.5, 0.3, 0, 255, 0, 0.25 },
    { 0, 0.4, 0, 0, 255, 0.8 }, { 1.2, 0.35, 255, 255, 0, 0.5 } };
  const std::array<double, 4> expected = columnComposite(column, 0.9, true);
  const Rendered first = renderColumn(column, 0.9, true, GetParam());
  expectEveryPixel(first.frame, expected, 1e-6);
  std::reverse(column.begin(), column.end());
  EXPECT_EQ(renderColumn(column, 0.9, true, GetParam()).frame.rgba, first.frame.rgba);
  std::swap(column[0], column[2]);
  EXPECT_EQ(renderColumn(column, 0.9, true, GetParam()).frame.rgba, first.frame.rgba);
}

TEST_P(TranslucentSpheres, OverlappingSpheresCountOnceEach)
{
  // The second sphere's front lies inside the first: the first's back surface, met after
  // the second's front, is not composited again; nor the second's.
  const std::vector<ColumnSphere> column = { { 0, 0.6, 255, 0, 0, 0.5 }, { -0.5, 0.6, 0, 0, 255, 0.5 } };
  const Rendered r = renderColumn(column, 1.0, true, GetParam());
  expectEveryPixel(r.frame, columnComposite(column, 1.0, true), 1e-6);
  EXPECT_EQ(r.stats.counter("translucent_layers"), Pixels * Pixels * 2);
}

TEST_P(TranslucentSpheres, CoincidentSpheresAreEachComposited)
{
  // Duplicated points (a mesh's nodes on block seams): three equal spheres in one place,
  // two more in another and a sixth 1.2e-7 in front of those, closer than a float ulp of
  // the rays' distance (9.5e-7 at 11.5), so their hits tie in float. Every one is a layer:
  // queries from just past a tied hit would composite one sphere of each tie.
  const std::vector<ColumnSphere> column = { { 0, 0.4, 200, 100, 50, 0.3 },
    { -1.5, 0.45, 50, 100, 200, 0.5 }, { 0, 0.4, 200, 100, 50, 0.5 },
    { -1.5 + 1.2e-7, 0.45, 50, 100, 200, 0.4 }, { 0, 0.4, 200, 100, 50, 0.2 },
    { -1.5, 0.45, 50, 100, 200, 0.25 } };
  const Rendered r = renderColumn(column, 1.0, true, GetParam());
  // Within each place one colour, so the composite does not depend on the order of a tie.
  expectEveryPixel(r.frame, columnComposite(column, 1.0, true), 1e-6);
  EXPECT_EQ(r.stats.counter("translucent_layers"), Pixels * Pixels * 6);
  // 40 in one place: the accelerator meets them in no particular order (Embree's leaves), and
  // of a tie the lowest index must come first, or the ones below it would be skipped.
  const Rendered forty = renderColumn(std::vector<ColumnSphere>(40, column[0]), 0.05, false, GetParam());
  const double alpha = 1.0 - std::pow(0.95, 40);
  expectEveryPixel(forty.frame, { alpha * 200 / 255.0, alpha * 100 / 255.0, alpha * 50 / 255.0, alpha },
    1e-6);
  EXPECT_EQ(forty.stats.counter("translucent_layers"), Pixels * Pixels * 40);
}

TEST_P(TranslucentSpheres, EarlyTerminationStaysWithinItsBound)
{
  // 40 spheres of opacity 1/2: the ray stops after k layers, 2^-k <= 1/512 (k = 9), and the
  // composite misses at most 1 - A <= 1/512 of the exact one in every channel.
  const int n = 40;
  const Rendered r = renderColumn(equalColumn(n), 0.5, false, GetParam());
  const double exact = 1.0 - std::pow(0.5, n);
  const double bound = 1.0 - TranslucentTerminationAlpha;
  EXPECT_EQ(r.stats.counter("translucent_layers"), Pixels * Pixels * 9);
  EXPECT_EQ(r.stats.counter("translucent_terminated"), Pixels * Pixels);
  for (int k = 0; k < Pixels * Pixels; ++k)
  {
    EXPECT_GE(r.frame.rgba[4 * k + 3], TranslucentTerminationAlpha);
    EXPECT_LE(exact - r.frame.rgba[4 * k + 3], bound);
    EXPECT_LE(exact * 200 / 255.0 - r.frame.rgba[4 * k], bound);
  }
}

TEST_P(TranslucentSpheres, RaysStopAtTheOpaqueDepth)
{
  // Opaque geometry between the second and the third sphere (z = -1.5, view distance 11.5
  // of the parallel camera with near 1 and far 40): two layers.
  const float depth = static_cast<float>((11.5 - 1) / 39);
  const std::vector<float> opaque(Pixels * Pixels, depth);
  const Rendered r = renderColumn(equalColumn(5), 0.3, false, GetParam(), opaque.data());
  const double alpha = 1.0 - 0.7 * 0.7;
  expectEveryPixel(r.frame, { alpha * 200 / 255.0, alpha * 100 / 255.0, alpha * 50 / 255.0, alpha },
    1e-6);
  EXPECT_EQ(r.stats.counter("translucent_layers"), Pixels * Pixels * 2);
}

TEST_P(TranslucentSpheres, UnusedOpacityRunsTheOpaquePath)
{
  // Opacity 1 and no per-sphere opacities: the closest-hit path, one query per packet, no
  // layer; per-sphere opacities of 1 give the same pixels through the translucent path.
  const Rendered opaque = renderColumn(equalColumn(3), 1.0, false, GetParam());
  EXPECT_FALSE(opaque.stats.effect("translucency"));
  EXPECT_EQ(opaque.stats.counter("translucent_layers"), 0);
  EXPECT_EQ(opaque.stats.counter("translucent_queries"), 0);
  expectEveryPixel(opaque.frame, { 200 / 255.0, 100 / 255.0, 50 / 255.0, 1.0 }, 1e-6);
  const Rendered ones = renderColumn(equalColumn(3), 1.0, true, GetParam());
  EXPECT_TRUE(ones.stats.effect("translucency"));
  EXPECT_EQ(ones.frame.rgba, opaque.frame.rgba);
  EXPECT_EQ(ones.frame.depth, opaque.frame.depth);
}

TEST_P(TranslucentSpheres, ZeroAndNaNOpacitiesDrawNothing)
{
  // A NaN opacity becomes 0 (setSphereOpacities): that sphere is not drawn, the others are.
  std::vector<ColumnSphere> column = equalColumn(3);
  column[1].opacity = std::numeric_limits<double>::quiet_NaN();
  SphereSet s = columnSet(column, false);
  EXPECT_EQ(setSphereOpacities(s, [&](std::uint32_t id) { return column[id].opacity; }), 1u);
  EXPECT_EQ(s.opacities[1], 0.f);
  const Rendered r = renderColumn(column, 0.5, true, GetParam());
  const double alpha = 0.75;
  expectEveryPixel(r.frame, { alpha * 200 / 255.0, alpha * 100 / 255.0, alpha * 50 / 255.0, alpha },
    1e-6);
  const Rendered none = renderColumn(equalColumn(3), 0.0, false, GetParam());
  expectEveryPixel(none.frame, { 0, 0, 0, 0 }, 0);
}

TEST_P(TranslucentSpheres, RegionsCuttingThroughSpheresBlendToTheWholeImage)
{
  // Distributed rendering (SphereScene::region): three boxes of a kd-tree cut, each given
  // every sphere, the plane z = -0.2 through the first sphere; each draws only surfaces
  // inside it, their images blended front to back are the whole image, opaque or
  // translucent, and each translucent layer is
  // counted in one box only (the back box's rays start inside the first sphere and meet
  // its far surface, which is not that sphere's first).
  for (const double opacity : { 1.0, 0.3 })
  {
    const Rendered whole = renderColumn(equalColumn(3), opacity, false, GetParam());
    Frame composite;
    composite.resize(Pixels, Pixels);
    double layers = 0;
    for (const RegionBox& region : kdCutFrontToBack(0.03, -0.2))
    {
      const Rendered part =
        renderColumn(equalColumn(3), opacity, false, GetParam(), nullptr, region);
      EXPECT_TRUE(part.stats.effect("region_clip"));
      for (std::size_t k = 0; k < part.frame.depth.size(); ++k)
      {
        // Every surface drawn lies in the box: z = 10 - (1 + 39 depth) for this camera.
        const double z = 10.0 - (1.0 + 39.0 * part.frame.depth[k]);
        if (part.frame.rgba[4 * k + 3] > 0.f)
        {
          ASSERT_TRUE(z >= region.lo[2] - 1e-4 && z <= region.hi[2] + 1e-4) << "z " << z;
        }
      }
      blendBehind(composite, part.frame);
      layers += part.stats.counter("translucent_layers");
    }
    EXPECT_FALSE(whole.stats.effect("region_clip"));
    for (std::size_t i = 0; i < whole.frame.rgba.size(); ++i)
    {
      ASSERT_NEAR(composite.rgba[i], whole.frame.rgba[i], 1e-6) << "opacity " << opacity << " value " << i;
    }
    EXPECT_EQ(layers, whole.stats.counter("translucent_layers"));
    EXPECT_EQ(whole.stats.counter("translucent_layers"), opacity < 1.0 ? 3 * Pixels * Pixels : 0);
  }
}

INSTANTIATE_TEST_SUITE_P(Accelerators, TranslucentSpheres, ::testing::Values(true, false),
  [](const ::testing::TestParamInfo<bool>& p) { return p.param ? "Grid" : "Embree"; });
