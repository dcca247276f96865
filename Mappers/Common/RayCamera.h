// Primary rays and depth values for a pixel grid, from a projective world-to-clip matrix.
//
// The matrix M maps homogeneous model coordinates to OpenGL clip coordinates
// (x_c, y_c, z_c, w_c); normalized device coordinates are x_c/w_c etc. in [-1, 1] and the
// window depth is d = (z_c/w_c + 1)/2 in [0, 1] (OpenGL's default depth range). The same
// code serves perspective and parallel projections: a pixel's ray joins the unprojections
// of its centre on the near (z_ndc = -1) and far (z_ndc = +1) planes.
//
// Precision: coordinates handed to the float kernels are relative to `Origin` (usually the
// centre of the data), so data far from the world origin keeps its float precision.
#ifndef RayMappers_RayCamera_h
#define RayMappers_RayCamera_h

#include "Mappers/Common/Vec3.h"

#include <array>
#include <string>

namespace raymappers
{

/// A ray in origin-relative coordinates: x(t) = org + t dir, t in [tnear, tfar], |dir| = 1.
struct Ray
{
  Vec3f org;
  Vec3f dir;
  float tnear = 0.f;
  float tfar = 0.f;
};

/// Along one ray, clip z and w are affine in t: z(t) = z0 + t zd, w(t) = w0 + t wd.
/// That gives the window depth of any t and its inverse in closed form.
struct RayDepthMap
{
  double z0 = 0, zd = 0, w0 = 1, wd = 0;
  /// Window depth d(t) = ((z0 + t zd)/(w0 + t wd) + 1)/2.
  double depthOf(double t) const { return 0.5 * (z0 + t * zd) / (w0 + t * wd) + 0.5; }
  /// Inverse of depthOf: t such that d(t) = d. (Inline: the sweep calls it for every
  /// face crossing of every pixel.)
  double distanceOf(double depth) const
  {
    // (2d - 1)(w0 + t wd) = z0 + t zd  =>  t = (z0 - n w0) / (n wd - zd), n = 2d - 1.
    const double n = 2.0 * depth - 1.0;
    return (z0 - n * w0) / (n * wd - zd);
  }
};

class RayCamera
{
public:
  /// `modelToClip`: row-major 4x4 (column vectors, p_clip = M p). `width` x `height` is the
  /// pixel grid the rays are made for (a renderer's viewport, or one tile of a tiled
  /// render: the matrix then already holds the tile's window shift). `origin`: the point
  /// subtracted from model coordinates before they become float.
  RayCamera(const std::array<double, 16>& modelToClip, int width, int height, const Vec3d& origin);
  /// No rays (a 0 x 0 grid), until assigned a camera.
  RayCamera() = default;

  int width() const { return Width; }
  int height() const { return Height; }
  const Vec3d& origin() const { return Origin; }
  /// The model (not origin-relative) to clip matrix the camera was made from.
  const std::array<double, 16>& modelToClip() const { return ModelToClip; }
  bool isParallel() const { return Parallel; }

  /// The ray through the point (px, py) of the pixel grid; pixel (i, j) has its centre at
  /// (i + 0.5, j + 0.5), row 0 at the bottom (OpenGL convention).
  Ray primaryRay(double px, double py) const;
  Ray pixelRay(int i, int j) const { return primaryRay(i + 0.5, j + 0.5); }
  /// Homogeneous unprojection of the near (z_ndc = -1) and far (z_ndc = +1) planes, linear in
  /// the pixel position: P(px, py) = base + px dx + py dy (4-vectors, then / w).
  struct PlanePoints
  {
    double near[4], far[4], dx[4], dy[4];
  };
  /// The rays of pixels (i[k], j[k]), k < n, bit for bit as pixelRay makes them, in SIMD
  /// lanes, into structure-of-arrays form: origins org[axis][k], unit directions
  /// dir[axis][k] and tfar[k] (tnear 0).
  void pixelRays(const int* i,
    const int* j,
    int n,
    float* const org[3],
    float* const dir[3],
    float* tfar) const;

  /// Whether this camera's rays cross the plane through the origin-relative point p with
  /// normal n along n (d . n > 0 for their directions d where they meet it in front of the
  /// eye): from the eye (perspective: d is along q - eye for every point q of the plane, and
  /// (q - eye) . n = (p - eye) . n) or the common direction (parallel), without a ray.
  bool raysAlong(const Vec3d& p, const Vec3d& n) const;

  /// Depth mapping along a ray of this camera (as returned by primaryRay).
  RayDepthMap depthMap(const Ray& ray) const;
  RayDepthMap pixelDepthMap(int i, int j) const { return depthMap(pixelRay(i, j)); }

  /// Window depth of a model-space point (not origin-relative), or > 1 / < 0 outside.
  double depthOfPoint(const Vec3d& modelPoint) const;

  /// Model-space (not origin-relative) point of normalized device coordinates.
  Vec3d unproject(double xn, double yn, double zn) const;

private:
  std::array<double, 16> ModelToClip{};
  std::array<double, 16> M{};    // origin-relative model -> clip
  std::array<double, 16> Minv{}; // clip -> origin-relative model
  PlanePoints Planes{};
  // The rays' common point (perspective: the eye, clip coordinates (0, 0, 1, 0) up to a
  // factor) or common direction (parallel), origin-relative.
  Vec3d Eye, ViewDirection;
  int Width = 0, Height = 0;
  Vec3d Origin;
  bool Parallel = false;
};

/// Inverse of a row-major 4x4 matrix (Gauss-Jordan with partial pivoting); returns false
/// when it is singular.
bool invert4x4(const std::array<double, 16>& m, std::array<double, 16>& inv);

/// Why a model-to-clip matrix gives no rays ("" when it gives them): NaN or infinite
/// entries (vtkCamera takes a NaN position or focal point as it is, a NaN prop transform
/// does the same), or a singular matrix (the eye at the focal point: vtkCamera then keeps a
/// zero direction of projection and its view transform loses three rows; a view up along
/// the direction of projection loses one). A zero view angle is not degenerate: vtkCamera
/// clamps it to 1e-8 degrees, which still inverts.
std::string degenerateProjection(const std::array<double, 16>& modelToClip);

} // namespace raymappers

#endif
