// RBF volume ray casting (Knoll et al. 2014) against closed forms and an independent
// brute-force reference: a per-pixel ray march in double precision that sums every
// particle at every sample (no BVH, no packets, std::exp in double).
#include "CameraFixtures.h"
#include "Mappers/RBF/FastExp.h"
#include "Mappers/RBF/ParticleBVH.h"
#include "Mappers/RBF/RBFVolumeRenderer.h"
#include "RegionFixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <vector>

using namespace raymappers;
using namespace raymappers::test;

namespace
{
struct Input
{
  std::vector<Vec3d> p;
  std::vector<double> r, k;
  std::vector<int> field;
  int numFields = 1;
};

RBFParticles makeParticles(const Input& in, const Vec3d& origin)
{
  RBFParticles s;
  buildRBFParticles(
    in.p.size(),
    origin,
    in.numFields,
    [&](std::size_t i) { return in.p[i]; },
    [&](std::size_t i) { return in.r[i]; },
    [&](std::size_t i) { return in.k.empty() ? 1.0 : in.k[i]; },
    [&](std::size_t i) { return in.field.empty() ? 0 : in.field[i]; },
    s);
  return s;
}

Input randomCloud(int n, double extent, unsigned seed, int numFields = 1)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-extent, extent), ur(0.3, 0.8), uk(0.5, 1.5);
  Input in;
  in.numFields = numFields;
  for (int i = 0; i < n; ++i)
  {
    in.p.push_back({ u(rng), u(rng), u(rng) });
    in.r.push_back(ur(rng));
    in.k.push_back(uk(rng));
    in.field.push_back(i % numFields);
  }
  return in;
}

/// A table of n samples over [0, hi]: colour ramps, opacity from `alpha`.
template<typename AlphaFn>
TransferFunctionTable table(double hi, int n, double unit, AlphaFn alpha, double hue = 0.0)
{
  std::vector<float> rgba;
  for (int k = 0; k < n; ++k)
  {
    const double x = double(k) / (n - 1);
    rgba.push_back(static_cast<float>(x));
    rgba.push_back(static_cast<float>(1.0 - x));
    rgba.push_back(static_cast<float>(hue));
    rgba.push_back(static_cast<float>(alpha(x * hi)));
  }
  TransferFunctionTable t;
  t.assign(rgba, 0.0, hi, unit);
  return t;
}

RayCamera camera(const Vec3d& eye, const Vec3d& at, const Vec3d& origin, int w = 40, int h = 32)
{
  return RayCamera(
    multiply(perspective(35, double(w) / h, 0.5, 100), lookAt(eye, at, { 0, 1, 0 })), w, h, origin);
}

struct Rendered
{
  Frame frame;
  RenderStatistics stats;
};

Rendered render(const Input& in,
  const Vec3d& origin,
  const RayCamera& cam,
  const RBFRenderParameters& params,
  const std::vector<TransferFunctionTable>& tf,
  int leafSize = 8)
{
  RBFParticles s = makeParticles(in, origin);
  ParticleBVH bvh;
  bvh.build(s, leafSize);
  Rendered out;
  renderRBF({ s, bvh, tf }, viewOf(cam), params, out.frame, out.stats);
  return out;
}

// Classification as VTK's volume mappers define it: the table's samples get their opacity
// corrected for the step, 1 - (1 - alpha)^(dt / unit), and are then interpolated linearly.
std::array<double, 4> classify(const TransferFunctionTable& tf, double v, double dt)
{
  const int n = tf.size();
  const double lo = tf.rangeMin(), hi = tf.rangeMax();
  const double x = std::clamp((v - lo) / (hi - lo) * (n - 1), 0.0, double(n - 1));
  const int k = std::min(int(x), n - 2);
  std::array<double, 4> out{};
  for (const int s : { k, k + 1 })
  {
    const double w = s == k ? 1.0 - (x - k) : x - k;
    const auto c = tf.lookup(lo + (hi - lo) * s / (n - 1)); // exactly sample s
    const double a = 1.0 - std::pow(1.0 - std::min<double>(c[3], 1.0), dt / tf.unitDistance());
    out[0] += w * c[0];
    out[1] += w * c[1];
    out[2] += w * c[2];
    out[3] += w * a;
  }
  return out;
}

// The independent reference: samples t_k = k dt over the ray, each the sum over every
// particle whose support the ray's line meets, in double, classified with the tables and
// blended front to back per field. With normalized weights the value classified is
// phi_m / w_m (w_m the sum of kappa exp(-d^2 / 2r^2)), the step's opacity a becomes
// 1 - (1 - a)^min(1, w_m), and a field no particle reaches adds nothing.
Frame bruteForce(const Input& in,
  const Vec3d& origin,
  const RayCamera& cam,
  const RBFRenderParameters& params,
  const std::vector<TransferFunctionTable>& tf)
{
  Frame f;
  f.resize(cam.width(), cam.height());
  const double dt = params.sampleDistance, sigma = params.sigma;
  for (int j = 0; j < cam.height(); ++j)
  {
    for (int i = 0; i < cam.width(); ++i)
    {
      const Ray ray = cam.pixelRay(i, j);
      const Vec3d o = Vec3d(ray.org) + cam.origin(), d(ray.dir);
      // The t interval where some particle's support lies, and the particles whose support
      // the ray's line meets (the others add nothing at any sample).
      double tMin = 1e300, tMax = -1e300;
      std::vector<std::size_t> near;
      for (std::size_t p = 0; p < in.p.size(); ++p)
      {
        const Vec3d fo = o - in.p[p];
        const double b = dot(fo, d);
        const double h2 = dot(fo, fo) - b * b;
        const double R = sigma * in.r[p];
        if (h2 < R * R)
        {
          const double w = std::sqrt(R * R - h2);
          tMin = std::min(tMin, -b - w);
          tMax = std::max(tMax, -b + w);
          near.push_back(p);
        }
      }
      tMin = std::max(tMin, double(ray.tnear));
      tMax = std::min(tMax, double(ray.tfar));
      double A = 0, Cr = 0, Cg = 0, Cb = 0;
      for (long k = long(std::ceil(tMin / dt)); k <= long(std::floor(tMax / dt)); ++k)
      {
        const Vec3d x = o + d * (k * dt);
        double phi[MaxRBFFields] = { 0, 0, 0, 0 }, weight[MaxRBFFields] = { 0, 0, 0, 0 };
        for (const std::size_t p : near)
        {
          const double d2 = dot(x - in.p[p], x - in.p[p]);
          const double r = in.r[p];
          if (d2 <= sigma * sigma * r * r)
          {
            const double g = params.kappa * std::exp(-d2 / (2 * r * r));
            phi[in.field.empty() ? 0 : in.field[p]] += (in.k.empty() ? 1.0 : in.k[p]) * g;
            weight[in.field.empty() ? 0 : in.field[p]] += g;
          }
        }
        for (int m = 0; m < in.numFields; ++m)
        {
          const bool average = params.normalizeWeights;
          if (average && weight[m] == 0)
          {
            continue;
          }
          const auto c = classify(
            tf[std::min<std::size_t>(m, tf.size() - 1)], average ? phi[m] / weight[m] : phi[m], dt);
          const double a = average ? 1 - std::pow(1 - c[3], std::min(1.0, weight[m])) : c[3];
          const double w = (1 - A) * a;
          Cr += w * c[0];
          Cg += w * c[1];
          Cb += w * c[2];
          A += w;
        }
        if (A >= params.terminationOpacity)
        {
          break;
        }
      }
      float* px = &f.rgba[4 * f.index(i, j)];
      px[0] = float(Cr);
      px[1] = float(Cg);
      px[2] = float(Cb);
      px[3] = float(A);
    }
  }
  return f;
}

double maxDifference(const Frame& a, const Frame& b)
{
  double m = 0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i)
  {
    EXPECT_TRUE(std::isfinite(a.rgba[i])) << "NaN or Inf at " << i;
    m = std::max(m, double(std::fabs(a.rgba[i] - b.rgba[i])));
  }
  return m;
}

double coverage(const Frame& f)
{
  double s = 0;
  for (std::size_t i = 3; i < f.rgba.size(); i += 4)
  {
    s += f.rgba[i];
  }
  return s;
}

// Shading on, one directional light, ambient 0.2 and diffuse 0.8.
void lightFromAbove(RBFRenderParameters& params)
{
  params.shade = true;
  Light light;
  light.direction = normalize(Vec3d(-1, -1, -2));
  params.lights = { light };
  params.material.ambient = 0.2;
  params.material.diffuse = 0.8;
}

// Opacity ramp with extinction proportional to the field: alpha over the unit distance is
// 1 - exp(-c Phi u), i.e. extinction c Phi.
std::vector<TransferFunctionTable> linearExtinction(double hi, double c, double unit = 1.0)
{
  return { table(hi, 4096, unit, [&](double v) { return 1.0 - std::exp(-c * v * unit); }) };
}
}

// A single particle seen head-on: the optical depth -ln(1 - A) of the centre pixel equals
// c times the closed-form integral of the truncated Gaussian along the ray,
//   kappa k r sqrt(2 pi) exp(-h^2 / 2r^2) erf(W / (r sqrt 2)),  W = sqrt(sigma^2 r^2 - h^2).
TEST(RBFVolume, SingleParticleOpticalDepthIsTheErfIntegral)
{
  Input in;
  in.p = { { 0.1, -0.05, 0.0 } };
  in.r = { 0.7 };
  in.k = { 1.3 };
  RBFRenderParameters params;
  params.kappa = 1.5;
  params.sigma = 3.0;
  params.sampleDistance = 0.02;
  params.terminationOpacity = 1.0;
  const double c = 0.4;
  const auto tf = linearExtinction(params.kappa * 1.3 * 1.01, c);
  const RayCamera cam = camera({ 0, 0, 8 }, { 0, 0, 0 }, { 0, 0, 0 }, 41, 41);
  for (const bool direct : { false, true })
  {
    params.direct = direct;
    const Rendered out = render(in, {}, cam, params, tf);
    for (const auto& [i, j] : { std::pair{ 20, 20 }, std::pair{ 22, 19 }, std::pair{ 25, 24 } })
    {
      const Ray ray = cam.pixelRay(i, j);
      const Vec3d f = Vec3d(ray.org) - in.p[0], d(ray.dir);
      const double b = dot(f, d), h2 = dot(f, f) - b * b, r = in.r[0];
      const double W = std::sqrt(params.sigma * params.sigma * r * r - h2);
      const double integral = params.kappa * in.k[0] * r * std::sqrt(2 * M_PI) *
                              std::exp(-h2 / (2 * r * r)) * std::erf(W / (r * std::sqrt(2.0)));
      const double A = out.frame.rgba[4 * out.frame.index(i, j) + 3];
      EXPECT_NEAR(-std::log(1.0 - A), c * integral, 1e-4 * c * integral)
        << (direct ? "direct" : "coherent") << " pixel " << i << "," << j;
    }
  }
}

TEST(RBFVolume, MatchesBruteForceForPacketsPassesAndLeaves)
{
  const Input in = randomCloud(150, 2.0, 3);
  const auto tf = linearExtinction(4.0, 0.8);
  const RayCamera cam = camera({ 1, 2, 9 }, { 0, 0, 0 }, { 0.2, 0.1, -0.3 });
  RBFRenderParameters params;
  params.sampleDistance = 0.05;
  // (Early termination is tested on its own: here a float and a double opacity could
  // cross the threshold one sample apart. Likewise sigma 4 makes the truncation's jump,
  // exp(-sigma^2 / 2), too small to matter where float and double disagree on whether a
  // sample lies inside a support.)
  params.terminationOpacity = 1.0;
  params.sigma = 4.0;
  const Frame ref = bruteForce(in, { 0.2, 0.1, -0.3 }, cam, params, tf);
  EXPECT_GT(coverage(ref), 50.0);
  for (const int side : { 1, 3, 4, 8 })
  {
    for (const int K : { 1, 7, 32 })
    {
      params.packetSide = side;
      params.samplesPerPass = K;
      const Rendered out = render(in, { 0.2, 0.1, -0.3 }, cam, params, tf, side == 3 ? 1 : 4);
      EXPECT_LT(maxDifference(out.frame, ref), 2e-4) << "packet " << side << " K " << K;
    }
  }
  params.direct = true;
  EXPECT_LT(maxDifference(render(in, { 0.2, 0.1, -0.3 }, cam, params, tf).frame, ref), 2e-4);
}

// A one-particle-thick layer (z = 0, like the LAMMPS crack) seen obliquely: neighbouring
// rays meet it many samples apart, so the SIMD blocks integrate each ray from its own first
// sample (the counter shows it); the picture matches the brute-force one and the direct
// method, with and without early termination.
TEST(RBFVolume, AnObliqueLayerIntegratesStaggeredRaysExactly)
{
  Input in;
  for (int i = -8; i <= 8; ++i)
  {
    for (int j = -8; j <= 8; ++j)
    {
      in.p.push_back({ 0.25 * i + 0.03 * (j % 3), 0.25 * j, 0.0 });
      in.r.push_back(0.15);
      in.k.push_back(1.0 + 0.1 * ((i + j) % 4));
      in.field.push_back(0);
    }
  }
  const auto tf = linearExtinction(4.0, 2.0);
  const Vec3d origin{ 0.0, 0.0, 0.0 };
  const RayCamera cam = camera({ 0.5, -3.5, 3.5 }, { 0, 0, 0 }, origin, 64, 48);
  RBFRenderParameters params;
  // The supports (z in [-0.6, 0.6]) take about 34 samples of a ray, all in one pass.
  params.sampleDistance = 0.05;
  params.samplesPerPass = 64;
  params.terminationOpacity = 1.0;
  params.sigma = 4.0;
  const Frame ref = bruteForce(in, origin, cam, params, tf);
  EXPECT_GT(coverage(ref), 100.0);
  for (const int side : { 4, 8 })
  {
    params.packetSide = side;
    const Rendered out = render(in, origin, cam, params, tf);
    EXPECT_LT(maxDifference(out.frame, ref), 2e-4) << "packet " << side;
    EXPECT_GT(out.stats.counter("staggered_blocks"), 20) << "packet " << side;
  }
  params.packetSide = 8;
  params.terminationOpacity = 0.6;
  const Rendered coherent = render(in, origin, cam, params, tf);
  EXPECT_GT(coherent.stats.counter("terminated_rays"), 50);
  params.direct = true;
  EXPECT_LT(maxDifference(coherent.frame, render(in, origin, cam, params, tf).frame), 1e-5);
}

// A cloud in one corner of the view, perspective and parallel: the packets whose rays
// cannot reach its box are culled before their rays are set up (the counter shows it), and
// the picture still matches the brute-force one everywhere, packet edges included.
TEST(RBFVolume, PacketsOutOfReachAreCulledWithoutChangingThePicture)
{
  const Input in = randomCloud(60, 1.0, 5);
  const auto tf = linearExtinction(4.0, 0.8);
  const Vec3d origin{ 0.1, 0.0, 0.2 };
  RBFRenderParameters params;
  params.sampleDistance = 0.05;
  params.terminationOpacity = 1.0;
  params.sigma = 4.0;
  const int w = 64, h = 48;
  const Mat4 view = lookAt({ 4, 3, 12 }, { 4, 3, 0 }, { 0, 1, 0 });
  for (const Mat4& projection :
    { perspective(35, double(w) / h, 0.5, 100), orthographic(6.5, 4.9, 0.5, 100) })
  {
    const RayCamera cam(multiply(projection, view), w, h, origin);
    const Frame ref = bruteForce(in, origin, cam, params, tf);
    EXPECT_GT(coverage(ref), 5.0);
    for (const int side : { 3, 8 })
    {
      params.packetSide = side;
      const Rendered out = render(in, origin, cam, params, tf);
      EXPECT_LT(maxDifference(out.frame, ref), 2e-4) << "packet " << side;
      EXPECT_GT(out.stats.counter("culled_packets"), out.stats.counter("packets") / 4)
        << "packet " << side;
    }
  }
}

// The renderer keeps the frame's storage from one render to the next and writes every
// pixel: a frame full of an earlier picture comes out as a fresh one, for the coherent
// method (packets culled or not) and the direct one, and empty when nothing can be drawn.
TEST(RBFVolume, AReusedFrameIsWhollyRewritten)
{
  const Input in = randomCloud(60, 1.0, 5);
  const auto tf = linearExtinction(4.0, 0.8);
  const Vec3d origin{ 0.1, 0.0, 0.2 };
  const int w = 64, h = 48;
  const RayCamera cam(multiply(perspective(35, double(w) / h, 0.5, 100),
                        lookAt({ 4, 3, 12 }, { 4, 3, 0 }, { 0, 1, 0 })),
    w, h, origin);
  RBFParticles s = makeParticles(in, origin);
  ParticleBVH bvh;
  bvh.build(s, 8);
  auto stale = [&]()
  {
    Frame f;
    f.resize(w, h);
    std::fill(f.rgba.begin(), f.rgba.end(), 0.5f);
    return f;
  };
  for (const bool direct : { false, true })
  {
    RBFRenderParameters params;
    params.sampleDistance = 0.05;
    params.direct = direct;
    Frame fresh, reused = stale();
    RenderStatistics a, b;
    renderRBF({ s, bvh, tf }, viewOf(cam), params, fresh, a);
    renderRBF({ s, bvh, tf }, viewOf(cam), params, reused, b);
    EXPECT_GT(coverage(fresh), 5.0);
    EXPECT_EQ(maxDifference(reused, fresh), 0.0) << (direct ? "direct" : "coherent");
    if (!direct)
    {
      EXPECT_GT(b.counter("culled_packets"), 0);
    }
  }
  RBFParticles none = makeParticles(Input{}, origin);
  ParticleBVH emptyBVH;
  emptyBVH.build(none, 8);
  Frame reused = stale();
  RenderStatistics stats;
  renderRBF({ none, emptyBVH, tf }, viewOf(cam), RBFRenderParameters{}, reused, stats);
  EXPECT_EQ(coverage(reused), 0.0);
}

// Distributed rendering (RegionBox.h): every region renders all particles but only its own
// samples; the regions' images blended front to back in visibility order are the whole
// image. Space is cut as a kd-tree: x = 0.3, then z = 0 on the eye's side (the eye is at
// x = 1, z = 9), so the order is (x >= 0.3, z >= 0), (x >= 0.3, z < 0), (x < 0.3).
TEST(RBFVolume, RegionsCompositeToTheWholeImage)
{
  const Input in = randomCloud(150, 2.0, 11);
  const auto tf = linearExtinction(4.0, 0.8);
  const RayCamera cam = camera({ 1, 2, 9 }, { 0, 0, 0 }, { 0.2, 0.1, -0.3 });
  RBFRenderParameters params;
  params.sampleDistance = 0.05;
  params.terminationOpacity = 1.0; // a region cannot know the opacity in front of it
  const Frame whole = render(in, { 0.2, 0.1, -0.3 }, cam, params, tf).frame;
  EXPECT_GT(coverage(whole), 50.0);

  Frame composite;
  composite.resize(cam.width(), cam.height());
  for (const RegionBox& region : kdCutFrontToBack(0.3, 0.0))
  {
    params.region = region;
    const Frame part = render(in, { 0.2, 0.1, -0.3 }, cam, params, tf).frame;
    EXPECT_GT(coverage(part), 1.0);
    blendBehind(composite, part);
  }
  EXPECT_LT(maxDifference(composite, whole), 2e-5);
}

// Two fields, each with its own transfer function, blended per sample; and shading, whose
// gradients must agree between the coherent and the direct method.
TEST(RBFVolume, MultiFieldAndShadingMatchTheDirectMethod)
{
  const Input in = randomCloud(200, 2.0, 5, 2);
  std::vector<TransferFunctionTable> tf = {
    table(
      3.0, 256, 1.0, [](double v) { return std::min(1.0, 0.3 * v); }, 0.0),
    table(
      3.0, 256, 1.0, [](double v) { return std::min(1.0, 0.6 * v); }, 1.0),
  };
  const RayCamera cam = camera({ -3, 2, 8 }, { 0, 0, 0 }, {});
  RBFRenderParameters params;
  params.sampleDistance = 0.05;
  params.sigma = 4.0; // (see MatchesBruteForceForPacketsPassesAndLeaves)
  params.terminationOpacity = 1.0;
  const Frame ref = bruteForce(in, {}, cam, params, tf);
  const Rendered coherent = render(in, {}, cam, params, tf);
  EXPECT_LT(maxDifference(coherent.frame, ref), 2e-4);
  EXPECT_TRUE(coherent.stats.effect("multi_field"));
  EXPECT_FALSE(coherent.stats.effect("shading"));

  lightFromAbove(params);
  const Rendered lit = render(in, {}, cam, params, tf);
  params.direct = true;
  const Rendered litDirect = render(in, {}, cam, params, tf);
  EXPECT_LT(maxDifference(lit.frame, litDirect.frame), 5e-4);
  EXPECT_GT(maxDifference(lit.frame, coherent.frame), 0.02); // the shading does something
  EXPECT_TRUE(lit.stats.effect("shading"));
}

// Normalized weights on signed heights with a map opaque at 0 (a pressure coloured by
// ParaView's default maps): the picture is the brute-force one, by both methods, shaded
// too, and a ray that meets no particle's support stays empty, where the paper's sum
// classifies the empty space between the supports as 0 and fills the bounds.
TEST(RBFVolume, NormalizedWeightsMatchBruteForceAndLeaveEmptySpaceEmpty)
{
  Input in = randomCloud(150, 2.0, 11, 2);
  for (std::size_t i = 0; i < in.k.size(); ++i)
  {
    in.k[i] = (i % 3 == 0 ? -1.0 : 1.0) * in.k[i]; // heights in [-1.5, 1.5]
  }
  // Colour ramps over [-1.5, 1.5], opacity 0.4 everywhere (0 included).
  std::vector<float> rgba;
  for (int k = 0; k < 256; ++k)
  {
    const float x = k / 255.f;
    rgba.insert(rgba.end(), { x, 1.f - x, 0.5f, 0.4f });
  }
  std::vector<TransferFunctionTable> tf(1);
  tf[0].assign(rgba, -1.5, 1.5, 1.0);
  const RayCamera cam = camera({ -3, 2, 12 }, { 0, 0, 0 }, {});
  RBFRenderParameters params;
  params.sampleDistance = 0.05;
  params.sigma = 4.0;
  params.terminationOpacity = 1.0;
  params.normalizeWeights = true;
  const Frame ref = bruteForce(in, {}, cam, params, tf);
  const Rendered coherent = render(in, {}, cam, params, tf);
  EXPECT_LT(maxDifference(coherent.frame, ref), 2e-4);
  EXPECT_TRUE(coherent.stats.effect("normalized_weights"));
  EXPECT_TRUE(coherent.stats.effect("empty_space_skipping"));
  params.direct = true;
  EXPECT_LT(maxDifference(render(in, {}, cam, params, tf).frame, ref), 2e-4);

  // Empty space: a pixel whose ray meets no support.
  int empty = 0, filledBySum = 0;
  params.direct = false;
  params.normalizeWeights = false;
  const Rendered sum = render(in, {}, cam, params, tf);
  EXPECT_FALSE(sum.stats.effect("normalized_weights"));
  for (int j = 0; j < cam.height(); ++j)
  {
    for (int i = 0; i < cam.width(); ++i)
    {
      const Ray ray = cam.pixelRay(i, j);
      bool meets = false;
      for (std::size_t p = 0; p < in.p.size() && !meets; ++p)
      {
        const Vec3d f = Vec3d(ray.org) - in.p[p];
        const double b = dot(f, Vec3d(ray.dir));
        const double R = params.sigma * in.r[p];
        meets = dot(f, f) - b * b < R * R;
      }
      const std::size_t px = 4 * coherent.frame.index(i, j);
      if (!meets)
      {
        ++empty;
        EXPECT_EQ(coherent.frame.rgba[px + 3], 0.f) << "pixel " << i << ", " << j;
        filledBySum += sum.frame.rgba[px + 3] > 0.1f;
      }
    }
  }
  EXPECT_GT(empty, 0);
  EXPECT_GT(filledBySum, 0); // the sum's slab, which the average has not

  params.normalizeWeights = true;
  lightFromAbove(params);
  const Rendered lit = render(in, {}, cam, params, tf);
  params.direct = true;
  EXPECT_LT(maxDifference(lit.frame, render(in, {}, cam, params, tf).frame), 5e-4);
  EXPECT_GT(maxDifference(lit.frame, coherent.frame), 0.02);
}

TEST(RBFVolume, SaturatingKappaTerminatesEarlyAndExactly)
{
  const Input in = randomCloud(300, 2.0, 7);
  const auto tf = linearExtinction(2.0, 5.0);
  const RayCamera cam = camera({ 0, 0, 9 }, { 0, 0, 0 }, {});
  RBFRenderParameters params;
  params.kappa = 1e4;
  params.sampleDistance = 0.05;
  params.terminationOpacity = 0.99;
  const Rendered early = render(in, {}, cam, params, tf);
  params.terminationOpacity = 1.0;
  const Rendered full = render(in, {}, cam, params, tf);
  // Stopping at opacity 0.99 changes a pixel by at most what the rest could add: 0.01.
  EXPECT_LE(maxDifference(early.frame, full.frame), 0.01 + 1e-6);
  EXPECT_GT(early.stats.counter("terminated_rays"), 0);
  EXPECT_LT(early.stats.counter("samples"), full.stats.counter("samples") / 4);
  EXPECT_LT(early.stats.counter("passes"), full.stats.counter("passes"));
}

TEST(RBFVolumeHardCases, CoincidentParticlesAddUp)
{
  Input two, one;
  two.p = { { 0, 0, 0 }, { 0, 0, 0 } };
  two.r = { 0.5, 0.5 };
  two.k = { 1.0, 1.0 };
  one.p = { { 0, 0, 0 } };
  one.r = { 0.5 };
  one.k = { 2.0 };
  const auto tf = linearExtinction(3.0, 1.0);
  const RayCamera cam = camera({ 0, 0, 4 }, { 0, 0, 0 }, {});
  RBFRenderParameters params;
  params.sampleDistance = 0.02;
  EXPECT_LT(
    maxDifference(render(two, {}, cam, params, tf).frame, render(one, {}, cam, params, tf).frame),
    1e-5);
}

TEST(RBFVolumeHardCases, InvalidParticlesAreSkippedAndCounted)
{
  Input in = randomCloud(50, 1.0, 9);
  in.r[3] = 0.0;
  in.r[4] = -1.0;
  in.r[5] = std::nan("");
  in.p[6].x = std::nan("");
  in.k[7] = std::numeric_limits<double>::infinity();
  const RBFParticles s = makeParticles(in, {});
  EXPECT_EQ(s.size(), 45u);
  EXPECT_EQ(s.skippedBadRadius, 3u);
  EXPECT_EQ(s.skippedNonFinite, 2u);
  const auto tf = linearExtinction(3.0, 1.0);
  RBFRenderParameters params;
  const Rendered out = render(in, {}, camera({ 0, 0, 6 }, { 0, 0, 0 }, {}), params, tf);
  EXPECT_GT(coverage(out.frame), 1.0);
  for (float v : out.frame.rgba)
  {
    ASSERT_TRUE(std::isfinite(v));
  }
}

TEST(RBFVolumeHardCases, TinyAndHugeSigma)
{
  const Input in = randomCloud(100, 1.5, 11);
  const auto tf = linearExtinction(3.0, 1.0);
  const RayCamera cam = camera({ 0, 0, 7 }, { 0, 0, 0 }, {});
  RBFRenderParameters params;
  params.sampleDistance = 0.05;
  params.sigma = 1e-4; // supports smaller than a step: (almost) nothing is sampled
  const Rendered tiny = render(in, {}, cam, params, tf);
  EXPECT_LT(coverage(tiny.frame), 1e-3);
  params.sigma = 8.0;
  const Rendered wide = render(in, {}, cam, params, tf);
  params.sigma = 60.0; // the Gaussians' tails beyond 8 r add nothing visible
  const Rendered huge = render(in, {}, cam, params, tf);
  EXPECT_LT(maxDifference(wide.frame, huge.frame), 1e-5);
}

TEST(RBFVolumeHardCases, CameraInsideTheCloud)
{
  const Input in = randomCloud(400, 2.0, 13);
  const auto tf = linearExtinction(4.0, 0.5);
  const RayCamera cam = camera({ 0.1, 0.2, 0.3 }, { 1, 0, 0 }, {});
  RBFRenderParameters params;
  params.sampleDistance = 0.05;
  params.sigma = 4.0; // (see MatchesBruteForceForPacketsPassesAndLeaves)
  params.terminationOpacity = 1.0;
  const Frame ref = bruteForce(in, {}, cam, params, tf);
  EXPECT_GT(coverage(ref), 100.0);
  EXPECT_LT(maxDifference(render(in, {}, cam, params, tf).frame, ref), 2e-4);
}

namespace
{
// The optical depth summed over the pixels, sum of -ln(1 - A).
double totalOpticalDepth(const Frame& f)
{
  double tau = 0;
  for (std::size_t i = 3; i < f.rgba.size(); i += 4)
  {
    tau += -std::log(1.0 - double(f.rgba[i]));
  }
  return tau;
}
}

// Gaussians narrower than a pixel and than the step (r = dt / 5, support sigma r = 0.8 dt):
// the renderer samples the field at t_k = k dt as documented, so a Gaussian between
// samples is not seen, one a sample lands in is seen at that sample's value; the coherent
// and the direct method give the brute force's picture (same samples). Energy: with a
// parallel view the samples form a lattice of cells dt x a (a the pixel's area), and with
// the extinction c Phi of the table the optical depths add, sum_p -ln(1 - A_p) =
// c dt sum over samples of Phi, whose expectation over the particles' positions is
// c sum_i V_i / (dt a), V_i = kappa k_i (2 pi)^(3/2) r^3 P(chi^2_3 <= sigma^2) the integral of
// the truncated Gaussian. Its relative spread is at most that of Poisson sampling,
// sqrt(m / (N lambda)), lambda = (4/3) pi (sigma r)^3 / (dt a) samples per support and m =
// E[g^2] / E[g]^2 for a sample uniform in the support ball.
TEST(RBFVolumeHardCases, SubPixelRadiiNarrowerThanTheStep)
{
  const int W = 48;
  const double half = 1.2, pixel = 2 * half / W, dt = pixel, r = dt / 5;
  const RayCamera cam(multiply(orthographic(half, half, 0.5, 20),
                        lookAt({ 0.3, 0.2, 5 }, { 0.3, 0.2, 0 }, { 0, 1, 0 })),
    W,
    W,
    {});
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1, 1);
  Input in;
  for (int i = 0; i < 2000; ++i)
  {
    in.p.push_back({ u(rng) + 0.3, u(rng) + 0.2, u(rng) });
    in.r.push_back(r);
    in.k.push_back(1.0);
  }
  RBFRenderParameters params;
  params.sampleDistance = dt;
  params.sigma = 4.0; // (see MatchesBruteForceForPacketsPassesAndLeaves)
  params.terminationOpacity = 1.0;
  const double c = 2.0;
  const auto tf = linearExtinction(4.0, c);
  const Frame ref = bruteForce(in, {}, cam, params, tf);
  const Rendered coherent = render(in, {}, cam, params, tf);
  params.direct = true;
  const Rendered direct = render(in, {}, cam, params, tf);
  EXPECT_LT(maxDifference(coherent.frame, ref), 2e-4);
  EXPECT_LT(maxDifference(direct.frame, ref), 2e-4);

  const double sigma = params.sigma;
  const double inside =
    std::erf(sigma / std::sqrt(2.0)) - std::sqrt(2 / M_PI) * sigma * std::exp(-sigma * sigma / 2);
  const double V = std::pow(2 * M_PI, 1.5) * r * r * r * inside;
  const double expected = c * in.p.size() * V / (pixel * pixel);
  // m from the radial integrals over [0, sigma] (midpoint rule).
  double i0 = 0, i1 = 0, i2 = 0;
  for (int k = 0; k < 4000; ++k)
  {
    const double q = (k + 0.5) * sigma / 4000;
    i0 += q * q;
    i1 += q * q * std::exp(-q * q / 2);
    i2 += q * q * std::exp(-q * q);
  }
  const double m = i2 * i0 / (i1 * i1);
  const double lambda = 4.0 / 3.0 * M_PI * std::pow(sigma * r, 3) / (dt * pixel * pixel);
  const double spread = std::sqrt(m / (in.p.size() * lambda));
  const double measured = totalOpticalDepth(coherent.frame);
  std::cout << "sub-step Gaussians: total optical depth " << measured << " (brute force "
            << totalOpticalDepth(ref) << "), expected " << expected << " +- " << spread * expected
            << "\n";
  EXPECT_LT(std::fabs(measured / expected - 1), 4 * spread);
}

// Radii over six decades, 1e-8 to 1e-2 (log-uniform), in a unit box, sampled at the
// mapper's default step (half the mean radius, 3.6e-4: 5000 samples a ray): no hang, no
// NaN, and the brute force's picture with both methods (Gaussians far below the float
// resolution of the rays, 1e-7, are missed by both: no ray's line comes within their
// support).
TEST(RBFVolumeHardCases, RadiiOverSixDecades)
{
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> u(0, 1);
  Input in;
  double sum = 0;
  for (int i = 0; i < 3000; ++i)
  {
    in.p.push_back({ u(rng), u(rng), u(rng) });
    in.r.push_back(std::pow(10.0, -8 + 6 * u(rng)));
    in.k.push_back(1.0);
    sum += in.r.back();
  }
  RBFRenderParameters params;
  params.sampleDistance = 0.5 * sum / in.p.size();
  params.sigma = 4.0;
  params.terminationOpacity = 1.0;
  const auto tf = linearExtinction(3.0, 20.0);
  const Vec3d centre(0.5, 0.5, 0.5);
  const RayCamera cam = camera({ 1.4, 1.2, 2.3 }, centre, centre, 24, 24);
  const Frame ref = bruteForce(in, centre, cam, params, tf);
  EXPECT_GT(coverage(ref), 5.0);
  const Rendered coherent = render(in, centre, cam, params, tf);
  EXPECT_LT(maxDifference(coherent.frame, ref), 2e-4);
  EXPECT_GT(coherent.stats.counter("samples"), 0);
  params.direct = true;
  EXPECT_LT(maxDifference(render(in, centre, cam, params, tf).frame, ref), 2e-4);
}

// Sigma 60: every Gaussian reaches 60 radii (exp(-1800) at the edge, far below float; the
// polynomial exp clamps the exponent at -87), the supports cover the whole cloud and the
// BVH's grown boxes overlap everywhere: no overflow, no NaN, and the brute force's picture.
TEST(RBFVolumeHardCases, SigmaSixtyMatchesBruteForce)
{
  const Input in = randomCloud(60, 1.5, 11);
  const auto tf = linearExtinction(20.0, 0.3);
  const RayCamera cam = camera({ 0, 0, 7 }, { 0, 0, 0 }, {}, 16, 16);
  RBFRenderParameters params;
  params.sampleDistance = 0.1;
  params.sigma = 60.0;
  params.terminationOpacity = 1.0;
  const Frame ref = bruteForce(in, {}, cam, params, tf);
  EXPECT_GT(coverage(ref), 10.0);
  EXPECT_LT(maxDifference(render(in, {}, cam, params, tf).frame, ref), 2e-4);
  params.direct = true;
  EXPECT_LT(maxDifference(render(in, {}, cam, params, tf).frame, ref), 2e-4);
}

// 1,000 particles at one point: the field is 1,000 times one particle's, so the optical
// depth is 1,000 times the closed-form line integral of SingleParticleOpticalDepthIsThe-
// ErfIntegral, to 1e-4: float sums of 1,000 equal terms are off by at most 1,000 u = 6e-5
// relative; the sum over samples dt = r / 14 apart is exact to far below that for the
// Gaussian, and sigma = 4 makes the truncation's jump exp(-8) = 3e-4 of the peak, off by
// at most dt times that, 1e-5 of the integral.
TEST(RBFVolumeHardCases, ThousandCoincidentParticles)
{
  Input in;
  for (int i = 0; i < 1000; ++i)
  {
    in.p.push_back({ 0.1, -0.05, 0.0 });
    in.r.push_back(0.7);
    in.k.push_back(1.3);
  }
  RBFRenderParameters params;
  params.kappa = 1.5;
  params.sigma = 4.0;
  params.sampleDistance = 0.05;
  params.terminationOpacity = 1.0;
  const double c = 0.4 / 1000;
  const auto tf = linearExtinction(1000 * params.kappa * 1.3 * 1.01, c);
  const RayCamera cam = camera({ 0, 0, 8 }, { 0, 0, 0 }, { 0, 0, 0 }, 21, 21);
  double worst = 0;
  for (const bool direct : { false, true })
  {
    params.direct = direct;
    const Rendered out = render(in, {}, cam, params, tf);
    EXPECT_TRUE(std::all_of(
      out.frame.rgba.begin(), out.frame.rgba.end(), [](float v) { return std::isfinite(v); }));
    for (const auto& [i, j] : { std::pair{ 10, 10 }, std::pair{ 11, 9 }, std::pair{ 13, 12 } })
    {
      const Ray ray = cam.pixelRay(i, j);
      const Vec3d f = Vec3d(ray.org) - in.p[0], d(ray.dir);
      const double b = dot(f, d), h2 = dot(f, f) - b * b, r = in.r[0];
      const double W = std::sqrt(params.sigma * params.sigma * r * r - h2);
      const double integral = 1000 * params.kappa * in.k[0] * r * std::sqrt(2 * M_PI) *
                              std::exp(-h2 / (2 * r * r)) * std::erf(W / (r * std::sqrt(2.0)));
      const double A = out.frame.rgba[4 * out.frame.index(i, j) + 3];
      EXPECT_NEAR(-std::log(1.0 - A), c * integral, 1e-4 * c * integral)
        << (direct ? "direct" : "coherent") << " pixel " << i << "," << j;
      worst = std::max(worst, std::fabs(-std::log(1.0 - A) / (c * integral) - 1));
    }
  }
  std::cout << "1000 coincident particles: optical depth within " << worst
            << " (relative) of 1000 times the closed form\n";
}

TEST(RBFVolumeHardCases, FarFromTheOriginGivesTheSameImage)
{
  Input near = randomCloud(150, 2.0, 15), far = near;
  const Vec3d shift(1e6, -2e6, 1e6);
  for (auto& p : far.p)
  {
    p = p + shift;
  }
  const auto tf = linearExtinction(4.0, 0.8);
  RBFRenderParameters params;
  params.sampleDistance = 0.05;
  const Rendered a = render(near, {}, camera({ 1, 2, 9 }, { 0, 0, 0 }, {}), params, tf);
  const Rendered b = render(far, shift, camera(Vec3d(1, 2, 9) + shift, shift, shift), params, tf);
  EXPECT_LT(maxDifference(a.frame, b.frame), 1e-4);
}

TEST(RBFVolumeHardCases, EmptyInputAndOpaqueGeometry)
{
  const auto tf = linearExtinction(3.0, 1.0);
  RBFRenderParameters params;
  const RayCamera cam = camera({ 0, 0, 6 }, { 0, 0, 0 }, {});
  const Rendered empty = render(Input{}, {}, cam, params, tf);
  EXPECT_EQ(coverage(empty.frame), 0.0);

  // Opaque geometry at window depth 0 in front of everything: nothing is sampled.
  const Input in = randomCloud(100, 1.0, 17);
  RBFParticles s = makeParticles(in, {});
  ParticleBVH bvh;
  bvh.build(s, 4);
  std::vector<float> depth(cam.width() * cam.height(), 0.0f);
  Frame f;
  RenderStatistics stats;
  renderRBF({ s, bvh, tf }, viewOf(cam, depth.data()), params, f, stats);
  EXPECT_EQ(coverage(f), 0.0);
}

// The coherent method's Gaussians take exp of -(u^2 + h^2) / 2r^2 in [-sigma^2 / 2, 0]
// (any sigma): relative error 1e-6 against std::exp on [-87, 0] (and up to 88), a tiny
// positive value below.
TEST(RBFVolume, FastExpMatchesStdExp)
{
  double worst = 0;
  for (int i = 0; i <= 2000000; ++i)
  {
    const float x = -87.f + 175.f * static_cast<float>(i) / 2000000.f;
    const double e = std::exp(static_cast<double>(x));
    worst = std::max(worst, std::fabs(fastExp(x) - e) / e);
  }
  EXPECT_LT(worst, 1e-6);
  for (const float x : { 0.f, -0.f, -1e-30f, -0.5f, -2.f, -8.f, -1800.f })
  {
    EXPECT_NEAR(fastExp(x), std::exp(x), 1e-6 * std::exp(x) + 1e-37) << x;
  }
  EXPECT_EQ(fastExp(0.f), 1.f);
  EXPECT_GT(fastExp(-1e4f), 0.f);
  EXPECT_LT(fastExp(-1e4f), 2e-38f);
}

TEST(ParticleBVH, EveryParticleInOneLeafInsideItsBounds)
{
  const Input in = randomCloud(5000, 5.0, 19);
  RBFParticles s = makeParticles(in, {});
  ParticleBVH bvh;
  bvh.build(s, 8);
  std::vector<int> seen(s.size(), 0);
  const auto& nodes = bvh.nodes();
  for (const BVHNode& n : nodes)
  {
    if (n.count == 0)
    {
      for (const auto c : { n.first, n.first + 1 })
      {
        for (int a = 0; a < 3; ++a)
        {
          ASSERT_GE(nodes[c].lo[a], n.lo[a]);
          ASSERT_LE(nodes[c].hi[a], n.hi[a]);
        }
        ASSERT_LE(nodes[c].rMax, n.rMax);
      }
      continue;
    }
    EXPECT_LE(n.count, 8u);
    for (auto i = n.first; i < n.first + n.count; ++i)
    {
      ++seen[i];
      for (int a = 0; a < 3; ++a)
      {
        ASSERT_GE(s.centers[i][a], n.lo[a]);
        ASSERT_LE(s.centers[i][a], n.hi[a]);
      }
      ASSERT_LE(s.radii[i], n.rMax);
    }
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; }));
  // Memory: the nodes take at most the size of the particle data (centre, radius, value).
  EXPECT_LE(bvh.memoryBytes(), s.size() * (sizeof(Vec3f) + 2 * sizeof(float)));
}

// The automatic kappa's density measure (ParticleBVH.h's medianWeightSum) against the closed
// form: on a cubic lattice of spacing s with r = s, the unit Gaussians at an interior
// particle, cut at sigma = 3 (offsets n with |n| <= 3 along each axis, and the whole offset
// vector within 3 s), sum to sum_{|n| <= 3} exp(-|n|^2 / 2), computed here by enumeration.
// A 40^3 lattice: more than half its particles (34^3 / 40^3 = 61%) are 3 spacings inside,
// so the median is the interior sum.
TEST(RBFVolume, MedianWeightSumOfALatticeIsTheClosedForm)
{
  const int side = 40;
  const double spacing = 0.25;
  Input in;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
      for (int k = 0; k < side; ++k)
      {
        in.p.emplace_back(i * spacing, j * spacing, k * spacing);
        in.r.push_back(spacing);
      }
  RBFParticles s = makeParticles(in, Vec3d(5, 5, 5));
  ParticleBVH bvh;
  bvh.build(s, 8);
  double expected = 0.0;
  for (int a = -3; a <= 3; ++a)
    for (int b = -3; b <= 3; ++b)
      for (int c = -3; c <= 3; ++c)
      {
        const int n2 = a * a + b * b + c * c;
        expected += n2 <= 9 ? std::exp(-0.5 * n2) : 0.0;
      }
  EXPECT_NEAR(medianWeightSum(s, bvh, 3.0f), expected, 1e-4 * expected);
  // No particles: 0 (the mapper then keeps kappa 1).
  EXPECT_EQ(medianWeightSum(RBFParticles(), ParticleBVH(), 3.0f), 0.0);
}
