// The kernels compiled once per instruction set (Mappers/Common/SimdTarget.h) draw the same
// bytes on every path: RBF's coherent and direct methods, SPH's volume ray casting, the SPH
// fluid (voxelizer and surface renderer) and ZSweep render the same scenes with RAYMAPPERS_SIMD=portable, avx2 and avx512 (those this CPU has), and
// every frame must equal the portable one bit for bit. (Same float operations in the same
// order on every path: -ffp-contract=off, no reassociation.)
#include "CameraFixtures.h"
#include "Mappers/SPH/FluidRenderer.h"
#include "Mappers/RBF/ParticleBVH.h"
#include "Mappers/RBF/RBFVolumeRenderer.h"
#include "Mappers/SPH/SPHVolumeRenderer.h"
#include "Mappers/CGT/SimdPath.h"
#include "Mappers/ZSweep/ZSweepRenderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

using namespace raymappers;
using namespace raymappers::test;

namespace
{
/// The paths this CPU runs, portable first.
std::vector<SimdPath> availablePaths()
{
  std::vector<SimdPath> paths;
  for (const SimdPath path : { SimdPath::Portable, SimdPath::Avx2, SimdPath::Avx512 })
  {
    if (resolveSimdPath(path) == path)
    {
      paths.push_back(path);
    }
  }
  return paths;
}

/// Renders `draw` once per path under RAYMAPPERS_SIMD and expects every frame's colours to
/// equal the portable frame's bytes; the portable frame must not be empty.
void expectSameFrameOnEveryPath(const std::string& scene,
  const std::function<void(Frame&, RenderStatistics&)>& draw)
{
  const std::vector<SimdPath> paths = availablePaths();
  if (paths.size() < 2)
  {
    GTEST_SKIP() << "this CPU has no AVX2";
  }
  std::vector<Frame> frames;
  for (const SimdPath path : paths)
  {
    ::setenv("RAYMAPPERS_SIMD", simdPathName(path), 1);
    ASSERT_EQ(resolveSimdPath(SimdPath::Auto), path);
    RenderStatistics stats;
    frames.emplace_back();
    draw(frames.back(), stats);
  }
  ::unsetenv("RAYMAPPERS_SIMD");
  const Frame& portable = frames.front();
  double alpha = 0;
  for (std::size_t i = 3; i < portable.rgba.size(); i += 4)
  {
    alpha += portable.rgba[i];
  }
  EXPECT_GT(alpha, 20.0) << scene << ": the picture is not empty";
  for (std::size_t p = 1; p < paths.size(); ++p)
  {
    const Frame& other = frames[p];
    ASSERT_EQ(other.rgba.size(), portable.rgba.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < portable.rgba.size(); ++i)
    {
      differing += std::memcmp(&portable.rgba[i], &other.rgba[i], sizeof(float)) != 0;
    }
    EXPECT_EQ(differing, 0u) << scene << ": " << simdPathName(paths[p])
                             << " against portable, values that differ";
  }
}

/// n random particles in a cube of side 2 about the origin with radii (or supports) in
/// [lo, hi], read by the particle builders through centre() and size().
struct Cloud
{
  std::vector<Vec3d> centres;
  std::vector<double> sizes;

  Cloud(int n, unsigned seed, double lo, double hi)
  {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1), ur(lo, hi);
    for (int i = 0; i < n; ++i)
    {
      centres.push_back({ u(rng), u(rng), u(rng) });
      sizes.push_back(ur(rng));
    }
  }
  std::size_t count() const { return centres.size(); }
  std::function<Vec3d(std::size_t)> centre() const
  {
    return [this](std::size_t i) { return centres[i]; };
  }
  std::function<double(std::size_t)> size() const
  {
    return [this](std::size_t i) { return sizes[i]; };
  }
};

/// n samples over [0, hi]: colour ramps, opacity rising to `alphaMax`.
TransferFunctionTable ramp(double hi, double alphaMax, int n = 256)
{
  std::vector<float> rgba;
  for (int k = 0; k < n; ++k)
  {
    const float x = static_cast<float>(k) / (n - 1);
    rgba.insert(rgba.end(), { x, 1.f - x, 0.4f, static_cast<float>(alphaMax) * x });
  }
  TransferFunctionTable table;
  table.assign(rgba, 0.0, hi, 1.0);
  return table;
}

Material shinyMaterial()
{
  Material m;
  m.ambient = 0.2;
  m.diffuse = 0.7;
  m.specular = 0.3;
  m.specularPower = 10;
  return m;
}
}

TEST(SimdDispatch, RBFFramesAreTheSameOnEveryPath)
{
  const Cloud cloud(400, 3, 0.1, 0.3);
  const Vec3d origin{ 0.2, -0.1, 0.3 };
  RBFParticles particles;
  buildRBFParticles(cloud.count(), origin, 2, cloud.centre(), cloud.size(),
    [](std::size_t i) { return 0.5 + 0.25 * static_cast<double>(i % 5); },
    [](std::size_t i) { return static_cast<int>(i % 2); }, particles);
  ParticleBVH bvh;
  bvh.build(particles, 8);
  const int w = 48, h = 40;
  const RayCamera camera(
    multiply(perspective(35, double(w) / h, 0.5, 100), lookAt({ 2.5, 1.5, 3.5 }, { 0, 0, 0 }, { 0, 1, 0 })),
    w,
    h,
    origin);
  const std::vector<TransferFunctionTable> tables = { ramp(2.0, 0.6), ramp(1.5, 0.4) };
  for (const bool direct : { false, true })
  {
    for (const bool shade : { false, true })
    {
      RBFRenderParameters params;
      params.sampleDistance = 0.03;
      params.direct = direct;
      params.shade = shade;
      params.lights = { Light() };
      params.material = shinyMaterial();
      expectSameFrameOnEveryPath(
        std::string(direct ? "direct" : "coherent") + (shade ? ", shaded" : ""),
        [&](Frame& frame, RenderStatistics& stats)
        { renderRBF({ particles, bvh, tables }, viewOf(camera), params, frame, stats); });
    }
  }
}

TEST(SimdDispatch, SPHVolumeFramesAreTheSameOnEveryPath)
{
  const Cloud cloud(300, 5, 0.15, 0.4);
  const std::vector<double>& H = cloud.sizes;
  SPHParticles particles;
  buildSPHParticles(cloud.count(), { 0.1, -0.2, 0.05 }, cloud.centre(), cloud.size(),
    [](std::size_t i) { return 1.0 + static_cast<double>(i % 4); },
    [&](std::size_t i) { return 0.5 * H[i] * H[i] * H[i]; }, particles);
  ViewRays rays;
  ASSERT_TRUE(rays.assign(
    multiply(perspective(40, 48.0 / 40, 0.1, 100), lookAt({ 1.5, 1.0, 3.5 }, { 0, 0, 0 }, { 0, 1, 0 })),
    48,
    40,
    particles.origin));
  const TransferFunctionTable table = ramp(5.0, 0.8);
  struct Case
  {
    SPHKernel kernel;
    SPHNormalization mode;
    bool shade, contour, jitter;
  };
  const Case cases[] = {
    { SPHKernel::Poly6, SPHNormalization::Normalized, false, false, false },
    { SPHKernel::CubicSpline, SPHNormalization::Normalized, true, false, false },
    { SPHKernel::WendlandC2, SPHNormalization::Unnormalized, false, true, true },
    { SPHKernel::Poly6, SPHNormalization::PseudoNormalized, true, true, true },
  };
  for (const Case& c : cases)
  {
    SPHRenderParameters params;
    params.kernel = c.kernel;
    params.normalization = c.mode;
    params.referenceWeightSum =
      referenceWeightSum(c.kernel, particles.medianVolume, particles.medianSupport);
    params.shade = c.shade;
    params.contour = c.contour;
    params.jitter = c.jitter;
    params.lights = { Light() };
    params.material = shinyMaterial();
    expectSameFrameOnEveryPath("SPH kernel " + std::to_string(static_cast<int>(c.kernel)) +
        " mode " + std::to_string(static_cast<int>(c.mode)) + (c.shade ? " shaded" : "") +
        (c.contour ? " contour" : "") + (c.jitter ? " jitter" : ""),
      [&](Frame& frame, RenderStatistics& stats)
      {
        PerspectiveGrid grid;
        renderSPH({ particles, table, grid }, viewOf(rays), params, frame, stats);
      });
  }
}

TEST(SimdDispatch, FluidFramesAreTheSameOnEveryPath)
{
  const Cloud cloud(500, 9, 0.08, 0.12);
  FluidParticles particles;
  buildFluidParticles(cloud.count(), { 0.05, 0.1, -0.1 }, cloud.centre(), cloud.size(), particles);
  ViewRays rays;
  ASSERT_TRUE(rays.assign(
    multiply(perspective(40, 1.0, 0.1, 100), lookAt({ 1.0, 1.5, 3.5 }, { 0, 0, 0 }, { 0, 1, 0 })),
    40,
    40,
    particles.origin));
  for (const double refractiveIndex : { 1.0, 1.33 })
  {
    FluidRenderParameters params;
    params.material = shinyMaterial();
    params.lights = { Light() };
    params.refractiveIndex = refractiveIndex;
    params.ambientOcclusion = refractiveIndex == 1.0;
    expectSameFrameOnEveryPath("fluid, index " + std::to_string(refractiveIndex),
      [&](Frame& frame, RenderStatistics& stats)
      {
        FluidSpans spans;
        EXPECT_TRUE(renderFluid({ particles, spans }, viewOf(rays), params, frame, stats));
      });
  }
}

TEST(SimdDispatch, ZSweepFramesAreTheSameOnEveryPath)
{
  // A 6 x 6 x 6 lattice of hexahedra over [-1, 1]^3 (VTK's vertex order) with a smooth point
  // scalar in [0, 1].
  const int n = 6;
  ZSweepGrid grid;
  const auto point = [&](int i, int j, int k) { return (k * (n + 1) + j) * (n + 1) + i; };
  for (int k = 0; k <= n; ++k)
  {
    for (int j = 0; j <= n; ++j)
    {
      for (int i = 0; i <= n; ++i)
      {
        const Vec3d p{ -1 + 2.0 * i / n, -1 + 2.0 * j / n, -1 + 2.0 * k / n };
        grid.points.push_back(p);
        grid.scalars.push_back(0.5 + 0.5 * std::sin(2 * p.x) * std::cos(1.5 * p.y + p.z));
      }
    }
  }
  grid.cellOffsets.push_back(0);
  for (int k = 0; k < n; ++k)
  {
    for (int j = 0; j < n; ++j)
    {
      for (int i = 0; i < n; ++i)
      {
        for (const int v : { point(i, j, k), point(i + 1, j, k), point(i + 1, j + 1, k),
               point(i, j + 1, k), point(i, j, k + 1), point(i + 1, j, k + 1),
               point(i + 1, j + 1, k + 1), point(i, j + 1, k + 1) })
        {
          grid.connectivity.push_back(v);
        }
        grid.cellTypes.push_back(ZSweepCellType::Hexahedron);
        grid.cellOffsets.push_back(static_cast<std::int64_t>(grid.connectivity.size()));
      }
    }
  }
  ZSweepMesh mesh;
  mesh.build(grid);
  OpticalModel optics;
  optics.assign({ 0.0, 0.3, 0.6, 1.0 },
    { 0.9, 0.1, 0.1, 0.1, 0.9, 0.2, 0.2, 0.3, 0.9, 1.0, 1.0, 0.4 },
    { 0.05, 0.5, 0.1, 0.8 },
    0.5);
  const Mat4 modelToClip =
    multiply(perspective(35, 1.0, 0.5, 100), lookAt({ 2.0, 2.5, 4.5 }, { 0, 0, 0 }, { 0, 1, 0 }));
  for (const ZSweepIntegrator integrator : { ZSweepIntegrator::Exact, ZSweepIntegrator::Farias })
  {
    ZSweepParameters params;
    params.integrator = integrator;
    expectSameFrameOnEveryPath(
      std::string("ZSweep ") + (integrator == ZSweepIntegrator::Exact ? "exact" : "Farias"),
      [&](Frame& frame, RenderStatistics& stats)
      {
        renderZSweep({ mesh, optics }, View(modelToClip, 40, 40, mesh.origin()), params, frame, stats);
      });
  }
}
