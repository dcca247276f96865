// The axis-aligned box a volume render is restricted to. In distributed rendering the
// space is split into disjoint boxes (ParaView's kd-tree cuts, one per process); every
// process integrates its rays only inside its own box, and the partial images, composited
// front to back in the boxes' visibility order, add up to the integral along the whole
// ray: for emission and absorption, with T the transmittance and C the colour of a
// segment, the ray [a, c] split at b gives C_ac = C_ab + T_ab C_bc and T_ac = T_ab T_bc.
// Samples sit on each ray's own grid (shared by all processes), so the boxes take turns:
// a sample belongs to the box whose half-open interval [entry, exit) holds it.
#ifndef RayMappers_RegionBox_h
#define RayMappers_RegionBox_h

#include "Mappers/Common/Vec3.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace raymappers
{

struct RegionBox
{
  static constexpr double Unbounded = std::numeric_limits<double>::infinity();
  // Model coordinates; the default box is all of space.
  double lo[3] = { -Unbounded, -Unbounded, -Unbounded };
  double hi[3] = { Unbounded, Unbounded, Unbounded };

  /// Whether any face is finite (a whole-space box clips nothing).
  bool bounded() const
  {
    for (int a = 0; a < 3; ++a)
    {
      if (std::isfinite(lo[a]) || std::isfinite(hi[a]))
      {
        return true;
      }
    }
    return false;
  }

  /// Shrinks [t0, t1] of the ray o + t d to the part inside the box, `origin` subtracted
  /// from the box first (rays in origin-relative coordinates). Returns false when nothing
  /// is left (t0 > t1) or the box is empty.
  bool clip(const Vec3d& o, const Vec3d& d, const Vec3d& origin, double& t0, double& t1) const
  {
    for (int a = 0; a < 3; ++a)
    {
      const double l = lo[a] - origin[a], h = hi[a] - origin[a];
      if (!(l <= h))
      {
        return false;
      }
      if (d[a] == 0.0)
      {
        if (o[a] < l || o[a] > h)
        {
          return false;
        }
        continue;
      }
      const double inv = 1.0 / d[a];
      double ta = (l - o[a]) * inv, tb = (h - o[a]) * inv;
      if (ta > tb)
      {
        std::swap(ta, tb);
      }
      // An infinite face gives an infinite or NaN (inf - inf never occurs: o is finite)
      // parameter; max/min with it keep the finite bound.
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    return t0 <= t1;
  }
};

} // namespace raymappers

#endif
