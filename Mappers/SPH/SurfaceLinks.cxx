#include "Mappers/SPH/SurfaceLinks.h"

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

/// The links of span k of pixel p towards one neighbour column q holding m spans (Listing 1):
/// e to the front entry of the overlapping neighbour spans (or, when that neighbour span also
/// overlaps the previous span, to the previous exit: a bubble wall), x to their back exit (or
/// to the next entry), or, when no neighbour span overlaps (a boundary span, figure 3c), e and
/// x to each other. `neighbour` counts the links that leave the column, `own` the others.
struct SpanLinks
{
  std::uint8_t entry, exit;
  int neighbour, own;
};

SpanLinks linkSpan(const FluidSpans& spans, std::size_t p, int k, int count, std::size_t q, int m)
{
  const float inf = std::numeric_limits<float>::infinity();
  const float e = spans.entry(p, k), x = spans.exit(p, k);
  const float prevExit = k > 0 ? spans.exit(p, k - 1) : -inf;
  const float nextEntry = k + 1 < count ? spans.entry(p, k + 1) : inf;
  int f = 0;
  while (f < m && spans.exit(q, f) < e)
  {
    ++f;
  }
  if (!(f < m && spans.entry(q, f) <= x))
  {
    return { static_cast<std::uint8_t>(OwnColumn | (2 * k + 1)),
      static_cast<std::uint8_t>(OwnColumn | (2 * k)),
      0,
      2 };
  }
  const bool entryToNeighbour = spans.entry(q, f) > prevExit;
  int b = f;
  while (b + 1 < m && spans.entry(q, b + 1) <= x)
  {
    ++b;
  }
  const bool exitToNeighbour = nextEntry > spans.exit(q, b);
  return { entryToNeighbour ? static_cast<std::uint8_t>(2 * f)
                            : static_cast<std::uint8_t>(OwnColumn | (2 * k - 1)),
    exitToNeighbour ? static_cast<std::uint8_t>(2 * b + 1)
                    : static_cast<std::uint8_t>(OwnColumn | (2 * k + 2)),
    int(entryToNeighbour) + int(exitToNeighbour),
    int(!entryToNeighbour) + int(!exitToNeighbour) };
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
              const SpanLinks l = linkSpan(spans, p, k, count, q, m);
              nb += l.neighbour;
              own += l.own;
              spans.links[spans.slot(p, 2 * k)] |= std::uint32_t(l.entry) << (8 * dir);
              spans.links[spans.slot(p, 2 * k + 1)] |= std::uint32_t(l.exit) << (8 * dir);
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

namespace
{
/// The depth slot of surface point k.
std::size_t depthSlot(const FluidSpans& spans, const SurfaceNeighbourhoods& nbh, std::size_t k)
{
  const std::uint32_t p = nbh.pixel[k];
  return spans.slot(p, static_cast<int>(k - nbh.pointStart[p]));
}

/// The smoothing filter's state per surface point (section 4.6): the value filtered (1 / zeta
/// perspective, zeta parallel) before and after an iteration, the point's own number of
/// iterations and whether its column holds a depth value before and after it.
struct SmoothingState
{
  std::vector<std::uint8_t> iterationsOf, hasPrev, hasNext;
  std::vector<float> cur, next;
  int iterations = 0; // the most any point takes
};

/// The filter's start: each point's value and its iterations n = min(maxIterations, 255,
/// ceil(R / w)), w = sigma zeta the pixel's width at its depth (sigma for parallel views), so
/// that n iterations spread over the world radius R.
void startSmoothing(const FluidSpans& spans,
  const SurfaceNeighbourhoods& nbh,
  const ViewRays& rays,
  double radius,
  int maxIterations,
  SmoothingState& f)
{
  const bool perspective = rays.isPerspective();
  const double sigma = rays.pixelSize();
  const std::size_t points = nbh.points();
  f.iterationsOf.resize(points);
  f.hasPrev.resize(points);
  f.hasNext.resize(points);
  f.cur.resize(points);
  f.next.resize(points);
  const auto iterationsAt = [&](float zeta)
  {
    const double width = perspective ? sigma * zeta : sigma;
    return static_cast<int>(
      std::min<double>(std::min(maxIterations, 255), std::ceil(radius / width)));
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points, 4096),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
      {
        const std::uint32_t p = nbh.pixel[k];
        const std::size_t s = k - nbh.pointStart[p];
        const float z = spans.depth[depthSlot(spans, nbh, k)];
        f.cur[k] = perspective ? 1.f / z : z;
        f.iterationsOf[k] = static_cast<std::uint8_t>(iterationsAt(z));
        f.hasPrev[k] = s > 0;
        f.hasNext[k] = k + 1 < nbh.pointStart[p + 1];
      }
    });
  f.iterations = points ? *std::max_element(f.iterationsOf.begin(), f.iterationsOf.end()) : 0;
}

/// Iteration `it` of the binomial kernel (1 2 1)^T (1 2 1) / 16 along the links: the points
/// that still take iterations average their present neighbours (weights renormalized), and
/// the result stays between the column's neighbouring depth values, so spans stay ordered.
void smoothingIteration(const SurfaceNeighbourhoods& nbh,
  bool perspective,
  int it,
  SmoothingState& f,
  tbb::combinable<std::int64_t>& filtered)
{
  // (1 2 1)^T (1 2 1) without the centre, in the neighbours' order.
  static constexpr float Weight[8] = { 1, 2, 1, 2, 2, 1, 2, 1 };
  const std::vector<float>& cur = f.cur;
  std::vector<float>& next = f.next;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nbh.points(), 4096),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      std::int64_t& done = filtered.local();
      for (std::size_t k = r.begin(); k != r.end(); ++k)
      {
        if (f.iterationsOf[k] <= it)
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
        if (f.hasPrev[k])
        {
          v = perspective ? std::min(v, cur[k - 1]) : std::max(v, cur[k - 1]);
        }
        if (f.hasNext[k])
        {
          v = perspective ? std::max(v, cur[k + 1]) : std::min(v, cur[k + 1]);
        }
        next[k] = v;
        ++done;
      }
    });
  std::swap(f.cur, f.next);
}
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
  stats.addCounter("filter_bytes", static_cast<std::int64_t>(11 * nbh.points()));
  SmoothingState f;
  startSmoothing(spans, nbh, rays, radius, maxIterations, f);
  tbb::combinable<std::int64_t> filtered;
  for (int it = 0; it < f.iterations; ++it)
  {
    smoothingIteration(nbh, perspective, it, f, filtered);
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nbh.points(), 4096),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
      {
        spans.depth[depthSlot(spans, nbh, k)] = perspective ? 1.f / f.cur[k] : f.cur[k];
      }
    });
  stats.addCounter("filter_iterations", f.iterations);
  stats.addCounter("filtered_points", filtered.combine(std::plus<std::int64_t>()));
}

namespace
{
/// The positions P[b + 1][a + 1] of the 3 x 3 neighbourhood of surface point k on their
/// pixels' centre rays (model coordinates); a missing point is replaced by the one a step
/// nearer to the centre (edges by the centre, corners by their edge in the same row).
void neighbourhoodPositions(const FluidSpans& spans,
  const SurfaceNeighbourhoods& nbh,
  const ViewRays& rays,
  std::size_t k,
  Vec3d P[3][3])
{
  const int W = spans.width;
  const auto position = [&](std::size_t q)
  {
    const std::uint32_t p = nbh.pixel[q];
    return rays.pointAt(p % W + 0.5, p / W + 0.5, spans.depth[depthSlot(spans, nbh, q)]);
  };
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
}

/// The Sobel normal n = G_x x G_y / |G_x x G_y| of the neighbourhood P (section 3.4), turned
/// to face out of the fluid: against the pixel's ray at an entry, along it at an exit (the
/// ray's direction where the neighbourhood is degenerate).
Vec3d sobelNormal(const Vec3d P[3][3], const Vec3d& ray, bool entry)
{
  Vec3d gx, gy;
  for (int c = 0; c < 3; ++c)
  {
    gx += (P[c][2] - P[c][0]) * SobelWeight[c];
    gy += (P[2][c] - P[0][c]) * SobelWeight[c];
  }
  Vec3d n = cross(gx, gy);
  const double len = length(n);
  n = len > 0 && std::isfinite(len) ? n * (1.0 / len) : normalize(ray);
  if ((dot(n, ray) > 0) == entry)
  {
    n = -n;
  }
  return n;
}
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
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points, 4096),
    [&](const tbb::blocked_range<std::size_t>& r)
    {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
      {
        const std::uint32_t p = nbh.pixel[k];
        const int s = static_cast<int>(k - nbh.pointStart[p]);
        Vec3d P[3][3];
        neighbourhoodPositions(spans, nbh, rays, k, P);
        const Vec3d ray = rays.direction(p % W + 0.5, p / W + 0.5);
        spans.normals[spans.slot(p, s)] = encodeNormal(Vec3f(sobelNormal(P, ray, (s & 1) == 0)));
      }
    });
  stats.addCounter("normals", static_cast<std::int64_t>(points));
}

} // namespace raymappers
