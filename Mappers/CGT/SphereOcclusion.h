// Occlusion of short rays that leave one point (ambient occlusion): whether each ray meets a
// sphere with t in [tnear, tfar), any sphere, not the closest. On the coherent grid the
// spheres are found around the point instead of by a packet traversal: a ray of length T
// from o reaches sphere (c, r) only if |c - o| <= T + r, so with the sphere-center method
// (each sphere is listed in the cell of its centre) the cells of the box
// o +- (T + r_max) list every sphere the rays can meet. The candidates within T + r of o are
// tested against all rays in SIMD lanes with the grid's own ray-sphere test
// (RaySphereLanes.h), so a ray is blocked exactly when the grid's traversal finds it a hit;
// the query stops at the first sphere after which every ray is blocked. Other accelerators
// answer through their any-hit query (SphereAccelerator::occluded; Embree: rtcOccluded16).
#ifndef RayMappers_SphereOcclusion_h
#define RayMappers_SphereOcclusion_h

#include "Mappers/CGT/SphereAccelerator.h"
#include "Mappers/CGT/SphereSet.h"

namespace raymappers
{

class CoherentGridAccelerator;

class SphereOcclusion
{
public:
  SphereOcclusion(const SphereSet& spheres, const SphereAccelerator& accel);

  /// blocked[a] for the packet's first `count` lanes (all valid), whose rays all start at
  /// the same origin: whether the ray meets a sphere that passes the accelerator's range
  /// filter. Returns how many are blocked.
  int occluded(const RayPacket& packet,
    int count,
    bool* blocked,
    TraversalCounters& counters) const;

  /// Whether queries run on the grid's cells (false: the accelerator's occluded).
  bool local() const { return Grid != nullptr; }

private:
  const SphereSet& Spheres;
  const SphereAccelerator& Accel;
  const CoherentGridAccelerator* Grid; // the accelerator when it is the coherent grid
};

} // namespace raymappers

#endif
