// SPH volume ray casting through a perspective grid (Limper 2012, chapter 3).
//
// Per frame: the perspective grid of the view is built (PerspectiveGrid.h), then every
// tile of tileSize x tileSize pixels is a ray bundle (section 3.6.1) that walks its column
// of cells front to back, leaping over runs of empty cells with the empty successors cache
// (section 3.4.3). In a cell the bundle takes its samples in slabs of slabDepth samples per
// ray (the slab cache, section 3.6.2, Listing 3.2): each particle of the cell adds its
// contribution to every buffered sample its support reaches, then the slab is classified,
// shaded and composited front to back. All rays of a bundle share their sample depths.
//
// The field (equations 3.14 to 3.16) at a sample x, with A = sum Q_i V_i W_i and
// B = sum V_i W_i:
//   normalized:        Q = A / B where B > 0; where B vanishes (outside the fluid) the
//                      sample is empty, never NaN; A/B is a weighted mean of the Q_i and is
//                      clamped to their range against rounding;
//   unnormalized:      Q = A;   pseudo-normalized: Q = A / w_max;
//                      (for these two a sample with A = 0 is empty, as in Listing 4.4);
// w_max (equation 3.16) is the sum of weights of a full neighbourhood.
//
// Classification: the transfer function gives colour and opacity per unit distance; a
// sample's segment of length l = (zeta_{k+1} - zeta_k) |B| (the adaptive step, clipped at
// opaque geometry) has opacity alpha = 1 - (1 - alpha_tf)^(l / unitDistance) (opacity
// correction, equation 3.27) and contributes alpha * colour, composited front to back
// (equations 3.29, 3.30).
// Gradient shading (section 3.7.1, only when on): the exact gradient of A,
//   grad A = sum Q_i V_i W'(r_i) (x - x_i)/r_i      (equation 3.22),
// accumulated with the samples; the normal is -grad A/|grad A| (3.23); the colour is lit by
// Lambert + Phong (Lighting.h) and weighted by the sample's opacity (3.31).
// Contour shading (section 3.7.2, only when on): I = clamp(1 - B / w_max, 0, 1) where B > 0
// (3.26, scaled to [0, 1]); the contour adds I * contourOpacity (per unit distance,
// corrected for l like any opacity) of contourColor: C += alpha_c C_contour,
// alpha = min(1, alpha + alpha_c) (3.24, 3.25, 3.32, 3.33).
// Stochastic jittering (section 3.2.2, optional): each pixel's samples sit at its own
// fraction in [0, 1) of their steps, from a fixed 32 x 32 pattern, instead of at the
// steps' midpoints.
// Early ray termination (section 4.1.3): a ray stops compositing once its opacity reaches
// terminationOpacity; the bundle stops when all of its rays have (and rows of finished
// rays take no more contributions). Opaque geometry (the depth buffer) ends each ray.
#ifndef RayMappers_SPHVolumeRenderer_h
#define RayMappers_SPHVolumeRenderer_h

#include "Mappers/Common/Frame.h"
#include "Mappers/Common/Lighting.h"
#include "Mappers/SPH/PerspectiveGrid.h"
#include "Mappers/Common/RegionBox.h"
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/SPH/SPHKernels.h"
#include "Mappers/SPH/SPHParticles.h"
#include "Mappers/Common/TransferFunctionTable.h"
#include "Mappers/Common/View.h"

#include <vector>

namespace raymappers
{

enum class SPHNormalization
{
  Normalized = 0,
  Unnormalized = 1,
  PseudoNormalized = 2
};

struct SPHRenderParameters
{
  SPHKernel kernel = SPHKernel::Poly6;
  SPHNormalization normalization = SPHNormalization::Normalized;
  double referenceWeightSum = 1.0; // w_max > 0
  int tileSize = 16;               // pixels per bundle side (and grid cell side)
  double stepFactor = 1.0;         // sample spacing relative to a pixel's footprint
  double samplesPerSupport = 0.0;  // > 0: steps at least (smallest support) / this
  // > 0: the smallest support that rule divides, instead of the particles' own (a region of
  // a distributed render passes that of all regions, so all step alike).
  double smallestSupport = 0.0;
  int slabDepth = 0;               // samples per ray per slab; 0: a whole cell
  double terminationOpacity = 0.99;
  bool jitter = false;
  bool shade = false;
  std::vector<Light> lights; // world space
  Material material;
  double modelToWorld[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  double normalToWorld[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  bool contour = false;
  double contourColor[3] = { 0, 0, 0 };
  double contourOpacity = 0.5; // per unit distance of the transfer function
  // Samples only inside this box (model coordinates; distributed rendering, RegionBox.h).
  // A sample's segment keeps its whole length: each step is owned by one region.
  RegionBox region;
};

/// The reference sum of weights of equation 3.16: n neighbours at half the support radius,
/// each of volume v: w_max = n v W(H/2, H).
double referenceWeightSum(SPHKernel kernel, double volume, double support, int neighbours = 12);

/// The jitter offset in [0, 1) of pixel (px, py)'s samples (a fixed 32 x 32 pattern).
float sphJitterOffset(int px, int py);

/// What the SPH renderer draws: the particles, their classification, and the perspective
/// grid they are binned into for each view (section 3.4; rebuilt by renderSPH, kept for its
/// memory).
struct SPHScene
{
  const SPHParticles& particles;
  const TransferFunctionTable& table;
  PerspectiveGrid& grid;
};

/// Renders the particles into `frame` (premultiplied RGBA; depth stays at the far plane:
/// a volume writes no depth) along the view's depth rays, rebuilding the scene's grid for
/// the view; rays stop at the view's opaque depth.
/// Phases: grid, raycast. Counters: particles_in_view, grid_cells, depth_cells,
/// samples_per_cell, grid_references, grid_bytes, bundles, cells_visited, cells_leaped,
/// samples, kernel_evaluations, weight_sums, gradient_evaluations, shaded_samples,
/// contour_samples, terminated_rays. Effects: normalization, gradient_shading,
/// contour_shading, jitter, early_termination, opaque_geometry.
void renderSPH(const SPHScene& scene,
  const View& view,
  const SPHRenderParameters& params,
  Frame& frame,
  RenderStatistics& stats);

} // namespace raymappers

#endif
