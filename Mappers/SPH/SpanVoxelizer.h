// The tiled voxelization of a fluid's particles into compressed spans (Zirr 2015,
// sections 3.1, 3.2, 4.1 to 4.4).
//
// The grid: one voxel column per pixel of the view, with the logarithmic depth layers of
// VoxelDepthLayers.h over the depth range the particles occupy (clipped to near and far),
// 1 bit per voxel, packed in 64-bit words along the column. The screen is split into square
// tiles (at most 64 pixels, a tile's grid within 1 MB so that it stays in a core's cache while
// its particles are splatted; smaller when the memory budget asks). Each particle's and box's
// footprint is listed in the tiles it overlaps; the tiles are voxelized in parallel, each into
// its thread's own grid, compressed into spans and the grid cleared for the next. The peak
// temporary memory is the footprints, the tile lists and one tile grid per thread, whatever
// the resolution.
//
// Splat (3.1, 4.1): per tile, each listed sphere's exact projected extent
// (ViewRays::projectedExtent) gives its pixels, and per row the pixels whose rays can meet it
// (the roots of a quadratic in the pixel's x, widened by a pixel; each is still tested
// exactly); the centre ray of each, p(zeta) = A + zeta B, meets the sphere |p - c| = r on
// [zeta_0, zeta_1], the roots of
//   |B|^2 zeta^2 + 2 (A - c).B zeta + |A - c|^2 - r^2 = 0,
// clipped to the layers' range (the near plane cuts the sphere there), and the bits of the
// layers overlapping it are set. With a
// gap threshold g >= 2 r_max (section 4.4) only the two layers holding zeta_0 and zeta_1 are
// set (the sphere's shell): the chord between them, at most 2 r long, is bridged anyway.
//
// Compress (3.1, 4.3): over the tile's columns a splat wrote, runs of set bits are found word
// by word with count-trailing-zeros on the word (runs of ones: on its complement). A run of
// layers [s, e) becomes the span [d_s, d_e].
//
// Gap bridging (3.2, 4.4): a run joins the span before it when the empty gap between them is
// shorter than g in world space, (d_s - d_e') |B| < g. (The paper bounds the gap's layer count
// from below to avoid evaluating depths; here the depths d_i are a table, so the exact test
// costs one subtraction.)
//
// Opaque geometry (an optional stop depth per pixel, VoxelizerParameters::stopDepth): a
// pixel's ray ends at the depth zeta_stop of what is already drawn there, so the spheres
// are clipped to zeta <= zeta_stop while splatting and exits beyond it are moved back to it
// (an exit at the geometry's surface); the fluid behind the geometry leaves no spans and
// absorbs nothing.
//
// Boundary-cell culling (FluidCells.h, sections 3.1 and 4.3): with
// VoxelizerParameters::cells only the particles it keeps are splatted, in its (Morton) order,
// and each of its boxes, the full cells, fills every layer between the ray's entry into and
// exit from the box, with the same clipping to the layers' range and the stop depth.
#ifndef RayMappers_SpanVoxelizer_h
#define RayMappers_SpanVoxelizer_h

#include "Mappers/SPH/FluidCells.h"
#include "Mappers/SPH/FluidParticles.h"
#include "Mappers/SPH/FluidSpans.h"
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/Common/ViewRays.h"

#include <cstddef>
#include <string>
#include <vector>

namespace raymappers
{

struct VoxelizerParameters
{
  double angleResolutionDeg = 14.0; // alpha of section 4.2
  int maxLayers = 16384;
  int maxSpans = 7;                                  // S, at most FluidSpans::MaxSpans
  std::size_t memoryBudget = 0;                      // bytes of temporary memory; 0: automatic
  double gapThreshold = 0.0;                         // g, world units
  /// Optional: per pixel (width x height, row 0 at the bottom) the depth zeta where the
  /// pixel's ray ends at opaque geometry (+inf or any value beyond the far plane: none).
  /// Not owned; must outlive voxelizeFluid.
  const float* stopDepth = nullptr;
  /// Optional: the particles to splat and the full cells' boxes (buildFluidCells on the same
  /// particles); null: every particle, in input order. Not owned.
  const FluidCells* cells = nullptr;
};

/// The stop depths (zeta) of VoxelizerParameters::stopDepth from OpenGL window depths of
/// what is drawn (width x height, row 0 at the bottom; 1 where nothing is: +inf).
std::vector<float> stopDepthsFromWindowDepth(const ViewRays& rays, const float* windowDepth);

/// The budget that VoxelizerParameters::memoryBudget 0 stands for, taken when a frame starts:
/// half the memory the process can still take (availableMemoryBytes), and at least the
/// 512 MB that was the fixed default (also when no limit can be read). The voxelizer takes
/// only what the chosen tiles need, so a large budget costs nothing where a small one fits.
std::size_t automaticMemoryBudget();

/// Why a voxelization that exceeded its budget drew nothing, from its counters: "The memory
/// budget of B MB [(automatic: ...)] cannot hold this view's voxelization (the tile lists of
/// N particles in view and a grid of L layers per thread need at least X MB)" (or "...: an
/// allocation failed)" when the need is not known).
std::string describeBudgetShortfall(const RenderStatistics& stats);

/// Voxelizes `particles` for `rays` into `out` (sized to the view; no spans where no
/// particle is). Returns false when the budget cannot hold one column's bits per thread with
/// the footprints and tile lists, or an allocation fails (out then has no spans; counter
/// budget_exceeded = 1). Phases: splat, compress (they alternate per tile: the loop's time
/// split in proportion to the threads' time in each). Counters: particles_in_view (splatted
/// ones), boxes_in_view, box_pixels, layers, angle_millidegrees (the angle resolution the
/// layers reach), words_per_column, tiles, tile_width, tile_height (the tiles' count and
/// size), splat_pixels, stopped_spans, set_bit_ops,
/// spans_found, spans_stored, spans_hidden, gaps_bridged, peak_temporary_bytes,
/// memory_budget_bytes (the budget in effect), memory_budget_automatic (1: memoryBudget was 0),
/// budget_exceeded. Effects: shell_splat, gap_bridging.
bool voxelizeFluid(const FluidParticles& particles,
  const ViewRays& rays,
  const VoxelizerParameters& params,
  FluidSpans& out,
  RenderStatistics& stats);

} // namespace raymappers

#endif
