// Ray casts a SphereSet into a Frame: primary rays in square packets per screen tile (TBB),
// closest hits from an accelerator (Embree's BVH or the coherent grid), the exact hit refined in
// double precision, Lambert + Phong shading in world space, and the window depth of the hit.
#ifndef RayMappers_SphereRenderer_h
#define RayMappers_SphereRenderer_h

#include "Mappers/Common/Frame.h"
#include "Mappers/Common/Lighting.h"
#include "Mappers/Common/RayCamera.h"
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/Common/View.h"
#include "Mappers/CGT/SphereAccelerator.h"
#include "Mappers/CGT/SphereSet.h"

#include <vector>

namespace raymappers
{

struct SphereShading
{
  std::vector<Light> lights; // world space; empty means unlit (flat colour)
  Material material;
  double modelToWorld[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  double normalToWorld[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  /// Ambient occlusion: rays per hit (0: off) reaching at most `aoRadius` (model units).
  int aoSamples = 0;
  double aoRadius = 0.0;
  /// Soft shadows from a rectangular area light (Gribble et al., section 4.3): side x side
  /// shadow rays per hit (0: off; 1: a hard shadow from the centre). The rectangle is
  /// given in the sphere set's origin-relative model coordinates (centre, two edge
  /// vectors) and, for shading, by its centre in world coordinates. When on, the area light
  /// is the direct light (the `lights` are not used) and the visible fraction of its
  /// samples scales its diffuse and specular terms.
  int shadowSide = 0;
  Vec3d lightCenter, lightEdgeU, lightEdgeV;
  Vec3d lightCenterWorld;
  double lightIntensity = 1.0;
};

/// Sample (a, b) of a side x side stratified pattern on the area light, shifted per
/// pixel: centre + (u - 1/2) U + (v - 1/2) V with u = (a + s0) / side, v = (b + s1) / side.
Vec3d shadowTarget(const SphereShading& shading, int a, int b, std::uint32_t pixel);

/// The k-th of `count` ambient-occlusion directions at a hit with unit normal n: a
/// cosine-weighted hemisphere sample (Hammersley point (k + 1/2)/count, radical inverse of
/// k), rotated by a per-pixel shift so neighbouring pixels do not share a pattern. The
/// occlusion of a hit is the fraction of these rays that meet a sphere within the radius.
Vec3d aoDirection(const Vec3d& n, int k, int count, std::uint32_t pixel);

/// What the spheres' renderer draws: the spheres and an accelerator built over them.
struct SphereScene
{
  const SphereSet& spheres;
  const SphereAccelerator& accel;
};

/// How it draws them: the shading, rays traced in packets of packetSide x packetSide
/// (clamped to [1, MaxPacketSide]) and scheduled in tiles of tileSize x tileSize pixels.
struct SphereRenderParameters
{
  SphereShading shading;
  int packetSide = 8;
  int tileSize = 32;
};

/// Renders the spheres seen by the view's camera into `frame` (resized to the view's grid).
/// Counters: rays, packets, hits, cells, culled, sphere_tests, range_culled, ao_rays,
/// shadow_rays. Effects: shading, specular, range_culling, ambient_occlusion, soft_shadows.
void renderSpheres(const SphereScene& scene,
  const View& view,
  const SphereRenderParameters& params,
  Frame& frame,
  RenderStatistics& stats);

/// A hardware-selection pass: for every pixel of the view, the input point (sourceIds) + 1
/// of the sphere its primary ray hits first and that hit's window depth (0 and depth 1 where
/// the ray meets nothing), traced like renderSpheres (same packets, accelerator, range
/// culling and exact root) without shading. Counters rays, packets, hits; effect
/// selection_ids.
void pickSpheres(const SphereScene& scene,
  const View& view,
  int packetSide,
  int tileSize,
  IdFrame& picks,
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
