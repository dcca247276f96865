// Reduced-resolution frames for time-critical rendering (Farias 2001, chapter 3: an image
// of p x p fewer rays under interaction, the exact one when it stops): the opaque depth
// sampled at the coarse pixels' centres, and the coarse image enlarged bilinearly.
#ifndef RayMappers_FrameResample_h
#define RayMappers_FrameResample_h

#include "Mappers/Common/Frame.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace raymappers
{

/// Depth of the full-resolution pixel under each coarse pixel's centre.
inline std::vector<float> sampleDepth(const std::vector<float>& depth,
  int width,
  int height,
  int coarseWidth,
  int coarseHeight)
{
  std::vector<float> out(static_cast<std::size_t>(coarseWidth) * coarseHeight);
  const double rx = double(width) / coarseWidth, ry = double(height) / coarseHeight;
  for (int j = 0; j < coarseHeight; ++j)
  {
    const int y = std::min(height - 1, static_cast<int>((j + 0.5) * ry));
    for (int i = 0; i < coarseWidth; ++i)
    {
      const int x = std::min(width - 1, static_cast<int>((i + 0.5) * rx));
      out[static_cast<std::size_t>(j) * coarseWidth + i] =
        depth[static_cast<std::size_t>(y) * width + x];
    }
  }
  return out;
}

/// `full` (already sized) filled from `coarse` by bilinear interpolation between the
/// coarse pixels' centres (premultiplied RGBA; depth left at the far plane).
inline void enlarge(const Frame& coarse, Frame& full)
{
  const double rx = double(full.width) / coarse.width, ry = double(full.height) / coarse.height;
  for (int y = 0; y < full.height; ++y)
  {
    const double v = std::clamp((y + 0.5) / ry - 0.5, 0.0, coarse.height - 1.0);
    const int j0 = static_cast<int>(v), j1 = std::min(j0 + 1, coarse.height - 1);
    const double fy = v - j0;
    for (int x = 0; x < full.width; ++x)
    {
      const double u = std::clamp((x + 0.5) / rx - 0.5, 0.0, coarse.width - 1.0);
      const int i0 = static_cast<int>(u), i1 = std::min(i0 + 1, coarse.width - 1);
      const double fx = u - i0;
      const float* a = &coarse.rgba[4 * coarse.index(i0, j0)];
      const float* b = &coarse.rgba[4 * coarse.index(i1, j0)];
      const float* c = &coarse.rgba[4 * coarse.index(i0, j1)];
      const float* d = &coarse.rgba[4 * coarse.index(i1, j1)];
      float* out = &full.rgba[4 * full.index(x, y)];
      for (int k = 0; k < 4; ++k)
      {
        out[k] = static_cast<float>((1 - fy) * ((1 - fx) * a[k] + fx * b[k]) +
          fy * ((1 - fx) * c[k] + fx * d[k]));
      }
    }
  }
}

/// `full`'s depth from the coarse pixel each full pixel lies in (nearest, not interpolated:
/// a blend of a surface's depth and the far plane would be neither).
inline void enlargeDepth(const Frame& coarse, Frame& full)
{
  const double rx = double(coarse.width) / full.width, ry = double(coarse.height) / full.height;
  for (int y = 0; y < full.height; ++y)
  {
    const int j = std::min(coarse.height - 1, static_cast<int>((y + 0.5) * ry));
    for (int x = 0; x < full.width; ++x)
    {
      const int i = std::min(coarse.width - 1, static_cast<int>((x + 0.5) * rx));
      full.depth[full.index(x, y)] = coarse.depth[coarse.index(i, j)];
    }
  }
}

} // namespace raymappers

#endif
