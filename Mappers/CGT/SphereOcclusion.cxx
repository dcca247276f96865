#include "Mappers/CGT/SphereOcclusion.h"

#include "Mappers/CGT/CoherentGridAccelerator.h"
#include "Mappers/CGT/RaySphereLanes.h"

#include <algorithm>
#include <cmath>

namespace raymappers
{

SphereOcclusion::SphereOcclusion(const SphereSet& spheres, const SphereAccelerator& accel)
  : Spheres(spheres)
  , Accel(accel)
  , Grid(dynamic_cast<const CoherentGridAccelerator*>(&accel))
{
}

namespace
{
// The packet's first `count` rays as lanes, and the longest of them.
float loadLanes(const RayPacket& packet, int count, RayLanes& R)
{
  float longest = 0.f;
  for (int a = 0; a < count; ++a)
  {
    const Ray& r = packet.rays[a];
    const bool traceable = isTraceable(r);
    R.ox[a] = r.org.x;
    R.oy[a] = r.org.y;
    R.oz[a] = r.org.z;
    R.dx[a] = traceable ? r.dir.x : 0.f;
    R.dy[a] = traceable ? r.dir.y : 0.f;
    R.dz[a] = traceable ? r.dir.z : 0.f;
    // An untraceable ray misses (as on every accelerator): an empty interval.
    R.tNear[a] = traceable ? r.tnear : std::numeric_limits<float>::infinity();
    R.tBest[a] = traceable ? r.tfar : 0.f;
    R.prim[a] = NoHit;
    longest = traceable ? std::max(longest, r.tfar) : longest;
  }
  R.pad(count);
  return longest;
}

int countHits(const RayLanes& R, int count)
{
  int hits = 0;
  for (int a = 0; a < count; ++a)
  {
    hits += R.prim[a] != NoHit ? 1 : 0;
  }
  return hits;
}

// The spheres of the grid cells in the box o +- (T + r_max) whose centre lies within
// (T + r)(1 + 1e-3) of o (the margin only adds candidates: the lane test decides), each
// tested against all lanes, until every lane is blocked.
template<typename Lanes>
void occludedOnGrid(const CoherentGrid& grid,
  const SphereSet& spheres,
  const RangeFilter& filter,
  const Vec3f& o,
  float T,
  int count,
  RayLanes& R,
  TraversalCounters& counters)
{
  const float reach = T + grid.maxRadius();
  const std::array<int, 3> lo = grid.cellOf(o - Vec3f(reach, reach, reach));
  const std::array<int, 3> hi = grid.cellOf(o + Vec3f(reach, reach, reach));
  const bool ranged = filter.count > 0 && filter.count <= spheres.numAttributes;
  const int padded = RayLanes::padded(count);
  int blocked = 0;
  for (int k = lo[2]; k <= hi[2]; ++k)
  {
    for (int j = lo[1]; j <= hi[1]; ++j)
    {
      for (int i = lo[0]; i <= hi[0]; ++i)
      {
        ++counters.cells;
        const std::int64_t c = grid.cellIndex(i, j, k);
        for (std::uint32_t id = grid.cellBegin(c); id < grid.cellEnd(c); ++id)
        {
          const Vec3f& center = spheres.centers[id];
          const float r = spheres.radii[id];
          const Vec3f f = center - o;
          const float within = (T + r) * 1.001f;
          if (dot(f, f) > within * within)
          {
            continue;
          }
          if (ranged && !filter.passes(spheres.attributesOf(id)))
          {
            ++counters.rangeCulled;
            continue;
          }
          counters.sphereTests += count;
          Lanes::template intersect<false>(R, padded, center.x, center.y, center.z, r * r, id);
          blocked = countHits(R, count);
          if (blocked == count)
          {
            return;
          }
        }
      }
    }
  }
}
}

int SphereOcclusion::occluded(const RayPacket& packet,
  int count,
  bool* blocked,
  TraversalCounters& counters) const
{
  count = std::clamp(count, 0, packet.side * packet.side);
  if (!Grid)
  {
    return Accel.occluded(packet, blocked, counters);
  }
  if (count == 0 || Grid->empty())
  {
    std::fill(blocked, blocked + count, false);
    return 0;
  }
  RayLanes R;
  const float T = loadLanes(packet, count, R);
  const Vec3f o = packet.rays[0].org;
  const RangeFilter& filter = Accel.rangeFilter();
  switch (Grid->simdPath())
  {
#ifdef RAYMAPPERS_X86_SIMD
    case SimdPath::Avx512:
      occludedOnGrid<Avx512Lanes>(Grid->grid(), Spheres, filter, o, T, count, R, counters);
      break;
    case SimdPath::Avx2:
      occludedOnGrid<Avx2Lanes>(Grid->grid(), Spheres, filter, o, T, count, R, counters);
      break;
#endif
    default:
      occludedOnGrid<PortableLanes>(Grid->grid(), Spheres, filter, o, T, count, R, counters);
  }
  for (int a = 0; a < count; ++a)
  {
    blocked[a] = R.prim[a] != NoHit;
  }
  return countHits(R, count);
}

} // namespace raymappers
