#include "Mappers/SPH/FluidColors.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace raymappers
{
namespace
{
/// Cell coordinates biased to be non-negative, 21 bits each, packed into one key.
constexpr std::int64_t CellBias = 1 << 20;

std::int64_t cellCoordinate(double v, double cellSize)
{
  const double c = std::floor(v / cellSize);
  return static_cast<std::int64_t>(std::clamp(c, -double(CellBias), double(CellBias - 1)));
}

std::uint64_t cellKey(std::int64_t i, std::int64_t j, std::int64_t k)
{
  return (static_cast<std::uint64_t>(i + CellBias) << 42) |
         (static_cast<std::uint64_t>(j + CellBias) << 21) |
         static_cast<std::uint64_t>(k + CellBias);
}

std::uint64_t keyOf(const Vec3d& x, double cellSize)
{
  return cellKey(
    cellCoordinate(x.x, cellSize), cellCoordinate(x.y, cellSize), cellCoordinate(x.z, cellSize));
}
}

void indexFluidColors(const FluidParticles& particles, FluidColors& out)
{
  const std::size_t n = particles.size();
  out.cellSize = 2.0 * particles.maxRadius;
  std::vector<std::uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    key[i] = keyOf(Vec3d(particles.centers[i]), out.cellSize);
  }
  out.order.resize(n);
  std::iota(out.order.begin(), out.order.end(), 0u);
  std::sort(out.order.begin(),
    out.order.end(),
    [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  out.keys.clear();
  out.start.clear();
  for (std::size_t s = 0; s < n; ++s)
  {
    if (s == 0 || key[out.order[s]] != out.keys.back())
    {
      out.keys.push_back(key[out.order[s]]);
      out.start.push_back(static_cast<std::uint32_t>(s));
    }
  }
  out.start.push_back(static_cast<std::uint32_t>(n));
}

Vec3d fluidColorAt(const FluidParticles& particles,
  const FluidColors& colors,
  const Vec3d& x,
  const Vec3d& solid,
  std::int64_t& visited)
{
  if (colors.empty() || !(colors.cellSize > 0))
  {
    return solid;
  }
  const std::int64_t ci = cellCoordinate(x.x, colors.cellSize);
  const std::int64_t cj = cellCoordinate(x.y, colors.cellSize);
  const std::int64_t ck = cellCoordinate(x.z, colors.cellSize);
  Vec3d sum;
  double weights = 0;
  for (std::int64_t i = ci - 1; i <= ci + 1; ++i)
    for (std::int64_t j = cj - 1; j <= cj + 1; ++j)
      for (std::int64_t k = ck - 1; k <= ck + 1; ++k)
      {
        const auto cell =
          std::lower_bound(colors.keys.begin(), colors.keys.end(), cellKey(i, j, k));
        if (cell == colors.keys.end() || *cell != cellKey(i, j, k))
        {
          continue;
        }
        const std::size_t c = static_cast<std::size_t>(cell - colors.keys.begin());
        for (std::uint32_t s = colors.start[c]; s < colors.start[c + 1]; ++s)
        {
          const std::uint32_t p = colors.order[s];
          // V_i W(|x - x_i|, 2 r_i) up to the constant 7/4: (1 - q)^4 (1 + 4q), q < 1.
          const double q = length(x - Vec3d(particles.centers[p])) / (2.0 * particles.radius[p]);
          ++visited;
          if (q < 1.0)
          {
            const double a = (1.0 - q) * (1.0 - q);
            const double w = a * a * (1.0 + 4.0 * q);
            sum += Vec3d(colors.color[p]) * w;
            weights += w;
          }
        }
      }
  return weights > 0 ? sum * (1.0 / weights) : solid;
}

} // namespace raymappers
