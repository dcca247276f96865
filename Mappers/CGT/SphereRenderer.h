// Ray casts a SphereSet into a Frame: primary rays in square packets per screen tile (TBB),
// closest hits from an accelerator (Embree's BVH or the coherent grid), the exact hit refined in
// double precision, Lambert + Phong shading in world space, and the window depth of the hit.
#ifndef RayMappers_SphereRenderer_h
#define RayMappers_SphereRenderer_h

#include "Frame.h"
#include "Lighting.h"
#include "RayCamera.h"
#include "RenderStatistics.h"
#include "SphereAccelerator.h"
#include "SphereSet.h"

#include <vector>

namespace raymappers
{

struct SphereShading
{
  std::vector<Light> lights; // world space; empty means unlit (flat colour)
  Material material;
  double modelToWorld[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  double normalToWorld[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
};

/// Renders the spheres seen by `camera` into `frame` (resized to the camera's grid), in
/// packets of packetSide x packetSide rays (clamped to [1, MaxPacketSide]).
/// Counters: rays, packets, hits, cells, culled, sphere_tests, range_culled. Effects:
/// shading, specular, range_culling.
void renderSpheres(const SphereSet& spheres,
  const SphereAccelerator& accel,
  int packetSide,
  const RayCamera& camera,
  const SphereShading& shading,
  int tileSize,
  Frame& frame,
  RenderStatistics& stats);

/// Exact closest intersection of a ray (unit direction) with a sphere, in double:
/// returns the root nearest to `tGuess` (the accelerator's float estimate), or tGuess
/// itself when the ray only grazes the sphere in float arithmetic.
double refineSphereHit(const Vec3d& org,
  const Vec3d& dir,
  const Vec3d& center,
  double radius,
  double tGuess);

} // namespace raymappers

#endif
