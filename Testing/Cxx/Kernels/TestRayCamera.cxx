// Primary rays and depth mapping against closed-form projections.
#include "CameraFixtures.h"
#include "Mappers/Common/RayCamera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace raymappers;
using namespace raymappers::test;

namespace
{
const Vec3d Eye{ 1, 2, 10 };
const Vec3d At{ 1, 2, 0 };
const Vec3d Up{ 0, 1, 0 };
}

TEST(RayCamera, PerspectiveCentreRayLooksAlongTheViewDirection)
{
  const RayCamera cam(multiply(perspective(30, 1, 0.5, 100), lookAt(Eye, At, Up)), 64, 64, {});
  const Ray r = cam.primaryRay(32, 32);
  EXPECT_NEAR(r.dir.x, 0, 1e-7);
  EXPECT_NEAR(r.dir.y, 0, 1e-7);
  EXPECT_NEAR(r.dir.z, -1, 1e-7);
  // The ray starts on the near plane, 0.5 in front of the eye.
  EXPECT_NEAR(r.org.z, 9.5, 1e-6);
  EXPECT_NEAR(r.tfar, 99.5, 1e-4);
}

TEST(RayCamera, PerspectiveRaysPassThroughTheEye)
{
  const RayCamera cam(multiply(perspective(40, 1.5, 0.1, 50), lookAt(Eye, At, Up)), 96, 64, {});
  for (int j = 0; j < 64; j += 9)
  {
    for (int i = 0; i < 96; i += 11)
    {
      const Ray r = cam.pixelRay(i, j);
      const Vec3d o(r.org), d(r.dir);
      // distance from the eye to the ray's line
      const Vec3d e = Eye - o;
      const Vec3d perp = e - d * dot(e, d);
      EXPECT_LT(length(perp), 1e-5) << i << "," << j;
    }
  }
}

TEST(RayCamera, PixelCornersSpanTheFieldOfView)
{
  // The top edge of the image (py = height) is at tan(fovy/2) in view space.
  const double fovy = 50;
  const RayCamera cam(multiply(perspective(fovy, 1, 1, 10), lookAt(Eye, At, Up)), 32, 32, {});
  const Ray r = cam.primaryRay(16, 32);
  const double slope = r.dir.y / -r.dir.z;
  EXPECT_NEAR(slope, std::tan(fovy * M_PI / 360), 1e-6);
}

TEST(RayCamera, PerspectiveDepthIsTheOpenGLClosedForm)
{
  const double n = 0.5, f = 100;
  const RayCamera cam(multiply(perspective(30, 1, n, f), lookAt(Eye, At, Up)), 64, 64, {});
  const Ray r = cam.primaryRay(32, 32);
  const RayDepthMap map = cam.depthMap(r);
  for (double z : { 0.5, 1.0, 3.0, 10.0, 99.0 })
  {
    // A point at view distance z: ndc = (f + n)/(f - n) - 2 f n / ((f - n) z).
    const double ndc = (f + n) / (f - n) - 2 * f * n / ((f - n) * z);
    const double expected = 0.5 * ndc + 0.5;
    const double t = z - n; // the centre ray starts on the near plane
    EXPECT_NEAR(map.depthOf(t), expected, 1e-9) << z;
    EXPECT_NEAR(cam.depthOfPoint(Eye + Vec3d(0, 0, -z)), expected, 1e-12) << z;
    EXPECT_NEAR(map.distanceOf(expected), t, 1e-6 * z) << z;
  }
  EXPECT_NEAR(map.depthOf(0), 0.0, 1e-12);
  EXPECT_NEAR(map.depthOf(r.tfar), 1.0, 1e-6);
}

TEST(RayCamera, ParallelRaysAreParallelAndDepthIsLinear)
{
  const double n = 1, f = 21;
  const RayCamera cam(multiply(orthographic(4, 3, n, f), lookAt(Eye, At, Up)), 80, 60, {});
  EXPECT_TRUE(cam.isParallel());
  const Ray a = cam.pixelRay(0, 0);
  const Ray b = cam.pixelRay(79, 59);
  EXPECT_NEAR(a.dir.z, -1, 1e-7);
  EXPECT_NEAR(b.dir.z, -1, 1e-7);
  // pixel (0,0)'s centre is half a pixel inside the corner (-4, -3) of the view box
  EXPECT_NEAR(a.org.x, Eye.x - 4 + 0.5 * 8.0 / 80, 1e-6);
  EXPECT_NEAR(a.org.y, Eye.y - 3 + 0.5 * 6.0 / 60, 1e-6);
  const RayDepthMap map = cam.depthMap(a);
  for (double t : { 0.0, 5.0, 10.0, 20.0 })
  {
    EXPECT_NEAR(map.depthOf(t), t / (f - n), 1e-9);
  }
}

TEST(RayCamera, OriginOffsetKeepsFloatPrecisionFarFromTheWorldOrigin)
{
  // Data a million units away: relative coordinates keep the ray exact to float epsilon of
  // the scene size, not of 1e6.
  const Vec3d far{ 1e6, -2e6, 3e6 };
  const RayCamera cam(
    multiply(perspective(30, 1, 0.5, 100), lookAt(far + Vec3d(0, 0, 10), far, Up)), 64, 64, far);
  const Ray r = cam.primaryRay(32, 32);
  EXPECT_NEAR(r.org.x, 0, 1e-6);
  EXPECT_NEAR(r.org.y, 0, 1e-6);
  EXPECT_NEAR(r.org.z, 9.5, 1e-5);
}

TEST(RayCamera, TilesOfALargeImageHaveTheRaysOfTheLargeImage)
{
  const Mat4 m = multiply(perspective(35, 1, 0.5, 80), lookAt(Eye, At, Up));
  const int s = 3, w = 90, h = 60;
  const RayCamera full(m, w, h, {});
  for (int b = 0; b < s; ++b)
  {
    for (int a = 0; a < s; ++a)
    {
      const RayCamera tile(multiply(tileTransform(s, a, b), m), w / s, h / s, {});
      for (int j = 0; j < h / s; j += 7)
      {
        for (int i = 0; i < w / s; i += 5)
        {
          const Ray rt = tile.pixelRay(i, j);
          const Ray rf = full.pixelRay(a * w / s + i, b * h / s + j);
          EXPECT_NEAR(rt.dir.x, rf.dir.x, 1e-6);
          EXPECT_NEAR(rt.dir.y, rf.dir.y, 1e-6);
          EXPECT_NEAR(rt.dir.z, rf.dir.z, 1e-6);
          EXPECT_NEAR(rt.org.x, rf.org.x, 1e-5);
          EXPECT_NEAR(tile.depthMap(rt).depthOf(7), full.depthMap(rf).depthOf(7), 1e-7);
        }
      }
    }
  }
}

TEST(RayCamera, PixelRaysInLanesAreThePixelRaysBitForBit)
{
  const Mat4 view = lookAt(Eye, At, Up);
  for (const Mat4& m : { multiply(perspective(35, 1.5, 0.5, 80), view),
         multiply(tileTransform(3, 2, 1), multiply(perspective(35, 1.5, 0.5, 80), view)),
         multiply(orthographic(4, 3, 1, 21), view) })
  {
    const RayCamera cam(m, 60, 40, {});
    // A packet's pixels, not in row order, one count that is no multiple of a SIMD width.
    std::vector<int> pi, pj;
    for (int q = 0; q < 37; ++q)
    {
      pi.push_back((q * 17) % 60);
      pj.push_back((q * 7) % 40);
    }
    const int n = static_cast<int>(pi.size());
    std::vector<float> o[3], d[3], tfar(n);
    for (int a = 0; a < 3; ++a)
    {
      o[a].resize(n);
      d[a].resize(n);
    }
    float* const org[3] = { o[0].data(), o[1].data(), o[2].data() };
    float* const dir[3] = { d[0].data(), d[1].data(), d[2].data() };
    cam.pixelRays(pi.data(), pj.data(), n, org, dir, tfar.data());
    for (int k = 0; k < n; ++k)
    {
      const Ray r = cam.pixelRay(pi[k], pj[k]);
      for (int a = 0; a < 3; ++a)
      {
        EXPECT_EQ(o[a][k], r.org[a]) << k << " axis " << a;
        EXPECT_EQ(d[a][k], r.dir[a]) << k << " axis " << a;
      }
      EXPECT_EQ(tfar[k], r.tfar) << k;
    }
  }
}

TEST(RayCamera, RaysAlongTellsTheSideTheRaysCrossAPlaneFrom)
{
  // Planes through points in front of the camera, normals all around: the rays go along n
  // when (p - eye) . n > 0 (perspective), when (0, 0, -1) . n > 0 (parallel, looking down
  // -z), with the eye and the view direction of the lookAt, not of the camera's matrices.
  const Mat4 view = lookAt(Eye, At, Up);
  const RayCamera persp(
    multiply(tileTransform(3, 0, 2), multiply(perspective(40, 1, 0.5, 80), view)), 32, 32, {});
  const RayCamera parallel(multiply(orthographic(4, 3, 1, 21), view), 32, 32, {});
  int along = 0, against = 0;
  for (int q = 0; q < 200; ++q)
  {
    const Vec3d p(At.x + std::sin(q * 1.7) * 3, At.y + std::cos(q * 2.3) * 2, std::sin(q * 0.9) * 4);
    const Vec3d n(std::sin(q * 0.37), std::cos(q * 1.13), std::sin(q * 2.71 + 1));
    const double dp = dot(p - Eye, n), dq = dot(Vec3d(0, 0, -1), n);
    if (std::abs(dp) > 1e-9 * length(p - Eye) * length(n))
    {
      EXPECT_EQ(persp.raysAlong(p, n), dp > 0) << q;
      (dp > 0 ? along : against) += 1;
    }
    if (std::abs(dq) > 1e-9 * length(n))
    {
      EXPECT_EQ(parallel.raysAlong(p, n), dq > 0) << q;
    }
  }
  EXPECT_GT(along, 20);
  EXPECT_GT(against, 20);
}

TEST(RayCamera, Invert4x4)
{
  const Mat4 m = multiply(perspective(35, 1.3, 0.5, 80), lookAt(Eye, At, Up));
  Mat4 inv;
  ASSERT_TRUE(invert4x4(m, inv));
  const Mat4 id = multiply(m, inv);
  for (int i = 0; i < 16; ++i)
  {
    EXPECT_NEAR(id[i], (i % 5 == 0) ? 1.0 : 0.0, 1e-12);
  }
  Mat4 singular{};
  EXPECT_FALSE(invert4x4(singular, inv));
}
