// The perspective access structure of Limper 2012 (section 3.4): a grid over the view
// frustum whose cells are pixel tiles in x and y and slabs of depth in z, built anew for
// every view and holding, per cell, the particles whose support reaches into it.
//
// Depth steps (section 3.3): samples sit at logarithmically spaced depths (perspective)
//   zeta(u) = zeta_0 exp(u delta),   delta = tile sigma / samplesPerCell   (equation 3.5)
// so each step is as long as a pixel is wide at that depth and every cell holds the same
// number of samples (equations 3.8, 3.9): a cell is tileSize pixels wide and tileSize sigma
// deep in log-depth (cubic at the view axis), and holds
//   samplesPerCell = ceil(tileSize * lambda / stepFactor)
// samples, lambda the obliquity of the frustum's corner rays (equation 3.4). Parallel views
// take uniform steps (section 3.4.1, "a fixed sampling rate"). The steps' boundaries lie on
// a lattice of depths set by the view alone (equation 3.5 read as zeta_k = zeta_a e^(k
// delta) for every integer k, from a fixed anchor zeta_a; uniform steps at the multiples of
// theirs), and zeta_0 is the last boundary at or before the particles' front (or the near
// plane: the first step then begins there). The thesis starts at the front itself, so two
// sets of particles under one camera (the regions of a distributed render, each with its
// own front) would be sampled at depths shifted by a fraction of a step; on the lattice they
// share every sample. The last cell reaches past the particles' back.
//
// The thesis ties the step to the pixel footprint alone, so the number of samples grows
// with the image resolution, and near the eye (where a pixel is tiny) far beyond the
// detail of the field. With a field step s_f (a fraction of the smallest kernel support)
// the step is the longer of the two: uniform steps of s_f up to the first of their
// boundaries at or beyond zeta* = s_f / (e^delta - 1), where the logarithmic step reaches
// s_f, logarithmic steps beyond (anchored there); the cells keep samplesPerCell samples.
//
// Construction (section 3.4.2), on the CPU: each particle's cell range is the box of its
// exact projected extent (tangent planes, ViewRays::projectedExtent) and its depth span
// [zeta_c - H, zeta_c + H], which is the thesis's six-plane test per candidate cell; the
// map from cells to particles is made by a counting sort (parallel count, prefix sum,
// parallel scatter, each cell's list then sorted so the result does not depend on the
// thread schedule) instead of sorting the pairs. The empty successors cache (section
// 3.4.3) holds, for every empty cell, how many empty cells follow it along z, itself
// included (0 for a cell with particles).
#ifndef RayMappers_PerspectiveGrid_h
#define RayMappers_PerspectiveGrid_h

#include "Mappers/SPH/SPHParticles.h"
#include "Mappers/Common/ViewRays.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace raymappers
{

/// The mapping between sample coordinate u (sample k spans [k, k + 1)) and depth: uniform
/// steps of uniformStep up to the break (coordinate uBreak, depth zetaBreak), then
/// logarithmic steps of log-depth delta (perspective) or uniform steps of delta (parallel).
/// Depths are computed from lattice indices (firstStep + u before the break, firstLogStep +
/// u - uBreak beyond it; integers held exactly in doubles) so that two grids on one lattice
/// (differing in their first step) give the same depth, bit for bit, at each boundary they
/// share.
struct DepthSteps
{
  bool logarithmic = true; // the part beyond the break is logarithmic (perspective)
  double zetaNear = 0.0;   // the view's near plane
  double zetaBase = 0.0;   // depth of lattice index 0 of the uniform part
  double firstStep = 0.0;  // lattice index of coordinate 0 in the uniform part
  double uniformStep = 0.0; // 0: no uniform part (perspective)
  double uBreak = 0.0;
  double zetaBreak = 1.0;    // log part: zeta = zetaBreak e^(n delta), n its lattice index
  double firstLogStep = 0.0; // lattice index of coordinate uBreak in the log part
  double delta = 1.0;
  int samplesPerCell = 16;
  int cells = 0;

  /// The depth of coordinate u, never before the near plane (the first step may begin there).
  double zeta(double u) const
  {
    if (!logarithmic)
    {
      return std::max(zetaNear, zetaBase + (firstStep + u) * delta);
    }
    if (u <= uBreak && uniformStep > 0)
    {
      return std::max(zetaNear, zetaBase + (firstStep + u) * uniformStep);
    }
    return std::max(zetaNear, zetaBreak * std::exp((firstLogStep + u - uBreak) * delta));
  }
  double coordinate(double z) const
  {
    if (!logarithmic)
    {
      return (z - zetaBase) / delta - firstStep;
    }
    if (z <= zetaBreak && uniformStep > 0)
    {
      return (z - zetaBase) / uniformStep - firstStep;
    }
    return z > 0 ? uBreak + std::log(z / zetaBreak) / delta - firstLogStep : -1e30;
  }
  int samples() const { return cells * samplesPerCell; }
};

struct PerspectiveGridParameters
{
  int tileSize = 16;       // pixels per cell side
  double stepFactor = 1.0; // > 0: sample spacing relative to a pixel's footprint
  // > 0: a step that resolves the field (model units, e.g. the smallest support over 8):
  // no step is shorter than this (nor than a pixel's footprint times stepFactor).
  double fieldStep = 0.0;
};

/// What the renderer needs of each particle: its pixel extent (centres of the pixels whose
/// rays can meet the support lie in [x0, x1] x [y0, y1]) and the depth of its centre.
struct ParticleFootprint
{
  float x0, x1, y0, y1;
  float zeta; // depth of the centre
};

class PerspectiveGrid
{
public:
  /// Builds the grid of `particles` for `rays`. Returns false (and an empty grid) when no
  /// particle is in view.
  bool build(const SPHParticles& particles,
    const ViewRays& rays,
    const PerspectiveGridParameters& params);

  int tileSize() const { return TileSize; }
  int tilesX() const { return TilesX; }
  int tilesY() const { return TilesY; }
  const DepthSteps& steps() const { return Steps; }
  std::size_t cellCount() const { return static_cast<std::size_t>(TilesX) * TilesY * Steps.cells; }
  /// Cells of tile column (tx, ty) are contiguous along z.
  std::size_t cellIndex(int tx, int ty, int tz) const
  {
    return (static_cast<std::size_t>(ty) * TilesX + tx) * Steps.cells + tz;
  }
  /// Particles of a cell: refs()[cellStart(c) .. cellStart(c + 1)).
  std::uint32_t cellStart(std::size_t c) const { return CellStart[c]; }
  const std::vector<std::uint32_t>& refs() const { return Refs; }
  /// Empty cells from c on along z, c included; 0 when c holds particles.
  std::uint32_t emptyRun(std::size_t c) const { return EmptyRun[c]; }
  const std::vector<ParticleFootprint>& footprints() const { return Footprints; }
  std::size_t particlesInView() const { return InView; }
  std::size_t memoryBytes() const;

private:
  void sortCellsAndCountEmptyRuns();

  int TileSize = 16, TilesX = 0, TilesY = 0;
  DepthSteps Steps;
  std::vector<std::uint32_t> CellStart; // cellCount() + 1
  std::vector<std::uint32_t> Refs;
  std::vector<std::uint32_t> EmptyRun;
  std::vector<ParticleFootprint> Footprints;
  std::size_t InView = 0;
};

} // namespace raymappers

#endif
