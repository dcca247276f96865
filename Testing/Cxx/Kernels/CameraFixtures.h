// Closed-form camera matrices shared by the kernel tests: OpenGL's frustum and orthographic
// projections and a look-at view, row-major, so tests need no VTK.
#ifndef RayMappers_Test_CameraFixtures_h
#define RayMappers_Test_CameraFixtures_h

#include "Mappers/Common/RayCamera.h"
#include "Mappers/Common/Vec3.h"
#include "Mappers/Common/View.h"
#include "Mappers/Common/ViewRays.h"

#include <array>

namespace raymappers::test
{

using Mat4 = std::array<double, 16>;

inline Mat4 multiply(const Mat4& a, const Mat4& b)
{
  Mat4 c{};
  for (int r = 0; r < 4; ++r)
  {
    for (int k = 0; k < 4; ++k)
    {
      double s = 0;
      for (int j = 0; j < 4; ++j)
      {
        s += a[4 * r + j] * b[4 * j + k];
      }
      c[4 * r + k] = s;
    }
  }
  return c;
}

/// View matrix of an eye at `eye` looking at `at` with up vector `up`.
inline Mat4 lookAt(const Vec3d& eye, const Vec3d& at, const Vec3d& up)
{
  const Vec3d f = normalize(at - eye);
  const Vec3d s = normalize(cross(f, up));
  const Vec3d u = cross(s, f);
  return { s.x,
    s.y,
    s.z,
    -dot(s, eye),
    u.x,
    u.y,
    u.z,
    -dot(u, eye),
    -f.x,
    -f.y,
    -f.z,
    dot(f, eye),
    0,
    0,
    0,
    1 };
}

/// Symmetric perspective projection: vertical field of view fovy (degrees), near n, far f.
inline Mat4 perspective(double fovyDeg, double aspect, double n, double f)
{
  const double t = 1.0 / std::tan(fovyDeg * M_PI / 360.0);
  return {
    t / aspect, 0, 0, 0, 0, t, 0, 0, 0, 0, -(f + n) / (f - n), -2 * f * n / (f - n), 0, 0, -1, 0
  };
}

/// Orthographic projection of the box [-hw, hw] x [-hh, hh] x [-n, -f] (view space).
inline Mat4 orthographic(double hw, double hh, double n, double f)
{
  return { 1 / hw, 0, 0, 0, 0, 1 / hh, 0, 0, 0, 0, -2 / (f - n), -(f + n) / (f - n), 0, 0, 0, 1 };
}

/// Clip-space transform selecting tile (a, b) of an s x s tiling: x' = s x + (s - 1 - 2a) w.
inline Mat4 tileTransform(int s, int a, int b)
{
  return { double(s),
    0,
    0,
    double(s - 1 - 2 * a),
    0,
    double(s),
    0,
    double(s - 1 - 2 * b),
    0,
    0,
    1,
    0,
    0,
    0,
    0,
    1 };
}


/// The kernels' View of a test's camera (either parameterization: both hold the matrix,
/// the grid and the origin they were made from) with opaque geometry at `opaqueDepth`.
inline View viewOf(const RayCamera& c, const float* opaqueDepth = nullptr)
{
  return View(c.modelToClip(), c.width(), c.height(), c.origin(), opaqueDepth);
}
inline View viewOf(const ViewRays& r, const float* opaqueDepth = nullptr)
{
  return View(r.modelToClip(), r.width(), r.height(), r.origin(), opaqueDepth);
}
}

#endif
