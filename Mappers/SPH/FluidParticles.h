// The particles of a fluid for the voxelizer (Zirr 2015, section 3.1): spheres of radius
// r_i (one constant radius or one per particle) around centres stored relative to an
// origin (float precision near the data). Invalid input (a non-finite centre; a radius
// not finite or not positive) is dropped while building and counted, the rest kept in
// input order, each with the index of its input point (sourceIds: its colour's source).
#ifndef RayMappers_FluidParticles_h
#define RayMappers_FluidParticles_h

#include "Mappers/Common/ParticleInput.h"
#include "Mappers/Common/Vec3.h"

#include <cstdint>
#include <vector>

namespace raymappers
{

struct FluidParticles
{
  Vec3d origin;
  std::vector<Vec3f> centers;           // relative to origin
  std::vector<float> radius;            // r_i > 0
  std::vector<std::uint32_t> sourceIds; // the input point of each particle
  float maxRadius = 0.f;
  double meanRadius = 0.0; // the mean r_i of the particles kept: the unit of relative lengths
  std::size_t skippedNonFinite = 0; // NaN/Inf centre
  std::size_t skippedBadRadius = 0; // radius NaN/Inf, zero, negative or above MaxLength

  std::size_t size() const { return centers.size(); }
};

/// Builds `out` from n input points in parallel: point(i) -> Vec3d, radius(i) -> double;
/// both are called from several threads.
template<typename PointFn, typename RadiusFn>
void buildFluidParticles(std::size_t n,
  const Vec3d& origin,
  PointFn point,
  RadiusFn radius,
  FluidParticles& out)
{
  out.origin = origin;
  out.centers.resize(n);
  out.radius.resize(n);
  out.sourceIds.resize(n);
  const ParticleTally tally = tallyParticles(n,
    [&](std::size_t i, ParticleTally& t)
    {
      const Vec3d p = point(i);
      const float r = t.admit(p, true, isFinite(p) ? radius(i) : 0.0);
      out.centers[i] = r > 0.f ? Vec3f(p - origin) : Vec3f();
      out.radius[i] = r;
      out.sourceIds[i] = static_cast<std::uint32_t>(i);
    });
  out.skippedNonFinite = tally.nonFinite;
  out.skippedBadRadius = tally.badRadius;
  out.maxRadius = tally.maxRadius;
  dropSkipped(tally, out.radius, out.centers, out.sourceIds, out.radius);
  double sum = 0.0;
  for (const float r : out.radius)
  {
    sum += r;
  }
  out.meanRadius = out.radius.empty() ? 0.0 : sum / static_cast<double>(out.radius.size());
}

} // namespace raymappers

#endif
