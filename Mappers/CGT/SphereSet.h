// The spheres a glyph renderer traces: centres relative to an origin (float precision near
// the data), radii, and one packed RGBA8 colour each. Invalid input (non-finite centre,
// non-finite / zero / negative radius) is dropped while building and counted.
#ifndef RayMappers_SphereSet_h
#define RayMappers_SphereSet_h

#include "Vec3.h"

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

  const float* attributesOf(std::size_t i) const
  {
    return attributes.data() + i * static_cast<std::size_t>(numAttributes);
  }
  float maxRadius = 0.f;
  std::size_t skippedNonFinite = 0; // centres with NaN/Inf
  std::size_t skippedBadRadius = 0; // radius NaN/Inf, zero or negative

  std::size_t size() const { return centers.size(); }
};

inline std::uint32_t packRGBA8(unsigned r, unsigned g, unsigned b, unsigned a)
{
  return r | (g << 8) | (b << 16) | (a << 24);
}

/// Builds `out` from n input points. point(i) -> Vec3d centre, radius(i) -> double,
/// color(i) -> uint32 RGBA8.
template<typename PointFn, typename RadiusFn, typename ColorFn>
void buildSphereSet(std::size_t n,
  const Vec3d& origin,
  PointFn point,
  RadiusFn radius,
  ColorFn color,
  SphereSet& out)
{
  out = SphereSet();
  out.origin = origin;
  out.centers.reserve(n);
  out.radii.reserve(n);
  out.colors.reserve(n);
  out.sourceIds.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const Vec3d p = point(i);
    if (!isFinite(p))
    {
      ++out.skippedNonFinite;
      continue;
    }
    const double r = radius(i);
    if (!(r > 0.0) || !std::isfinite(r))
    {
      ++out.skippedBadRadius;
      continue;
    }
    out.centers.emplace_back(p - origin);
    out.radii.push_back(static_cast<float>(r));
    out.colors.push_back(color(i));
    out.sourceIds.push_back(static_cast<std::uint32_t>(i));
    out.maxRadius = std::max(out.maxRadius, static_cast<float>(r));
  }
}

/// Sets `count` attributes per sphere from value(sourceId, a).
template<typename ValueFn>
void setSphereAttributes(SphereSet& s, int count, ValueFn value)
{
  s.numAttributes = count;
  s.attributes.resize(s.size() * static_cast<std::size_t>(count));
  for (std::size_t i = 0; i < s.size(); ++i)
  {
    for (int a = 0; a < count; ++a)
    {
      s.attributes[i * count + a] = static_cast<float>(value(s.sourceIds[i], a));
    }
  }
}

} // namespace raymappers

#endif
