// A fluid coloured per particle (a colour array through a lookup table): the colour of the
// fluid at a point is the normalized SPH interpolation of the particles' colours.
//
// Zirr and Dachsbacher's media are homogeneous (section 6 names particles with scalar
// attributes as future work), so the colour is taken where the voxelization has a point of
// the fluid: its front surface. At a point x the colour is the normalized interpolation
// (Limper 2012, section 3.5, equation 3.14; as vtkSPHVolumeMapper's field)
//   C(x) = sum_i C_i V_i W(|x - x_i|, H_i) / sum_i V_i W(|x - x_i|, H_i)
// with the Wendland C2 kernel W = 21/(2 pi H^3) (1 - q)^4 (1 + 4q), q = |x - x_i| / H_i
// (SPHKernels.h), of support H_i = 2 r_i (r_i the sphere's radius, the particle spacing by
// default: the support reaches the second neighbours), and the sphere's volume
// V_i = 4/3 pi r_i^3. V_i W is then (7/4) (1 - q)^4 (1 + 4q) for every radius: the weight of
// a particle depends only on q. A point of the union of spheres lies within r_i of some x_i
// (q <= 1/2, weight >= (1/2)^4 3 > 0), so the sum never vanishes there; where it does (a
// point more than 2 r_max from every particle, which only smoothing could make) the colour
// is the solid one.
//
// Search: the particles sorted by the cells of a grid of size 2 r_max; the cells are listed
// in key order and found by binary search, so memory is O(particles) however sparse the data.
// The 27 cells around x's cell hold every particle whose support reaches x.
#ifndef RayMappers_FluidColors_h
#define RayMappers_FluidColors_h

#include "Mappers/Common/Vec3.h"
#include "Mappers/SPH/FluidParticles.h"

#include <cstdint>
#include <vector>

namespace raymappers
{

struct FluidColors
{
  std::vector<Vec3f> color;         // C_i, in FluidParticles order; empty: not coloured
  double cellSize = 0;              // 2 r_max
  std::vector<std::uint64_t> keys;  // the occupied cells' keys, ascending
  std::vector<std::uint32_t> start; // cell k's particles are order[start[k], start[k + 1])
  std::vector<std::uint32_t> order; // particle indices sorted by cell

  bool empty() const { return color.empty(); }
};

/// Colours every particle of `particles` with colorOf(sourceId) -> Vec3d (rgb in [0, 1]) and
/// sorts them into the search cells.
template<typename ColorFn>
void buildFluidColors(const FluidParticles& particles, ColorFn colorOf, FluidColors& out);

/// Sorts the particles into the search cells of `out` (its colours already set).
void indexFluidColors(const FluidParticles& particles, FluidColors& out);

/// C(x) at the origin-relative point x (the file comment); `solid` where no support reaches.
/// Adds the particles visited to `visited`.
Vec3d fluidColorAt(const FluidParticles& particles,
  const FluidColors& colors,
  const Vec3d& x,
  const Vec3d& solid,
  std::int64_t& visited);

template<typename ColorFn>
void buildFluidColors(const FluidParticles& particles, ColorFn colorOf, FluidColors& out)
{
  out.color.resize(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i)
  {
    out.color[i] = Vec3f(colorOf(particles.sourceIds[i]));
  }
  indexFluidColors(particles, out);
}

} // namespace raymappers

#endif
