// The independent references of the end-to-end tests: what every mapper should draw, computed
// again from the definitions in double precision, sharing no code with Mappers/ (only the
// camera's world-to-NDC matrix is read from VTK, and everything is derived from it here).
//
// A scene is a camera (the composite projection matrix M of vtkCamera for the viewport's
// aspect, world -> normalized device coordinates in [-1, 1]^3, and the pixel grid), the
// particles, transfer functions sampled from the VTK functions, lights and a material. The
// renderers (ReferenceRenderers.h) give per pixel the colour and opacity (premultiplied) and
// the window depth of the first surface.
#ifndef RayMappers_Reference_ReferenceScene_h
#define RayMappers_Reference_ReferenceScene_h

#include <array>
#include <cmath>
#include <vector>

namespace raymappers::reference
{

struct Point
{
  double x = 0, y = 0, z = 0;
};
inline Point operator+(Point a, Point b)
{
  return { a.x + b.x, a.y + b.y, a.z + b.z };
}
inline Point operator-(Point a, Point b)
{
  return { a.x - b.x, a.y - b.y, a.z - b.z };
}
inline Point operator*(Point a, double s)
{
  return { a.x * s, a.y * s, a.z * s };
}
inline double dot(Point a, Point b)
{
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline double norm(Point a)
{
  return std::sqrt(dot(a, a));
}
inline Point unit(Point a)
{
  return a * (1.0 / norm(a));
}

/// A pixel's ray: x(t) = origin + t direction (unit), from the near plane (t = 0) to the
/// far plane (t = length).
struct PixelRay
{
  Point origin, direction;
  double length = 0;
};

/// The camera of a render: pixel (i, j) of a W x H viewport has its centre at NDC
/// (2 (i + 1/2) / W - 1, 2 (j + 1/2) / H - 1); its ray joins that point's unprojections
/// M^-1 (x, y, -1, 1) (near plane) and M^-1 (x, y, 1, 1) (far plane). The window depth of a
/// world point p is (z_c / w_c + 1) / 2 with (x_c, y_c, z_c, w_c) = M p.
class ReferenceCamera
{
public:
  /// `worldToNDC`: M row-major (vtkMatrix4x4 element (r, c) at 4 r + c).
  ReferenceCamera(const std::array<double, 16>& worldToNDC, int width, int height);
  int width() const { return Width; }
  int height() const { return Height; }
  PixelRay ray(int i, int j) const;
  double windowDepth(Point p) const;
  /// The pixel coordinates (x, y) of a world point (pixel (i, j) spans [i, i + 1) x
  /// [j, j + 1)); false when the point is not in front of the eye (w <= 0).
  bool project(Point p, double& x, double& y) const;
  /// The world point of pixel (i, j)'s centre at a window depth (a depth buffer's value).
  Point pointAt(int i, int j, double windowDepth) const;

private:
  Point unproject(double x, double y, double z) const;
  std::array<double, 16> M, Inverse;
  int Width, Height;
};

/// A transfer function sampled at n evenly spaced values over [lo, hi] (from VTK's
/// vtkColorTransferFunction and vtkPiecewiseFunction), interpolated linearly and clamped to
/// the range. The opacity is per unitDistance of path: extinction
/// tau(v) = -ln(1 - alpha(v)) / unitDistance.
struct ReferenceTransferFunction
{
  std::vector<std::array<double, 4>> rgba; // straight colour and opacity
  double lo = 0, hi = 1;
  double unitDistance = 1;

  std::array<double, 4> at(double v) const;
  double extinction(double alpha) const;
};

/// A directional light of VTK (a light kit's or the headlight), in world space.
struct ReferenceLight
{
  Point toLight; // unit vector from the surface to the light
  Point color;   // diffuse colour times intensity
};

/// The Phong model of VTK's OpenGL polygon mappers: for unit normal n, unit direction to the
/// eye v and per light l and colour c,
///   colour = Ka C + sum over lights with n.l > 0 of [Kd (n.l) c C + Ks max(0, r.v)^p c S],
/// r = 2 (n.l) n - l, each channel clamped to [0, 1].
struct ReferenceMaterial
{
  double ambient = 0, diffuse = 1, specular = 0, specularPower = 1;
  Point specularColor{ 1, 1, 1 };
};
Point phong(const std::vector<ReferenceLight>& lights,
  const ReferenceMaterial& m,
  Point color,
  Point n,
  Point toEye);

/// Per pixel, row 0 at the bottom: premultiplied RGBA and the window depth of the first
/// surface (1 where there is none).
struct ReferenceImage
{
  int width = 0, height = 0;
  std::vector<std::array<double, 4>> rgba;
  std::vector<double> depth;

  ReferenceImage(int w, int h)
    : width(w)
    , height(h)
    , rgba(static_cast<std::size_t>(w) * h, { 0, 0, 0, 0 })
    , depth(static_cast<std::size_t>(w) * h, 1.0)
  {
  }
  std::array<double, 4>& at(int i, int j) { return rgba[static_cast<std::size_t>(j) * width + i]; }
  /// 8-bit RGB of the picture over a background colour (C + (1 - A) background, rounded),
  /// rows bottom to top as VTK reads windows and PNG files.
  std::vector<unsigned char> over(Point background) const;
};

}

#endif
