// The compressed voxelization of a fluid (Zirr 2015, sections 3.1 to 3.4, 4.5): per pixel
// (row 0 at the bottom) up to S spans [entry, exit] of depth zeta (ViewRays: distance along
// the view axis, perspective, or from the near plane, parallel) along the pixel's centre
// ray, front to back. When a column holds more than S spans, the last stored span is
// extended to the last exit and the empty space inside it is kept (hiddenEmpty), so the
// fluid thickness along the ray stays exact (section 3.1):
//   thickness = sum_k (exit_k - entry_k) - hiddenEmpty      (in zeta; times |B| in world).
//
// Depth values: pixel p's 2 count[p] slots lie together from first[p], entry k at 2k, exit
// k at 2k + 1, the pixels in row order (compressed: a column takes memory only for the spans
// it stores, so that a march across the columns reads a few cache lines). Each has four surface
// links (section 3.3, one byte each, packed into one word in the order +x, -x, +y, -y):
// a slot index in that neighbour's column, or OwnColumn | slot for a link within its own
// column (an entry to its own exit at a boundary, an inner entry to the preceding exit or
// an inner exit to the next entry: the walls of bubbles). Normals (section 4.5) are
// octahedron-encoded [MSS*10] in two 16-bit snorm halves of one word.
#ifndef RayMappers_FluidSpans_h
#define RayMappers_FluidSpans_h

#include "Mappers/Common/Vec3.h"
#include "Mappers/SPH/VoxelDepthLayers.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace raymappers
{

struct FluidSpans
{
  static constexpr std::uint8_t OwnColumn = 0x80;
  static constexpr int MaxSpans = 63; // 2S slots must fit in the 7 bits of a link

  int width = 0;
  int height = 0;
  int maxSpans = 7; // S
  VoxelDepthLayers layers;
  std::vector<std::uint8_t> count;    // spans stored per pixel (<= S)
  std::vector<std::uint32_t> found;   // spans in the column (>= count)
  std::vector<float> hiddenEmpty;     // zeta length of empty space inside the last stored span
  std::vector<std::size_t> first;     // per pixel: its first slot
  std::vector<float> depth;           // 2 count[p] slots per pixel
  std::vector<std::uint32_t> links;   // per slot, 4 link bytes
  std::vector<std::uint32_t> normals; // per slot, octahedron-encoded

  void reset(int w, int h, int spans)
  {
    width = w;
    height = h;
    maxSpans = spans;
    const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    count.assign(n, 0);
    found.assign(n, 0);
    hiddenEmpty.assign(n, 0.f);
    first.assign(n, 0);
    depth.clear();
    links.clear();
    normals.clear();
  }
  std::size_t pixel(int i, int j) const
  {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(width) +
           static_cast<std::size_t>(i);
  }
  std::size_t slot(std::size_t pixelIndex, int s) const
  {
    return first[pixelIndex] + static_cast<std::size_t>(s);
  }
  float entry(std::size_t p, int k) const { return depth[slot(p, 2 * k)]; }
  float exit(std::size_t p, int k) const { return depth[slot(p, 2 * k + 1)]; }
  /// The fluid's thickness along pixel p's ray, in zeta.
  double thickness(std::size_t p) const
  {
    double t = -static_cast<double>(hiddenEmpty[p]);
    for (int k = 0; k < count[p]; ++k)
    {
      t += static_cast<double>(exit(p, k)) - entry(p, k);
    }
    return t;
  }
  std::size_t bytes() const
  {
    return count.size() + found.size() * 4 + hiddenEmpty.size() * 4 +
           first.size() * sizeof(std::size_t) + depth.size() * 4 +
           links.size() * 4 + normals.size() * 4;
  }
};

/// Octahedron normal encoding [MSS*10]: the unit vector projected onto the octahedron
/// |x| + |y| + |z| = 1, the lower half folded over the diagonals, as two 16-bit snorms.
inline std::uint32_t encodeNormal(const Vec3f& n)
{
  const float s = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
  float u = s > 0 ? n.x / s : 0.f, v = s > 0 ? n.y / s : 0.f;
  if (n.z < 0)
  {
    const float fu = (1.f - std::abs(v)) * (u >= 0 ? 1.f : -1.f);
    const float fv = (1.f - std::abs(u)) * (v >= 0 ? 1.f : -1.f);
    u = fu;
    v = fv;
  }
  const auto q = [](float x)
  {
    return static_cast<std::uint32_t>(static_cast<std::uint16_t>(
      static_cast<std::int16_t>(std::lround(std::clamp(x, -1.f, 1.f) * 32767.f))));
  };
  return q(u) | (q(v) << 16);
}

inline Vec3f decodeNormal(std::uint32_t e)
{
  const float u = static_cast<std::int16_t>(e & 0xFFFFu) / 32767.f;
  const float v = static_cast<std::int16_t>(e >> 16) / 32767.f;
  Vec3f n(u, v, 1.f - std::abs(u) - std::abs(v));
  if (n.z < 0)
  {
    n.x = (1.f - std::abs(v)) * (u >= 0 ? 1.f : -1.f);
    n.y = (1.f - std::abs(u)) * (v >= 0 ? 1.f : -1.f);
  }
  return normalize(n);
}

} // namespace raymappers

#endif
