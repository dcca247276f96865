// Embree's BVH over sphere primitives (RTC_GEOMETRY_TYPE_SPHERE_POINT) as the accelerator
// of the sphere glyph renderer, traced in packets of 16 coherent rays.
#ifndef RayMappers_EmbreeSphereAccelerator_h
#define RayMappers_EmbreeSphereAccelerator_h

#include "Mappers/CGT/SphereAccelerator.h"
#include "Mappers/CGT/SphereSet.h"

#include <embree3/rtcore.h>

namespace raymappers
{

class EmbreeSphereAccelerator : public SphereAccelerator
{
public:
  enum class Quality
  {
    Low,
    Medium,
    High
  };

  /// `deviceConfig`: Embree's device configuration (nullptr: Embree's defaults for this
  /// CPU), e.g. "isa=avx2" for the code path CPUs without AVX-512 take.
  explicit EmbreeSphereAccelerator(const char* deviceConfig = nullptr);
  ~EmbreeSphereAccelerator() override;
  EmbreeSphereAccelerator(const EmbreeSphereAccelerator&) = delete;
  EmbreeSphereAccelerator& operator=(const EmbreeSphereAccelerator&) = delete;

  /// (Re)builds the BVH over the spheres. primID of a hit is the index in `spheres`, which
  /// must outlive this object and stay unchanged until the next build.
  void build(const SphereSet& spheres, Quality quality = Quality::Medium);
  bool empty() const override { return Count == 0; }

  /// The packet in chunks of 16 rays (4 x 4 pixels when side is 4) through rtcIntersect16,
  /// with the context flagged coherent (primary rays of a pixel block).
  void intersect(const RayPacket& packet,
    PacketHits& hits,
    TraversalCounters& counters) const override;

  /// Any-hit queries (ambient occlusion): chunks of 16 rays through rtcOccluded16, with
  /// the context flagged incoherent.
  int occluded(const RayPacket& packet, bool* blocked, TraversalCounters& counters) const override;

  /// Lanes [base, base + 16) of the packet as Embree's packet of 16 rays: valid[k] is -1 for
  /// the packet's valid lanes whose rays are traceable (isTraceable), and every other lane
  /// holds an empty ray (tnear > tfar). Returns whether any lane is to be traced.
  static bool toEmbreePacket(const RayPacket& packet, int base, RTCRayHit16& rays, int* valid);

  /// The scene released: an empty accelerator (also after a failed build).
  void clear();

private:
  RTCDevice Device = nullptr;
  RTCScene Scene = nullptr;
  std::size_t Count = 0;
  const SphereSet* Spheres = nullptr; // for the range filter's attributes
};

} // namespace raymappers

#endif
