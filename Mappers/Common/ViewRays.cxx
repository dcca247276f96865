#include "Mappers/Common/ViewRays.h"

#include <algorithm>
#include <cmath>

namespace raymappers
{
namespace
{
Vec3d row(const std::array<double, 16>& m, int r)
{
  return { m[4 * r], m[4 * r + 1], m[4 * r + 2] };
}

/// Solves [a; b; c] x = rhs (rows a, b, c) by Cramer's rule; false when singular.
bool solve3(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& rhs, Vec3d& x)
{
  const double det = dot(a, cross(b, c));
  if (!(std::abs(det) > 0) || !std::isfinite(det))
  {
    return false;
  }
  // Columns of the inverse are the cross products of the rows, over det.
  const Vec3d bc = cross(b, c), ca = cross(c, a), ab = cross(a, b);
  x = (bc * rhs.x + ca * rhs.y + ab * rhs.z) * (1.0 / det);
  return true;
}
}

bool ViewRays::assign(const std::array<double, 16>& modelToClip,
  int width,
  int height,
  const Vec3d& origin)
{
  Width = width;
  Height = height;
  ModelToClip = modelToClip;
  Origin = origin;
  // Origin-relative: p_model = p + origin, so each row's constant term absorbs r . origin.
  M = modelToClip;
  for (int r = 0; r < 4; ++r)
  {
    M[4 * r + 3] += dot(row(modelToClip, r), origin);
  }
  const Vec3d r0 = row(M, 0), r1 = row(M, 1), r2 = row(M, 2), r3 = row(M, 3);
  const double r3len = length(r3);
  Perspective = r3len > 1e-12 * std::abs(M[15]);
  // NDC of pixel coordinates: x_ndc = 2 px / W - 1.
  const double sx = 2.0 / width, sy = 2.0 / height;
  if (Perspective)
  {
    // Eye: rows 0, 1 and 3 vanish. Direction at NDC (x, y): r0.B = x |r3|, r1.B = y |r3|,
    // r3.B = |r3| (zeta grows by 1 per unit of B).
    Vec3d E, Bc, Bxn, Byn;
    if (!solve3(r0, r1, r3, Vec3d(-M[3], -M[7], -M[15]), E) ||
        !solve3(r0, r1, r3, Vec3d(0, 0, r3len), Bc) ||
        !solve3(r0, r1, r3, Vec3d(r3len, 0, 0), Bxn) ||
        !solve3(r0, r1, r3, Vec3d(0, r3len, 0), Byn))
    {
      return false;
    }
    // B(x_ndc, y_ndc) = Bc + x_ndc Bxn + y_ndc Byn with x_ndc = sx px - 1.
    A0 = E;
    Ax = Ay = Vec3d();
    Bx = Bxn * sx;
    By = Byn * sy;
    B0 = Bc - Bxn - Byn;
    ZetaGrad = r3 * (1.0 / r3len);
    ZetaOffset = M[15] / r3len;
    // Near and far: z_clip = -w_clip and +w_clip on the central ray.
    const Vec3d Bmid = direction(0.5 * width, 0.5 * height);
    const double z0 = dot(r2, E) + M[11], zd = dot(r2, Bmid);
    Near = -z0 / (zd + r3len);
    Far = z0 / (r3len - zd);
    PixelSize = length(By);
    const double hx = 0.5 * width * length(Bx), hy = 0.5 * height * length(By);
    Obliquity = std::sqrt(hx * hx + hy * hy) + 1.0;
  }
  else
  {
    const double w = M[15];
    if (!(std::abs(w) > 0))
    {
      return false;
    }
    const Vec3d q0 = r0 * (1 / w), q1 = r1 * (1 / w), q2 = r2 * (1 / w);
    const double c0 = M[3] / w, c1 = M[7] / w, c2 = M[11] / w;
    const double r2len = length(q2);
    Vec3d Ac, Axn, Ayn, B;
    // Start on the near plane (z_clip = -1) at NDC (x, y); direction along the rays with
    // zeta growing by 1 per unit.
    if (!solve3(q0, q1, q2, Vec3d(-c0, -c1, -1 - c2), Ac) ||
        !solve3(q0, q1, q2, Vec3d(1, 0, 0), Axn) || !solve3(q0, q1, q2, Vec3d(0, 1, 0), Ayn) ||
        !solve3(q0, q1, q2, Vec3d(0, 0, r2len), B))
    {
      return false;
    }
    Ax = Axn * sx;
    Ay = Ayn * sy;
    A0 = Ac - Axn - Ayn;
    B0 = B;
    Bx = By = Vec3d();
    ZetaGrad = q2 * (1.0 / r2len);
    ZetaOffset = (c2 + 1.0) / r2len;
    Near = 0.0;
    Far = 2.0 / r2len;
    PixelSize = length(Ay);
    Obliquity = 1.0;
  }
  return std::isfinite(PixelSize) && PixelSize > 0;
}

bool ViewRays::projectedExtent(const Vec3d& c, double H, int axis, double& lo, double& hi) const
{
  // The planes of constant NDC coordinate s are r_a.p - s r3.p = 0 (r3 = (0,0,0,1) for a
  // parallel view); the sphere touches one where (x - s w)^2 = H^2 |r_a - s r3|^2, with
  // x = r_a.c, w = r3.c: a quadratic in s whose roots are the extent.
  const int ra = axis == 0 ? 0 : 1;
  const Vec3d a = row(M, ra), b = row(M, 3);
  const double x = dot(a, c) + M[4 * ra + 3];
  const double w = dot(b, c) + M[15];
  const double H2 = H * H;
  const double qa = w * w - H2 * dot(b, b);
  if (!(w > 0) || !(qa > 0))
  {
    return false;
  }
  const double qb = x * w - H2 * dot(a, b);
  const double qc = x * x - H2 * dot(a, a);
  const double disc = std::sqrt(std::max(0.0, qb * qb - qa * qc));
  const double s0 = (qb - disc) / qa, s1 = (qb + disc) / qa;
  const double size = axis == 0 ? Width : Height;
  lo = 0.5 * (s0 + 1.0) * size;
  hi = 0.5 * (s1 + 1.0) * size;
  return true;
}

SphereFootprint ViewRays::footprint(const Vec3d& c, double H) const
{
  SphereFootprint f;
  f.zc = zetaOf(c);
  f.zlo = std::max(f.zc - H, Near);
  f.zhi = std::min(f.zc + H, Far);
  if (!(f.zlo < f.zhi))
  {
    return f;
  }
  double x0 = -1e30, x1 = 1e30, y0 = -1e30, y1 = 1e30;
  if (projectedExtent(c, H, 0, x0, x1))
  {
    projectedExtent(c, H, 1, y0, y1);
  }
  // Clamped to the image on both sides before the pixel indices are taken: a sphere far off
  // screen can project beyond int's range (a view angle of 1e-8 degrees, VTK's smallest,
  // magnifies by 1e10), and converting such a value to int is undefined (it came out as
  // INT_MIN: a sphere "in view" from pixel -2^31). A NaN extent is out of view.
  f.x0 = std::clamp(x0, 0.0, double(Width));
  f.x1 = std::clamp(x1, 0.0, double(Width));
  f.y0 = std::clamp(y0, 0.0, double(Height));
  f.y1 = std::clamp(y1, 0.0, double(Height));
  if (!(f.x0 <= f.x1) || !(f.y0 <= f.y1))
  {
    return f;
  }
  f.i0 = static_cast<int>(std::ceil(f.x0 - 0.5));
  f.i1 = static_cast<int>(std::floor(f.x1 - 0.5));
  f.j0 = static_cast<int>(std::ceil(f.y0 - 0.5));
  f.j1 = static_cast<int>(std::floor(f.y1 - 0.5));
  f.inView = f.i0 <= f.i1 && f.j0 <= f.j1;
  return f;
}

double ViewRays::zetaOfWindowDepth(double px, double py, double d) const
{
  const double zn = 2.0 * d - 1.0;
  const Vec3d r2 = row(M, 2), r3 = row(M, 3);
  const Vec3d A = start(px, py), B = direction(px, py);
  // z_clip and w_clip are affine along the ray: z0 + zeta zd, w0 + zeta wd.
  const double z0 = dot(r2, A) + M[11], zd = dot(r2, B);
  const double w0 = dot(r3, A) + M[15], wd = dot(r3, B);
  const double den = zd - zn * wd;
  return std::abs(den) > 0 ? (zn * w0 - z0) / den : Far;
}

std::array<double, 4> ViewRays::clip(const Vec3d& p) const
{
  std::array<double, 4> c{};
  for (int r = 0; r < 4; ++r)
  {
    c[r] = dot(row(M, r), p) + M[4 * r + 3];
  }
  return c;
}

} // namespace raymappers
