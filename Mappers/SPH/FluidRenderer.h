// Rendering a fluid from its compressed voxelization (Zirr 2015, sections 3.5, 3.6), and the
// whole frame: voxelize (SpanVoxelizer.h), connect, smooth, normals (SurfaceLinks.h), render.
//
// The fluid is a homogeneous medium with absorption coefficient kappa_c = density *
// absorptionColor_c per world unit (per colour channel c). Its surface colour C at a point
// p is the solid `color`, or the particles' colours interpolated there (FluidColors.h) when
// `colors` is set; its appearance at a surface point with outward normal n is lit as
// shade(lights, material, C, p, n, v) (Lighting.h, world space; Lambert + Phong), split into
// the diffuse part D (ambient and diffuse terms, carrying C) and the specular highlight S,
// both times the ambient occlusion A(p) when that is on. With D, S those of the front
// surface (the first entry):
//   opaque (translucency off): rgb = D + S, alpha = 1;
//   translucent, index of refraction 1 (section 3.5, "iterate over all depth entries and
//     apply a scattering and absorption model"): the transmittance along the pixel's ray is
//     T_c = exp(-kappa_c l), l the fluid's thickness over all spans, including the hidden
//     empty space beyond the last stored one (FluidSpans::thickness times |B|), which is
//     exact Beer-Lambert however many layers. The medium scatters D back with the grey
//     scattering coefficient sigma = min_k kappa_k (the least absorbed channel's extinction
//     is all scattering): the light scattered along the ray, integral_0^l sigma D_c
//     exp(-kappa_c t) dt, is omega_c D_c (1 - T_c) with the albedo omega_c = sigma / kappa_c
//     (1 where kappa_c = 0). So rgb_c = S_c + omega_c D_c (1 - T_c): a thin body is grey,
//     sigma l D, and a thick one takes the colour of the channels it absorbs least (water's
//     blue for the default absorption), never the complement of its absorption; grey
//     absorption (omega = 1) gives D (1 - T). The highlight S is reflected at the surface,
//     neither absorbed nor tinted. alpha = 1 - mean_c T_c (the background shows through by T);
//   refraction (translucency on, index eta != 1; section 3.5, Listing 2): S goes to the pixel
//     and a path of weight w_c = 1 starts at the front entry. At each surface event the
//     Fresnel reflectance R of an unpolarized dielectric interface (eta inside, 1 outside;
//     R = 1 beyond the critical angle: total internal reflection) splits it: w R D goes to
//     the pixel and the path refracts with w (1 - R) (under total internal reflection it
//     reflects, keeping w). Inside, a segment of length s adds w_c omega_c (1 - exp(-kappa_c
//     s)) D_c and leaves w_c exp(-kappa_c s). The path is marched through the columns
//     (screen-space march along the ray's projection, pixel boundary to pixel boundary,
//     finding in each column the first stored depth between the depths where the ray enters
//     and leaves it, or a change between inside and outside at the column's side; tiles of
//     64 and 8 pixels whose columns provably hold no surface over the ray's depths there,
//     in depth bins per tile, are crossed in one step, to the same hits) until it
//     leaves the grid (its weight then reaches the background: alpha = 1 - mean_c w_c) or
//     `bounces` events have happened (a path still inside is then absorbed: w omega D goes
//     to the pixel). The weights of all branches sum to 1 per channel, so no pixel exceeds
//     S + D: energy is never created. A hidden extension of the last span counts as fluid
//     for the march.
// Ambient occlusion (section 3.6, only when on): K points q_k = p + r_k d_k in the hemisphere
// around the front surface's normal (fixed spiral directions, radii up to aoRadius) are
// occluded when their depth lies in any stored span of the column they project to (deep:
// all layers, not only the front); A = 1 - occluded / K.
// Normals are in model coordinates (the march refracts there; modelToWorld is assumed to be
// a similarity); lighting is in world space.
#ifndef RayMappers_FluidRenderer_h
#define RayMappers_FluidRenderer_h

#include "Mappers/Common/Frame.h"
#include "Mappers/Common/Lighting.h"
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/Common/View.h"
#include "Mappers/SPH/FluidColors.h"
#include "Mappers/SPH/FluidParticles.h"
#include "Mappers/SPH/FluidSpans.h"
#include "Mappers/SPH/SpanVoxelizer.h"
#include "Mappers/SPH/SurfaceLinks.h"

#include <vector>

namespace raymappers
{

struct FluidRenderParameters
{
  VoxelizerParameters voxelizer;
  double smoothingRadius = 0.0;        // world units; 0: no smoothing pass
  int smoothingIterations = 20;        // at most
  Vec3d color{ 0.55, 0.75, 0.95 };     // the solid colour
  const FluidColors* colors = nullptr; // per-particle colours of `colorParticles`; null: solid
  const FluidParticles* colorParticles = nullptr;
  Material material;
  std::vector<Light> lights; // world space
  double modelToWorld[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  double normalToWorld[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  bool translucency = true;
  Vec3d absorptionColor{ 0.8, 0.35, 0.15 }; // kappa_c / density
  double density = 1.0;
  double refractiveIndex = 1.0; // 1: no refraction march
  int bounces = 4;
  /// The march crosses tiles it can prove hold no surface along the ray in one step (the same
  /// hits as column by column); false: every column, as Listing 2.
  bool marchTileSkipping = true;
  bool ambientOcclusion = false;
  double aoRadius = 0.1; // world units
  int aoSamples = 16;
};

/// Renders `spans` (with normals) into `frame`: premultiplied RGBA and the window depth of
/// the front surface (the far plane where there is no fluid).
/// Phases: ao, render (opaque or translucent) or refract. Counters: shaded_pixels,
/// translucent_pixels, refraction_paths, surface_events, tir_events, march_columns (steps:
/// columns and tiles crossed), march_tile_skips (tiles crossed in one step), ao_samples, color_samples (particles visited for the colours). Effects: translucency,
/// refraction, ambient_occlusion, particle_colors.
void renderFluidSpans(const FluidSpans& spans,
  const ViewRays& rays,
  const Vec3d& origin,
  const FluidRenderParameters& params,
  Frame& frame,
  RenderStatistics& stats);

/// What the fluid renderer draws: the particles, and the spans they are voxelized into for
/// each view and their surfaces' neighbourhoods (rebuilt by renderFluid, kept for their
/// memory: a frame reuses the last one's pages; null neighbourhoods: the frame's own).
struct FluidScene
{
  const FluidParticles& particles;
  FluidSpans& spans;
  SurfaceNeighbourhoods* neighbourhoods = nullptr;
};

/// The whole frame along the view's depth rays: voxelizeFluid, connectSurfaces,
/// findNeighbourhoods, smoothSurfaces, computeNormals and renderFluidSpans, with their
/// phases and counters (and particles_skipped from the input, spans_bytes the memory of the
/// spans with their links and normals). The view's opaque depth, when
/// it has one, ends the fluid there (VoxelizerParameters::stopDepth). Returns false when the
/// voxelization does not fit the memory budget (the frame is then empty).
bool renderFluid(const FluidScene& scene,
  const View& view,
  const FluidRenderParameters& params,
  Frame& frame,
  RenderStatistics& stats);

} // namespace raymappers

#endif
