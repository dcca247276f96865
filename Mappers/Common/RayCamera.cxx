#include "Mappers/Common/RayCamera.h"

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

std::string degenerateProjection(const std::array<double, 16>& modelToClip)
{
  for (const double m : modelToClip)
  {
    if (!std::isfinite(m))
    {
      return "its projection matrix has NaN or infinite entries (a NaN or infinite camera "
             "position, focal point or view up, or prop transform)";
    }
  }
  std::array<double, 16> inverse;
  if (!invert4x4(modelToClip, inverse))
  {
    return "its projection is singular (the eye at the focal point, or the view up along the "
           "direction of projection)";
  }
  return "";
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
  : ModelToClip(modelToClip)
  , Width(width)
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
    Planes.dx[r] = Minv[4 * r] * 2.0 / Width;
    Planes.dy[r] = Minv[4 * r + 1] * 2.0 / Height;
    const double corner = -Minv[4 * r] - Minv[4 * r + 1] + Minv[4 * r + 3];
    Planes.near[r] = corner - Minv[4 * r + 2];
    Planes.far[r] = corner + Minv[4 * r + 2];
  }
  if (Parallel)
  {
    // The far point minus the near point of the corner pixel, the same for all.
    ViewDirection = Vec3d(Planes.far[0] / Planes.far[3] - Planes.near[0] / Planes.near[3],
      Planes.far[1] / Planes.far[3] - Planes.near[1] / Planes.near[3],
      Planes.far[2] / Planes.far[3] - Planes.near[2] / Planes.near[3]);
  }
  else
  {
    const double ew = Minv[14];
    Eye = Vec3d(Minv[2] / ew, Minv[6] / ew, Minv[10] / ew);
  }
}

bool RayCamera::raysAlong(const Vec3d& p, const Vec3d& n) const
{
  return dot(Parallel ? ViewDirection : p - Eye, n) > 0;
}

Vec3d RayCamera::unproject(double xn, double yn, double zn) const
{
  const double c[4] = { xn, yn, zn, 1.0 };
  double p[4];
  transform(Minv, c, p);
  const double iw = 1.0 / p[3];
  return { p[0] * iw + Origin.x, p[1] * iw + Origin.y, p[2] * iw + Origin.z };
}

namespace
{
// The ray through (px, py): the points P = base + px dx + py dy of the near and the far
// plane (homogeneous, then / w) give the origin a (the near point), the unit direction
// (b - a) / |b - a| and the distance |b - a| to the far plane. One inline body for
// primaryRay and pixelRays, so that both compute every ray bit for bit alike. (Written
// without local arrays: in a SIMD loop GCC 12 would keep them per lane in memory and leave
// the loop scalar.)
struct RayLane
{
  float ox, oy, oz, dx, dy, dz, len;
};

inline RayLane rayThrough(const RayCamera::PlanePoints& c, double px, double py)
{
  const double nx = c.near[0] + px * c.dx[0] + py * c.dy[0];
  const double ny = c.near[1] + px * c.dx[1] + py * c.dy[1];
  const double nz = c.near[2] + px * c.dx[2] + py * c.dy[2];
  const double nw = c.near[3] + px * c.dx[3] + py * c.dy[3];
  const double fx = c.far[0] + px * c.dx[0] + py * c.dy[0];
  const double fy = c.far[1] + px * c.dx[1] + py * c.dy[1];
  const double fz = c.far[2] + px * c.dx[2] + py * c.dy[2];
  const double fw = c.far[3] + px * c.dx[3] + py * c.dy[3];
  const double in = 1.0 / nw, inf = 1.0 / fw;
  const double ax = nx * in, ay = ny * in, az = nz * in;
  const double vx = fx * inf - ax, vy = fy * inf - ay, vz = fz * inf - az;
  const double l = std::sqrt(vx * vx + vy * vy + vz * vz);
  const double il = 1.0 / l;
  return RayLane{ static_cast<float>(ax),
    static_cast<float>(ay),
    static_cast<float>(az),
    static_cast<float>(vx * il),
    static_cast<float>(vy * il),
    static_cast<float>(vz * il),
    static_cast<float>(l) };
}
}

Ray RayCamera::primaryRay(double px, double py) const
{
  const RayLane l = rayThrough(Planes, px, py);
  Ray ray;
  ray.org = Vec3f(l.ox, l.oy, l.oz);
  ray.dir = Vec3f(l.dx, l.dy, l.dz);
  ray.tnear = 0.f;
  ray.tfar = l.len;
  return ray;
}

void RayCamera::pixelRays(const int* i,
  const int* j,
  int n,
  float* const org[3],
  float* const dir[3],
  float* tfar) const
{
  const PlanePoints c = Planes; // (a local: the lanes read it from registers)
  float *ox = org[0], *oy = org[1], *oz = org[2], *dx = dir[0], *dy = dir[1], *dz = dir[2];
#pragma omp simd
  for (int k = 0; k < n; ++k)
  {
    const RayLane l = rayThrough(c, i[k] + 0.5, j[k] + 0.5);
    ox[k] = l.ox;
    oy[k] = l.oy;
    oz[k] = l.oz;
    dx[k] = l.dx;
    dy[k] = l.dy;
    dz[k] = l.dz;
    tfar[k] = l.len;
  }
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
