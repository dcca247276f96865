// What the sphere renderer asks of an accelerator: the closest hits of a square packet of
// primary rays (side x side pixels, row by row). Embree's BVH and the coherent grid answer
// the same question, so the renderer, its shading and its tests are shared.
#ifndef RayMappers_SphereAccelerator_h
#define RayMappers_SphereAccelerator_h

#include "Mappers/Common/RayCamera.h"
#include "Mappers/CGT/SphereSet.h"

#include <cmath>
#include <cstdint>

namespace raymappers
{

constexpr int MaxPacketSide = 16;
constexpr int MaxPacketRays = MaxPacketSide * MaxPacketSide;
constexpr std::uint32_t NoHit = 0xFFFFFFFFu;

struct RayPacket
{
  int side = 4;              // rays are side x side, lane = row * side + column
  bool valid[MaxPacketRays]; // false for lanes outside the image (their rays are not read)
  // True for the rays of a block of pixels of a projective camera: rays along each edge
  // of the block are coplanar, so the corner rays bound a frustum. False for other rays
  // (ambient occlusion), which get no frustum culling.
  bool pixelBlock = true;
  // True when the hits must come in the total order of (t, sphere index), so that queries
  // from each hit on meet every sphere along a ray once, coincident ones too (translucency):
  // a hit at t == tnear then counts only on spheres of index >= tieFrom[lane], and of hits
  // at one t the lowest index wins. False: the closest hit, ties broken as found.
  bool ordered = false;
  Ray rays[MaxPacketRays];
  std::uint32_t tieFrom[MaxPacketRays]; // read only when ordered
};

struct PacketHits
{
  float t[MaxPacketRays];
  std::uint32_t prim[MaxPacketRays]; // index in the SphereSet, NoHit when missed
};

/// Whether an accelerator traces the ray: origin and direction within FLT_LARGE = 1.844e18
/// (beyond it Embree rejects a ray, by an assertion that Debian's build keeps) and
/// 0 <= tnear <= tfar (no NaN). Other rays (a NaN direction from a degenerate shadow ray,
/// an interval behind the origin) miss on every accelerator.
inline bool isTraceable(const Ray& r)
{
  const float largest = 1.844e18f;
  for (int a = 0; a < 3; ++a)
  {
    if (!(std::fabs(r.org[a]) <= largest && std::fabs(r.dir[a]) <= largest))
    {
      return false;
    }
  }
  return r.tnear >= 0.f && r.tnear <= r.tfar;
}

/// Work done by a traversal, summed into the render statistics.
struct TraversalCounters
{
  std::int64_t cells = 0;       // grid cells visited
  std::int64_t culled = 0;      // spheres rejected by the packet's frustum
  std::int64_t sphereTests = 0; // ray-sphere intersection tests (rays x spheres)
  std::int64_t rangeCulled = 0; // spheres and macrocells skipped by parameter ranges
};

class SphereAccelerator
{
public:
  virtual ~SphereAccelerator() = default;
  virtual bool empty() const = 0;
  /// Parameter ranges for the following renders (count 0: none); never rebuilds.
  void setRangeFilter(const RangeFilter& filter) { Filter = filter; }
  const RangeFilter& rangeFilter() const { return Filter; }
  /// Closest hit per valid lane with t in [tnear, tfar] (the first in (t, index) order when
  /// the packet is ordered); NoHit for the other lanes and for rays that are not traceable
  /// (isTraceable).
  virtual void intersect(const RayPacket& packet,
    PacketHits& hits,
    TraversalCounters& counters) const = 0;
  /// Whether each valid lane meets any sphere with t in [tnear, tfar] (occlusion: not the
  /// closest one), the same answer as intersect's hit or miss; blocked[lane] for every lane
  /// (false for invalid ones). Returns how many are blocked. By default, from intersect.
  virtual int occluded(const RayPacket& packet, bool* blocked, TraversalCounters& counters) const
  {
    PacketHits hits;
    this->intersect(packet, hits, counters);
    int n = 0;
    for (int lane = 0; lane < packet.side * packet.side; ++lane)
    {
      blocked[lane] = packet.valid[lane] && hits.prim[lane] != NoHit;
      n += blocked[lane] ? 1 : 0;
    }
    return n;
  }

protected:
  RangeFilter Filter;
};

} // namespace raymappers

#endif
