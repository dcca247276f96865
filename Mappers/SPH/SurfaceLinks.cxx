#include "SurfaceLinks.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace raymappers
{
namespace
{
constexpr int DX[4] = { 1, -1, 0, 0 };
constexpr int DY[4] = { 0, 0, 1, -1 };
constexpr std::uint8_t OwnColumn = FluidSpans::OwnColumn;
constexpr double SobelWeight[3] = { 1, 2, 1 };

/// A depth value: pixel index and slot (2k entry, 2k + 1 exit); pixel < 0 when missing.
struct Point
{
  std::ptrdiff_t pixel;
  int slot;
  int i, j;
};

/// The depth value that `pt`'s link in direction `dir` leads to in the neighbour's column;
/// missing when the link stays in its own column.
inline Point follow(const FluidSpans& spans, const Point& pt, int dir)
{
  if (pt.pixel < 0)
  {
    return pt;
  }
  const std::uint8_t link =
    static_cast<std::uint8_t>(spans.links[spans.slot(pt.pixel, pt.slot)] >> (8 * dir));
  if (link & OwnColumn)
  {
    return { -1, 0, 0, 0 };
  }
  const int i = pt.i + DX[dir], j = pt.j + DY[dir];
  return { static_cast<std::ptrdiff_t>(spans.pixel(i, j)), link, i, j };
}

/// The point a steps in x and b in y away (|a|, |b| <= 1): x first, else y first.
inline Point reach(const FluidSpans& spans, const Point& c, int a, int b)
{
  const int dx = a > 0 ? 0 : 1, dy = b > 0 ? 2 : 3;
  if (a == 0 && b == 0)
  {
    return c;
  }
  if (b == 0)
  {
    return follow(spans, c, dx);
  }
  if (a == 0)
  {
    return follow(spans, c, dy);
  }
  const Point viaX = follow(spans, follow(spans, c, dx), dy);
  return viaX.pixel >= 0 ? viaX : follow(spans, follow(spans, c, dy), dx);
}
}

void connectSurfaces(FluidSpans& spans, RenderStatistics& stats)
{
  stats.declareCounter("links_neighbour");
  stats.declareCounter("links_own");
  ScopedPhase phase(stats, "connect");
  const int W = spans.width, H = spans.height;
  spans.links.assign(spans.depth.size(), 0);
  tbb::combinable<std::int64_t> neighbourLinks, ownLinks;
  const float inf = std::numeric_limits<float>::infinity();
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 1),
    [&](const tbb::blocked_range<int>& r)
    {
      std::int64_t& nb = neighbourLinks.local();
      std::int64_t& own = ownLinks.local();
      for (int j = r.begin(); j != r.end(); ++j)
      {
        for (int i = 0; i < W; ++i)
        {
          const std::size_t p = spans.pixel(i, j);
          const int count = spans.count[p];
          for (int dir = 0; dir < 4; ++dir)
          {
            const int ni = i + DX[dir], nj = j + DY[dir];
            const bool inside = ni >= 0 && ni < W && nj >= 0 && nj < H;
            const std::size_t q = inside ? spans.pixel(ni, nj) : 0;
            const int m = inside ? spans.count[q] : 0;
            for (int k = 0; k < count; ++k)
            {
              const float e = spans.entry(p, k), x = spans.exit(p, k);
              const float prevExit = k > 0 ? spans.exit(p, k - 1) : -inf;
              const float nextEntry = k + 1 < count ? spans.entry(p, k + 1) : inf;
              int f = 0;
              while (f < m && spans.exit(q, f) < e)
              {
                ++f;
              }
              std::uint8_t entryLink, exitLink;
              if (f < m && spans.entry(q, f) <= x)
              {
                const bool entryToNeighbour = spans.entry(q, f) > prevExit;
                entryLink = entryToNeighbour ? static_cast<std::uint8_t>(2 * f)
                                             : static_cast<std::uint8_t>(OwnColumn | (2 * k - 1));
                int b = f;
                while (b + 1 < m && spans.entry(q, b + 1) <= x)
                {
                  ++b;
                }
                const bool exitToNeighbour = nextEntry > spans.exit(q, b);
                exitLink = exitToNeighbour ? static_cast<std::uint8_t>(2 * b + 1)
                                           : static_cast<std::uint8_t>(OwnColumn | (2 * k + 2));
                nb += int(entryToNeighbour) + int(exitToNeighbour);
                own += int(!entryToNeighbour) + int(!exitToNeighbour);
              }
              else
              {
                entryLink = static_cast<std::uint8_t>(OwnColumn | (2 * k + 1));
                exitLink = static_cast<std::uint8_t>(OwnColumn | (2 * k));
                own += 2;
              }
              spans.links[spans.slot(p, 2 * k)] |= std::uint32_t(entryLink) << (8 * dir);
              spans.links[spans.slot(p, 2 * k + 1)] |= std::uint32_t(exitLink) << (8 * dir);
            }
          }
        }
      }
    });
  stats.addCounter("links_neighbour", neighbourLinks.combine(std::plus<std::int64_t>()));
  stats.addCounter("links_own", ownLinks.combine(std::plus<std::int64_t>()));
}

void findNeighbourhoods(const FluidSpans& spans,
  SurfaceNeighbourhoods& nbh,
  RenderStatistics& stats)
{
  stats.declareCounter("neighbourhood_bytes");
  ScopedPhase phase(stats, "connect");
  const int W = spans.width, H = spans.height;
  const std::size_t n = static_cast<std::size_t>(W) * H;
  nbh.pointStart.assign(n + 1, 0);
  for (std::size_t p = 0; p < n; ++p)
  {
    nbh.pointStart[p + 1] = nbh.pointStart[p] + 2u * spans.count[p];
  }
  const std::size_t points = nbh.pointStart[n];
  nbh.pixel.resize(points);
  nbh.neighbours.resize(8 * points);
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 1),
    [&](const tbb::blocked_range<int>& r)
    {
      for (int j = r.begin(); j != r.end(); ++j)
      {
        for (int i = 0; i < W; ++i)
        {
          const std::size_t p = spans.pixel(i, j);
          for (int s = 0; s < 2 * spans.count[p]; ++s)
          {
            const std::size_t k = nbh.pointStart[p] + s;
            nbh.pixel[k] = static_cast<std::uint32_t>(p);
            const Point c{ static_cast<std::ptrdiff_t>(p), s, i, j };
            std::int32_t* nb = &nbh.neighbours[8 * k];
            for (int b = -1; b <= 1; ++b)
            {
              for (int a = -1; a <= 1; ++a)
              {
                if (a != 0 || b != 0)
                {
                  const Point q = reach(spans, c, a, b);
                  *nb++ =
                    q.pixel >= 0 ? static_cast<std::int32_t>(nbh.pointStart[q.pixel] + q.slot) : -1;
                }
              }
            }
          }
        }
      }
    });
  stats.addCounter("neighbourhood_bytes", static_cast<std::int64_t>(nbh.bytes()));
}

void smoothSurfaces(FluidSpans& spans,
  const SurfaceNeighbourhoods& nbh,
  const ViewRays& rays,
  double radius,
  int maxIterations,
  RenderStatistics& stats)
{
  stats.declareCounter("filter_iterations");
  stats.declareCounter("filtered_points");
  stats.declareCounter("filter_bytes");
  const bool on = radius > 0 && maxIterations > 0;
  stats.setEffect("smoothing", on);
  if (!on || spans.depth.empty())
  {
    return;
  }
  ScopedPhase phase(stats, "filter");
  const bool perspective = rays.isPerspective();
  const double sigma = rays.pixelSize();
  const std::size_t points = nbh.points();
  std::vector<std::uint8_t> iterationsOf(points), hasPrev(points), hasNext(points);
  std::vector<float> cur(points), next(points);
  stats.addCounter("filter_bytes", static_cast<std::int64_t>(11 * points));
  const auto iterationsAt = [&](float zeta)
  {
    const double width = perspective ? sigma * zeta : sigma;
    return static_cast<int>(
      std::min<double>(std::min(maxIterations, 255), std::ceil(radius / width)));
  };
  const auto slotOf = [&](std::size_t k)
  {
    const std::uint32_t p = nbh.pixel[k];
    return spans.slot(p, static_cast<int>(k - nbh.pointStart[p]));
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points, 4096),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
      {
        const std::uint32_t p = nbh.pixel[k];
        const std::size_t s = k - nbh.pointStart[p];
        const float z = spans.depth[slotOf(k)];
        // Values filtered: 1 / zeta (perspective) or zeta.
        cur[k] = perspective ? 1.f / z : z;
        iterationsOf[k] = static_cast<std::uint8_t>(iterationsAt(z));
        hasPrev[k] = s > 0;
        hasNext[k] = k + 1 < nbh.pointStart[p + 1];
      }
    });
  const int iterations = points ? *std::max_element(iterationsOf.begin(), iterationsOf.end()) : 0;
  // (1 2 1)^T (1 2 1) without the centre, in the neighbours' order.
  static constexpr float Weight[8] = { 1, 2, 1, 2, 2, 1, 2, 1 };
  tbb::combinable<std::int64_t> filtered;
  for (int it = 0; it < iterations; ++it)
  {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points, 4096),
      [&](const tbb::blocked_range<std::size_t>& r)
      {
        std::int64_t& done = filtered.local();
        for (std::size_t k = r.begin(); k != r.end(); ++k)
        {
          if (iterationsOf[k] <= it)
          {
            next[k] = cur[k];
            continue;
          }
          float sum = 4.f * cur[k], wsum = 4.f;
          const std::int32_t* nb = &nbh.neighbours[8 * k];
          for (int m = 0; m < 8; ++m)
          {
            if (nb[m] >= 0)
            {
              sum += Weight[m] * cur[nb[m]];
              wsum += Weight[m];
            }
          }
          // Stay between the column's neighbouring depth values (1/zeta falls with depth).
          float v = sum / wsum;
          if (hasPrev[k])
          {
            v = perspective ? std::min(v, cur[k - 1]) : std::max(v, cur[k - 1]);
          }
          if (hasNext[k])
          {
            v = perspective ? std::max(v, cur[k + 1]) : std::min(v, cur[k + 1]);
          }
          next[k] = v;
          ++done;
        }
      });
    std::swap(cur, next);
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points, 4096),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
      {
        spans.depth[slotOf(k)] = perspective ? 1.f / cur[k] : cur[k];
      }
    });
  stats.addCounter("filter_iterations", iterations);
  stats.addCounter("filtered_points", filtered.combine(std::plus<std::int64_t>()));
}

void computeNormals(FluidSpans& spans,
  const SurfaceNeighbourhoods& nbh,
  const ViewRays& rays,
  RenderStatistics& stats)
{
  stats.declareCounter("normals");
  ScopedPhase phase(stats, "normals");
  const int W = spans.width;
  spans.normals.assign(spans.depth.size(), 0);
  const std::size_t points = nbh.points();
  // Position of point k on its pixel's centre ray.
  const auto position = [&](std::size_t k)
  {
    const std::uint32_t p = nbh.pixel[k];
    const double z = spans.depth[spans.slot(p, static_cast<int>(k - nbh.pointStart[p]))];
    return rays.pointAt(p % W + 0.5, p / W + 0.5, z);
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points, 4096),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
      {
        const std::uint32_t p = nbh.pixel[k];
        const int s = static_cast<int>(k - nbh.pointStart[p]);
        // P[b + 1][a + 1]; a missing point is replaced by the one a step nearer to the
        // centre (edges by the centre, corners by their edge in the same row).
        Vec3d P[3][3];
        bool found[3][3];
        P[1][1] = position(k);
        found[1][1] = true;
        const std::int32_t* nb = &nbh.neighbours[8 * k];
        for (int m = 0, b = 0; b < 3; ++b)
        {
          for (int a = 0; a < 3; ++a)
          {
            if (a != 1 || b != 1)
            {
              found[b][a] = nb[m] >= 0;
              if (found[b][a])
              {
                P[b][a] = position(static_cast<std::size_t>(nb[m]));
              }
              ++m;
            }
          }
        }
        for (const auto& [b, a] : { std::pair{ 1, 0 }, { 1, 2 }, { 0, 1 }, { 2, 1 } })
        {
          if (!found[b][a])
          {
            P[b][a] = P[1][1];
          }
        }
        for (const int b : { 0, 2 })
        {
          for (const int a : { 0, 2 })
          {
            if (!found[b][a])
            {
              P[b][a] = P[b][1];
            }
          }
        }
        Vec3d gx, gy;
        for (int c = 0; c < 3; ++c)
        {
          gx += (P[c][2] - P[c][0]) * SobelWeight[c];
          gy += (P[2][c] - P[0][c]) * SobelWeight[c];
        }
        const Vec3d ray = rays.direction(p % W + 0.5, p / W + 0.5);
        Vec3d n = cross(gx, gy);
        const double len = length(n);
        const bool entry = (s & 1) == 0;
        n = len > 0 && std::isfinite(len) ? n * (1.0 / len) : normalize(ray);
        if ((dot(n, ray) > 0) == entry)
        {
          n = -n;
        }
        spans.normals[spans.slot(p, s)] = encodeNormal(Vec3f(n));
      }
    });
  stats.addCounter("normals", static_cast<std::int64_t>(points));
}

} // namespace raymappers
