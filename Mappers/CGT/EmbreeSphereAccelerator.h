// Embree's BVH over sphere primitives (RTC_GEOMETRY_TYPE_SPHERE_POINT) as the accelerator
// of the sphere glyph renderer, traced in packets of 16 coherent rays.
#ifndef RayMappers_EmbreeSphereAccelerator_h
#define RayMappers_EmbreeSphereAccelerator_h

#include "SphereSet.h"

#include <embree3/rtcore.h>

namespace raymappers
{

class EmbreeSphereAccelerator
{
public:
  enum class Quality
  {
    Low,
    Medium,
    High
  };

  EmbreeSphereAccelerator();
  ~EmbreeSphereAccelerator();
  EmbreeSphereAccelerator(const EmbreeSphereAccelerator&) = delete;
  EmbreeSphereAccelerator& operator=(const EmbreeSphereAccelerator&) = delete;

  /// (Re)builds the BVH over the spheres. primID of a hit is the index in `spheres`.
  void build(const SphereSet& spheres, Quality quality = Quality::Medium);
  bool empty() const { return Count == 0; }

  /// Closest hits of up to 16 rays (valid[i] = -1 for active lanes, 0 otherwise); the
  /// context is flagged coherent (primary rays of a pixel block).
  void intersect16(const int* valid, RTCRayHit16& rayhit) const;

private:
  RTCDevice Device = nullptr;
  RTCScene Scene = nullptr;
  std::size_t Count = 0;
};

} // namespace raymappers

#endif
