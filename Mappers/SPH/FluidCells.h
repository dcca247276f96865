// Boundary-cell culling for the voxelizer (Zirr 2015, sections 3.1 and 4.3): a uniform
// grid over the fluid's particles sorts them into cells; particles in full *inner* cells
// (full cells whose 26 neighbours are all full) add nothing to the fluid's surfaces, so
// they are left out of the splat, and the full cells are filled as boxes instead.
//
// Full cells. The paper takes fullness from the simulation's constraints (an incompressible
// fluid's cell holds at most so many particles). A visualization gets no such guarantee, so
// fullness is proven on the union of spheres U = union_i B(c_i, r_i) itself: a cell is full
// when its box is split into sub-cubes (adaptively, at most 4 halvings) each of which lies
// inside one sphere of a particle of the cell or of its 26 neighbours. The test is
// conservative: a cell it cannot prove covered is not full (and keeps its particles).
//
// Why the culling leaves U unchanged. Let the cell size be s >= r_max. Every full cell's box
// lies in U and is filled. A particle of an inner cell C has its sphere inside the 3 x 3 x 3
// block of cells around C (its centre is in C and r <= s), every one of them full and filled:
// dropping it loses nothing, and the filled boxes add nothing outside U. So U, and with it
// every span, entry and exit, is unchanged. (Filling only the inner cells would not do: a full
// cell at the boundary may owe its coverage to a neighbour's particle that was culled.)
//
// Column skipping (4.3). The filled boxes are splatted as one depth interval per pixel (the
// ray's entry into and exit from the box), so the voxels of the fluid's interior cost one
// ranged bit fill per pixel and box rather than one per particle; the full cells are merged
// greedily into large boxes (runs along x, grown into rectangles along y and boxes along z). Compression then walks the columns word by
// word, 64 layers a step, so full and empty stretches are skipped at that rate.
//
// Order. The kept particles are listed cell by cell in Morton order of the cells, so the
// particles one thread splats in a row are neighbours in space and in the image: their
// columns share cache lines.
#ifndef RayMappers_FluidCells_h
#define RayMappers_FluidCells_h

#include "Mappers/SPH/FluidParticles.h"
#include "Mappers/Common/Vec3.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace raymappers
{

/// An axis-aligned box, origin-relative like FluidParticles::centers.
struct FluidBox
{
  Vec3f lo, hi;
};

struct FluidCells
{
  double cellSize = 0;
  std::vector<std::uint32_t> kept; // particle indices to splat, cell by cell in Morton order
  std::vector<FluidBox> boxes;     // the full cells, merged greedily into boxes
  std::size_t occupiedCells = 0;
  std::size_t fullCells = 0;
  std::size_t innerCells = 0;
  std::size_t culledParticles = 0;
};

/// Sorts `particles` into cells of size max(cellSize, r_max) (cellSize <= 0: 2 r_max) and, when
/// `cull`, leaves out the particles of full inner cells and lists the full cells as boxes. Without
/// `cull` every particle is kept (in Morton order) and there are no boxes.
void buildFluidCells(const FluidParticles& particles, double cellSize, bool cull, FluidCells& out);

} // namespace raymappers

#endif
