// What the particle kernels share when they take points from the user: each point is
// checked (finite centre and value, a radius in (0, MaxLength]), the checks of all points are
// tallied in parallel, and the points that fail are removed afterwards by a stable
// compaction, so the kept points stay in input order.
#ifndef RayMappers_ParticleInput_h
#define RayMappers_ParticleInput_h

#include "Mappers/Common/Limits.h"
#include "Mappers/Common/Vec3.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace raymappers
{

/// Whether a value stays finite once stored as float (a finite double beyond 3.4e38 does
/// not; NaN and infinity do not either).
inline bool finiteAsFloat(double v)
{
  return std::fabs(v) <= static_cast<double>(std::numeric_limits<float>::max());
}

struct ParticleTally
{
  std::size_t nonFinite = 0; // NaN/Inf centre or value
  std::size_t badRadius = 0; // radius NaN/Inf, zero, negative or above MaxLength
  float maxRadius = 0.f;

  /// The radius to store for a point: r as float when the point is valid, else 0 (and the
  /// reason is counted).
  float admit(const Vec3d& center, bool valueFinite, double r)
  {
    if (!isFinite(center) || !valueFinite)
    {
      ++nonFinite;
      return 0.f;
    }
    if (!(r > 0.0) || !(r <= MaxLength))
    {
      ++badRadius;
      return 0.f;
    }
    const float rf = static_cast<float>(r);
    maxRadius = std::max(maxRadius, rf);
    return rf;
  }
  std::size_t skipped() const { return nonFinite + badRadius; }
};

/// Calls visit(i, tally) for every i in [0, n) in parallel and returns the summed tally.
template<typename Visit>
ParticleTally tallyParticles(std::size_t n, Visit visit)
{
  return tbb::parallel_reduce(
    tbb::blocked_range<std::size_t>(0, n, 16384),
    ParticleTally(),
    [&](const tbb::blocked_range<std::size_t>& range, ParticleTally t)
    {
      for (std::size_t i = range.begin(); i != range.end(); ++i)
      {
        visit(i, t);
      }
      return t;
    },
    [](ParticleTally a, const ParticleTally& b)
    {
      a.nonFinite += b.nonFinite;
      a.badRadius += b.badRadius;
      a.maxRadius = std::max(a.maxRadius, b.maxRadius);
      return a;
    });
}

/// Keeps the entries i of every vector for which keep(i), in order, and shrinks them.
template<typename Keep, typename... Vectors>
void compactStable(std::size_t n, Keep keep, Vectors&... vectors)
{
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (keep(i))
    {
      ((vectors[kept] = vectors[i]), ...);
      ++kept;
    }
  }
  (vectors.resize(kept), ...);
}

/// Drops the particles a tally skipped (ParticleTally::admit gave them radius 0) from every
/// vector, the others kept in input order; `radii`, one of `vectors`, tells which (entry i
/// is read before any write reaches it: writes go to kept <= i).
template<typename... Vectors>
void dropSkipped(const ParticleTally& tally, const std::vector<float>& radii, Vectors&... vectors)
{
  if (tally.skipped() > 0)
  {
    compactStable(
      radii.size(), [&](std::size_t i) { return radii[i] > 0.f; }, vectors...);
  }
}

} // namespace raymappers

#endif
