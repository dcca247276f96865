#include "Mappers/CGT/CoherentGridAccelerator.h"
#include "Mappers/CGT/RaySphereLanes.h"

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

// (The phases of traverse below that its three SIMD instantiations share are declared
// inline: out of line, as GCC 12 leaves them otherwise, the copy of the rays into SIMD lanes
// can no longer tell the lanes from the packet and stays scalar.)

// The packet's frustum: the four side planes through its corner rays when its lanes are a
// full rectangle of a pixel block (section 4.3's sphere/frustum culling); none otherwise.
struct Frustum
{
  Plane planes[4];
  int count = 0;
};

inline Frustum packetFrustum(const RayPacket& packet, const int* lanes, int count)
{
  Frustum f;
  if (count <= 1 || !packet.pixelBlock)
  {
    return f;
  }
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
    f.count = (sidePlane(a, b, c, f.planes[0]) && sidePlane(b, c, d, f.planes[1]) &&
                sidePlane(c, d, a, f.planes[2]) && sidePlane(d, a, b, f.planes[3]))
                ? 4
                : 0;
  }
  return f;
}

// The major axis K of a packet: the axis along which every ray moves the same way, and
// fastest (-1: none, a very wide packet). Without branches per ray: stopping at the first
// ray that turns made this loop 8 % of a shadowed frame's time (mispredicted exits).
int majorAxis(const RayPacket& packet, const int* lanes, int count)
{
  int axis = -1;
  float best = 0.f;
  for (int a = 0; a < 3; ++a)
  {
    const float first = packet.rays[lanes[0]].dir[a];
    float slowest = std::fabs(first);
    bool same = true;
    for (int i = 1; i < count; ++i)
    {
      const float da = packet.rays[lanes[i]].dir[a];
      same &= ((da > 0) == (first > 0)) & (da != 0);
      slowest = std::min(slowest, std::fabs(da));
    }
    slowest = same ? slowest : 0.f;
    if (slowest > best)
    {
      best = slowest;
      axis = a;
    }
  }
  return axis;
}

// The traversal's axes: K the major one, U and V the others.
struct Axes
{
  int K, U, V;
};

// Per ray, in grid units: origin, K-speed, U and V slopes along K, and the K-interval it
// spends inside the grid's box grown by r_max.
// Trivially constructible (no Vec3f, whose members start at zero): traverse declares
// MaxPacketRays of them per packet, and zeroing 256 origins was 14 % of its time with
// 16-ray shadow packets.
struct Lane
{
  int id;
  float o[3]; // the origin in cell units
  float dk;     // dK/dt in cell units
  float su, sv; // dU/dK, dV/dK
  float kLo, kHi;
};

// What the packet's rays span together: their K-interval and their largest U and V slopes.
struct PacketSpan
{
  float kMin = std::numeric_limits<float>::max(), kMax = -std::numeric_limits<float>::max();
  float slopeU = 0.f, slopeV = 0.f;
};

// The rays' set-up in grid units (a ray that misses the grid's box grown by r_max is left
// out); returns how many rays remain, in L[0, active).
inline int setUpLanes(const CoherentGrid& grid,
  const RayPacket& packet,
  const int* lanes,
  int count,
  const Axes& ax,
  Lane* L,
  PacketSpan& span)
{
  const auto& dims = grid.dims();
  const float inv = grid.inverseCellSize();
  const float rG = grid.maxRadius() * inv; // r_max in cell units
  const Vec3f lower = grid.lower();
  int active = 0;
  for (int i = 0; i < count; ++i)
  {
    const Ray& r = packet.rays[lanes[i]];
    Lane l;
    l.id = lanes[i];
    for (int a = 0; a < 3; ++a)
    {
      l.o[a] = (r.org[a] - lower[a]) * inv;
    }
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
    l.dk = r.dir[ax.K] * inv;
    l.su = r.dir[ax.U] / r.dir[ax.K];
    l.sv = r.dir[ax.V] / r.dir[ax.K];
    const float ka = l.o[ax.K] + t0 * l.dk, kb = l.o[ax.K] + t1 * l.dk;
    l.kLo = std::min(ka, kb);
    l.kHi = std::max(ka, kb);
    span.kMin = std::min(span.kMin, l.kLo);
    span.kMax = std::max(span.kMax, l.kHi);
    span.slopeU = std::max(span.slopeU, std::fabs(l.su));
    span.slopeV = std::max(span.slopeV, std::fabs(l.sv));
    L[active++] = l;
  }
  return active;
}

// The active rays in structure-of-arrays form, padded for the SIMD lanes.
inline void loadRayLanes(const RayPacket& packet, const Lane* L, int active, RayLanes& R)
{
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
    R.tieFrom[i] = packet.ordered ? packet.tieFrom[L[i].id] : 0;
  }
  R.pad(active);
}

// Cells [u0, u1] x [v0, v1] of a slice.
struct CellRect
{
  int u0, u1, v0, v1;
};

// The packet's U and V extents as linear functions of K (section 2's incremental frustum
// traversal): each ray's U is linear in K, u_i(k) = u_i(kA) + (k - kA) su_i, so for k in
// [kA, kB] the lerp of min_i u_i(kA) and min_i u_i(kB) bounds min_i u_i(k) from below (and
// likewise the maxima from above), exact at both ends. A slice's cell range then costs O(1)
// instead of a pass over the packet's rays; the bounds are remade when rays retire.
struct PacketExtents
{
  float kA = 0.f, kB = 1.f;
  float uMin[2], uMax[2], vMin[2], vMax[2]; // at kA and kB
};

inline PacketExtents packetExtents(const Lane* L, int active, const Axes& ax, float kA, float kB)
{
  PacketExtents e;
  e.kA = kA;
  e.kB = kB;
  const float big = std::numeric_limits<float>::max();
  for (int end = 0; end < 2; ++end)
  {
    const float k = end == 0 ? kA : kB;
    float uMin = big, uMax = -big, vMin = big, vMax = -big;
    for (int i = 0; i < active; ++i)
    {
      const Lane& l = L[i];
      const float u = l.o[ax.U] + (k - l.o[ax.K]) * l.su;
      const float v = l.o[ax.V] + (k - l.o[ax.K]) * l.sv;
      uMin = std::min(uMin, u);
      uMax = std::max(uMax, u);
      vMin = std::min(vMin, v);
      vMax = std::max(vMax, v);
    }
    e.uMin[end] = uMin;
    e.uMax[end] = uMax;
    e.vMin[end] = vMin;
    e.vMax[end] = vMax;
  }
  return e;
}

// The U and V (cell units) that the packet's rays take for K in [k0, k1] (slices s0..s1,
// s0 <= s1: [s0, s1 + 1]): the extents at the range's two faces (a linear bound takes its extrema
// there), widened by a margin for the rounding of the lerp.
struct SliceBounds
{
  float uMin, uMax, vMin, vMax;
};

inline SliceBounds boundsBetween(const PacketExtents& e, float k0, float k1)
{
  const float t0 = (k0 - e.kA) / (e.kB - e.kA);
  const float t1 = (k1 - e.kA) / (e.kB - e.kA);
  auto at = [](const float* f, float t) { return f[0] + t * (f[1] - f[0]); };
  const float margin = 1e-3f;
  return { std::min(at(e.uMin, t0), at(e.uMin, t1)) - margin,
    std::max(at(e.uMax, t0), at(e.uMax, t1)) + margin,
    std::min(at(e.vMin, t0), at(e.vMin, t1)) - margin,
    std::max(at(e.vMax, t0), at(e.vMax, t1)) + margin };
}

inline SliceBounds sliceBounds(const PacketExtents& e, int s0, int s1)
{
  return boundsBetween(e, static_cast<float>(s0), static_cast<float>(s1 + 1));
}

// The cells whose spheres of radius up to r (cell units) rays within `b` can reach: b grown
// by the sphere-center shift r sqrt(1 + dU^2), r sqrt(1 + dV^2) (section 4.1; `slope` holds
// the two square roots), clamped to the grid.
struct SlopeFactors
{
  float u, v;
};

inline CellRect reachableCells(const SliceBounds& b,
  float r,
  const SlopeFactors& slope,
  const Axes& ax,
  const std::array<int, 3>& dims)
{
  const float uMin = b.uMin - r * slope.u, uMax = b.uMax + r * slope.u;
  const float vMin = b.vMin - r * slope.v, vMax = b.vMax + r * slope.v;
  return { std::max(0, static_cast<int>(std::floor(std::max(uMin, -1.f)))),
    std::min(
      dims[ax.U] - 1, static_cast<int>(std::floor(std::min(uMax, static_cast<float>(dims[ax.U]))))),
    std::max(0, static_cast<int>(std::floor(std::max(vMin, -1.f)))),
    std::min(dims[ax.V] - 1,
      static_cast<int>(std::floor(std::min(vMax, static_cast<float>(dims[ax.V]))))) };
}

// Whether every macrocell of macrocell layer `layer` (along K) that `rect` touches is empty
// (section 4.2's second level): then the packet skips the layer's slices at once.
inline bool macrocellsEmpty(const CoherentGrid& grid,
  const Axes& ax,
  int layer,
  const CellRect& rect)
{
  const int M = grid.macrocellSize();
  for (int mv = rect.v0 / M; mv <= rect.v1 / M && rect.u0 <= rect.u1; ++mv)
  {
    for (int mu = rect.u0 / M; mu <= rect.u1 / M; ++mu)
    {
      int mc[3];
      mc[ax.K] = layer;
      mc[ax.U] = mu;
      mc[ax.V] = mv;
      if (!grid.macrocellEmpty(grid.macrocellIndex(mc[0], mc[1], mc[2])))
      {
        return false;
      }
    }
  }
  return true;
}

// What a slice's visit needs of the packet's traversal: the spheres and their culling
// (parameter ranges, the packet's frustum), the axes, the rays' U and V extents with the
// sphere-center shift's slope factors and the direction along K, and the active rays.
struct PacketWalk
{
  bool ordered; // RayPacket::ordered
  const SphereSet& spheres;
  const RangeFilter& filter;
  bool ranged;
  const Frustum& frustum;
  const Axes& ax;
  const PacketExtents& extents;
  const SlopeFactors& slope;
  bool ascending;
  const Lane* L;
  RayLanes& R;
  int active;
  TraversalCounters& counters;
};

// The spheres of one cell against the packet (section 4.3): parameter-range culling, then
// sphere/frustum culling (the centre farther than the radius outside a side plane), then
// the ray-sphere test of every active ray in SIMD lanes.
template<typename Lanes>
void testSpheres(const PacketWalk& w, std::uint32_t begin, std::uint32_t end)
{
  const SphereSet& spheres = w.spheres;
  const Frustum& frustum = w.frustum;
  TraversalCounters& counters = w.counters;
  for (std::uint32_t id = begin; id < end; ++id)
  {
    if (w.ranged && !w.filter.passes(spheres.attributesOf(id)))
    {
      ++counters.rangeCulled;
      continue;
    }
    const Vec3f& center = spheres.centers[id];
    const float radius = spheres.radii[id];
    bool outside = false;
    for (int p = 0; p < frustum.count && !outside; ++p)
    {
      outside = dot(frustum.planes[p].n, center) + frustum.planes[p].d < -radius;
    }
    if (outside)
    {
      ++counters.culled;
      continue;
    }
    counters.sphereTests += w.active;
    const int padded = RayLanes::padded(w.active);
    if (w.ordered)
    {
      Lanes::template intersect<true>(w.R, padded, center.x, center.y, center.z, radius * radius, id);
    }
    else
    {
      Lanes::template intersect<false>(w.R, padded, center.x, center.y, center.z, radius * radius, id);
    }
  }
}

// Whether every active ray's hit lies before K = face (ascending; after it descending) by
// more than r (cell units): no sphere whose centre lies beyond the face can come nearer.
inline bool settledBefore(const Lane* L,
  const RayLanes& R,
  int active,
  bool ascending,
  float face,
  float r,
  int K)
{
  for (int i = 0; i < active; ++i)
  {
    const float kHit = L[i].o[K] + R.tBest[i] * L[i].dk;
    if (R.prim[i] == NoHit || (ascending ? kHit > face - r : kHit < face + r))
    {
      return false;
    }
  }
  return true;
}

// The spheres of a nested cell (cell c, in slice c[K]) against the packet: the traversal one
// level down, its m sub-slices in the direction of travel, in each the subcells the rays
// reach with the cell's own largest radius (the U and V bounds of the sub-slice's K-range,
// in subcells from the cell's corner, grown by the sphere-center shift); it stops when every
// ray's hit lies before the next sub-slice minus that radius.
template<typename Lanes>
void visitNested(const CoherentGrid& grid, const PacketWalk& w, const NestedCell& n, const int* c)
{
  const int m = n.m;
  const float fm = static_cast<float>(m);
  const float rCell = n.maxRadius * grid.inverseCellSize(); // cell units
  const float rSub = rCell * fm;                            // subcell units
  const std::array<int, 3> subDims{ m, m, m };
  const Axes& ax = w.ax;
  for (int step = 0; step < m; ++step)
  {
    const int ks = w.ascending ? step : m - 1 - step;
    const float k0 = static_cast<float>(c[ax.K]) + static_cast<float>(ks) / fm;
    const float k1 = static_cast<float>(c[ax.K]) + static_cast<float>(ks + 1) / fm;
    const SliceBounds cellUnits = boundsBetween(w.extents, k0, k1);
    const SliceBounds b{ (cellUnits.uMin - static_cast<float>(c[ax.U])) * fm,
      (cellUnits.uMax - static_cast<float>(c[ax.U])) * fm,
      (cellUnits.vMin - static_cast<float>(c[ax.V])) * fm,
      (cellUnits.vMax - static_cast<float>(c[ax.V])) * fm };
    const CellRect rect = reachableCells(b, rSub, w.slope, ax, subDims);
    const std::int64_t testsBefore = w.counters.sphereTests;
    for (int v = rect.v0; v <= rect.v1; ++v)
    {
      for (int u = rect.u0; u <= rect.u1; ++u)
      {
        int a[3];
        a[ax.K] = ks;
        a[ax.U] = u;
        a[ax.V] = v;
        const auto [begin, end] = grid.nestedRange(n, a[0], a[1], a[2]);
        if (begin == end)
        {
          continue;
        }
        ++w.counters.cells;
        testSpheres<Lanes>(w, begin, end);
      }
    }
    if (w.counters.sphereTests != testsBefore &&
        settledBefore(w.L, w.R, w.active, w.ascending, w.ascending ? k1 : k0, rCell, ax.K))
    {
      return;
    }
  }
}

// The cells of slice s within `rect` (the reach of the grid's r_max), by macrocells (section
// 4.2): an empty macrocell is skipped, and so is one whose attribute extrema miss the
// parameter ranges (section 4.3); in the others, the cells within the reach of the
// macrocell's own largest radius are visited (with mixed radii, a crowd of small spheres is
// not searched as widely as the largest sphere needs), and the spheres of every occupied one
// (by the macrocell's cell bits, before any offset is read) are tested.
template<typename Lanes>
void visitSlice(const CoherentGrid& grid, const PacketWalk& w, int s, const CellRect& rect)
{
  const SliceBounds bounds = sliceBounds(w.extents, s, s);
  const Axes& ax = w.ax;
  const int M = grid.macrocellSize();
  for (int mv = rect.v0 / M; mv <= rect.v1 / M && rect.u0 <= rect.u1; ++mv)
  {
    for (int mu = rect.u0 / M; mu <= rect.u1 / M; ++mu)
    {
      int mc[3];
      mc[ax.K] = s / M;
      mc[ax.U] = mu;
      mc[ax.V] = mv;
      const std::size_t macro = grid.macrocellIndex(mc[0], mc[1], mc[2]);
      if (grid.macrocellEmpty(macro))
      {
        continue;
      }
      if (w.ranged && !grid.macrocellInRange(macro, w.filter))
      {
        ++w.counters.rangeCulled;
        continue;
      }
      const CellRect own = reachableCells(
        bounds, grid.macrocellMaxRadius(macro) * grid.inverseCellSize(), w.slope, ax, grid.dims());
      for (int v = std::max(own.v0, mv * M); v <= std::min(own.v1, mv * M + M - 1); ++v)
      {
        for (int u = std::max(own.u0, mu * M); u <= std::min(own.u1, mu * M + M - 1); ++u)
        {
          int c[3];
          c[ax.K] = s;
          c[ax.U] = u;
          c[ax.V] = v;
          if (!grid.cellOccupied(macro, c[0] - mc[0] * M, c[1] - mc[1] * M, c[2] - mc[2] * M))
          {
            continue;
          }
          const std::int64_t cell = grid.cellIndex(c[0], c[1], c[2]);
          const std::uint32_t begin = grid.cellBegin(cell), end = grid.cellEnd(cell);
          if (const NestedCell* nested = grid.nestedCell(macro, cell))
          {
            visitNested<Lanes>(grid, w, *nested, c);
            continue;
          }
          ++w.counters.cells;
          testSpheres<Lanes>(w, begin, end);
        }
      }
    }
  }
}

// A ray's result goes to the packet when it leaves the active set.
inline void storeHit(const Lane& l, const RayLanes& R, int i, PacketHits& hits)
{
  hits.prim[l.id] = R.prim[i];
  hits.t[l.id] = R.prim[i] == NoHit ? 0.f : R.tBest[i];
}

// Early exit after slice s: a ray is done when its hit lies before every point of every
// sphere still ahead (their centres are past the next slice face, so their points are past
// it minus r_max), or when the slices ahead are beyond the part of the grid it crosses. Its
// hit is stored and the rays left are compacted; returns how many are left.
inline int retireRays(Lane* L,
  RayLanes& R,
  int active,
  int s,
  bool ascending,
  float rG,
  int K,
  PacketHits& hits)
{
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
      storeHit(l, R, i, hits);
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
    R.tieFrom[kept] = R.tieFrom[i];
    ++kept;
  }
  R.pad(kept);
  return kept;
}
// The first slice after which retireRays can retire a ray, from its two conditions solved
// for s: ascending, a ray settles once s >= kHit + rG - 1 and passes once s > kHi + rG - 1
// (descending, s <= kHit - rG and s < kLo - rG). Rays change only when a slice tests spheres,
// so until this slice (one earlier, for the rounding) no other slice needs retireRays.
inline int firstRetirement(const Lane* L,
  const RayLanes& R,
  int active,
  bool ascending,
  float rG,
  int K)
{
  float k = ascending ? std::numeric_limits<float>::max() : -std::numeric_limits<float>::max();
  for (int i = 0; i < active; ++i)
  {
    const Lane& l = L[i];
    const bool hit = R.prim[i] != NoHit;
    const float kHit = l.o[K] + R.tBest[i] * l.dk;
    k = ascending ? std::min(k, hit ? std::min(kHit, l.kHi) : l.kHi)
                  : std::max(k, hit ? std::max(kHit, l.kLo) : l.kLo);
  }
  const float s = ascending ? k + rG - 1.f : k - rG;
  const float bound = std::numeric_limits<int>::max() / 2;
  return ascending ? static_cast<int>(std::floor(std::clamp(s, -bound, bound))) - 1
                   : static_cast<int>(std::ceil(std::clamp(s, -bound, bound))) + 1;
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
  const int axis = majorAxis(packet, lanes, count);
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
  const Axes ax{ axis, (axis + 1) % 3, (axis + 2) % 3 };
  const float rG = Grid.maxRadius() * Grid.inverseCellSize(); // r_max in cell units
  const bool ascending = packet.rays[lanes[0]].dir[ax.K] > 0;
  Lane L[MaxPacketRays];
  PacketSpan span;
  int active = setUpLanes(Grid, packet, lanes, count, ax, L, span);
  if (active == 0)
  {
    return;
  }
  RayLanes R;
  loadRayLanes(packet, L, active, R);
  // Sphere-center method: a ray reaches a sphere of radius r whose centre is at most
  // r sqrt(1 + dU^2) away from it in U within the centre's K-plane (same for V).
  const SlopeFactors slope{ std::sqrt(1.f + span.slopeU * span.slopeU),
    std::sqrt(1.f + span.slopeV * span.slopeV) };
  const Frustum frustum = packetFrustum(packet, lanes, count);
  const bool ranged = Filter.count > 0 && Filter.count <= spheres.numAttributes;
  // Near and far shifted by r_max: a sphere whose centre lies up to r_max before a ray's
  // start (or after its end) along K can still be hit (section 4.1).
  const float kMin = span.kMin - rG, kMax = span.kMax + rG;
  const int first =
    std::clamp(static_cast<int>(std::floor(ascending ? kMin : kMax)), 0, dims[ax.K] - 1);
  const int last =
    std::clamp(static_cast<int>(std::floor(ascending ? kMax : kMin)), 0, dims[ax.K] - 1);
  const int step = ascending ? 1 : -1;
  const float kA = static_cast<float>(std::min(first, last));
  const float kB = static_cast<float>(std::max(first, last) + 1);
  PacketExtents extents = packetExtents(L, active, ax, kA, kB);
  const int M = Grid.macrocellSize();
  int occupiedLayer = -1; // the macrocell layer last found to hold spheres near the packet
  int retirement = firstRetirement(L, R, active, ascending, rG, ax.K);
  for (int s = first; active > 0;)
  {
    // The slices of s's macrocell layer still ahead, s..end in the direction of travel: all
    // skipped when the macrocells they reach are empty, else visited one by one.
    const int layer = s / M;
    const int end = ascending ? std::min(last, layer * M + M - 1) : std::max(last, layer * M);
    int through = s; // the last slice covered by this step
    if (layer != occupiedLayer &&
        macrocellsEmpty(Grid,
          ax,
          layer,
          reachableCells(
            sliceBounds(extents, std::min(s, end), std::max(s, end)), rG, slope, ax, dims)))
    {
      through = end;
    }
    else
    {
      occupiedLayer = layer;
      const std::int64_t testsBefore = counters.sphereTests;
      const PacketWalk walk{ packet.ordered, spheres, Filter, ranged, frustum, ax, extents, slope,
        ascending, L, R, active, counters };
      visitSlice<Lanes>(
        Grid, walk, s, reachableCells(sliceBounds(extents, s, s), rG, slope, ax, dims));
      if (counters.sphereTests != testsBefore)
      {
        retirement = firstRetirement(L, R, active, ascending, rG, ax.K);
      }
    }
    if (through == last)
    {
      break;
    }
    if (ascending ? through >= retirement : through <= retirement)
    {
      const int kept = retireRays(L, R, active, through, ascending, rG, ax.K, hits);
      if (kept != active && kept > 0)
      {
        extents = packetExtents(L, kept, ax, kA, kB);
      }
      active = kept;
      retirement = firstRetirement(L, R, active, ascending, rG, ax.K);
    }
    s = through + step;
  }
  for (int i = 0; i < active; ++i)
  {
    storeHit(L[i], R, i, hits);
  }
}

} // namespace raymappers
