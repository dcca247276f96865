#include "RayCamera.h"

#include <cmath>
#include <utility>

namespace raymappers
{

namespace
{
// p_clip = M [p; 1], M row-major.
inline void transform(const std::array<double, 16>& m, const double p[4], double out[4])
{
  for (int r = 0; r < 4; ++r)
  {
    out[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3] * p[3];
  }
}
}

bool invert4x4(const std::array<double, 16>& m, std::array<double, 16>& inv)
{
  double a[4][8];
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      a[r][c] = m[4 * r + c];
      a[r][c + 4] = (r == c) ? 1.0 : 0.0;
    }
  }
  for (int c = 0; c < 4; ++c)
  {
    int pivot = c;
    for (int r = c + 1; r < 4; ++r)
    {
      if (std::fabs(a[r][c]) > std::fabs(a[pivot][c]))
      {
        pivot = r;
      }
    }
    if (a[pivot][c] == 0.0 || !std::isfinite(a[pivot][c]))
    {
      return false;
    }
    if (pivot != c)
    {
      for (int k = 0; k < 8; ++k)
      {
        std::swap(a[c][k], a[pivot][k]);
      }
    }
    const double s = 1.0 / a[c][c];
    for (int k = 0; k < 8; ++k)
    {
      a[c][k] *= s;
    }
    for (int r = 0; r < 4; ++r)
    {
      if (r != c)
      {
        const double f = a[r][c];
        for (int k = 0; k < 8; ++k)
        {
          a[r][k] -= f * a[c][k];
        }
      }
    }
  }
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      inv[4 * r + c] = a[r][c + 4];
    }
  }
  return true;
}

RayCamera::RayCamera(const std::array<double, 16>& modelToClip,
  int width,
  int height,
  const Vec3d& origin)
  : Width(width)
  , Height(height)
  , Origin(origin)
{
  // M_rel = M T(origin): the matrix of origin-relative coordinates.
  M = modelToClip;
  for (int r = 0; r < 4; ++r)
  {
    M[4 * r + 3] = modelToClip[4 * r] * origin.x + modelToClip[4 * r + 1] * origin.y +
                   modelToClip[4 * r + 2] * origin.z + modelToClip[4 * r + 3];
  }
  if (!invert4x4(M, Minv))
  {
    Minv.fill(0.0);
  }
  // A projection is parallel when w does not depend on the position.
  Parallel = M[12] == 0.0 && M[13] == 0.0 && M[14] == 0.0;
  // x_ndc = 2 px / W - 1: the column of Minv for x, scaled by 2/W, per pixel step.
  for (int r = 0; r < 4; ++r)
  {
    PixelDx[r] = Minv[4 * r] * 2.0 / Width;
    PixelDy[r] = Minv[4 * r + 1] * 2.0 / Height;
    const double corner = -Minv[4 * r] - Minv[4 * r + 1] + Minv[4 * r + 3];
    NearBase[r] = corner - Minv[4 * r + 2];
    FarBase[r] = corner + Minv[4 * r + 2];
  }
}

Vec3d RayCamera::unproject(double xn, double yn, double zn) const
{
  const double c[4] = { xn, yn, zn, 1.0 };
  double p[4];
  transform(Minv, c, p);
  const double iw = 1.0 / p[3];
  return { p[0] * iw + Origin.x, p[1] * iw + Origin.y, p[2] * iw + Origin.z };
}

Ray RayCamera::primaryRay(double px, double py) const
{
  double n[4], f[4];
  for (int r = 0; r < 4; ++r)
  {
    n[r] = NearBase[r] + px * PixelDx[r] + py * PixelDy[r];
    f[r] = FarBase[r] + px * PixelDx[r] + py * PixelDy[r];
  }
  const double in = 1.0 / n[3], inf = 1.0 / f[3];
  const Vec3d a(n[0] * in, n[1] * in, n[2] * in);
  const Vec3d b(f[0] * inf, f[1] * inf, f[2] * inf);
  const Vec3d d = b - a;
  const double len = length(d);
  Ray ray;
  ray.org = Vec3f(a);
  ray.dir = Vec3f(d * (1.0 / len));
  ray.tnear = 0.f;
  ray.tfar = static_cast<float>(len);
  return ray;
}

RayDepthMap RayCamera::depthMap(const Ray& ray) const
{
  const double o[4] = { ray.org.x, ray.org.y, ray.org.z, 1.0 };
  const double d[4] = { ray.dir.x, ray.dir.y, ray.dir.z, 0.0 };
  double co[4], cd[4];
  transform(M, o, co);
  transform(M, d, cd);
  RayDepthMap map;
  map.z0 = co[2];
  map.w0 = co[3];
  map.zd = cd[2];
  map.wd = cd[3];
  return map;
}

double RayCamera::depthOfPoint(const Vec3d& modelPoint) const
{
  const Vec3d r = modelPoint - Origin;
  const double p[4] = { r.x, r.y, r.z, 1.0 };
  double c[4];
  transform(M, p, c);
  return 0.5 * c[2] / c[3] + 0.5;
}

} // namespace raymappers
