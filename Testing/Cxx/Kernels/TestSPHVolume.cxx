// SPH volume ray casting (Limper 2012): the kernels, the perspective grid and the renderer,
// against closed forms and the brute-force reference of SPHReference.h, and its hard cases.
#include "CameraFixtures.h"
#include "RegionFixtures.h"
#include "SPHReference.h"
#include "Mappers/SPH/SPHVolumeRenderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace raymappers;
using namespace raymappers::test;

namespace
{
constexpr double Pi = 3.14159265358979323846;

struct InputParticle
{
  Vec3d x;
  double H, Q, V;
};

SPHParticles makeParticles(const std::vector<InputParticle>& in, const Vec3d& origin = Vec3d())
{
  SPHParticles P;
  buildSPHParticles(
    in.size(),
    origin,
    [&](std::size_t i) { return in[i].x; },
    [&](std::size_t i) { return in[i].H; },
    [&](std::size_t i) { return in[i].Q; },
    [&](std::size_t i) { return in[i].V; },
    P);
  return P;
}

ViewRays perspectiveRays(const Vec3d& eye, const Vec3d& at, const Vec3d& origin, int w, int h,
  double n = 0.1, double f = 100, double fovy = 40)
{
  ViewRays rays;
  EXPECT_TRUE(rays.assign(
    multiply(perspective(fovy, double(w) / h, n, f), lookAt(eye, at, { 0, 1, 0 })), w, h, origin));
  return rays;
}

/// A table of n nodes over [lo, hi]: colour red ramping 0 -> 1, green 1 - red, blue 0.5;
/// opacity per unit distance from alpha(v).
template<typename AlphaFn>
TransferFunctionTable rampTable(double lo, double hi, AlphaFn alpha, int n = 4096)
{
  std::vector<float> rgba;
  for (int k = 0; k < n; ++k)
  {
    const double t = double(k) / (n - 1);
    const double v = lo + t * (hi - lo);
    rgba.insert(rgba.end(), { float(t), float(1 - t), 0.5f, float(alpha(v)) });
  }
  TransferFunctionTable tf;
  tf.assign(rgba, lo, hi, 1.0);
  return tf;
}

/// A random cloud of particles: supports spanning `hRange` (ratio max/min), Q in [1, 5].
std::vector<InputParticle> cloud(int n, double hMin, double hRange, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), q(1, 5), e(0, 1);
  std::vector<InputParticle> out;
  for (int i = 0; i < n; ++i)
  {
    const double H = hMin * std::pow(hRange, e(rng));
    out.push_back({ { u(rng), u(rng), u(rng) }, H, q(rng), 0.5 * H * H * H });
  }
  return out;
}

double maxDifference(const Frame& f, const std::vector<double>& ref)
{
  double m = 0;
  for (std::size_t i = 0; i < ref.size(); ++i)
  {
    m = std::max(m, std::abs(double(f.rgba[i]) - ref[i]));
  }
  return m;
}

bool allFinite(const Frame& f)
{
  for (const float v : f.rgba)
  {
    if (!std::isfinite(v))
    {
      return false;
    }
  }
  return true;
}
}

TEST(SPH, KernelsAreNormalizedAndTheirDerivativesExact)
{
  for (const SPHKernel k : { SPHKernel::Poly6, SPHKernel::CubicSpline, SPHKernel::WendlandC2 })
  {
    const double H = 0.7;
    // Integral over space: 4 pi int_0^H r^2 W(r) dr (Simpson, 20000 intervals).
    const int m = 20000;
    double sum = 0;
    for (int i = 0; i <= m; ++i)
    {
      const double r = H * i / m;
      const double wgt = (i == 0 || i == m) ? 1 : (i % 2 ? 4 : 2);
      sum += wgt * r * r * kernelValue(k, r, H);
    }
    EXPECT_NEAR(4 * Pi * sum * H / m / 3, 1.0, 1e-9) << int(k);
    // The float shape and its derivative against the double value and central differences.
    const double c = kernelNormalization(k) / (H * H * H);
    for (double q : { 0.0, 0.1, 0.3, 0.49, 0.51, 0.7, 0.95 })
    {
      const float q2 = float(q * q);
      float shape = 0, dshape = 0;
      switch (k)
      {
        case SPHKernel::Poly6:
          shape = kernelShape<SPHKernel::Poly6>(q2);
          dshape = kernelShapeDerivativeOverQ<SPHKernel::Poly6>(q2);
          break;
        case SPHKernel::CubicSpline:
          shape = kernelShape<SPHKernel::CubicSpline>(q2);
          dshape = kernelShapeDerivativeOverQ<SPHKernel::CubicSpline>(q2);
          break;
        default:
          shape = kernelShape<SPHKernel::WendlandC2>(q2);
          dshape = kernelShapeDerivativeOverQ<SPHKernel::WendlandC2>(q2);
      }
      EXPECT_NEAR(c * shape, kernelValue(k, q * H, H), 1e-6 * c) << int(k) << " q " << q;
      if (q > 0)
      {
        const double e = 1e-6 * H;
        const double dW = (kernelValue(k, q * H + e, H) - kernelValue(k, q * H - e, H)) / (2 * e);
        // W'(r) = c/H^3 shape'(q)/H = c/H^5 (shape'(q)/q) r.
        EXPECT_NEAR(c / (H * H) * dshape * q * H, dW, 1e-5 * c / H) << int(k) << " q " << q;
      }
    }
  }
}

TEST(SPH, SingleParticleLineIntegralMatchesTheKernelsClosedForm)
{
  // One particle, unnormalized, transfer function with extinction kappa * v: a pixel's
  // opacity is 1 - exp(-kappa Q V int W ds). Through the centre the integral is
  // c/H^2 * (32/35, 3/4, 2/3) for poly6, cubic spline, Wendland C2; off centre at impact b,
  // poly6 gives c/H^9 * 32/35 (H^2 - b^2)^(7/2).
  const int N = 65; // odd: the middle pixel's ray goes through the centre
  const Vec3d eye(0.3, 0.2, 6), centre(0.3, 0.2, 0);
  const ViewRays rays = perspectiveRays(eye, centre, centre, N, N);
  const double H = 0.8, Q = 2.0, V = 0.25, kappa = 1.5;
  for (const SPHKernel k : { SPHKernel::Poly6, SPHKernel::CubicSpline, SPHKernel::WendlandC2 })
  {
    const SPHParticles P = makeParticles({ { centre, H, Q, V } }, centre);
    const double c = kernelNormalization(k);
    const double peak = Q * V * c / (H * H * H);
    const TransferFunctionTable tf =
      rampTable(0, peak, [&](double v) { return 1 - std::exp(-kappa * v); });
    SPHRenderParameters params;
    params.kernel = k;
    params.normalization = SPHNormalization::Unnormalized;
    params.terminationOpacity = 1.0;
    params.stepFactor = 0.25;
    PerspectiveGrid grid;
    Frame frame;
    RenderStatistics stats;
    renderSPH({ P, tf, grid }, viewOf(rays), params, frame, stats);
    const double through = k == SPHKernel::Poly6 ? 32.0 / 35 : (k == SPHKernel::CubicSpline ? 0.75 : 2.0 / 3);
    const double expected = 1 - std::exp(-kappa * Q * V * c / (H * H) * through);
    EXPECT_NEAR(frame.rgba[4 * frame.index(N / 2, N / 2) + 3], expected, 1e-3) << int(k);
    if (k == SPHKernel::Poly6)
    {
      for (const int px : { 36, 40, 44, 48 })
      {
        // Impact parameter: the distance of the centre from the pixel's ray.
        const Vec3d o = rays.start(px + 0.5, N / 2 + 0.5), d = normalize(rays.direction(px + 0.5, N / 2 + 0.5));
        const Vec3d f = Vec3d() - o;
        const double b2 = dot(f, f) - dot(f, d) * dot(f, d);
        const double L2 = std::max(0.0, H * H - b2);
        const double integral = c / std::pow(H, 9) * 32.0 / 35 * std::pow(L2, 3.5);
        EXPECT_NEAR(frame.rgba[4 * frame.index(px, N / 2) + 3], 1 - std::exp(-kappa * Q * V * integral), 1e-3)
          << "pixel " << px;
      }
    }
  }
}

TEST(SPH, NormalizedFieldOfAUniformLatticeEqualsItsValue)
{
  // A 10^3 lattice of spacing dx with constant Q: the normalized field is Q at every
  // sample inside (and at the free surface), so with an opacity independent of the value
  // each pixel's colour over its opacity is the colour of Q. Unnormalized sampling sees the
  // sum of weights instead and does not.
  const double dx = 0.1, Q = 3.0;
  std::vector<InputParticle> in;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k)
        in.push_back({ { i * dx, j * dx, k * dx }, 2.1 * dx, Q, dx * dx * dx });
  const SPHParticles P = makeParticles(in, { 0.45, 0.45, 0.45 });
  const ViewRays rays = perspectiveRays({ 1.9, 1.6, 2.6 }, { 0.45, 0.45, 0.45 }, P.origin, 48, 48);
  const TransferFunctionTable tf = rampTable(0, 10, [](double) { return 0.2; });
  double worstNormalized = 0, worstUnnormalized = 0;
  for (const SPHNormalization mode : { SPHNormalization::Normalized, SPHNormalization::Unnormalized })
  {
    SPHRenderParameters params;
    params.normalization = mode;
    params.terminationOpacity = 1.0;
    PerspectiveGrid grid;
    Frame frame;
    RenderStatistics stats;
    renderSPH({ P, tf, grid }, viewOf(rays), params, frame, stats);
    int covered = 0;
    for (int p = 0; p < 48 * 48; ++p)
    {
      const float a = frame.rgba[4 * p + 3];
      if (a > 0.01f)
      {
        ++covered;
        const double red = frame.rgba[4 * p] / a; // red ramps v / 10
        double& worst = mode == SPHNormalization::Normalized ? worstNormalized : worstUnnormalized;
        worst = std::max(worst, std::abs(red * 10 - Q));
      }
    }
    EXPECT_GT(covered, 400);
  }
  EXPECT_LT(worstNormalized, 1e-5 * 10);
  EXPECT_GT(worstUnnormalized, 0.5);
}

TEST(SPH, MatchesTheBruteForceReferenceInEveryMode)
{
  // Supports varying 100x, coincident particles, and every mode and effect.
  std::vector<InputParticle> in = cloud(60, 0.02, 100, 7);
  in.push_back(in[3]);
  in.push_back({ in[5].x, in[5].H, 4.5, in[5].V });
  const SPHParticles P = makeParticles(in, { 0.1, -0.2, 0.05 });
  const ViewRays rays = perspectiveRays({ 1.5, 1.0, 3.5 }, { 0, 0, 0 }, P.origin, 40, 36);
  const TransferFunctionTable tf = rampTable(0, 6, [](double v) { return std::min(0.9, 0.15 * v); }, 64);
  struct Case
  {
    SPHKernel kernel;
    SPHNormalization mode;
    bool shade, contour, jitter;
    int tile, slab;
  };
  const Case cases[] = {
    { SPHKernel::Poly6, SPHNormalization::Normalized, false, false, false, 16, 0 },
    { SPHKernel::CubicSpline, SPHNormalization::Normalized, true, false, false, 8, 3 },
    { SPHKernel::WendlandC2, SPHNormalization::Normalized, false, true, false, 16, 4 },
    { SPHKernel::Poly6, SPHNormalization::Unnormalized, false, false, true, 12, 0 },
    { SPHKernel::WendlandC2, SPHNormalization::PseudoNormalized, true, true, true, 16, 1 },
  };
  for (const Case& c : cases)
  {
    SPHRenderParameters params;
    params.kernel = c.kernel;
    params.normalization = c.mode;
    params.referenceWeightSum = referenceWeightSum(c.kernel, P.medianVolume, P.medianSupport);
    params.shade = c.shade;
    params.contour = c.contour;
    params.contourColor[0] = 0.2;
    params.jitter = c.jitter;
    params.tileSize = c.tile;
    params.slabDepth = c.slab;
    params.lights = { Light() };
    params.material.ambient = 0.2;
    params.material.diffuse = 0.7;
    params.material.specular = 0.3;
    params.material.specularPower = 10;
    PerspectiveGrid grid;
    Frame frame;
    RenderStatistics stats;
    renderSPH({ P, tf, grid }, viewOf(rays), params, frame, stats);
    const std::vector<double> ref = renderReference(P, rays, grid.steps(), params, tf, nullptr);
    double sumAlpha = 0;
    for (std::size_t i = 3; i < ref.size(); i += 4)
    {
      sumAlpha += ref[i];
    }
    EXPECT_GT(sumAlpha, 50.0); // the picture is not empty
    EXPECT_TRUE(allFinite(frame));
    // Shading: where grad A nearly vanishes (near a lone particle's centre) the normal is
    // ill-conditioned, and float sums against double central differences move it a little.
    EXPECT_LT(maxDifference(frame, ref), c.shade ? 1e-2 : 2e-3)
      << "kernel " << int(c.kernel) << " mode " << int(c.mode) << " shade " << c.shade
      << " contour " << c.contour << " jitter " << c.jitter;
  }
}

TEST(SPH, CameraInsideTheFluidAndParticlesCutByTheNearPlane)
{
  // The eye sits inside the cloud; the near plane cuts through particles.
  const std::vector<InputParticle> in = cloud(200, 0.25, 3, 11);
  const SPHParticles P = makeParticles(in);
  const ViewRays rays = perspectiveRays({ 0.05, 0.0, 0.1 }, { 0.3, 0.2, -1 }, P.origin, 32, 32, 0.05, 10, 60);
  const TransferFunctionTable tf = rampTable(0, 6, [](double v) { return std::min(0.9, 0.1 * v); }, 64);
  SPHRenderParameters params;
  params.terminationOpacity = 0.98;
  PerspectiveGrid grid;
  Frame frame;
  RenderStatistics stats;
  renderSPH({ P, tf, grid }, viewOf(rays), params, frame, stats);
  EXPECT_GE(grid.steps().zeta(0), rays.nearZeta() - 1e-9);
  const std::vector<double> ref = renderReference(P, rays, grid.steps(), params, tf, nullptr);
  EXPECT_TRUE(allFinite(frame));
  EXPECT_LT(maxDifference(frame, ref), 2e-3);
  double coverage = 0;
  for (std::size_t i = 3; i < ref.size(); i += 4)
  {
    coverage += frame.rgba[i];
  }
  EXPECT_GT(coverage, 0.3 * 32 * 32); // the fluid around the eye covers much of the view
}

TEST(SPH, OpaqueGeometryStopsTheRays)
{
  const SPHParticles P = makeParticles(cloud(50, 0.2, 2, 3));
  const ViewRays rays = perspectiveRays({ 0.5, 0.5, 4 }, { 0, 0, 0 }, P.origin, 32, 32, 1, 10);
  const TransferFunctionTable tf = rampTable(0, 6, [](double v) { return std::min(0.9, 0.1 * v); }, 64);
  // Geometry over the left half at window depth 0.83, zeta = 4 (near 1, far 10): in the
  // middle of the cloud.
  std::vector<float> depth(32 * 32, 1.f);
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 16; ++i)
      depth[j * 32 + i] = 0.83f;
  SPHRenderParameters params;
  PerspectiveGrid grid;
  Frame frame, open;
  RenderStatistics stats;
  renderSPH({ P, tf, grid }, viewOf(rays, depth.data()), params, frame, stats);
  const std::vector<double> ref = renderReference(P, rays, grid.steps(), params, tf, depth.data());
  EXPECT_LT(maxDifference(frame, ref), 2e-3);
  renderSPH({ P, tf, grid }, viewOf(rays), params, open, stats);
  double left = 0, leftOpen = 0;
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 16; ++i)
    {
      left += frame.rgba[4 * frame.index(i, j) + 3];
      leftOpen += open.rgba[4 * open.index(i, j) + 3];
    }
  EXPECT_LT(left, 0.9 * leftOpen);
}

// Distributed rendering (RegionBox.h): every region renders all particles but only its own
// samples (a sample's segment keeps its whole length); the regions' images blended front to
// back in visibility order are the whole image. A kd-tree cut: x = 0.1, then z = 0 on the
// eye's side (eye at x = 0.5, z = 4), so the order is (x >= 0.1, z >= 0), (x >= 0.1,
// z < 0), (x < 0.1).
TEST(SPH, RegionsCompositeToTheWholeImage)
{
  const SPHParticles P = makeParticles(cloud(200, 0.2, 3, 7));
  const ViewRays rays = perspectiveRays({ 0.5, 0.5, 4 }, { 0, 0, 0 }, P.origin, 32, 32, 1, 10);
  const TransferFunctionTable tf = rampTable(0, 6, [](double v) { return std::min(0.9, 0.1 * v); }, 64);
  for (const bool shade : { false, true })
  {
    SPHRenderParameters params;
    params.terminationOpacity = 1.0; // a region cannot know the opacity in front of it
    params.shade = shade;
    params.lights.push_back(Light{});
    PerspectiveGrid grid;
    Frame whole;
    RenderStatistics stats;
    renderSPH({ P, tf, grid }, viewOf(rays), params, whole, stats);

    Frame composite;
    composite.resize(32, 32);
    double alphaWhole = 0;
    for (const RegionBox& region : kdCutFrontToBack(0.1, 0.0))
    {
      params.region = region;
      Frame part;
      renderSPH({ P, tf, grid }, viewOf(rays), params, part, stats);
      blendBehind(composite, part);
    }
    std::vector<double> ref(whole.rgba.begin(), whole.rgba.end());
    for (std::size_t i = 3; i < ref.size(); i += 4)
    {
      alphaWhole += ref[i];
    }
    EXPECT_GT(alphaWhole, 0.2 * 32 * 32);
    EXPECT_TRUE(allFinite(composite));
    EXPECT_LT(maxDifference(composite, ref), 2e-5) << (shade ? "shaded" : "unshaded");
  }
}

// Distributed rendering as the representation does it: each region holds only its own
// particles and the ghosts whose support meets it (so each has its own front, back and
// smallest support), the smallest support of all regions given to every one. The sample
// depths lie on the view's lattice (PerspectiveGrid.h), so the regions share every sample
// of the one-region image and their blend is that image to float rounding, for
// pixel-tied steps (samplesPerSupport 0) and field steps, perspective and parallel views.
// Anchoring each region's steps at its own front instead (the thesis's zeta_0) fails it by
// about 0.05 (samples shifted by a fraction of a step).
TEST(SPHHardCases, RegionsWithTheirOwnParticlesCompositeToTheWholeImage)
{
  const std::vector<InputParticle> in = cloud(300, 0.15, 3, 5);
  const SPHParticles P = makeParticles(in);
  const TransferFunctionTable tf =
    rampTable(0, 6, [](double v) { return std::min(0.9, 0.15 * v); }, 64);
  const auto regions = kdCutFrontToBack(0.1, 0.0);
  std::vector<SPHParticles> pieces;
  for (const RegionBox& box : regions)
  {
    std::vector<InputParticle> mine;
    for (const InputParticle& p : in)
    {
      double d2 = 0; // squared distance from the centre to the box
      for (int a = 0; a < 3; ++a)
      {
        const double e = std::max({ box.lo[a] - p.x[a], 0.0, p.x[a] - box.hi[a] });
        d2 += e * e;
      }
      if (d2 <= p.H * p.H) // H is the support radius here
      {
        mine.push_back(p);
      }
    }
    pieces.push_back(makeParticles(mine, mine.empty() ? Vec3d() : mine.front().x));
  }
  ViewRays parallel;
  ASSERT_TRUE(parallel.assign(multiply(orthographic(2, 2, 0.5, 10),
                                lookAt({ 0.5, 0.5, 4 }, { 0, 0, 0 }, { 0, 1, 0 })),
    48, 48, P.origin));
  const ViewRays perspective =
    perspectiveRays({ 0.5, 0.5, 4 }, { 0, 0, 0 }, P.origin, 48, 48, 1, 10);
  for (const ViewRays* rays : { &perspective, static_cast<const ViewRays*>(&parallel) })
  {
    for (const double samplesPerSupport : { 0.0, 8.0 })
    {
      SPHRenderParameters params;
      params.terminationOpacity = 1.0; // a region cannot know the opacity in front of it
      params.samplesPerSupport = samplesPerSupport;
      params.smallestSupport = P.minSupport;
      PerspectiveGrid grid;
      RenderStatistics stats;
      Frame whole, composite;
      renderSPH({ P, tf, grid }, viewOf(*rays), params, whole, stats);
      composite.resize(whole.width, whole.height);
      for (std::size_t r = 0; r < regions.size(); ++r)
      {
        params.region = regions[r];
        Frame part;
        // Each region's float origin is its own (as the mapper's, the centre of its points).
        const View view(rays->modelToClip(), rays->width(), rays->height(), pieces[r].origin);
        renderSPH({ pieces[r], tf, grid }, view, params, part, stats);
        blendBehind(composite, part);
      }
      double alpha = 0;
      for (std::size_t i = 3; i < whole.rgba.size(); i += 4)
      {
        alpha += whole.rgba[i];
      }
      const std::vector<double> ref(whole.rgba.begin(), whole.rgba.end());
      std::printf("%s, %g samples per support: max difference %.3g\n",
        rays == &parallel ? "parallel" : "perspective", samplesPerSupport,
        maxDifference(composite, ref));
      EXPECT_GT(alpha, 0.2 * whole.width * whole.height);
      EXPECT_LT(maxDifference(composite, ref), 1e-4);
    }
  }
}

TEST(SPH, OpacityCorrectionMakesTheStepIrrelevantInAHomogeneousMedium)
{
  // The normalized field of a constant-Q lattice is constant, so the opacity along a ray
  // depends only on its length inside: the same for any step factor.
  const double dx = 0.1;
  std::vector<InputParticle> in;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      for (int k = 0; k < 8; ++k)
        in.push_back({ { i * dx, j * dx, k * dx }, 2.1 * dx, 2.0, dx * dx * dx });
  const SPHParticles P = makeParticles(in, { 0.35, 0.35, 0.35 });
  const ViewRays rays = perspectiveRays({ 0.35, 0.35, 2.5 }, { 0.35, 0.35, 0.35 }, P.origin, 64, 64);
  const TransferFunctionTable tf = rampTable(0, 4, [](double) { return 0.6; });
  std::vector<Frame> frames(3);
  const double factors[] = { 0.5, 1.0, 2.0 };
  for (int f = 0; f < 3; ++f)
  {
    SPHRenderParameters params;
    params.stepFactor = factors[f];
    params.terminationOpacity = 1.0;
    PerspectiveGrid grid;
    RenderStatistics stats;
    renderSPH({ P, tf, grid }, viewOf(rays), params, frames[f], stats);
  }
  // The middle pixel's ray crosses the whole lattice (about 0.7 + 2 x 0.21 long).
  EXPECT_GT(frames[1].rgba[4 * frames[1].index(32, 32) + 3], 0.5f);
  double worst = 0, mean = 0;
  for (std::size_t i = 3; i < frames[0].rgba.size(); i += 4)
  {
    const double e = std::max(std::abs(frames[0].rgba[i] - frames[1].rgba[i]),
      std::abs(frames[2].rgba[i] - frames[1].rgba[i]));
    worst = std::max(worst, e);
    mean += e / (64 * 64);
  }
  // Without the correction a step twice as long would double the optical depth; with it
  // the only difference is where the last step ends at the fluid's hard boundary (about
  // a pixel's footprint, about 0.025 here, at an extinction of -ln(0.4)).
  EXPECT_LT(mean, 0.01);
  EXPECT_LT(worst, 0.06);
}

TEST(SPH, BadParticlesAreSkippedAndCounted)
{
  std::vector<InputParticle> good = cloud(30, 0.2, 2, 5);
  std::vector<InputParticle> all = good;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  all.insert(all.begin() + 4, { { nan, 0, 0 }, 0.2, 1, 0.01 });
  all.insert(all.begin() + 9, { { 0, 0, 0 }, nan, 1, 0.01 });
  all.insert(all.begin() + 12, { { 0, 0, 0 }, 0.0, 1, 0.01 });
  all.insert(all.begin() + 15, { { 0, 0, 0 }, -0.3, 1, 0.01 });
  all.insert(all.begin() + 17, { { 0, 0, 0 }, 0.3, nan, 0.01 });
  all.insert(all.begin() + 20, { { 0, 0, 0 }, 0.3, 1, -0.01 });
  const SPHParticles P = makeParticles(all), Pgood = makeParticles(good);
  EXPECT_EQ(P.size(), good.size());
  EXPECT_EQ(P.skippedNonFinite, 2u);
  EXPECT_EQ(P.skippedBadSupport, 3u);
  EXPECT_EQ(P.skippedBadVolume, 1u);
  const ViewRays rays = perspectiveRays({ 0.5, 0.5, 4 }, { 0, 0, 0 }, P.origin, 24, 24);
  const TransferFunctionTable tf = rampTable(0, 6, [](double v) { return std::min(0.9, 0.1 * v); }, 64);
  SPHRenderParameters params;
  PerspectiveGrid grid;
  Frame a, b;
  RenderStatistics stats;
  renderSPH({ P, tf, grid }, viewOf(rays), params, a, stats);
  renderSPH({ Pgood, tf, grid }, viewOf(rays), params, b, stats);
  EXPECT_EQ(a.rgba, b.rgba);
}

TEST(SPH, EmptyInputAndParticlesOutOfViewGiveAnEmptyFrame)
{
  const TransferFunctionTable tf = rampTable(0, 1, [](double) { return 0.5; }, 8);
  SPHRenderParameters params;
  PerspectiveGrid grid;
  Frame frame;
  RenderStatistics stats;
  const SPHParticles none = makeParticles({});
  const ViewRays rays = perspectiveRays({ 0, 0, 4 }, { 0, 0, 0 }, Vec3d(), 16, 16);
  renderSPH({ none, tf, grid }, viewOf(rays), params, frame, stats);
  EXPECT_EQ(frame.width, 16);
  for (const float v : frame.rgba)
    EXPECT_EQ(v, 0.f);
  const SPHParticles behind = makeParticles({ { { 0, 0, 9 }, 0.5, 1, 1 } });
  renderSPH({ behind, tf, grid }, viewOf(rays), params, frame, stats);
  EXPECT_EQ(stats.counter("particles_in_view"), 0);
  for (const float v : frame.rgba)
    EXPECT_EQ(v, 0.f);
}

TEST(SPH, FootprintsBeyondIntRangeUnderATinyViewAngleStayOutOfView)
{
  // VTK's smallest view angle, 1e-8 degrees (what a zero view angle becomes), magnifies the
  // projection by 1e10: a sphere 0.5 off the axis at depth 4 projects 1e9 image widths
  // away. Its extent must not wrap into the image through an int conversion (it crashed
  // the perspective grid's cell counting with tiles at -2^27).
  const ViewRays rays =
    perspectiveRays({ 0, 0, 4 }, { 0, 0, 0 }, Vec3d(), 16, 16, 0.1, 100, 1e-8);
  for (const Vec3d& c : { Vec3d(0.5, 0, 0), Vec3d(-0.5, 0, 0), Vec3d(0, 0.5, 0), Vec3d(0, -0.5, 0) })
  {
    const SphereFootprint f = rays.footprint(c, 0.1);
    EXPECT_FALSE(f.inView) << c.x << " " << c.y;
  }
  // The sphere on the axis covers every pixel.
  const SphereFootprint f = rays.footprint(Vec3d(0, 0, 0), 0.1);
  EXPECT_TRUE(f.inView);
  EXPECT_EQ(f.i0, 0);
  EXPECT_EQ(f.i1, 15);
  const TransferFunctionTable tf = rampTable(0, 1, [](double) { return 0.5; }, 8);
  SPHRenderParameters params;
  PerspectiveGrid grid;
  Frame frame;
  RenderStatistics stats;
  const SPHParticles P = makeParticles({ { { 0.5, 0, 0 }, 0.1, 1, 1 }, { { 0, 0, 0 }, 0.1, 1, 1 } });
  renderSPH({ P, tf, grid }, viewOf(rays), params, frame, stats);
  EXPECT_EQ(stats.counter("particles_in_view"), 1);
  for (const float v : frame.rgba)
  {
    EXPECT_TRUE(std::isfinite(v));
  }
}

TEST(SPH, AnEffectThatIsOffCostsNothing)
{
  const SPHParticles P = makeParticles(cloud(40, 0.2, 2, 9));
  const ViewRays rays = perspectiveRays({ 0.5, 0.5, 4 }, { 0, 0, 0 }, P.origin, 32, 32);
  const TransferFunctionTable tf = rampTable(0, 6, [](double v) { return std::min(0.9, 0.1 * v); }, 64);
  PerspectiveGrid grid;
  Frame frame;
  SPHRenderParameters params;
  params.normalization = SPHNormalization::Unnormalized;
  params.tileSize = 4;
  RenderStatistics plain;
  renderSPH({ P, tf, grid }, viewOf(rays), params, frame, plain);
  EXPECT_GT(plain.counter("kernel_evaluations"), 0);
  EXPECT_EQ(plain.counter("weight_sums"), 0);
  EXPECT_EQ(plain.counter("gradient_evaluations"), 0);
  EXPECT_EQ(plain.counter("shaded_samples"), 0);
  EXPECT_EQ(plain.counter("contour_samples"), 0);
  EXPECT_FALSE(plain.effect("normalization"));
  EXPECT_FALSE(plain.effect("gradient_shading"));
  EXPECT_GT(plain.counter("cells_leaped"), 0);

  params.normalization = SPHNormalization::Normalized;
  params.shade = true;
  params.lights = { Light() };
  params.contour = true;
  RenderStatistics all;
  renderSPH({ P, tf, grid }, viewOf(rays), params, frame, all);
  EXPECT_EQ(all.counter("weight_sums"), all.counter("kernel_evaluations"));
  EXPECT_EQ(all.counter("gradient_evaluations"), all.counter("kernel_evaluations"));
  EXPECT_GT(all.counter("shaded_samples"), 0);
  EXPECT_GT(all.counter("contour_samples"), 0);
  EXPECT_TRUE(all.effect("normalization"));
}

TEST(SPH, ParallelProjectionTakesUniformSteps)
{
  const SPHParticles P = makeParticles(cloud(40, 0.2, 2, 13));
  ViewRays rays;
  ASSERT_TRUE(rays.assign(multiply(orthographic(1.5, 1.5, 1, 10), lookAt({ 0.4, 0.3, 5 }, { 0, 0, 0 }, { 0, 1, 0 })),
    28, 28, P.origin));
  EXPECT_FALSE(rays.isPerspective());
  const TransferFunctionTable tf = rampTable(0, 6, [](double v) { return std::min(0.9, 0.1 * v); }, 64);
  SPHRenderParameters params;
  PerspectiveGrid grid;
  Frame frame;
  RenderStatistics stats;
  renderSPH({ P, tf, grid }, viewOf(rays), params, frame, stats);
  EXPECT_FALSE(grid.steps().logarithmic);
  const std::vector<double> ref = renderReference(P, rays, grid.steps(), params, tf, nullptr);
  EXPECT_LT(maxDifference(frame, ref), 2e-3);
}

TEST(SPH, TheFieldStepFollowsTheSupportNotTheResolution)
{
  // At 256 x 256 the pixel footprint is far finer than the particles' support; a step of
  // H_min / 8 takes a fraction of the samples and stays close to the converged picture.
  const SPHParticles P = makeParticles(cloud(150, 0.25, 1.5, 17));
  const ViewRays rays = perspectiveRays({ 0.6, 0.5, 4 }, { 0, 0, 0 }, P.origin, 256, 256);
  const TransferFunctionTable tf = rampTable(0, 6, [](double v) { return std::min(0.9, 0.1 * v); }, 64);
  SPHRenderParameters fine, bounded;
  fine.stepFactor = 0.5;
  fine.terminationOpacity = bounded.terminationOpacity = 1.0;
  bounded.samplesPerSupport = 8;
  PerspectiveGrid grid;
  Frame reference, frame;
  RenderStatistics a, b;
  renderSPH({ P, tf, grid }, viewOf(rays), fine, reference, a);
  renderSPH({ P, tf, grid }, viewOf(rays), bounded, frame, b);
  // The step at the particles' far end is the longest inside them.
  double farEnd = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
  {
    farEnd = std::max(farEnd, rays.zetaOf(Vec3d(P.centers[i])) + P.support[i]);
  }
  const DepthSteps& s = grid.steps();
  const double k = std::floor(s.coordinate(farEnd));
  EXPECT_LE(s.zeta(k + 1) - s.zeta(k), P.minSupport / 8.0 * (1 + 1e-6));
  EXPECT_LT(b.counter("kernel_evaluations") * 4, a.counter("kernel_evaluations"));
  double worst = 0, mean = 0;
  for (std::size_t i = 0; i < frame.rgba.size(); ++i)
  {
    const double e = std::abs(frame.rgba[i] - reference.rgba[i]);
    worst = std::max(worst, e);
    mean += e / frame.rgba.size();
  }
  std::printf("field step: %lld vs %lld evaluations, max %.4f mean %.5f\n",
    static_cast<long long>(b.counter("kernel_evaluations")),
    static_cast<long long>(a.counter("kernel_evaluations")), worst, mean);
  EXPECT_LT(worst, 0.03);
}

namespace
{
/// A block of n^3 particles at spacing dx (support 2.1 dx, volume scale * dx^3) with Q
/// uniform in [qLo, qHi] (the extremes included), centred on the origin.
std::vector<InputParticle> block(int n, double dx, double qLo, double qHi, double volumeScale)
{
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<InputParticle> out;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
      {
        const Vec3d x((i - 0.5 * (n - 1)) * dx, (j - 0.5 * (n - 1)) * dx, (k - 0.5 * (n - 1)) * dx);
        out.push_back({ x, 2.1 * dx, qLo + (qHi - qLo) * u(rng), volumeScale * dx * dx * dx });
      }
  out[0].Q = qLo;
  out[1].Q = qHi;
  return out;
}
}

// The free surface, where the sum of weights B goes to 0: near the supports' edges W ~
// (1 - q^2)^3 comes down to 2e-22 in float. The normalized field A / B is a weighted mean of
// the Q_i, so it must stay in [Qmin, Qmax]: the transfer function here spans three times
// that range, with blue 0 on [Qmin, Qmax] (and one node either side) and 1 beyond, so any
// sample classified outside Q's range turns its pixel blue. Three scales: Q in [1, 2];
// Q ~ 1e-37 (Q_i V_i is a denormal float, and A underflows to 0 near the edges while B
// does not: A / B would be 0 there, or off by the denormals' rounding); volumes 1e-20
// dx^3 (B itself is denormal near the edges: below FLT_MIN the sample is empty, at 0 it
// would be 0 / 0). No NaN anywhere, no blue, and for the first scale the brute force's
// picture, with every kernel, shading and contours.
TEST(SPHHardCases, WeightSumVanishingAtTheFreeSurface)
{
  struct Scale
  {
    double qLo, qHi, volume;
  };
  for (const Scale& scale : { Scale{ 1, 2, 1 }, Scale{ 1e-37, 2e-37, 1 }, Scale{ 1, 2, 1e-20 } })
  {
    const SPHParticles P = makeParticles(block(8, 0.1, scale.qLo, scale.qHi, scale.volume));
    ASSERT_EQ(P.minQ, float(scale.qLo));
    ASSERT_EQ(P.maxQ, float(scale.qHi));
    const ViewRays rays = perspectiveRays({ 0.9, 0.7, 1.6 }, { 0, 0, 0 }, P.origin, 40, 40);
    // 3001 nodes over [Qmin - D, Qmax + D]: Qmin and Qmax are nodes 1000 and 2000.
    const double D = double(P.maxQ) - double(P.minQ);
    std::vector<float> rgba;
    for (int k = 0; k <= 3000; ++k)
    {
      const bool outside = k < 999 || k > 2001;
      rgba.insert(rgba.end(), { 1.f, 0.5f, outside ? 1.f : 0.f, 0.4f });
    }
    TransferFunctionTable tf;
    tf.assign(rgba, double(P.minQ) - D, double(P.maxQ) + D, 1.0);
    for (const SPHKernel kernel :
      { SPHKernel::Poly6, SPHKernel::CubicSpline, SPHKernel::WendlandC2 })
    {
      SPHRenderParameters params;
      params.kernel = kernel;
      params.terminationOpacity = 1.0;
      params.referenceWeightSum = referenceWeightSum(kernel, P.medianVolume, P.medianSupport);
      params.contour = kernel == SPHKernel::WendlandC2;
      params.shade = kernel == SPHKernel::CubicSpline;
      params.lights = { Light() };
      PerspectiveGrid grid;
      Frame frame;
      RenderStatistics stats;
      renderSPH({ P, tf, grid }, viewOf(rays), params, frame, stats);
      EXPECT_TRUE(allFinite(frame));
      int blue = 0;
      double coverage = 0;
      for (std::size_t p = 0; p < frame.depth.size(); ++p)
      {
        blue += frame.rgba[4 * p + 2] != 0.f;
        coverage += frame.rgba[4 * p + 3];
      }
      EXPECT_EQ(blue, 0) << "Q from " << scale.qLo << ", volume " << scale.volume << ", kernel "
                         << int(kernel);
      EXPECT_GT(coverage, 300.0);
      if (scale.qLo == 1 && scale.volume == 1)
      {
        const std::vector<double> ref = renderReference(P, rays, grid.steps(), params, tf, nullptr);
        EXPECT_LT(maxDifference(frame, ref), params.shade ? 1e-2 : 2e-3) << int(kernel);
      }
    }
  }
}

// Smoothing lengths over three decades: 60 particles with supports 0.1 to 1 in a box of
// side 2, and beyond their reach a cluster of 300 with supports 0.001 to 0.002 in a box of
// side 0.1 (the field there is theirs alone), seen from 0.25 away (a pixel 0.004 wide
// there), from just above it and from inside it. The field step is the mapper's default, the
// smallest support over 8 (1.3e-4); the step is the longer of it and the pixel-tied one, so from
// inside (near plane 0.002) uniform steps of 1.3e-4 run up to where the pixel-tied ones are longer,
// and beyond that the smallest supports take a few samples each. No hang, no NaN, the brute force's
// picture (the same samples).
TEST(SPHHardCases, SmoothingLengthsOverThreeDecades)
{
  std::vector<InputParticle> in = cloud(60, 0.1, 10, 43);
  std::mt19937 rng(47);
  std::uniform_real_distribution<double> u(-1, 1), e(0, 1), q(1, 5);
  for (int k = 0; k < 300; ++k)
  {
    const double H = 0.001 * std::pow(2.0, e(rng));
    in.push_back(
      { { 0.05 * u(rng), 0.05 * u(rng), 2.5 + 0.05 * u(rng) }, H, q(rng), 0.5 * H * H * H });
  }
  const SPHParticles P = makeParticles(in);
  EXPECT_GT(P.maxSupport / P.minSupport, 500);
  const TransferFunctionTable tf = rampTable(
    0, 6, [](double v) { return std::min(0.999, 0.2 * v); }, 64);
  const ViewRays near =
    perspectiveRays({ 0.05, 0.03, 2.75 }, { 0, 0, 2.5 }, P.origin, 48, 48, 0.02, 10, 40);
  const ViewRays above =
    perspectiveRays({ 0.01, 0.0, 2.556 }, { 0, 0, 0 }, P.origin, 48, 48, 0.002, 10, 40);
  const ViewRays inside =
    perspectiveRays({ 0.01, 0.0, 2.53 }, { 0, 0, 0 }, P.origin, 48, 48, 0.002, 10, 20);
  for (const ViewRays* rays : { &near, &above, &inside })
  {
    SPHRenderParameters params;
    params.samplesPerSupport = 8;
    params.terminationOpacity = 1.0;
    PerspectiveGrid grid;
    Frame frame;
    RenderStatistics stats;
    renderSPH({ P, tf, grid }, viewOf(*rays), params, frame, stats);
    const DepthSteps& steps = grid.steps();
    int small = 0; // pixels whose ray meets a support below 0.002
    for (int py = 0; py < 48; ++py)
    {
      for (int px = 0; px < 48; ++px)
      {
        for (const std::size_t k : particlesNearLine(
               P, rays->start(px + 0.5, py + 0.5), rays->direction(px + 0.5, py + 0.5), 0.0))
        {
          if (P.support[k] <= 0.002f)
          {
            ++small;
            break;
          }
        }
      }
    }
    std::printf("three decades: %lld depth cells of %lld samples, uniform steps of %g up to %g, "
                "%lld samples taken, %d pixels see supports below 0.002\n",
      static_cast<long long>(stats.counter("depth_cells")),
      static_cast<long long>(stats.counter("samples_per_cell")),
      steps.uniformStep,
      steps.zetaBreak,
      static_cast<long long>(stats.counter("samples")),
      small);
    EXPECT_LE(stats.counter("depth_cells"), 2048);
    EXPECT_EQ(steps.uniformStep > 0, rays == &inside);
    EXPECT_GT(small, 40);
    EXPECT_TRUE(allFinite(frame));
    const std::vector<double> ref = renderReference(P, *rays, steps, params, tf, nullptr);
    EXPECT_LT(maxDifference(frame, ref), 2e-3);
  }
}

// The camera inside one particle's support (radius 2, the eye 0.4 from its centre, the
// near plane at 0.05): the normalized field is Q wherever B > 0, so the opacity of a pixel
// is 1 - exp(-tau L) with L the length of its ray from the near plane to where it leaves
// the support, up to half the step there (the last sample inside stands for its whole
// step). A first sample beyond the near plane would lose the fluid in front of it.
TEST(SPHHardCases, CameraInsideTheFluidLosesNothingInFront)
{
  const double H = 2.0;
  const SPHParticles P = makeParticles({ { { 0, 0, 0 }, H, 3.0, 1.0 } });
  const ViewRays rays =
    perspectiveRays({ 0.2, 0.1, 0.3 }, { 1, 0.5, -2 }, P.origin, 32, 32, 0.05, 10, 60);
  const double tau = -std::log(1 - 0.3);
  const TransferFunctionTable tf = rampTable(
    0, 6, [](double) { return 0.3; }, 64);
  for (const SPHKernel kernel : { SPHKernel::Poly6, SPHKernel::CubicSpline, SPHKernel::WendlandC2 })
  {
    SPHRenderParameters params;
    params.kernel = kernel;
    params.terminationOpacity = 1.0;
    PerspectiveGrid grid;
    Frame frame;
    RenderStatistics stats;
    renderSPH({ P, tf, grid }, viewOf(rays), params, frame, stats);
    EXPECT_TRUE(allFinite(frame));
    const DepthSteps& steps = grid.steps();
    EXPECT_NEAR(steps.zeta(0), rays.nearZeta(), 1e-9);
    int wrong = 0;
    for (int py = 0; py < 32; ++py)
    {
      for (int px = 0; px < 32; ++px)
      {
        const Vec3d a = rays.start(px + 0.5, py + 0.5), b = rays.direction(px + 0.5, py + 0.5);
        // |a + z b| = H: the exit depth.
        const double qa = dot(b, b), qb = dot(a, b), qc = dot(a, a) - H * H;
        const double zExit = (-qb + std::sqrt(qb * qb - qa * qc)) / qa;
        const double k = std::floor(steps.coordinate(zExit));
        const double halfStep = 0.5 * (steps.zeta(k + 1) - steps.zeta(k)) * length(b);
        const double L = (zExit - rays.nearZeta()) * length(b);
        const double A = frame.rgba[4 * frame.index(px, py) + 3];
        const double travelled = -std::log(1 - A) / tau;
        wrong += std::fabs(travelled - L) > halfStep + 1e-4 * L;
      }
    }
    EXPECT_EQ(wrong, 0) << "kernel " << int(kernel);
  }
}
