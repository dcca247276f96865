// Surfaces across the voxel columns of a fluid's spans (Zirr 2015, sections 3.3, 3.4, 4.6):
// links between the depth values of neighbouring pixels, smoothing of the linked surface
// depths and normals by a Sobel operator along the links.
//
// Connection (section 3.3, Listing 1), per stored span [e, x] of a pixel and per direct
// neighbour (+x, -x, +y, -y), with p the pixel's previous span's exit (-inf if none) and n
// its next span's entry (+inf if none):
//   F = the neighbour's first span whose exit >= e;
//   if F exists and F.entry <= x (the spans overlap):
//     e links to F.entry if F.entry > p (F is not the neighbour of the previous span too),
//       else to p (the neighbour recurs: a bubble wall between the two spans);
//     K = the neighbour's last span whose entry <= x;
//     x links to K.exit if n > K.exit, else to n (bubble wall);
//   else (a boundary span, figure 3c) e and x link to each other.
// Links to the pixel's own column carry FluidSpans::OwnColumn; pixels beyond the image have
// no spans.
//
// Smoothing (section 4.6): iterations of the 3x3 binomial kernel (1 2 1)^T (1 2 1) / 16 on the
// reciprocal depth 1 / zeta (perspective; zeta itself for parallel views, where depth is
// already linear on screen), each neighbour reached along the links (a diagonal one by two
// links, x then y, else y then x); neighbours that are missing or in the own column drop out
// and the weights are renormalized. n iterations reach n pixels, so a surface point at depth
// zeta takes n = min(maxIterations, ceil(R / (sigma zeta))) of them (sigma zeta the pixel's
// width there, sigma for parallel views): a world-space radius R held constant. Each value is
// kept between its column's previous and next depth values, so spans stay ordered.
//
// Normals (section 3.4): with P(a, b) the position of the surface point reached from a depth
// value by a steps in x and b in y along the links (a missing point replaced by the one a
// step nearer to the centre), the Sobel derivatives
//   G_x = sum_b w_b (P(1, b) - P(-1, b)),  G_y = sum_a w_a (P(a, 1) - P(a, -1)),  w = (1, 2, 1)
// give n = G_x x G_y / |G_x x G_y|, turned to face out of the fluid (against the ray at an
// entry, along it at an exit). Model coordinates, as the particles' centres.
#ifndef RayMappers_SurfaceLinks_h
#define RayMappers_SurfaceLinks_h

#include "Mappers/SPH/FluidSpans.h"
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/Common/ViewRays.h"

#include <cstdint>
#include <vector>

namespace raymappers
{

/// Fills spans.links. Phase: connect. Counters: links_neighbour, links_own.
void connectSurfaces(FluidSpans& spans, RenderStatistics& stats);

/// The surface points (stored depth values) numbered pixel by pixel, point pointStart[p] + s
/// being slot s of pixel p, each with the points of its 3 x 3 neighbourhood along the links
/// (found once for the filter's iterations and the normals).
struct SurfaceNeighbourhoods
{
  std::vector<std::uint32_t> pointStart; // per pixel, and the total at the end
  std::vector<std::uint32_t> pixel;      // per point
  /// 8 per point, offsets (a, b) = (-1, -1), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1),
  /// (0, 1), (1, 1); -1 where missing.
  std::vector<std::int32_t> neighbours;

  std::size_t points() const { return pixel.size(); }
  std::size_t bytes() const { return 4 * (pointStart.size() + pixel.size() + neighbours.size()); }
};

/// Fills `nbh` from the links of `spans`. Phase: connect. Counter: neighbourhood_bytes.
void findNeighbourhoods(const FluidSpans& spans,
  SurfaceNeighbourhoods& nbh,
  RenderStatistics& stats);

/// Smooths the linked depths with world radius `radius` (no pass, and effect smoothing
/// off, when radius <= 0 or maxIterations <= 0). Phase: filter. Counters: filter_iterations,
/// filtered_points, filter_bytes (per point the value twice and three bytes).
void smoothSurfaces(FluidSpans& spans,
  const SurfaceNeighbourhoods& nbh,
  const ViewRays& rays,
  double radius,
  int maxIterations,
  RenderStatistics& stats);

/// Fills spans.normals. Phase: normals. Counter: normals.
void computeNormals(FluidSpans& spans,
  const SurfaceNeighbourhoods& nbh,
  const ViewRays& rays,
  RenderStatistics& stats);

} // namespace raymappers

#endif
