// The spheres a glyph renderer traces: centres relative to an origin (float precision near
// the data), radii, and one packed RGBA8 colour each. Invalid input (non-finite centre,
// non-finite / zero / negative radius) is dropped while building and counted.
#ifndef RayMappers_SphereSet_h
#define RayMappers_SphereSet_h

#include "Mappers/Common/ParticleInput.h"
#include "Mappers/Common/Vec3.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace raymappers
{

constexpr int MaxRangeAttributes = 4;

/// Parameter-range culling (Gribble et al., section 4.3): a sphere is drawn only when each
/// of its first `count` attributes lies in [lo, hi] (a NaN attribute never does).
struct RangeFilter
{
  int count = 0; // 0: no culling
  float lo[MaxRangeAttributes] = { 0, 0, 0, 0 };
  float hi[MaxRangeAttributes] = { 0, 0, 0, 0 };

  bool passes(const float* values) const
  {
    for (int a = 0; a < count; ++a)
    {
      if (!(values[a] >= lo[a] && values[a] <= hi[a]))
      {
        return false;
      }
    }
    return true;
  }
  /// Whether some value of [mn, mx] per attribute can pass (mn > mx: no value at all).
  bool overlaps(const float* mn, const float* mx) const
  {
    for (int a = 0; a < count; ++a)
    {
      if (!(mx[a] >= lo[a] && mn[a] <= hi[a]))
      {
        return false;
      }
    }
    return true;
  }
};

struct SphereSet
{
  Vec3d origin;
  std::vector<Vec3f> centers; // relative to origin
  std::vector<float> radii;
  std::vector<std::uint32_t> colors;    // RGBA8, red in the low byte
  std::vector<std::uint32_t> sourceIds; // the input point of each sphere
  int numAttributes = 0;                // values per sphere for range culling (<= 4)
  std::vector<float> attributes;        // numAttributes per sphere, interleaved
  /// Opacity per sphere in [0, 1] (its own array mapped through its transfer function);
  /// empty: every sphere has opacity 1 (the renderer's global opacity still applies).
  std::vector<float> opacities;

  const float* attributesOf(std::size_t i) const
  {
    return attributes.data() + i * static_cast<std::size_t>(numAttributes);
  }
  float maxRadius = 0.f;
  std::size_t skippedNonFinite = 0; // centres with NaN/Inf
  std::size_t skippedBadRadius = 0; // radius NaN/Inf, zero, negative or above MaxLength

  std::size_t size() const { return centers.size(); }
};

inline std::uint32_t packRGBA8(unsigned r, unsigned g, unsigned b, unsigned a)
{
  return r | (g << 8) | (b << 16) | (a << 24);
}

/// Builds `out` from n input points, in parallel: point(i) -> Vec3d centre, radius(i) ->
/// double, color(i) -> uint32 RGBA8 (all three are called from several threads at once).
/// The vectors of `out` keep their capacity, so a new time step reuses the memory.
template<typename PointFn, typename RadiusFn, typename ColorFn>
void buildSphereSet(std::size_t n,
  const Vec3d& origin,
  PointFn point,
  RadiusFn radius,
  ColorFn color,
  SphereSet& out)
{
  out.origin = origin;
  out.numAttributes = 0;
  out.attributes.clear();
  out.opacities.clear();
  out.centers.resize(n);
  out.radii.resize(n);
  out.colors.resize(n);
  out.sourceIds.resize(n);
  // Each point goes to its own slot; an invalid one gets radius 0 and is compacted away
  // below (valid radii are positive).
  const ParticleTally tally = tallyParticles(n,
    [&](std::size_t i, ParticleTally& t)
    {
      const Vec3d p = point(i);
      const float rf = t.admit(p, true, isFinite(p) ? radius(i) : 0.0);
      out.centers[i] = rf > 0.f ? Vec3f(p - origin) : Vec3f();
      out.radii[i] = rf;
      out.colors[i] = rf > 0.f ? color(i) : 0u;
      out.sourceIds[i] = static_cast<std::uint32_t>(i);
    });
  out.skippedNonFinite = tally.nonFinite;
  out.skippedBadRadius = tally.badRadius;
  out.maxRadius = tally.maxRadius;
  dropSkipped(tally, out.radii, out.centers, out.radii, out.colors, out.sourceIds);
}

/// Sets every sphere's opacity to opacity(sourceId), clamped to [0, 1] (NaN: 0, the
/// sphere not drawn), in parallel; returns how many were NaN.
template<typename OpacityFn>
std::size_t setSphereOpacities(SphereSet& s, OpacityFn opacity)
{
  s.opacities.resize(s.size());
  return tbb::parallel_reduce(
    tbb::blocked_range<std::size_t>(0, s.size(), 16384),
    std::size_t(0),
    [&](const tbb::blocked_range<std::size_t>& range, std::size_t nan)
    {
      for (std::size_t i = range.begin(); i != range.end(); ++i)
      {
        const double a = opacity(s.sourceIds[i]);
        nan += std::isnan(a) ? 1 : 0;
        s.opacities[i] = std::isnan(a) ? 0.f : static_cast<float>(std::clamp(a, 0.0, 1.0));
      }
      return nan;
    },
    [](std::size_t x, std::size_t y) { return x + y; });
}

/// Sets `count` attributes per sphere from value(sourceId, a), in parallel.
template<typename ValueFn>
void setSphereAttributes(SphereSet& s, int count, ValueFn value)
{
  s.numAttributes = count;
  s.attributes.resize(s.size() * static_cast<std::size_t>(count));
  if (count == 0)
  {
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.size(), 16384),
    [&](const tbb::blocked_range<std::size_t>& range)
    {
      for (std::size_t i = range.begin(); i != range.end(); ++i)
      {
        for (int a = 0; a < count; ++a)
        {
          s.attributes[i * count + a] = static_cast<float>(value(s.sourceIds[i], a));
        }
      }
    });
}

} // namespace raymappers

#endif
