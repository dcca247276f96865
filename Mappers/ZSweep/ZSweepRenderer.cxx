#include "ZSweepRenderer.h"

#include "RayCamera.h"
#include "ZSweepNearPlane.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace raymappers
{

namespace
{

// A face crossing on a pixel's ray.
struct Entry
{
  double t;   // distance along the pixel's ray
  double s;   // scalar there (point data)
  std::int32_t entered;
  std::int32_t exited;
};

// Per-frame data of a binned triangle.
struct TriangleKey
{
  double depth;         // window depth of its nearest vertex (the event)
  std::uint32_t vertex; // that vertex
  std::uint32_t triangle;
};

bool eventLess(const TriangleKey& a, const TriangleKey& b)
{
  if (a.depth != b.depth)
  {
    return a.depth < b.depth;
  }
  if (a.vertex != b.vertex)
  {
    return a.vertex < b.vertex;
  }
  return a.triangle < b.triangle;
}

// orient(u, v, p) = (v - u) x (p - u), positive when p is left of u -> v (y up).
inline double orient(const ProjectedVertex& u, const ProjectedVertex& v, double px, double py)
{
  return (v.x - u.x) * (py - u.y) - (v.y - u.y) * (px - u.x);
}

// The edge function of u -> v of a counter-clockwise triangle (positive inside):
//   E(p) = orient(u, v, p) = (v - u) x (p - u),
// evaluated with the endpoints in global-id order (and negated as needed), so that the two
// triangles sharing the edge compute bit-identical values. Along a pixel row the part in y
// is computed once: E = sign (row - dy (px - ux)), row = dx (py - uy).
//
// Top-left rule (y up): a pixel centre exactly on the edge belongs to the triangle when
// the edge goes down, or is horizontal and goes left; the neighbour across the edge walks
// it the other way, so exactly one of the two owns it.
struct EdgeEquation
{
  double ux, uy, dx, dy, sign;
  bool owned;

  EdgeEquation(const ProjectedVertex& u, std::uint64_t iu, const ProjectedVertex& v, std::uint64_t iv)
  {
    const ProjectedVertex& p = iu < iv ? u : v;
    const ProjectedVertex& q = iu < iv ? v : u;
    ux = p.x;
    uy = p.y;
    dx = q.x - p.x;
    dy = q.y - p.y;
    sign = iu < iv ? 1.0 : -1.0;
    const double ey = v.y - u.y, ex = v.x - u.x;
    owned = ey < 0 || (ey == 0 && ex < 0);
  }
  double row(double py) const { return dx * (py - uy); }
  double at(double rowTerm, double px) const { return sign * (rowTerm - dy * (px - ux)); }
  bool inside(double e) const { return e > 0 || (e == 0 && owned); }
  // Narrows [lo, hi] to where E >= 0 along the row (in real x; empty when E < 0 all along),
  // widened by a tolerance that covers the rounding of both this bound and E itself: a
  // pixel centre outside the widened bound has E < 0 as computed by at(), so the exact test
  // of the pixels left inside decides alone. (The bound x = ux - q, q = sign row / m, is off
  // by a few ulps of |ux| + |q|; at() is off by a few ulps of |row| + |m| |px - ux|. A margin
  // of 1e-9 (|ux| + |q| + 1) pixels exceeds both by orders of magnitude for any pixel
  // coordinate below 1e6.)
  void narrow(double rowTerm, double& lo, double& hi, bool& empty) const
  {
    const double m = -sign * dy; // E = sign row + m (px - ux)
    if (m == 0)
    {
      empty = empty || sign * rowTerm < 0;
      return;
    }
    const double q = sign * rowTerm / m;
    const double bound = ux - q;
    const double margin = 1e-9 * (std::abs(ux) + std::abs(q) + 1.0);
    if (m > 0)
    {
      lo = std::max(lo, bound - margin);
    }
    else
    {
      hi = std::min(hi, bound + margin);
    }
  }
};

// Compositing state of one pixel of a tile.
struct PixelState
{
  RayDepthMap map;
  double tOpaque = std::numeric_limits<double>::infinity();
  double prevT = 0;
  double prevS = 0;
  std::int32_t cell = -1; // the cell the ray is in after prevT (-1: outside)
  bool done = false;
  SegmentLight light;
};

// Pixels a flush integrates as one batch (their segments stay in the L1/L2 caches).
constexpr std::size_t FlushChunk = 64;

// A pixel's segments in a flush's batch.
struct FlushRange
{
  std::size_t pixel, begin, end;
  bool opaque; // opaque geometry ends the ray within them
};

struct TileWork
{
  std::vector<std::vector<Entry>> lists;
  SegmentBatch batch;
  std::vector<FlushRange> ranges;
  std::vector<PixelState> pixels;
  std::vector<int> dirty; // pixels whose list is not empty
  std::vector<char> isDirty;
  std::int64_t entries = 0, flushes = 0, kGrowths = 0, segments = 0, transparentSegments = 0,
               tieGroups = 0;
  std::size_t maxList = 0;
};
} // namespace

void renderZSweep(const ZSweepMesh& mesh,
  const OpticalModel& optics,
  const std::array<double, 16>& modelToClip,
  const ZSweepParameters& params,
  const float* opaqueDepth,
  Frame& frame,
  RenderStatistics& stats,
  ZSweepEventOrder* previousOrder)
{
  const int W = frame.width, H = frame.height;
  std::fill(frame.rgba.begin(), frame.rgba.end(), 0.f);
  std::fill(frame.depth.begin(), frame.depth.end(), 1.f);
  const bool cellData = mesh.cellScalars();
  stats.setEffect("cell_data", cellData);
  stats.setEffect("early_termination", params.terminationOpacity < 1.0);
  stats.setEffect("sparse_mesh", mesh.sparse());
  const auto& points = mesh.points();
  const auto& scalars = mesh.scalars();
  if (W <= 0 || H <= 0 || mesh.numTriangles() == 0 || optics.empty())
  {
    return;
  }
  // A sparse mesh's triangles, decoded from its kept cells for this frame.
  std::vector<ZSweepTriangle> decoded;
  const std::vector<ZSweepTriangle>& triangles = [&]() -> const std::vector<ZSweepTriangle>& {
    if (!mesh.sparse())
    {
      return mesh.triangles(decoded);
    }
    ScopedPhase phase(stats, "decode");
    return mesh.triangles(decoded);
  }();
  const RayCamera camera(modelToClip, W, H, mesh.origin());

  // Origin-relative model -> clip: M T(origin).
  std::array<double, 16> M = modelToClip;
  const Vec3d o = mesh.origin();
  for (int r = 0; r < 4; ++r)
  {
    M[4 * r + 3] += M[4 * r] * o.x + M[4 * r + 1] * o.y + M[4 * r + 2] * o.z;
  }

  // 1. Project the vertices.
  std::vector<ProjectedVertex> proj(points.size());
  {
    ScopedPhase phase(stats, "project");
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i)
        {
          const Vec3d& p = points[i];
          double c[4];
          for (int k = 0; k < 4; ++k)
          {
            c[k] = M[4 * k] * p.x + M[4 * k + 1] * p.y + M[4 * k + 2] * p.z + M[4 * k + 3];
          }
          ProjectedVertex& v = proj[i];
          v.valid = c[3] > 0 && c[2] >= -c[3];
          const double iw = c[3] != 0 ? 1.0 / c[3] : 0.0;
          v.x = (c[0] * iw + 1.0) * 0.5 * W;
          v.y = (c[1] * iw + 1.0) * 0.5 * H;
          v.d = (c[2] * iw + 1.0) * 0.5;
          v.invW = iw;
        }
      });
  }

  // 2. Bin the triangles into tiles, in event order.
  const int S = std::max(8, params.tileSize);
  const int nx = (W + S - 1) / S, ny = (H + S - 1) / S;
  std::vector<std::uint32_t> eventVertex(triangles.size());
  std::vector<double> eventDepth(triangles.size());
  std::vector<std::int32_t> box(4 * triangles.size()); // pixel bounds, x0 < 0: not drawn
  std::vector<char> forward(triangles.size());          // the rays cross front -> back
  const std::size_t numTiles = static_cast<std::size_t>(nx) * ny;
  std::vector<char> crosses(triangles.size(), 0); // across the near plane
  // The side the rays cross a triangle from: whether they go along its normal
  // (v1 - v0) x (v2 - v0), the same over its whole plane.
  auto forwardOf = [&](const ZSweepTriangle& t) {
    const Vec3d& p0 = points[t.v[0]];
    return camera.raysAlong(p0, cross(points[t.v[1]] - p0, points[t.v[2]] - p0));
  };
  {
    ScopedPhase phase(stats, "bin");
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size()),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t f = r.begin(); f != r.end(); ++f)
        {
          const ZSweepTriangle& t = triangles[f];
          const ProjectedVertex& a = proj[t.v[0]];
          const ProjectedVertex& b = proj[t.v[1]];
          const ProjectedVertex& c = proj[t.v[2]];
          // The event: the nearest vertex (ties to the lowest id), also of the triangles
          // not drawn this frame, for the event order below (a depth that is not finite,
          // of a vertex behind the eye, orders last).
          std::uint32_t ev = t.v[0];
          for (int k = 1; k < 3; ++k)
          {
            const std::uint32_t v = t.v[k];
            if (proj[v].d < proj[ev].d || (proj[v].d == proj[ev].d && v < ev))
            {
              ev = v;
            }
          }
          eventVertex[f] = ev;
          eventDepth[f] = std::isfinite(proj[ev].d) ? proj[ev].d : std::numeric_limits<double>::infinity();
          box[4 * f] = -1;
          if (!a.valid || !b.valid || !c.valid)
          {
            if (a.valid || b.valid || c.valid)
            {
              // Across the near plane: clipped below. The rays cross its plane from the
              // same side everywhere.
              forward[f] = forwardOf(t);
              crosses[f] = 1;
            }
            continue;
          }
          if (a.d > 1 && b.d > 1 && c.d > 1)
          {
            continue;
          }
          // Pixel centres i + 0.5 in [min x, max x].
          const int x0 = std::max(0, static_cast<int>(std::ceil(std::min({ a.x, b.x, c.x }) - 0.5)));
          const int x1 = std::min(W - 1, static_cast<int>(std::floor(std::max({ a.x, b.x, c.x }) - 0.5)));
          const int y0 = std::max(0, static_cast<int>(std::ceil(std::min({ a.y, b.y, c.y }) - 0.5)));
          const int y1 = std::min(H - 1, static_cast<int>(std::floor(std::max({ a.y, b.y, c.y }) - 0.5)));
          if (x0 > x1 || y0 > y1)
          {
            continue;
          }
          box[4 * f] = x0;
          box[4 * f + 1] = y0;
          box[4 * f + 2] = x1;
          box[4 * f + 3] = y1;
          forward[f] = forwardOf(t);
        }
      });
  }
  // The event order of all the triangles, sorted from the previous frame's order (the
  // previous order as the start of the next sort): a camera that stayed (an edited transfer
  // function, a re-render) leaves it sorted, and an insertion sort checks it with one
  // comparison per triangle; a small move costs a move per inversion. Past a budget of 8
  // moves a triangle (the camera moved farther), or for a new mesh, a full sort. (Triangles
  // out of view keep their place by the same key, so that they rejoin in order when they
  // come back into view.)
  std::vector<std::uint32_t> localOrder;
  std::vector<std::uint32_t>& order = previousOrder ? previousOrder->triangles : localOrder;
  std::int64_t orderMoves = 0, orderSorts = 0;
  {
    ScopedPhase orderPhase(stats, "order");
    auto less = [&](std::uint32_t a, std::uint32_t b) {
      return eventLess(TriangleKey{ eventDepth[a], eventVertex[a], a },
        TriangleKey{ eventDepth[b], eventVertex[b], b });
    };
    const std::int64_t budget = 8 * static_cast<std::int64_t>(triangles.size());
    bool full = order.size() != triangles.size();
    if (full)
    {
      order.resize(triangles.size());
      for (std::size_t f = 0; f < order.size(); ++f)
      {
        order[f] = static_cast<std::uint32_t>(f);
      }
    }
    // (A still camera: the check in parallel first.)
    const bool sorted = !full &&
      tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(1, std::max<std::size_t>(order.size(), 1)), true,
        [&](const tbb::blocked_range<std::size_t>& r, bool ok) {
          for (std::size_t i = r.begin(); ok && i != r.end(); ++i)
          {
            ok = !less(order[i], order[i - 1]);
          }
          return ok;
        },
        [](bool a, bool b) { return a && b; });
    for (std::size_t i = 1; !full && !sorted && i < order.size(); ++i)
    {
      const std::uint32_t f = order[i];
      std::size_t j = i;
      for (; j > 0 && less(f, order[j - 1]); --j)
      {
        order[j] = order[j - 1];
      }
      order[j] = f;
      orderMoves += static_cast<std::int64_t>(i - j);
      full = orderMoves > budget;
    }
    if (full)
    {
      tbb::parallel_sort(order.begin(), order.end(), less);
      orderSorts = 1;
    }
  }
  stats.addCounter("order_moves", orderMoves);
  stats.addCounter("order_sorts", orderSorts);
  // Each tile's triangles in event order: the order cut into chunks, each chunk's
  // triangles counted per tile and then written, in parallel, from where the chunks
  // before it end in each tile's list.
  const std::size_t chunks =
    std::clamp<std::size_t>(order.size() / 8192, 1, 16);
  const std::size_t chunkSize = (order.size() + chunks - 1) / chunks;
  std::vector<std::size_t> chunkStart(chunks * numTiles, 0); // count, then write position
  std::vector<std::size_t> tileStart(numTiles + 1, 0);
  std::vector<TriangleKey> binned;
  {
    ScopedPhase fillPhase(stats, "bin");
    auto forEachTileOf = [&](std::size_t c, auto&& visit) {
      const std::size_t end = std::min(order.size(), (c + 1) * chunkSize);
      for (std::size_t k = c * chunkSize; k < end; ++k)
      {
        const std::uint32_t f = order[k];
        if (box[4 * static_cast<std::size_t>(f)] < 0)
        {
          continue;
        }
        for (int ty = box[4 * f + 1] / S; ty <= box[4 * f + 3] / S; ++ty)
        {
          for (int tx = box[4 * f] / S; tx <= box[4 * f + 2] / S; ++tx)
          {
            visit(f, static_cast<std::size_t>(ty) * nx + tx);
          }
        }
      }
    };
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
      forEachTileOf(c, [&](std::uint32_t, std::size_t tile) { ++chunkStart[c * numTiles + tile]; });
    });
    for (std::size_t tile = 0; tile < numTiles; ++tile)
    {
      std::size_t at = tileStart[tile];
      for (std::size_t c = 0; c < chunks; ++c)
      {
        const std::size_t count = chunkStart[c * numTiles + tile];
        chunkStart[c * numTiles + tile] = at;
        at += count;
      }
      tileStart[tile + 1] = at;
    }
    binned.resize(tileStart.back());
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
      forEachTileOf(c, [&](std::uint32_t f, std::size_t tile) {
        binned[chunkStart[c * numTiles + tile]++] = TriangleKey{ proj[eventVertex[f]].d, eventVertex[f], f };
      });
    });
  }

  // The faces across the near plane, clipped, and the caps of the cells they bound (a
  // camera close to or inside the grid), binned into per-tile lists in event order.
  std::vector<std::uint32_t> crossing;
  for (std::size_t f = 0; f < triangles.size(); ++f)
  {
    if (crosses[f])
    {
      crossing.push_back(static_cast<std::uint32_t>(f));
    }
  }
  // In the order of their vertex ids (a dense mesh's own order; a sparse mesh decodes its
  // triangles in another): the caps' fans start at their first segment, so this order makes
  // the caps the same for both.
  std::sort(crossing.begin(), crossing.end(), [&](std::uint32_t a, std::uint32_t b) {
    return std::lexicographical_compare(triangles[a].v, triangles[a].v + 3, triangles[b].v, triangles[b].v + 3);
  });
  std::vector<DrawTriangle> extras;
  std::size_t openCaps = 0;
  std::vector<std::vector<std::uint32_t>> tileExtras(numTiles);
  std::vector<std::array<int, 4>> extraBox;
  std::vector<double> extraEvent;
  if (!crossing.empty())
  {
    ScopedPhase nearPhase(stats, "near_plane");
    openCaps = nearPlaneTriangles(mesh, triangles, M, W, H, crossing, forward, extras);
    for (std::size_t e = 0; e < extras.size(); ++e)
    {
      const auto& v = extras[e].v;
      const int x0 = std::max(0, static_cast<int>(std::ceil(std::min({ v[0].x, v[1].x, v[2].x }) - 0.5)));
      const int x1 = std::min(W - 1, static_cast<int>(std::floor(std::max({ v[0].x, v[1].x, v[2].x }) - 0.5)));
      const int y0 = std::max(0, static_cast<int>(std::ceil(std::min({ v[0].y, v[1].y, v[2].y }) - 0.5)));
      const int y1 = std::min(H - 1, static_cast<int>(std::floor(std::max({ v[0].y, v[1].y, v[2].y }) - 0.5)));
      extraBox.push_back({ x0, y0, x1, y1 });
      extraEvent.push_back(std::min({ v[0].d, v[1].d, v[2].d }));
      if (x0 > x1 || y0 > y1)
      {
        continue;
      }
      for (int ty = y0 / S; ty <= y1 / S; ++ty)
      {
        for (int tx = x0 / S; tx <= x1 / S; ++tx)
        {
          tileExtras[static_cast<std::size_t>(ty) * nx + tx].push_back(static_cast<std::uint32_t>(e));
        }
      }
    }
    for (auto& list : tileExtras)
    {
      std::stable_sort(list.begin(), list.end(),
        [&](std::uint32_t a, std::uint32_t b) { return extraEvent[a] < extraEvent[b]; });
    }
  }

  // Ties: crossings closer than this along a ray are one crossing (a shared vertex or edge).
  const double tieT = 1e-9 * std::max(mesh.extent(), 1e-300);
  const double termination = std::clamp(params.terminationOpacity, 0.0, 1.0);
  const int K0 = std::max(2, params.listThreshold);

  // 3.-5. Sweep the tiles.
  tbb::enumerable_thread_specific<TileWork> works;
  ScopedPhase phase(stats, "sweep");
  tbb::parallel_for(tbb::blocked_range<int>(0, nx * ny, 1), [&](const tbb::blocked_range<int>& range) {
    TileWork& work = works.local();
    for (int tileIndex = range.begin(); tileIndex != range.end(); ++tileIndex)
    {
      const int tx = tileIndex % nx, ty = tileIndex / nx;
      const int X0 = tx * S, Y0 = ty * S;
      const int TW = std::min(S, W - X0), TH = std::min(S, H - Y0);
      const std::size_t numPixels = static_cast<std::size_t>(TW) * TH;
      work.lists.resize(std::max(work.lists.size(), numPixels));
      work.pixels.assign(numPixels, PixelState());
      work.isDirty.assign(numPixels, 0);
      work.dirty.clear();
      work.ranges.resize(FlushChunk);
      for (int j = 0; j < TH; ++j)
      {
        for (int i = 0; i < TW; ++i)
        {
          PixelState& px = work.pixels[static_cast<std::size_t>(j) * TW + i];
          px.map = camera.pixelDepthMap(X0 + i, Y0 + j);
          if (opaqueDepth)
          {
            const float d = opaqueDepth[static_cast<std::size_t>(Y0 + j) * W + X0 + i];
            if (d < 1.f)
            {
              px.tOpaque = px.map.distanceOf(d);
            }
          }
        }
      }

      // Moves the final crossings of a pixel's list (tie groups wholly before distance
      // tLimit) into segments of the batch: from the pixel's last crossing to each group's
      // first; returns whether opaque geometry ends the ray there.
      auto gather = [&](PixelState& px, std::vector<Entry>& list, double tLimit) {
        bool opaque = false;
        std::size_t i = 0;
        while (i < list.size() && !opaque)
        {
          // The tie group starting at i: it must be final as a whole.
          std::size_t j = i + 1;
          while (j < list.size() && list[j].t - list[j - 1].t <= tieT)
          {
            ++j;
          }
          if (!(list[j - 1].t + tieT < tLimit))
          {
            break;
          }
          double tEnd = list[i].t, sEnd = list[i].s;
          if (tEnd > px.tOpaque)
          {
            // Opaque geometry ends the ray inside this segment.
            sEnd = tEnd > px.prevT
              ? px.prevS + (sEnd - px.prevS) * (px.tOpaque - px.prevT) / (tEnd - px.prevT)
              : sEnd;
            tEnd = px.tOpaque;
            opaque = true;
          }
          const double L = tEnd - px.prevT;
          if (px.cell >= 0 && L > 0)
          {
            const double s0 = cellData ? scalars[static_cast<std::size_t>(px.cell)] : px.prevS;
            work.batch.push(s0, cellData ? s0 : sEnd, L);
          }
          std::int32_t cell = list[j - 1].entered;
          if (j - i > 1)
          {
            // The cell some member entered and no member left.
            ++work.tieGroups;
            for (std::size_t a = i; a < j; ++a)
            {
              bool left = false;
              for (std::size_t b = i; b < j && !left; ++b)
              {
                left = list[b].exited == list[a].entered;
              }
              if (!left)
              {
                cell = list[a].entered;
                break;
              }
            }
          }
          px.prevT = list[j - 1].t;
          px.prevS = list[j - 1].s;
          px.cell = cell;
          i = j;
        }
        list.erase(list.begin(), list.begin() + static_cast<std::ptrdiff_t>(i));
        return opaque;
      };

      // Composites the batch's segments [begin, end) behind the pixel's light, in order, up
      // to the termination opacity.
      auto composite = [&](PixelState& px, std::size_t begin, std::size_t end) {
        const SegmentBatch& batch = work.batch;
        for (std::size_t q = begin; q < end && !px.done; ++q)
        {
          ++work.segments;
          const SegmentLight seg{ batch.r[q], batch.g[q], batch.b[q], batch.transmittance[q] };
          if (seg.transmittance == 1.0 && seg.r == 0.0 && seg.g == 0.0 && seg.b == 0.0)
          {
            ++work.transparentSegments; // no opacity over the segment's scalars
            continue;
          }
          compositeBehind(px.light, seg);
          px.done = 1.0 - px.light.transmittance >= termination;
        }
      };

      // Composites the dirty pixels' lists up to window depth depthLimit (everything when
      // it is >= 1). The pixels go in chunks: a chunk's segments are gathered, integrated
      // as one batch (independent of each other), then composited pixel by pixel in order.
      auto flush = [&](double depthLimit) {
        ++work.flushes;
        std::size_t longest = 0;
        std::size_t keep = 0;
        for (std::size_t c0 = 0; c0 < work.dirty.size(); c0 += FlushChunk)
        {
          const std::size_t c1 = std::min(work.dirty.size(), c0 + FlushChunk);
          work.batch.clear();
          for (std::size_t k = c0; k < c1; ++k)
          {
            const std::size_t p = static_cast<std::size_t>(work.dirty[k]);
            PixelState& px = work.pixels[p];
            const double tLimit = depthLimit >= 1.0 ? std::numeric_limits<double>::infinity()
                                                    : px.map.distanceOf(depthLimit);
            FlushRange& chunkRange = work.ranges[k - c0];
            chunkRange.pixel = p;
            chunkRange.begin = work.batch.size();
            chunkRange.opaque = gather(px, work.lists[p], tLimit);
            chunkRange.end = work.batch.size();
          }
          if (cellData)
          {
            optics.integrateHomogeneous(work.batch);
          }
          else
          {
            optics.integrate(params.integrator, work.batch);
          }
          for (std::size_t k = c0; k < c1; ++k)
          {
            const FlushRange& chunkRange = work.ranges[k - c0];
            PixelState& px = work.pixels[chunkRange.pixel];
            std::vector<Entry>& list = work.lists[chunkRange.pixel];
            composite(px, chunkRange.begin, chunkRange.end);
            px.done = px.done || chunkRange.opaque;
            if (px.done)
            {
              list.clear();
            }
            longest = std::max(longest, list.size());
            if (!list.empty())
            {
              work.dirty[keep++] = static_cast<int>(chunkRange.pixel);
            }
            else
            {
              work.isDirty[chunkRange.pixel] = 0;
            }
          }
        }
        work.dirty.resize(keep);
        return longest;
      };

      std::size_t K = static_cast<std::size_t>(K0);
      bool overK = false;

      // Scan converts one triangle into the tile's pixel lists (keys: the vertices' ids,
      // for the shared-edge fill rule; bounds: its pixel box).
      auto rasterize = [&](const ProjectedVertex* va, std::uint64_t ka, double sa,
                         const ProjectedVertex* vb, std::uint64_t kb, double sb,
                         const ProjectedVertex* vc, std::uint64_t kc, double sc,
                         std::int32_t entered, std::int32_t exited, const int bounds[4]) {
        double area = orient(*va, *vb, vc->x, vc->y);
        if (area == 0)
        {
          return; // seen edge on: covers no pixel centre
        }
        if (area < 0)
        {
          std::swap(vb, vc);
          std::swap(kb, kc);
          std::swap(sb, sc);
          area = -area;
        }
        const ProjectedVertex &a = *va, &b = *vb, &c = *vc;
        const EdgeEquation edges[3] = { EdgeEquation(b, kb, c, kc), EdgeEquation(c, kc, a, ka),
          EdgeEquation(a, ka, b, kb) };
        const double invArea = 1.0 / area;
        const int x0 = std::max(bounds[0], X0), x1 = std::min(bounds[2], X0 + TW - 1);
        const int y0 = std::max(bounds[1], Y0), y1 = std::min(bounds[3], Y0 + TH - 1);
        for (int y = y0; y <= y1; ++y)
        {
          const double py = y + 0.5;
          double rows[3];
          // The row's span inside all three edges (with narrow's margin): the exact test
          // below decides each pixel of it.
          double lo = x0 + 0.5, hi = x1 + 0.5; // pixel centres
          bool empty = false;
          for (int q = 0; q < 3; ++q)
          {
            rows[q] = edges[q].row(py);
            edges[q].narrow(rows[q], lo, hi, empty);
          }
          if (empty)
          {
            continue;
          }
          if (lo > hi)
          {
            continue;
          }
          const int xs = std::max(x0, static_cast<int>(std::ceil(lo - 0.5)));
          const int xe = std::min(x1, static_cast<int>(std::floor(hi - 0.5)));
          for (int xi = xs; xi <= xe; ++xi)
          {
            const double pxc = xi + 0.5;
            const double eBC = edges[0].at(rows[0], pxc);
            const double eCA = edges[1].at(rows[1], pxc);
            const double eAB = edges[2].at(rows[2], pxc);
            if (!edges[0].inside(eBC) || !edges[1].inside(eCA) || !edges[2].inside(eAB))
            {
              continue;
            }
            const std::size_t p = static_cast<std::size_t>(y - Y0) * TW + (xi - X0);
            PixelState& pxs = work.pixels[p];
            if (pxs.done)
            {
              continue;
            }
            // Barycentrics; depth is affine in the window, the scalar perspective-correct.
            const double la = eBC * invArea, lb = eCA * invArea, lc = eAB * invArea;
            const double d = la * a.d + lb * b.d + lc * c.d;
            double s = 0;
            if (!cellData)
            {
              const double wa = la * a.invW, wb = lb * b.invW, wc = lc * c.invW;
              s = (wa * sa + wb * sb + wc * sc) / (wa + wb + wc);
            }
            const Entry entry{ pxs.map.distanceOf(d), s, entered, exited };
            std::vector<Entry>& list = work.lists[p];
            // Usually the sweep order puts the entry at the end (section 4.2); when it does
            // not, pending entries beyond it are found by bisection.
            auto pos = list.end();
            if (!list.empty() && list.back().t > entry.t)
            {
              pos = std::upper_bound(list.begin(), list.end(), entry.t,
                [](double v, const Entry& en) { return v < en.t; });
            }
            list.insert(pos, entry);
            ++work.entries;
            work.maxList = std::max(work.maxList, list.size());
            overK = overK || list.size() > K;
            if (!work.isDirty[p])
            {
              work.isDirty[p] = 1;
              work.dirty.push_back(static_cast<int>(p));
            }
          }
        }
      };

      // Delayed compositing before an event at depth zv whose triangles reach zFar.
      double zTarget = -std::numeric_limits<double>::infinity();
      auto beforeEvent = [&](double zv, double zFar) {
        if (zv >= zTarget || overK)
        {
          const std::size_t longest = flush(zv);
          overK = false;
          if (longest > K)
          {
            K *= 2; // the lists cannot be flushed below K yet (section 4.2)
            ++work.kGrowths;
          }
          zTarget = std::max(zv, zFar);
        }
      };

      // The events of the mesh's triangles and of the near-plane triangles, merged in order.
      const std::size_t begin = tileStart[static_cast<std::size_t>(tileIndex)];
      const std::size_t end = tileStart[static_cast<std::size_t>(tileIndex) + 1];
      const std::vector<std::uint32_t>& near = tileExtras[static_cast<std::size_t>(tileIndex)];
      std::size_t e = begin, n = 0;
      while (e < end || n < near.size())
      {
        if (n < near.size() && (e >= end || extraEvent[near[n]] <= binned[e].depth))
        {
          const DrawTriangle& t = extras[near[n]];
          beforeEvent(extraEvent[near[n]], std::max({ t.v[0].d, t.v[1].d, t.v[2].d }));
          rasterize(&t.v[0], t.key[0], t.s[0], &t.v[1], t.key[1], t.s[1], &t.v[2], t.key[2],
            t.s[2], t.entered, t.exited, extraBox[near[n]].data());
          ++n;
          continue;
        }
        // The event: all triangles whose nearest vertex is this one.
        std::size_t g = e + 1;
        while (g < end && binned[g].vertex == binned[e].vertex)
        {
          ++g;
        }
        double zFar = binned[e].depth;
        for (std::size_t k = e; k < g; ++k)
        {
          const ZSweepTriangle& t = triangles[binned[k].triangle];
          zFar = std::max({ zFar, proj[t.v[0]].d, proj[t.v[1]].d, proj[t.v[2]].d });
        }
        beforeEvent(binned[e].depth, zFar);
        for (std::size_t k = e; k < g; ++k)
        {
          const std::uint32_t f = binned[k].triangle;
          const ZSweepTriangle& t = triangles[f];
          const std::uint32_t ia = t.v[0], ib = t.v[1], ic = t.v[2];
          rasterize(&proj[ia], ia, cellData ? 0.0 : scalars[ia], &proj[ib], ib,
            cellData ? 0.0 : scalars[ib], &proj[ic], ic, cellData ? 0.0 : scalars[ic],
            forward[f] ? t.back : t.front, forward[f] ? t.front : t.back, &box[4 * f]);
        }
        e = g;
      }
      flush(2.0); // everything is final at the end of the sweep
      for (int j = 0; j < TH; ++j)
      {
        for (int i = 0; i < TW; ++i)
        {
          const PixelState& px = work.pixels[static_cast<std::size_t>(j) * TW + i];
          float* out = &frame.rgba[4 * frame.index(X0 + i, Y0 + j)];
          out[0] = static_cast<float>(px.light.r);
          out[1] = static_cast<float>(px.light.g);
          out[2] = static_cast<float>(px.light.b);
          out[3] = static_cast<float>(1.0 - px.light.transmittance);
        }
      }
    }
  });

  std::int64_t entries = 0, flushes = 0, kGrowths = 0, segs = 0, transparent = 0, ties = 0;
  std::size_t maxList = 0;
  for (const TileWork& w : works)
  {
    entries += w.entries;
    flushes += w.flushes;
    kGrowths += w.kGrowths;
    segs += w.segments;
    transparent += w.transparentSegments;
    ties += w.tieGroups;
    maxList = std::max(maxList, w.maxList);
  }
  stats.addCounter("triangles", static_cast<std::int64_t>(triangles.size()));
  stats.addCounter("decoded_triangles", static_cast<std::int64_t>(decoded.size()));
  stats.addCounter("binned_triangles", static_cast<std::int64_t>(binned.size()));
  stats.addCounter("entries", entries);
  stats.addCounter("flushes", flushes);
  stats.addCounter("k_growths", kGrowths);
  stats.addCounter("segments", segs);
  stats.addCounter("transparent_segments", transparent);
  stats.addCounter("near_plane_triangles", static_cast<std::int64_t>(extras.size()));
  stats.addCounter("open_caps", static_cast<std::int64_t>(openCaps));
  stats.addCounter("max_list", static_cast<std::int64_t>(maxList));
  stats.addCounter("tie_groups", ties);
}

} // namespace raymappers
