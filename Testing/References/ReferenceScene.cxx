#include "ReferenceScene.h"

#include <algorithm>
#include <stdexcept>

namespace raymappers::reference
{

namespace
{
// The inverse of a 4x4 matrix by Gauss-Jordan elimination with partial pivoting.
std::array<double, 16> invert(const std::array<double, 16>& m)
{
  double a[4][8];
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      a[r][c] = m[4 * r + c];
      a[r][c + 4] = r == c ? 1.0 : 0.0;
    }
  }
  for (int c = 0; c < 4; ++c)
  {
    int pivot = c;
    for (int r = c + 1; r < 4; ++r)
    {
      pivot = std::fabs(a[r][c]) > std::fabs(a[pivot][c]) ? r : pivot;
    }
    if (a[pivot][c] == 0)
    {
      throw std::runtime_error("the camera matrix is singular");
    }
    std::swap(a[c], a[pivot]);
    const double s = 1.0 / a[c][c];
    for (double& v : a[c])
    {
      v *= s;
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
  std::array<double, 16> inverse;
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      inverse[4 * r + c] = a[r][c + 4];
    }
  }
  return inverse;
}
}

ReferenceCamera::ReferenceCamera(const std::array<double, 16>& worldToNDC, int width, int height)
  : M(worldToNDC)
  , Inverse(invert(worldToNDC))
  , Width(width)
  , Height(height)
{
}

Point ReferenceCamera::unproject(double x, double y, double z) const
{
  double p[4];
  for (int r = 0; r < 4; ++r)
  {
    p[r] =
      Inverse[4 * r] * x + Inverse[4 * r + 1] * y + Inverse[4 * r + 2] * z + Inverse[4 * r + 3];
  }
  return { p[0] / p[3], p[1] / p[3], p[2] / p[3] };
}

PixelRay ReferenceCamera::ray(int i, int j) const
{
  const double x = 2.0 * (i + 0.5) / Width - 1.0, y = 2.0 * (j + 0.5) / Height - 1.0;
  const Point nearPoint = unproject(x, y, -1.0), farPoint = unproject(x, y, 1.0);
  PixelRay r;
  r.origin = nearPoint;
  r.length = norm(farPoint - nearPoint);
  r.direction = (farPoint - nearPoint) * (1.0 / r.length);
  return r;
}

Point ReferenceCamera::pointAt(int i, int j, double windowDepth) const
{
  return unproject(
    2.0 * (i + 0.5) / Width - 1.0, 2.0 * (j + 0.5) / Height - 1.0, 2 * windowDepth - 1);
}

bool ReferenceCamera::project(Point p, double& x, double& y) const
{
  double c[4];
  for (int r = 0; r < 4; ++r)
  {
    c[r] = M[4 * r] * p.x + M[4 * r + 1] * p.y + M[4 * r + 2] * p.z + M[4 * r + 3];
  }
  x = (c[0] / c[3] + 1) * 0.5 * Width;
  y = (c[1] / c[3] + 1) * 0.5 * Height;
  return c[3] > 0;
}

double ReferenceCamera::windowDepth(Point p) const
{
  const double z = M[8] * p.x + M[9] * p.y + M[10] * p.z + M[11];
  const double w = M[12] * p.x + M[13] * p.y + M[14] * p.z + M[15];
  return 0.5 * z / w + 0.5;
}

std::array<double, 4> ReferenceTransferFunction::at(double v) const
{
  const int n = static_cast<int>(rgba.size());
  if (n == 1 || !(hi > lo))
  {
    return rgba.front();
  }
  const double x = std::clamp((v - lo) / (hi - lo), 0.0, 1.0) * (n - 1);
  const int k = std::min(static_cast<int>(x), n - 2);
  const double f = x - k;
  std::array<double, 4> out;
  for (int c = 0; c < 4; ++c)
  {
    out[c] = rgba[k][c] + f * (rgba[k + 1][c] - rgba[k][c]);
  }
  return out;
}

double ReferenceTransferFunction::extinction(double alpha) const
{
  return -std::log1p(-std::min(alpha, 1.0 - 1e-12)) / unitDistance;
}

Point phong(const std::vector<ReferenceLight>& lights,
  const ReferenceMaterial& m,
  Point color,
  Point n,
  Point toEye)
{
  Point c = color * m.ambient;
  for (const ReferenceLight& light : lights)
  {
    const double nl = dot(n, light.toLight);
    if (nl <= 0)
    {
      continue;
    }
    const Point r = n * (2 * nl) - light.toLight;
    const double rv = std::max(0.0, dot(r, toEye));
    const double s = m.specular > 0 ? m.specular * std::pow(rv, m.specularPower) : 0.0;
    c.x += light.color.x * (m.diffuse * nl * color.x + s * m.specularColor.x);
    c.y += light.color.y * (m.diffuse * nl * color.y + s * m.specularColor.y);
    c.z += light.color.z * (m.diffuse * nl * color.z + s * m.specularColor.z);
  }
  return { std::clamp(c.x, 0.0, 1.0), std::clamp(c.y, 0.0, 1.0), std::clamp(c.z, 0.0, 1.0) };
}

std::vector<unsigned char> ReferenceImage::over(Point background) const
{
  std::vector<unsigned char> out(3 * rgba.size());
  const double bg[3] = { background.x, background.y, background.z };
  for (std::size_t p = 0; p < rgba.size(); ++p)
  {
    for (int c = 0; c < 3; ++c)
    {
      const double v = rgba[p][c] + (1.0 - rgba[p][3]) * bg[c];
      out[3 * p + c] = static_cast<unsigned char>(std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
    }
  }
  return out;
}

}
