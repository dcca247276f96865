// Coherent grid traversal of sphere glyphs (Gribble et al. 2007, after Wald et al. 2006):
// a packet of rays walks the grid slice by slice along its major axis K; in each slice the
// rectangle of cells in U and V that any ray of the packet can reach is found from the
// rays' extreme U and V coordinates at the slice's two faces, enlarged for the sphere-center
// method by s = r_max sqrt(1 + dU^2) (section 4.1), and its cells are visited, skipping
// empty macrocells (a layer of slices at once when every macrocell the packet reaches there is
// empty), and within a macrocell only the cells its own largest radius can reach; a nested
// cell (CoherentGrid: one crowded with spheres) is walked the same way one level down, its
// sub-slices front to back. Each sphere of a visited cell is culled against the packet's frustum
// (its centre farther than its radius outside one of the four side planes, section 4.3)
// before the rays of the packet are tested against it. The walk stops once every ray's
// closest hit lies before the next slice minus r_max: no later sphere can come nearer.
#ifndef RayMappers_CoherentGridAccelerator_h
#define RayMappers_CoherentGridAccelerator_h

#include "Mappers/CGT/CoherentGrid.h"
#include "Mappers/CGT/SimdPath.h"
#include "Mappers/CGT/SphereAccelerator.h"

namespace raymappers
{

class CoherentGridAccelerator : public SphereAccelerator
{
public:
  /// Builds the grid; permutes `spheres` into cell order (they must outlive this object
  /// and stay unchanged until the next build).
  void build(SphereSet& spheres, const CoherentGridParameters& params);

  bool empty() const override { return Spheres == nullptr || Grid.empty(); }
  void intersect(const RayPacket& packet,
    PacketHits& hits,
    TraversalCounters& counters) const override;

  const CoherentGrid& grid() const { return Grid; }

  /// The SIMD path of the ray-sphere tests (Auto: the widest the CPU has).
  void setSimdPath(SimdPath path) { Simd = resolveSimdPath(path); }
  SimdPath simdPath() const { return Simd; }

private:
  /// Traversal of the lanes in `lanes` (all valid, sharing the direction signs of `axis`),
  /// testing spheres with Lanes::intersect.
  template<typename Lanes>
  void traverse(const RayPacket& packet,
    const int* lanes,
    int count,
    int axis,
    PacketHits& hits,
    TraversalCounters& counters) const;

  CoherentGrid Grid;
  const SphereSet* Spheres = nullptr;
  SimdPath Simd = resolveSimdPath(SimdPath::Auto);
};

} // namespace raymappers

#endif
