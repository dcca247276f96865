// The references checked against closed forms before they check anything else: the camera's
// rays and depths, a sphere's hit, the optical depth of one Gaussian along a line, the SPH
// kernels' unit integral and a normalized field's exactness, and the volume integral's
// convergence in its step.
#include "ReferenceRenderers.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace raymappers::reference;

namespace
{
constexpr double pi = 3.14159265358979323846;

// VTK's perspective camera looking down -z from (0, 0, eye) at the origin, view angle 30
// degrees, square viewport, near n and far f: M = P V with V a translation by -eye in z.
ReferenceCamera lookDownZ(double eye, double n, double f, int size)
{
  const double c = 1.0 / std::tan(15.0 * pi / 180.0);
  const std::array<double, 16> m = { c,
    0,
    0,
    0,
    0,
    c,
    0,
    0,
    0,
    0,
    -(f + n) / (f - n),
    -2 * f * n / (f - n) + (f + n) / (f - n) * eye,
    0,
    0,
    -1,
    eye };
  return ReferenceCamera(m, size, size);
}

// A table of n entries whose opacity per unit distance 1 gives tau(v) = v:
// alpha(v) = 1 - exp(-v), colour white, over [0, hi].
ReferenceTransferFunction linearExtinction(double hi, int n = 20001)
{
  ReferenceTransferFunction tf;
  tf.lo = 0;
  tf.hi = hi;
  for (int k = 0; k < n; ++k)
  {
    const double v = hi * k / (n - 1);
    tf.rgba.push_back({ 1, 1, 1, -std::expm1(-v) });
  }
  return tf;
}
}

TEST(References, CameraRaysAndDepths)
{
  const ReferenceCamera cam = lookDownZ(10, 1, 100, 101);
  const PixelRay centre = cam.ray(50, 50);
  EXPECT_NEAR(centre.origin.z, 9.0, 1e-9);
  EXPECT_NEAR(centre.direction.z, -1.0, 1e-12);
  EXPECT_NEAR(centre.length, 99.0, 1e-6);
  EXPECT_NEAR(cam.windowDepth({ 0, 0, 9 }), 0.0, 1e-12);
  EXPECT_NEAR(cam.windowDepth({ 0, 0, -90 }), 1.0, 1e-12);
  // The corner pixel's ray leaves at the half angle of the view minus half a pixel.
  const PixelRay corner = cam.ray(100, 50);
  const double expected = std::atan(std::tan(15.0 * pi / 180.0) * (1 - 1.0 / 101));
  EXPECT_NEAR(std::atan2(corner.direction.x, -corner.direction.z), expected, 1e-12);
}

TEST(References, SphereHitIsClosedForm)
{
  const ReferenceCamera cam = lookDownZ(10, 1, 100, 101);
  const ReferenceImage im = renderSpheres(
    cam, { { { 0, 0, 0 }, 2.0, { 1, 0.5, 0.25 } } }, {}, ReferenceMaterial{ 1, 0, 0, 1 });
  // The front point (0, 0, 2) at the centre pixel, coloured by the ambient term alone.
  EXPECT_NEAR(im.depth[50 * 101 + 50], cam.windowDepth({ 0, 0, 2 }), 1e-12);
  EXPECT_EQ(im.rgba[50 * 101 + 50][1], 0.5);
  // The disc covers pi R^2 pixels, R the projected radius in pixels.
  int covered = 0;
  for (const auto& p : im.rgba)
  {
    covered += p[3] > 0;
  }
  const double R = std::tan(std::asin(2.0 / 10.0)) / std::tan(15.0 * pi / 180.0) * 50.5;
  EXPECT_NEAR(covered, pi * R * R, 2 * pi * R);
}

TEST(References, GaussianOpticalDepthIsClosedForm)
{
  // One Gaussian of radius r and weight k on the axis, tau = phi: along a ray at distance b
  // from the centre the optical depth is k r sqrt(2 pi) exp(-b^2 / 2 r^2) (the whole line;
  // the cut at 6 r loses a fraction erfc(6 / sqrt 2) = 2e-9 of it).
  const ReferenceCamera cam = lookDownZ(10, 1, 100, 61);
  const double r = 0.7, k = 0.8;
  RBFReference params;
  params.step = r / 64;
  const ReferenceImage im =
    renderRBF(cam, { { { 0, 0, 0 }, r, k } }, params, linearExtinction(2.0));
  for (int i : { 30, 34, 38 })
  {
    const PixelRay ray = cam.ray(i, 30);
    const double t = -dot(ray.origin, ray.direction);
    const double b = norm(ray.origin + ray.direction * t);
    const double depth = k * r * std::sqrt(2 * pi) * std::exp(-b * b / (2 * r * r));
    EXPECT_NEAR(im.rgba[30 * 61 + i][3], -std::expm1(-depth), 1e-5) << "pixel " << i;
    EXPECT_NEAR(im.rgba[30 * 61 + i][0], -std::expm1(-depth), 1e-5);
  }
}

TEST(References, KernelsIntegrateToOne)
{
  for (ReferenceKernel kernel :
    { ReferenceKernel::Poly6, ReferenceKernel::CubicSpline, ReferenceKernel::WendlandC2 })
  {
    const double H = 1.3;
    const int n = 200000;
    double sum = 0;
    for (int k = 0; k < n; ++k)
    {
      const double r = (k + 0.5) * H / n;
      sum += 4 * pi * r * r * kernelWeight(kernel, r, H) * H / n;
    }
    EXPECT_NEAR(sum, 1.0, 1e-8) << static_cast<int>(kernel);
    EXPECT_EQ(kernelWeight(kernel, H, H), 0.0);
  }
}

TEST(References, NormalizedFieldOfEqualQuantitiesIsThatQuantity)
{
  // Particles all of Q = 1.5 (different volumes and supports): A / B = 1.5 wherever B > 0,
  // so every covered pixel has the colour of the table at 1.5 and the opacity of the
  // covered length.
  const ReferenceCamera cam = lookDownZ(10, 1, 100, 41);
  std::vector<ReferenceSPHParticle> p = { { { -0.3, 0, 0 }, 0.6, 1.5, 0.2 },
    { { 0.2, 0.1, 0.1 }, 0.5, 1.5, 0.05 },
    { { 0, -0.2, -0.3 }, 0.7, 1.5, 1.0 } };
  ReferenceTransferFunction tf;
  tf.lo = 0;
  tf.hi = 3;
  tf.rgba = { { 0, 0, 0, 0.1 }, { 1, 0.5, 0.25, 0.1 } };
  SPHReference params;
  params.step = 0.001;
  const ReferenceImage im = renderSPH(cam, p, params, tf);
  int covered = 0;
  for (const auto& c : im.rgba)
  {
    if (c[3] > 0)
    {
      ++covered;
      EXPECT_NEAR(c[0] / c[3], 0.5, 1e-9);
      EXPECT_NEAR(c[1] / c[3], 0.25, 1e-9);
    }
  }
  EXPECT_GT(covered, 50);
}

TEST(References, VolumeIntegralConvergesInItsStep)
{
  // Halving the step changes no pixel by a tenth of a level at the steps the tests use: a
  // sixty-fourth of the smallest support for SPH, a thirty-second of the smallest radius for
  // RBF. (The error falls fourfold per halving, so the step's own error is about 4/3 of
  // the change: measured 0.06 and 0.0005 levels.)
  const ReferenceCamera cam = lookDownZ(4, 1, 10, 24);
  std::vector<ReferenceSPHParticle> p;
  std::vector<ReferenceGaussian> g;
  for (int k = 0; k < 40; ++k)
  {
    const Point x{ std::sin(1.7 * k) * 0.6, std::cos(2.3 * k) * 0.5, std::sin(0.9 * k) * 0.4 };
    p.push_back({ x, 0.3 + 0.1 * (k % 3), 0.2 * (k % 7), 0.01 });
    g.push_back({ x, 0.1 + 0.03 * (k % 3), 0.3 + 0.1 * (k % 5) });
  }
  ReferenceTransferFunction tf;
  tf.lo = 0;
  tf.hi = 1.2;
  tf.rgba = { { 0.1, 0.2, 0.9, 0.02 }, { 0.9, 0.9, 0.9, 0.3 }, { 0.9, 0.2, 0.1, 0.9 } };
  SPHReference sph;
  sph.step = 0.3 / 64;
  RBFReference rbf;
  rbf.step = 0.1 / 32;
  const ReferenceImage a = renderSPH(cam, p, sph, tf), b = renderRBF(cam, g, rbf, tf);
  sph.step /= 2;
  rbf.step /= 2;
  const ReferenceImage a2 = renderSPH(cam, p, sph, tf), b2 = renderRBF(cam, g, rbf, tf);
  double worst = 0, shown = 0;
  for (std::size_t k = 0; k < a.rgba.size(); ++k)
  {
    for (int c = 0; c < 4; ++c)
    {
      worst = std::max({ worst,
        std::fabs(a.rgba[k][c] - a2.rgba[k][c]),
        std::fabs(b.rgba[k][c] - b2.rgba[k][c]) });
      shown = std::max({ shown, a.rgba[k][3], b.rgba[k][3] });
    }
  }
  EXPECT_GT(shown, 0.3);
  EXPECT_LT(worst, 0.1 / 255);
}
