// Ray casts a SphereSet into a Frame: primary rays in square packets per screen tile (TBB),
// closest hits from an accelerator (Embree's BVH or the coherent grid), the exact hit refined in
// double precision, Lambert + Phong shading in world space, and the window depth of the hit.
//
// Translucent spheres (a global opacity below 1 or per-sphere opacities; not in Gribble et
// al., whose glyphs are opaque) are composited exactly along each ray, front to back: the
// packet is traced again from each hit on as an ordered packet (RayPacket::ordered: t_near =
// the hit's t, and at that t only spheres of higher index), so the surfaces come in the
// order of (t, sphere index), and sphere i, met at its first surface, adds
//   C += (1 - A) a_i c_i,   A += (1 - A) a_i        (premultiplied "over", Porter-Duff)
// to the pixel. Each sphere counts once per ray, at its first surface at or after the ray's
// start: its front surface, or its back surface when the ray starts inside it (the near plane
// cuts it, as the opaque path shows it); a hit on a sphere's back surface after its front is
// skipped. Spheres whose surfaces the ray meets at the same float distance (coincident points,
// e.g. a mesh's duplicated nodes) each count, in index order. A ray stops when A >= TranslucentTerminationAlpha,
// at the opaque depth of the view, or when nothing is left. Shadow and ambient-occlusion rays
// treat every sphere as opaque (any sphere in the way blocks), whatever its opacity.
// With no opacity below 1 and no per-sphere opacities the opaque closest-hit path runs, one
// query per packet (effect "translucency" off, counter "translucent_layers" 0).
#ifndef RayMappers_SphereRenderer_h
#define RayMappers_SphereRenderer_h

#include "Mappers/Common/Frame.h"
#include "Mappers/Common/Lighting.h"
#include "Mappers/Common/RayCamera.h"
#include "Mappers/Common/RegionBox.h"
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/Common/View.h"
#include "Mappers/CGT/SphereAccelerator.h"
#include "Mappers/CGT/SphereSet.h"

#include <cstdint>
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
/// cosine-weighted hemisphere sample (Hammersley point (u, v) = ((k + 1/2)/count, radical
/// inverse of k)), toroidally shifted per pixel (Cranley-Patterson, u + s0 and v + s1 mod 1)
/// so neighbouring pixels do not share a pattern:
///   d = normalize(t sqrt(u) cos(2 pi v) + b sqrt(u) sin(2 pi v) + n sqrt(1 - u))
/// in the tangent frame (t, b, n). The occlusion of a hit is the fraction of these rays that
/// meet a sphere within the radius.
Vec3d aoDirection(const Vec3d& n, int k, int count, std::uint32_t pixel);

/// What the directions of one frame share, per k: the Hammersley point's u and the cosine
/// and sine of 2 pi v (one table for all hits). The pixel's shift s1 enters by the angle
/// sum, cos(2 pi (v + s1)) = cos(2 pi v) cos(2 pi s1) - sin(2 pi v) sin(2 pi s1), so a hit
/// computes one sine and cosine, not one per ray.
struct AoSample
{
  double u, cosV, sinV;
};
AoSample aoSample(int k, int count);

/// What the directions of one hit share: the pixel's shift (s0, and the cosine and sine of
/// 2 pi s1) and the tangent frame (t, b, n) of its normal. aoDirection(n, k, count, pixel)
/// is aoDirectionIn(aoBasis(n, pixel), aoSample(k, count)).
struct AoBasis
{
  double shift0, cosShift1, sinShift1;
  Vec3d t, b, n;
};
AoBasis aoBasis(const Vec3d& n, std::uint32_t pixel);
Vec3d aoDirectionIn(const AoBasis& basis, const AoSample& sample);

/// What the spheres' renderer draws: the spheres and an accelerator built over them, seen
/// by the primary rays only inside `region` (distributed rendering, RegionBox.h; all of
/// space by default). A process whose box holds its spheres and the neighbours' spheres
/// reaching into it draws every surface point inside its box and nothing else: each ray's
/// interval is cut to [entry, exit) of the box (a ray starting inside a sphere cut by a face
/// sees its far surface, hidden in the composite by the near one the neighbour draws), so
/// the boxes' images, depth composited or blended in visibility order, are the one box's.
/// A translucent sphere counts in the box holding its first surface along the whole ray.
/// Shadow and occlusion rays are not cut (they see the spheres the process has).
struct SphereScene
{
  const SphereSet& spheres;
  const SphereAccelerator& accel;
  RegionBox region = {};
};

/// Early termination of translucent compositing: a ray stops once its accumulated alpha A
/// reaches this. The layers left out add at most (1 - A) to every premultiplied channel and
/// to alpha (their weights (1 - A) a_j sum to at most 1 - A), so the error is below
/// 1/512, under half a step of an 8-bit channel: the 8-bit picture is within one level of
/// the exact composite.
constexpr float TranslucentTerminationAlpha = 1.f - 1.f / 512.f;

/// Progressive ambient occlusion: the N = aoSamples directions of every hit,
/// aoDirection(n, k, N, pixel), are traced over several frames in order, frame f taking
/// k in [k0, k1) with k1 = min(N, k0 + aoSamplesPerFrame). Per pixel it keeps U, the
/// unoccluded rays among k in [0, k1), and shades with the fraction so far,
///   1 - (k1 - U) / k1,
/// the one-shot expression 1 - occluded / N once k1 = N: the converged frame equals a
/// one-shot render bit for bit, and the frames after it trace no AO ray (they reuse U).
/// It restarts (k0 = 0) whenever the image would change: the view (matrix, size, origin),
/// the shading, the opacity, the range filter, the sphere set or accelerator (object,
/// size) or the caller's sceneVersion (data, colours, properties the kernel does not see).
struct AoAccumulation
{
  std::vector<std::uint16_t> unoccluded; // U per pixel of the frame's grid
  int done = 0;                          // k1 of the last frame (0: nothing accumulated)
  std::vector<std::uint64_t> key;        // the bits of what the image depended on
  void reset()
  {
    done = 0;
    key.clear();
  }
};

/// How it draws them: the shading, rays traced in packets of packetSide x packetSide
/// (clamped to [1, MaxPacketSide]) and scheduled in tiles of tileSize x tileSize pixels.
struct SphereRenderParameters
{
  SphereShading shading;
  int packetSide = 8;
  int tileSize = 32;
  /// Opacity of every sphere (the actor's), times its own (SphereSet::opacities) when set;
  /// 0 (or NaN) draws nothing.
  double opacity = 1.0;
  /// Ambient-occlusion directions per hit and frame (AoAccumulation): 0 (or no
  /// accumulation) traces all N in every frame; a budget above N is N. Translucent spheres
  /// (several hits per pixel) always trace all N.
  int aoSamplesPerFrame = 0;
  AoAccumulation* aoAccumulation = nullptr;
  /// Changed by the caller whenever something the kernel cannot compare changed (the
  /// spheres' positions, radii or colours, ...): restarts the accumulation.
  std::uint64_t sceneVersion = 0;
};

/// Whether renderSpheres composites translucent spheres (an opacity below 1 or per-sphere
/// opacities) rather than drawing the opaque closest hits.
inline bool drawsTranslucent(const SphereSet& spheres, const SphereRenderParameters& params)
{
  return params.opacity < 1.0 || !spheres.opacities.empty();
}

/// Renders the spheres seen by the view's camera into `frame` (resized to the view's grid).
/// Counters: rays, packets, hits, cells, culled, sphere_tests, range_culled, ao_rays,
/// ao_samples_done (AO directions per hit accumulated after this frame, k1), ao_converged
/// (1 when all N are in, or AO is off: nothing is left to refine), shadow_rays,
/// translucent_layers (spheres composited), translucent_queries (packet queries of the
/// translucent path, each packet's first included), translucent_terminated (rays stopped by
/// TranslucentTerminationAlpha).
/// Effects: shading, specular, range_culling, ambient_occlusion, ao_progressive (directions
/// split over frames), ao_local_queries (AO rays answered from the grid's cells around the
/// hit, SphereOcclusion.h), soft_shadows, translucency, region_clip (the primary rays cut
/// to the scene's region). A translucent render stops its rays
/// at the view's opaque depth; an opaque one writes depth and leaves the depth test to the
/// caller.
void renderSpheres(const SphereScene& scene,
  const View& view,
  const SphereRenderParameters& params,
  Frame& frame,
  RenderStatistics& stats);

/// The roots t0 <= t1 of |o + t d - c|^2 = r^2 (unit d), in double: t = -b -+ sqrt(disc)
/// with b = (o - c).d and disc = r^2 - |(o - c) - b d|^2 (the squared distance from the centre
/// to the ray's line; this form avoids the cancellation of |o - c|^2 - r^2 far from the
/// sphere). disc < 0: the line misses (t0 = t1 = -b, the closest approach).
struct SphereRoots
{
  double disc, t0, t1;
};
SphereRoots sphereRoots(const Vec3d& org, const Vec3d& dir, const Vec3d& center, double radius);
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
