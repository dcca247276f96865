// The primary rays of a view parameterized by depth along the view axis, as the perspective
// grid of Limper 2012 (section 3.4, figure 4.2) needs them: every ray reaches the same
// depth zeta at the same parameter, so the rays of a pixel tile share their sample depths.
//
// From a projective model-to-clip matrix with rows r0..r3 (p_clip = M p), in
// origin-relative model coordinates:
//   perspective: zeta(p) = (r3 . p) / |r3_xyz| is the distance from the eye plane along
//     the view axis (w_clip = -z_eye for VTK's cameras); the ray of pixel (px, py) is
//     p(zeta) = E + zeta B(px, py), E the eye (rows 0, 1, 3 vanish there) and B on the
//     plane zeta = 1;
//   parallel: zeta(p) = (z_clip(p) + 1) / |r2_xyz| is the distance from the near plane; the
//     ray is p(zeta) = A(px, py) + zeta B, A on the near plane.
// A and B are affine in the pixel position: A = A0 + px Ax + py Ay, B = B0 + px Bx + py By
// (Ax = Ay = 0 for perspective, Bx = By = 0 for parallel). |grad zeta| = 1, so a sphere
// of radius H around a centre at depth zeta_c spans exactly [zeta_c - H, zeta_c + H].
#ifndef RayMappers_ViewRays_h
#define RayMappers_ViewRays_h

#include "Mappers/Common/Vec3.h"

#include <array>

namespace raymappers
{

/// What a sphere covers of a view: its depth span clipped to near and far, its projected
/// extent clipped to the image ([x0, x1] x [y0, y1] in pixel coordinates) and the pixels whose
/// centres (i + 0.5, j + 0.5) lie in it, [i0, i1] x [j0, j1]; inView is false when either is
/// empty.
struct SphereFootprint
{
  bool inView = false;
  double zc = 0, zlo = 0, zhi = 0;
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  int i0 = 0, i1 = -1, j0 = 0, j1 = -1;
};

class ViewRays
{
public:
  /// `modelToClip`: row-major 4x4 (column vectors), model coordinates not origin-relative;
  /// `width` x `height` the pixel grid (pixel (i, j) has its centre at (i + 0.5, j + 0.5),
  /// row 0 at the bottom). Returns false when the matrix is degenerate.
  bool assign(const std::array<double, 16>& modelToClip,
    int width,
    int height,
    const Vec3d& origin);

  bool isPerspective() const { return Perspective; }
  int width() const { return Width; }
  int height() const { return Height; }

  Vec3d start(double px, double py) const { return A0 + Ax * px + Ay * py; }
  Vec3d direction(double px, double py) const { return B0 + Bx * px + By * py; }
  Vec3d pointAt(double px, double py, double zeta) const
  {
    return start(px, py) + direction(px, py) * zeta;
  }
  const Vec3d& startBase() const { return A0; }
  const Vec3d& startPerPixelX() const { return Ax; }
  const Vec3d& startPerPixelY() const { return Ay; }
  const Vec3d& directionBase() const { return B0; }
  const Vec3d& directionPerPixelX() const { return Bx; }
  const Vec3d& directionPerPixelY() const { return By; }

  /// Depth of an (origin-relative) point.
  double zetaOf(const Vec3d& p) const { return dot(ZetaGrad, p) + ZetaOffset; }
  /// The camera's near and far clipping depths (on the central ray).
  double nearZeta() const { return Near; }
  double farZeta() const { return Far; }
  /// The size of a pixel (the y spacing of neighbouring rays) at zeta = 1 (perspective:
  /// the thesis's sigma, equation 3.3) or everywhere (parallel), in model units.
  double pixelSize() const { return PixelSize; }
  /// Equation 3.4: 1 + the half-diagonal of the image plane at zeta = 1 in units of zeta,
  /// the factor by which the longest ray's step exceeds its depth step (1 for parallel).
  double obliquity() const { return Obliquity; }

  /// The pixel-coordinate interval [lo, hi] along x (axis 0) or y (axis 1) that the
  /// projection of the sphere (centre c, origin-relative; radius H) covers: exact tangent
  /// planes through the eye (perspective) or along the rays (parallel). Returns false when
  /// the sphere reaches behind the eye plane, where the projection is unbounded.
  bool projectedExtent(const Vec3d& c, double H, int axis, double& lo, double& hi) const;

  /// The footprint of the sphere (centre c, origin-relative; radius H): its projected
  /// extent is exact (projectedExtent), or the whole image when the sphere reaches behind
  /// the eye plane.
  SphereFootprint footprint(const Vec3d& c, double H) const;

  /// The depth along the ray of pixel (px, py) at which OpenGL's window depth is d.
  double zetaOfWindowDepth(double px, double py, double d) const;

  /// Clip coordinates (x, y, z, w) of an origin-relative point. They are affine in the
  /// point, so along a line p0 + t d they are clip(p0) + t (clip(p0 + d) - clip(p0)); the
  /// pixel coordinates are ((x / w + 1) W / 2, (y / w + 1) H / 2), the window depth
  /// (z / w + 1) / 2.
  std::array<double, 4> clip(const Vec3d& p) const;
  /// The model (not origin-relative) to clip matrix and the origin the rays were made from.
  const std::array<double, 16>& modelToClip() const { return ModelToClip; }
  const Vec3d& origin() const { return Origin; }
  /// The origin-relative model-to-clip matrix (row-major) that clip() applies.
  const std::array<double, 16>& originRelativeClip() const { return M; }

private:
  std::array<double, 16> ModelToClip{};
  Vec3d Origin;
  std::array<double, 16> M{}; // origin-relative model -> clip
  bool Perspective = true;
  int Width = 0, Height = 0;
  Vec3d A0, Ax, Ay, B0, Bx, By;
  Vec3d ZetaGrad;
  double ZetaOffset = 0;
  double Near = 0, Far = 0;
  double PixelSize = 0, Obliquity = 1;
};

} // namespace raymappers

#endif
