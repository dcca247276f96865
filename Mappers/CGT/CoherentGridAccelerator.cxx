#include "CoherentGridAccelerator.h"
#include "RaySphereLanes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace raymappers
{

namespace
{
// A side plane of the packet's frustum: n . x + d >= 0 inside (origin-relative coords).
struct Plane
{
  Vec3f n;
  float d;
};

// The plane through the (coplanar) rays a and b, oriented so that a point on ray c is
// inside. Pixel rays of a projective camera along one edge of a pixel block are coplanar.
bool sidePlane(const Ray& a, const Ray& b, const Ray& c, Plane& plane)
{
  const Vec3d oa(a.org), da(a.dir), ob(b.org), db(b.dir);
  // The plane holds ray a and the point of ray b at a distance along it: robust whether the
  // rays share their origin (never exactly, they start on the near plane) or direction.
  const Vec3d q = ob + db * std::max(1.0, static_cast<double>(b.tfar) * 0.5);
  Vec3d n = cross(da, q - oa);
  const double len = length(n);
  if (!(len > 0) || !std::isfinite(len))
  {
    return false;
  }
  n = n * (1.0 / len);
  const Vec3d inside =
    Vec3d(c.org) + Vec3d(c.dir) * std::max(1.0, static_cast<double>(c.tfar) * 0.5);
  if (dot(n, inside - oa) < 0)
  {
    n = -n;
  }
  plane.n = Vec3f(n);
  plane.d = static_cast<float>(-dot(n, oa));
  return true;
}
}

void CoherentGridAccelerator::build(SphereSet& spheres, const CoherentGridParameters& params)
{
  Grid.build(spheres, params);
  Spheres = &spheres;
}

void CoherentGridAccelerator::intersect(const RayPacket& packet,
  PacketHits& hits,
  TraversalCounters& counters) const
{
  const int n = packet.side * packet.side;
  int lanes[MaxPacketRays];
  int count = 0;
  for (int k = 0; k < n; ++k)
  {
    hits.prim[k] = NoHit;
    hits.t[k] = 0.f;
    if (packet.valid[k] && isTraceable(packet.rays[k]))
    {
      lanes[count++] = k;
    }
  }
  if (count == 0 || empty())
  {
    return;
  }
  // The major axis K: the axis along which every ray moves the same way, and fastest.
  int axis = -1;
  float best = 0.f;
  for (int a = 0; a < 3; ++a)
  {
    const float first = packet.rays[lanes[0]].dir[a];
    float slowest = std::fabs(first);
    for (int i = 1; i < count && slowest > 0; ++i)
    {
      const float da = packet.rays[lanes[i]].dir[a];
      slowest = (da > 0) == (first > 0) && da != 0 ? std::min(slowest, std::fabs(da)) : 0.f;
    }
    if (slowest > best)
    {
      best = slowest;
      axis = a;
    }
  }
  auto run = [&](const int* which, int howMany, int k)
  {
    switch (Simd)
    {
#ifdef RAYMAPPERS_X86_SIMD
      case SimdPath::Avx512:
        traverse<Avx512Lanes>(packet, which, howMany, k, hits, counters);
        break;
      case SimdPath::Avx2:
        traverse<Avx2Lanes>(packet, which, howMany, k, hits, counters);
        break;
#endif
      default:
        traverse<PortableLanes>(packet, which, howMany, k, hits, counters);
    }
  };
  if (axis >= 0)
  {
    run(lanes, count, axis);
    return;
  }
  // No common axis (a very wide packet): each ray on its own.
  for (int i = 0; i < count; ++i)
  {
    const Vec3f& d = packet.rays[lanes[i]].dir;
    const int own = std::fabs(d.x) >= std::fabs(d.y) ? (std::fabs(d.x) >= std::fabs(d.z) ? 0 : 2)
                                                     : (std::fabs(d.y) >= std::fabs(d.z) ? 1 : 2);
    run(&lanes[i], 1, own);
  }
}

template<typename Lanes>
void CoherentGridAccelerator::traverse(const RayPacket& packet,
  const int* lanes,
  int count,
  int axis,
  PacketHits& hits,
  TraversalCounters& counters) const
{
  const SphereSet& spheres = *Spheres;
  const auto& dims = Grid.dims();
  const int K = axis, U = (axis + 1) % 3, V = (axis + 2) % 3;
  const float inv = Grid.inverseCellSize();
  const float rG = Grid.maxRadius() * inv; // r_max in cell units
  const Vec3f lower = Grid.lower();
  const bool ascending = packet.rays[lanes[0]].dir[K] > 0;

  // Per ray, in grid units: origin, K-speed, U and V slopes along K, and the K-interval it
  // spends inside the grid's box grown by r_max.
  struct Lane
  {
    int id;
    Vec3f o;
    float dk;     // dK/dt in cell units
    float su, sv; // dU/dK, dV/dK
    float kLo, kHi;
  };
  Lane L[MaxPacketRays];
  int active = 0;
  float kMin = std::numeric_limits<float>::max(), kMax = -kMin;
  float slopeU = 0.f, slopeV = 0.f;
  for (int i = 0; i < count; ++i)
  {
    const Ray& r = packet.rays[lanes[i]];
    Lane l;
    l.id = lanes[i];
    l.o = Vec3f((r.org.x - lower.x) * inv, (r.org.y - lower.y) * inv, (r.org.z - lower.z) * inv);
    float t0 = r.tnear, t1 = r.tfar;
    for (int a = 0; a < 3; ++a)
    {
      const float lo = -rG, hi = static_cast<float>(dims[a]) + rG;
      const float da = r.dir[a] * inv;
      if (da == 0.f)
      {
        if (l.o[a] < lo || l.o[a] > hi)
        {
          t1 = -1.f;
        }
        continue;
      }
      float ta = (lo - l.o[a]) / da, tb = (hi - l.o[a]) / da;
      if (ta > tb)
      {
        std::swap(ta, tb);
      }
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    if (!(t0 <= t1))
    {
      continue; // misses the grid
    }
    l.dk = r.dir[K] * inv;
    l.su = r.dir[U] / r.dir[K];
    l.sv = r.dir[V] / r.dir[K];
    const float ka = l.o[K] + t0 * l.dk, kb = l.o[K] + t1 * l.dk;
    l.kLo = std::min(ka, kb);
    l.kHi = std::max(ka, kb);
    kMin = std::min(kMin, l.kLo);
    kMax = std::max(kMax, l.kHi);
    slopeU = std::max(slopeU, std::fabs(l.su));
    slopeV = std::max(slopeV, std::fabs(l.sv));
    L[active++] = l;
  }
  if (active == 0)
  {
    return;
  }
  // The active rays in structure-of-arrays form, padded for the SIMD lanes.
  RayLanes R;
  for (int i = 0; i < active; ++i)
  {
    const Ray& r = packet.rays[L[i].id];
    R.ox[i] = r.org.x;
    R.oy[i] = r.org.y;
    R.oz[i] = r.org.z;
    R.dx[i] = r.dir.x;
    R.dy[i] = r.dir.y;
    R.dz[i] = r.dir.z;
    R.tNear[i] = r.tnear;
    R.tBest[i] = r.tfar;
    R.prim[i] = NoHit;
  }
  R.pad(active);
  // A ray's result goes to the packet when it leaves the active set.
  auto store = [&](int i)
  {
    hits.prim[L[i].id] = R.prim[i];
    hits.t[L[i].id] = R.prim[i] == NoHit ? 0.f : R.tBest[i];
  };
  // Sphere-center method: a ray reaches a sphere of radius r whose centre is at most
  // r sqrt(1 + dU^2) away from it in U within the centre's K-plane (same for V).
  const float sU = rG * std::sqrt(1.f + slopeU * slopeU);
  const float sV = rG * std::sqrt(1.f + slopeV * slopeV);

  // The packet's frustum from its corner rays (a full rectangle of lanes).
  Plane planes[4];
  int numPlanes = 0;
  if (count > 1 && packet.pixelBlock)
  {
    int c0 = MaxPacketSide, c1 = -1, r0 = MaxPacketSide, r1 = -1;
    for (int i = 0; i < count; ++i)
    {
      c0 = std::min(c0, lanes[i] % packet.side);
      c1 = std::max(c1, lanes[i] % packet.side);
      r0 = std::min(r0, lanes[i] / packet.side);
      r1 = std::max(r1, lanes[i] / packet.side);
    }
    if (c1 > c0 && r1 > r0 && (c1 - c0 + 1) * (r1 - r0 + 1) == count)
    {
      const Ray& a = packet.rays[r0 * packet.side + c0];
      const Ray& b = packet.rays[r0 * packet.side + c1];
      const Ray& c = packet.rays[r1 * packet.side + c1];
      const Ray& d = packet.rays[r1 * packet.side + c0];
      numPlanes = (sidePlane(a, b, c, planes[0]) && sidePlane(b, c, d, planes[1]) &&
                    sidePlane(c, d, a, planes[2]) && sidePlane(d, a, b, planes[3]))
                    ? 4
                    : 0;
    }
  }

  const int M = Grid.macrocellSize();
  const bool ranged = Filter.count > 0 && Filter.count <= spheres.numAttributes;
  // Near and far shifted by r_max: a sphere whose centre lies up to r_max before a ray's
  // start (or after its end) along K can still be hit (section 4.1).
  kMin -= rG;
  kMax += rG;
  const int first =
    std::clamp(static_cast<int>(std::floor(ascending ? kMin : kMax)), 0, dims[K] - 1);
  const int last =
    std::clamp(static_cast<int>(std::floor(ascending ? kMax : kMin)), 0, dims[K] - 1);
  const int step = ascending ? 1 : -1;
  for (int s = first; active > 0; s += step)
  {
    // The cells of slice s that the packet can reach: the rays' U and V at the slice's two
    // faces, grown by the sphere-center shift.
    float uMin = std::numeric_limits<float>::max(), uMax = -uMin, vMin = uMin, vMax = -uMin;
    for (int i = 0; i < active; ++i)
    {
      const Lane& l = L[i];
      for (const float k : { static_cast<float>(s), static_cast<float>(s + 1) })
      {
        const float u = l.o[U] + (k - l.o[K]) * l.su;
        const float v = l.o[V] + (k - l.o[K]) * l.sv;
        uMin = std::min(uMin, u);
        uMax = std::max(uMax, u);
        vMin = std::min(vMin, v);
        vMax = std::max(vMax, v);
      }
    }
    const int u0 = std::max(0, static_cast<int>(std::floor(uMin - sU)));
    const int u1 = std::min(dims[U] - 1, static_cast<int>(std::floor(uMax + sU)));
    const int v0 = std::max(0, static_cast<int>(std::floor(vMin - sV)));
    const int v1 = std::min(dims[V] - 1, static_cast<int>(std::floor(vMax + sV)));
    for (int mv = v0 / M; mv <= v1 / M && u0 <= u1; ++mv)
    {
      for (int mu = u0 / M; mu <= u1 / M; ++mu)
      {
        int mc[3];
        mc[K] = s / M;
        mc[U] = mu;
        mc[V] = mv;
        const std::size_t macro = Grid.macrocellIndex(mc[0], mc[1], mc[2]);
        if (Grid.macrocellEmpty(macro))
        {
          continue;
        }
        if (ranged && !Grid.macrocellInRange(macro, Filter))
        {
          ++counters.rangeCulled;
          continue;
        }
        for (int v = std::max(v0, mv * M); v <= std::min(v1, mv * M + M - 1); ++v)
        {
          for (int u = std::max(u0, mu * M); u <= std::min(u1, mu * M + M - 1); ++u)
          {
            int c[3];
            c[K] = s;
            c[U] = u;
            c[V] = v;
            const std::int64_t cell = Grid.cellIndex(c[0], c[1], c[2]);
            const std::uint32_t begin = Grid.cellBegin(cell), end = Grid.cellEnd(cell);
            if (begin == end)
            {
              continue;
            }
            ++counters.cells;
            for (std::uint32_t id = begin; id < end; ++id)
            {
              if (ranged && !Filter.passes(spheres.attributesOf(id)))
              {
                ++counters.rangeCulled;
                continue;
              }
              const Vec3f& center = spheres.centers[id];
              const float radius = spheres.radii[id];
              bool outside = false;
              for (int p = 0; p < numPlanes && !outside; ++p)
              {
                outside = dot(planes[p].n, center) + planes[p].d < -radius;
              }
              if (outside)
              {
                ++counters.culled;
                continue;
              }
              counters.sphereTests += active;
              Lanes::intersect(
                R, RayLanes::padded(active), center.x, center.y, center.z, radius * radius, id);
            }
          }
        }
      }
    }
    if (s == last)
    {
      break;
    }
    // A ray is done when its hit lies before every point of every sphere still ahead (their
    // centres are past the next slice face, so their points are past it minus r_max), or
    // when the slices ahead are beyond the part of the grid it crosses.
    const float face = ascending ? static_cast<float>(s + 1) - rG : static_cast<float>(s) + rG;
    int kept = 0;
    for (int i = 0; i < active; ++i)
    {
      const Lane& l = L[i];
      const bool hit = R.prim[i] != NoHit;
      const float kHit = l.o[K] + R.tBest[i] * l.dk;
      const bool settled = hit && (ascending ? kHit <= face : kHit >= face);
      const bool passed =
        ascending ? l.kHi + rG < static_cast<float>(s + 1) : l.kLo - rG > static_cast<float>(s);
      if (settled || passed)
      {
        store(i);
        continue;
      }
      L[kept] = l;
      R.ox[kept] = R.ox[i];
      R.oy[kept] = R.oy[i];
      R.oz[kept] = R.oz[i];
      R.dx[kept] = R.dx[i];
      R.dy[kept] = R.dy[i];
      R.dz[kept] = R.dz[i];
      R.tNear[kept] = R.tNear[i];
      R.tBest[kept] = R.tBest[i];
      R.prim[kept] = R.prim[i];
      ++kept;
    }
    active = kept;
    R.pad(active);
  }
  for (int i = 0; i < active; ++i)
  {
    store(i);
  }
}

} // namespace raymappers
