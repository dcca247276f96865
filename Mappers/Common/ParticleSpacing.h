// The typical spacing of a particle set, the length every data-derived default (a sphere
// radius, a smoothing length, a fluid's absorption per radius) is measured in, so that the
// same data in other units gives the same picture.
//
// Definition: the median, over a deterministic sample of up to `sampleSize` finite
// particles (evenly strided indices; the pieces of a set on several processes sample their
// shares and gather the distances: spacingSampleDistances), of each sampled
// particle's distance to its nearest distinct particle of the whole set (coincident points
// do not count as neighbours). The median, not the mean: on a
// clustered set (a galaxy halo) the few particles of the sparse outskirts have neighbours
// hundreds of times farther than the core's and would dominate a mean.
//
// Method (O(N) per pass, O(sampleSize) memory, no copy of the points):
//  1. a first guess g from the sample alone: the median nearest-neighbour distance within
//     the sample times (m / N)^(1/3), the scaling of the nearest-neighbour distance with
//     the number density (a Poisson set's mean distance is 0.554 n^(-1/3));
//  2. a search radius R = 2 g; each sample point registers the cells of side 2R its ball of
//     radius R touches (at most 8); one pass over all N points looks each point's cell up
//     (a bit filter first, then a sorted key list) and measures only the sample points
//     registered there, so every neighbour within R of a sample point is seen;
//  3. when half the samples or more found no neighbour within R, R grows 4-fold and the
//     pass repeats: the median is then exact, since every unfound distance exceeds R.
#ifndef RayMappers_ParticleSpacing_h
#define RayMappers_ParticleSpacing_h

#include "Mappers/Common/Vec3.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace raymappers
{

namespace spacingdetail
{
/// A 64-bit key of an integer cell (a hash: a collision only adds a distance test).
inline std::uint64_t cellKey(std::int64_t x, std::int64_t y, std::int64_t z)
{
  std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull;
  h ^= static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
  h ^= static_cast<std::uint64_t>(z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
  return h;
}

/// The integer cell of side `cell` holding p, false when a coordinate's cell index would not
/// fit in 62 bits (such a point is farther than any search radius from the sample).
inline bool cellOf(const Vec3d& p, double cell, std::array<std::int64_t, 3>& index)
{
  const double limit = 4.0e18;
  const double t[3] = { std::floor(p.x / cell), std::floor(p.y / cell), std::floor(p.z / cell) };
  for (int a = 0; a < 3; ++a)
  {
    if (!(std::fabs(t[a]) < limit))
    {
      return false;
    }
    index[a] = static_cast<std::int64_t>(t[a]);
  }
  return true;
}

inline bool finitePoint(const Vec3d& p)
{
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

inline double median(std::vector<double> values)
{
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  return values[mid];
}

/// Step 1: the sample's own median nearest-neighbour distance scaled to the full density.
inline double firstGuess(const std::vector<Vec3d>& sample, std::size_t total)
{
  std::vector<double> nearest;
  for (std::size_t i = 0; i < sample.size(); ++i)
  {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < sample.size(); ++j)
    {
      const double d = length(sample[i] - sample[j]);
      if (d > 0.0)
      {
        best = std::min(best, d);
      }
    }
    if (std::isfinite(best))
    {
      nearest.push_back(best);
    }
  }
  if (nearest.empty())
  {
    return 0.0;
  }
  return median(nearest) *
         std::cbrt(static_cast<double>(sample.size()) / static_cast<double>(total));
}
} // namespace spacingdetail

/// Steps 2 and 3 for `sample`: each sample point's nearest-distinct-neighbour distance among
/// the `count` points, +infinity for those with none within the final search radius (fewer
/// than half of them); empty when no search radius could be set.
template <typename PointAt>
std::vector<double> sampleNeighbourDistances(
  std::size_t count, PointAt pointAt, const std::vector<Vec3d>& sample)
{
  using namespace spacingdetail;
  double radius = 2.0 * firstGuess(sample, count);
  if (!(radius > 0.0) || !std::isfinite(radius))
  {
    return {};
  }
  constexpr std::size_t FilterBits = 1u << 16;
  for (int pass = 0; pass < 24; ++pass)
  {
    // Step 2: register each sample point in the cells (side 2R) its R-ball touches.
    const double cell = 2.0 * radius;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> registered;
    std::vector<std::uint64_t> filter(FilterBits / 64, 0);
    for (std::size_t s = 0; s < sample.size(); ++s)
    {
      std::array<std::int64_t, 3> lo;
      if (!cellOf(sample[s] - Vec3d(radius, radius, radius), cell, lo))
      {
        continue;
      }
      for (int c = 0; c < 8; ++c)
      {
        const std::uint64_t key = cellKey(lo[0] + (c & 1), lo[1] + ((c >> 1) & 1), lo[2] + (c >> 2));
        registered.emplace_back(key, static_cast<std::uint32_t>(s));
        filter[(key % FilterBits) / 64] |= 1ull << (key % 64);
      }
    }
    std::sort(registered.begin(), registered.end());
    registered.erase(std::unique(registered.begin(), registered.end()), registered.end());
    std::vector<double> best(sample.size(), std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < count; ++i)
    {
      const Vec3d p = pointAt(i);
      std::array<std::int64_t, 3> at;
      if (!finitePoint(p) || !cellOf(p, cell, at))
      {
        continue;
      }
      const std::uint64_t key = cellKey(at[0], at[1], at[2]);
      if (!(filter[(key % FilterBits) / 64] >> (key % 64) & 1))
      {
        continue;
      }
      auto it = std::lower_bound(registered.begin(), registered.end(), std::make_pair(key, 0u));
      for (; it != registered.end() && it->first == key; ++it)
      {
        const double d = length(p - sample[it->second]);
        if (d > 0.0 && d <= radius)
        {
          best[it->second] = std::min(best[it->second], d);
        }
      }
    }
    // Step 3: the median is exact once more than half the samples found a neighbour.
    const std::size_t found = static_cast<std::size_t>(std::count_if(
      best.begin(), best.end(), [](double d) { return std::isfinite(d); }));
    if (2 * found > best.size())
    {
      return best;
    }
    radius *= 4.0;
    if (!std::isfinite(radius * 4.0))
    {
      break;
    }
  }
  return {};
}

/// The sample's nearest-neighbour distances (sampleNeighbourDistances) for `count` points
/// given by pointAt(i) -> Vec3d, the sample being up to `sampleSize` of them at evenly
/// strided indices (each the next finite point): deterministic, and the same for the set in
/// other units. The `count` points may be one process's piece of a larger set, sampled in
/// proportion to its share (then each neighbour is sought among the piece's own points: a
/// sample point whose nearest neighbour lies in another piece measures a farther one).
/// Empty when there is no sample or no search radius.
template <typename PointAt>
std::vector<double> spacingSampleDistances(
  std::size_t count, PointAt pointAt, std::size_t sampleSize = 1024)
{
  std::vector<Vec3d> sample;
  const std::size_t m = std::min(count, sampleSize);
  for (std::size_t k = 0; k < m; ++k)
  {
    for (std::size_t i = (2 * k + 1) * count / (2 * m); i < count; ++i)
    {
      const Vec3d p = pointAt(i);
      if (spacingdetail::finitePoint(p))
      {
        sample.push_back(p);
        break;
      }
    }
  }
  return sample.empty() ? std::vector<double>() : sampleNeighbourDistances(count, pointAt, sample);
}

/// The median of sample distances (of one set, or gathered from its pieces): 0 when there
/// are none or when the median is not finite (half of them found no neighbour).
inline double medianSpacing(const std::vector<double>& distances)
{
  if (distances.empty())
  {
    return 0.0;
  }
  const double m = spacingdetail::median(distances);
  return std::isfinite(m) ? m : 0.0;
}

/// The median nearest-neighbour distance described above, for `count` points given by
/// pointAt(i) -> Vec3d; 0 when fewer than two distinct finite points exist.
template <typename PointAt>
double typicalParticleSpacing(std::size_t count, PointAt pointAt, std::size_t sampleSize = 1024)
{
  return medianSpacing(spacingSampleDistances(count, pointAt, sampleSize));
}

} // namespace raymappers

#endif
