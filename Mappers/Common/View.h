// One frame's view, as every method's kernel receives it: made once from one projective
// model-to-clip matrix M (row-major, column vectors: p_clip = M p; model coordinates, not
// origin-relative), the pixel grid it is rendered at (the renderer's viewport, a tile's, or
// a reduced frame's), the origin subtracted from model coordinates before they become float,
// and the window depth of opaque geometry already drawn there.
//
// From M it holds both ray parameterizations the methods use (RayCamera.h, ViewRays.h):
//   camera(): rays by distance, x(t) = org + t dir with |dir| = 1 (CGT's packets, the RBF
//     traversals, ZSweep's per-pixel depth maps);
//   depthRays(): rays by depth zeta along the view axis, so the rays of a tile share their
//     sample depths (Limper's perspective grid, section 3.4; the voxelizer's layers).
// Pixel (i, j) has its centre at (i + 0.5, j + 0.5), row 0 at the bottom (OpenGL).
#ifndef RayMappers_View_h
#define RayMappers_View_h

#include "Mappers/Common/RayCamera.h"
#include "Mappers/Common/Vec3.h"
#include "Mappers/Common/ViewRays.h"

#include <array>
#include <cstddef>

namespace raymappers
{

class View
{
public:
  /// An empty view (0 x 0 pixels).
  View() = default;
  /// `opaqueDepth`: width x height window depths in [0, 1] (rows from the bottom), or
  /// nullptr when no opaque geometry is drawn; it must outlive the view.
  View(const std::array<double, 16>& modelToClip,
    int width,
    int height,
    const Vec3d& origin,
    const float* opaqueDepth = nullptr);

  const std::array<double, 16>& modelToClip() const { return ModelToClip; }
  /// M with the origin folded in: the matrix of origin-relative model coordinates.
  const std::array<double, 16>& originRelativeClip() const
  {
    return DepthRays.originRelativeClip();
  }
  int width() const { return Width; }
  int height() const { return Height; }
  const Vec3d& origin() const { return Origin; }

  /// The window depth of opaque geometry at each pixel, or nullptr when there is none.
  const float* opaqueDepth() const { return OpaqueDepth; }
  /// The window depth of opaque geometry at pixel (i, j); 1 (the far plane) without any.
  float opaqueDepthAt(int i, int j) const
  {
    return OpaqueDepth ? OpaqueDepth[static_cast<std::size_t>(j) * Width + i] : 1.f;
  }

  /// Rays by distance.
  const RayCamera& camera() const { return Camera; }
  /// Rays by view depth; valid only when hasDepthRays().
  const ViewRays& depthRays() const { return DepthRays; }
  /// False when M gives no depth parameterization (its eye or its plane zeta = 1 cannot
  /// be solved for: a degenerate matrix).
  bool hasDepthRays() const { return DepthRaysValid; }

private:
  std::array<double, 16> ModelToClip{};
  int Width = 0;
  int Height = 0;
  Vec3d Origin;
  const float* OpaqueDepth = nullptr;
  RayCamera Camera;
  ViewRays DepthRays;
  bool DepthRaysValid = false;
};

} // namespace raymappers

#endif
