// The particles of an RBF volume (Knoll et al. 2014, section 3.1): each particle i adds the
// truncated Gaussian
//   phi_i(x) = kappa k_i exp(-d_i(x)^2 / (2 r_i^2))   for d_i(x) <= sigma r_i, else 0
// to the field Phi of its field (a category such as an atom type; section 5.5), with
// d_i(x) = |x - x_i|. Centres are stored relative to an origin (float precision near the
// data). kappa and sigma are render parameters, not stored: changing them rebuilds nothing.
// Invalid input (non-finite centre or value, radius not finite or not positive) is dropped
// while building and counted.
#ifndef RayMappers_RBFParticles_h
#define RayMappers_RBFParticles_h

#include "Mappers/Common/ParticleInput.h"
#include "Mappers/Common/Vec3.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace raymappers
{

constexpr int MaxRBFFields = 4;

struct RBFParticles
{
  Vec3d origin;
  std::vector<Vec3f> centers;       // relative to origin
  std::vector<float> radii;         // r_i > 0
  std::vector<float> values;        // k_i
  std::vector<std::uint8_t> fields; // field index in [0, numFields)
  int numFields = 1;
  float maxRadius = 0.f;
  std::size_t skippedNonFinite = 0; // NaN/Inf centre, or a value not finite as float
  std::size_t skippedBadRadius = 0; // radius NaN/Inf, zero, negative or above MaxLength

  std::size_t size() const { return centers.size(); }
};

/// Builds `out` from n input points in parallel: point(i) -> Vec3d, radius(i) -> double,
/// value(i) -> double, field(i) -> int in [0, numFields) (called from several threads).
template<typename PointFn, typename RadiusFn, typename ValueFn, typename FieldFn>
void buildRBFParticles(std::size_t n,
  const Vec3d& origin,
  int numFields,
  PointFn point,
  RadiusFn radius,
  ValueFn value,
  FieldFn field,
  RBFParticles& out)
{
  out.origin = origin;
  out.numFields = std::clamp(numFields, 1, MaxRBFFields);
  out.centers.resize(n);
  out.radii.resize(n);
  out.values.resize(n);
  out.fields.resize(n);
  // Every point goes to its own slot; an invalid one gets radius 0 and is compacted away.
  const ParticleTally tally = tallyParticles(n,
    [&](std::size_t i, ParticleTally& t)
    {
      const Vec3d p = point(i);
      const double k = value(i);
      const float rf = t.admit(p, finiteAsFloat(k), isFinite(p) ? radius(i) : 0.0);
      out.centers[i] = rf > 0.f ? Vec3f(p - origin) : Vec3f();
      out.radii[i] = rf;
      out.values[i] = rf > 0.f ? static_cast<float>(k) : 0.f;
      out.fields[i] =
        static_cast<std::uint8_t>(std::clamp(rf > 0.f ? field(i) : 0, 0, out.numFields - 1));
    });
  out.skippedNonFinite = tally.nonFinite;
  out.skippedBadRadius = tally.badRadius;
  out.maxRadius = tally.maxRadius;
  dropSkipped(tally, out.radii, out.centers, out.radii, out.values, out.fields);
}

} // namespace raymappers

#endif
