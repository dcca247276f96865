#include "Mappers/ZSweep/ZSweepRenderer.h"

#include "Mappers/Common/RayCamera.h"
#include "Mappers/ZSweep/IsoparametricCell.h"
#include "Mappers/ZSweep/ZSweepNearPlane.h"
#include "Mappers/Common/SimdTarget.h"

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

RAYMAPPERS_SIMD_VARIANTS(renderZSweep)

RAYMAPPERS_SIMD_BEGIN

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
  Vec3d org, dir; // the ray t is measured along (curved cells' fields only)
};

// Pixels a flush integrates as one batch (their segments stay in the L1/L2 caches).
constexpr std::size_t FlushChunk = 64;

// A pixel's segments in a flush's batch.
struct FlushRange
{
  std::size_t pixel, begin, end;
  bool opaque; // opaque geometry ends the ray within them
};

// A tile sweep's counters (the statistics of renderZSweep).
struct SweepCounters
{
  LinearizeCounts curved;
  std::int64_t curvedSegments = 0;
  std::int64_t entries = 0, flushes = 0, kGrowths = 0, segments = 0, transparentSegments = 0,
               tieGroups = 0;
  std::size_t maxList = 0;

  void add(const SweepCounters& o)
  {
    entries += o.entries;
    flushes += o.flushes;
    kGrowths += o.kGrowths;
    segments += o.segments;
    curvedSegments += o.curvedSegments;
    curved.evaluations += o.curved.evaluations;
    curved.failures += o.curved.failures;
    curved.pieces += o.curved.pieces;
    transparentSegments += o.transparentSegments;
    tieGroups += o.tieGroups;
    maxList = std::max(maxList, o.maxList);
  }
};

struct TileWork
{
  std::vector<std::vector<Entry>> lists;
  SegmentBatch batch;
  std::vector<FlushRange> ranges;
  std::vector<PixelState> pixels;
  std::vector<int> dirty; // pixels whose list is not empty
  std::vector<char> isDirty;
  SweepCounters counts;
};

// The screen tiles (chapter 5): S x S pixels, nx across and ny up.
struct TileGrid
{
  int S, nx, ny;
  std::size_t count() const { return static_cast<std::size_t>(nx) * ny; }
};

// Per frame and triangle: its event, its pixel box and the side the rays cross it from.
struct TriangleEvents
{
  explicit TriangleEvents(std::size_t n)
    : vertex(n)
    , depth(n)
    , box(4 * n)
    , forward(n)
    , crosses(n, 0)
  {
  }
  std::vector<std::uint32_t> vertex; // the event: the nearest vertex
  std::vector<double> depth;         // its window depth (infinite when not finite)
  std::vector<std::int32_t> box;     // pixel bounds, x0 < 0: not drawn
  std::vector<char> forward;         // the rays cross front -> back
  std::vector<char> crosses;         // across the near plane
};

// Each tile's triangles in event order: tile t's are binned[start[t], start[t + 1]).
struct TileBins
{
  std::vector<std::size_t> start;
  std::vector<TriangleKey> binned;
};

// The clipped faces and caps of a camera close to or inside the grid (ZSweepNearPlane.h),
// with their pixel boxes, events (the window depth of the nearest vertex) and tile lists.
struct NearPlaneFaces
{
  std::vector<DrawTriangle> triangles;
  std::size_t openCaps = 0;
  std::vector<std::vector<std::uint32_t>> perTile; // in event order
  std::vector<std::array<int, 4>> box;
  std::vector<double> event;
};

// A sparse mesh's triangles, decoded from its kept cells for this frame; a dense mesh's own.
const std::vector<ZSweepTriangle>& frameTriangles(
  const ZSweepMesh& mesh, std::vector<ZSweepTriangle>& decoded, RenderStatistics& stats)
{
  if (!mesh.sparse())
  {
    return mesh.triangles(decoded);
  }
  ScopedPhase phase(stats, "decode");
  return mesh.triangles(decoded);
}

// 1. The vertices projected: window x, y (pixels) and depth, and 1/w for the
// perspective-correct scalars; valid: in front of the eye and not before the near plane.
void projectVertices(const std::vector<Vec3d>& points,
  const std::array<double, 16>& M,
  int W,
  int H,
  std::vector<ProjectedVertex>& proj)
{
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

// The pixels whose centres i + 0.5 lie in the bounding box of a, b, c, within the window:
// { x0, y0, x1, y1 }, empty when x0 > x1 or y0 > y1.
std::array<int, 4> pixelBox(
  const ProjectedVertex& a, const ProjectedVertex& b, const ProjectedVertex& c, int W, int H)
{
  return { std::max(0, static_cast<int>(std::ceil(std::min({ a.x, b.x, c.x }) - 0.5))),
    std::max(0, static_cast<int>(std::ceil(std::min({ a.y, b.y, c.y }) - 0.5))),
    std::min(W - 1, static_cast<int>(std::floor(std::max({ a.x, b.x, c.x }) - 0.5))),
    std::min(H - 1, static_cast<int>(std::floor(std::max({ a.y, b.y, c.y }) - 0.5))) };
}

// A triangle's event (section 4.2): its nearest vertex, ties to the lowest id.
std::uint32_t nearestVertex(const ZSweepTriangle& t, const std::vector<ProjectedVertex>& proj)
{
  std::uint32_t ev = t.v[0];
  for (int k = 1; k < 3; ++k)
  {
    const std::uint32_t v = t.v[k];
    if (proj[v].d < proj[ev].d || (proj[v].d == proj[ev].d && v < ev))
    {
      ev = v;
    }
  }
  return ev;
}

// 2. (first part) Each triangle's event, also of the triangles not drawn this frame, for
// the event order (a depth that is not finite, of a vertex behind the eye, orders last);
// the pixel box of the ones drawn; the ones across the near plane, to clip.
void findEvents(const std::vector<ZSweepTriangle>& triangles,
  const std::vector<ProjectedVertex>& proj,
  const std::vector<Vec3d>& points,
  const RayCamera& camera,
  int W,
  int H,
  TriangleEvents& events)
{
  // The side the rays cross a triangle from: whether they go along its normal
  // (v1 - v0) x (v2 - v0), the same over its whole plane.
  auto forwardOf = [&](const ZSweepTriangle& t) {
    const Vec3d& p0 = points[t.v[0]];
    return camera.raysAlong(p0, cross(points[t.v[1]] - p0, points[t.v[2]] - p0));
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size()),
    [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t f = r.begin(); f != r.end(); ++f)
      {
        const ZSweepTriangle& t = triangles[f];
        const ProjectedVertex& a = proj[t.v[0]];
        const ProjectedVertex& b = proj[t.v[1]];
        const ProjectedVertex& c = proj[t.v[2]];
        const std::uint32_t ev = nearestVertex(t, proj);
        events.vertex[f] = ev;
        events.depth[f] =
          std::isfinite(proj[ev].d) ? proj[ev].d : std::numeric_limits<double>::infinity();
        events.box[4 * f] = -1;
        if (!a.valid || !b.valid || !c.valid)
        {
          if (a.valid || b.valid || c.valid)
          {
            // Across the near plane: clipped. The rays cross its plane from the same side
            // everywhere.
            events.forward[f] = forwardOf(t);
            events.crosses[f] = 1;
          }
          continue;
        }
        if (a.d > 1 && b.d > 1 && c.d > 1)
        {
          continue;
        }
        const std::array<int, 4> box = pixelBox(a, b, c, W, H);
        if (box[0] > box[2] || box[1] > box[3])
        {
          continue;
        }
        std::copy(box.begin(), box.end(), &events.box[4 * f]);
        events.forward[f] = forwardOf(t);
      }
    });
}

// 2. (the order) The event order of all the triangles, sorted from the previous frame's
// order (the previous order as the start of the next sort): a camera that stayed (an edited
// transfer function, a re-render) leaves it sorted, and an insertion sort checks it with one
// comparison per triangle; a small move costs a move per inversion. Past a budget of 8 moves
// a triangle (the camera moved farther), or for a new mesh, a full sort. (Triangles out of
// view keep their place by the same key, so that they rejoin in order when they come back
// into view.) Returns { the insertion sort's moves, 1 for a full sort }.
std::array<std::int64_t, 2> sortEvents(
  std::vector<std::uint32_t>& order, const TriangleEvents& events)
{
  auto less = [&](std::uint32_t a, std::uint32_t b) {
    return eventLess(TriangleKey{ events.depth[a], events.vertex[a], a },
      TriangleKey{ events.depth[b], events.vertex[b], b });
  };
  const std::size_t n = events.vertex.size();
  const std::int64_t budget = 8 * static_cast<std::int64_t>(n);
  bool full = order.size() != n;
  if (full)
  {
    order.resize(n);
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
  std::int64_t moves = 0;
  for (std::size_t i = 1; !full && !sorted && i < order.size(); ++i)
  {
    const std::uint32_t f = order[i];
    std::size_t j = i;
    for (; j > 0 && less(f, order[j - 1]); --j)
    {
      order[j] = order[j - 1];
    }
    order[j] = f;
    moves += static_cast<std::int64_t>(i - j);
    full = moves > budget;
  }
  if (full)
  {
    tbb::parallel_sort(order.begin(), order.end(), less);
  }
  return { moves, full ? 1 : 0 };
}

// 2. (the bins) Each tile's triangles in event order: the order cut into chunks, each
// chunk's triangles counted per tile and then written, in parallel, from where the chunks
// before it end in each tile's list.
TileBins binIntoTiles(const std::vector<std::uint32_t>& order,
  const TriangleEvents& events,
  const std::vector<ProjectedVertex>& proj,
  const TileGrid& grid)
{
  const std::size_t numTiles = grid.count();
  const std::size_t chunks = std::clamp<std::size_t>(order.size() / 8192, 1, 16);
  const std::size_t chunkSize = (order.size() + chunks - 1) / chunks;
  std::vector<std::size_t> chunkStart(chunks * numTiles, 0); // count, then write position
  TileBins bins;
  bins.start.assign(numTiles + 1, 0);
  const std::vector<std::int32_t>& box = events.box;
  auto forEachTileOf = [&](std::size_t c, auto&& visit) {
    const std::size_t end = std::min(order.size(), (c + 1) * chunkSize);
    for (std::size_t k = c * chunkSize; k < end; ++k)
    {
      const std::uint32_t f = order[k];
      if (box[4 * static_cast<std::size_t>(f)] < 0)
      {
        continue;
      }
      for (int ty = box[4 * f + 1] / grid.S; ty <= box[4 * f + 3] / grid.S; ++ty)
      {
        for (int tx = box[4 * f] / grid.S; tx <= box[4 * f + 2] / grid.S; ++tx)
        {
          visit(f, static_cast<std::size_t>(ty) * grid.nx + tx);
        }
      }
    }
  };
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    forEachTileOf(c, [&](std::uint32_t, std::size_t tile) { ++chunkStart[c * numTiles + tile]; });
  });
  for (std::size_t tile = 0; tile < numTiles; ++tile)
  {
    std::size_t at = bins.start[tile];
    for (std::size_t c = 0; c < chunks; ++c)
    {
      const std::size_t count = chunkStart[c * numTiles + tile];
      chunkStart[c * numTiles + tile] = at;
      at += count;
    }
    bins.start[tile + 1] = at;
  }
  bins.binned.resize(bins.start.back());
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    forEachTileOf(c, [&](std::uint32_t f, std::size_t tile) {
      bins.binned[chunkStart[c * numTiles + tile]++] =
        TriangleKey{ proj[events.vertex[f]].d, events.vertex[f], f };
    });
  });
  return bins;
}

// The triangles across the near plane, in the order of their vertex ids (a dense mesh's own
// order; a sparse mesh decodes its triangles in another): the caps' fans start at their
// first segment, so this order makes the caps the same for both.
std::vector<std::uint32_t> nearPlaneCrossings(
  const std::vector<ZSweepTriangle>& triangles, const std::vector<char>& crosses)
{
  std::vector<std::uint32_t> crossing;
  for (std::size_t f = 0; f < triangles.size(); ++f)
  {
    if (crosses[f])
    {
      crossing.push_back(static_cast<std::uint32_t>(f));
    }
  }
  std::sort(crossing.begin(), crossing.end(), [&](std::uint32_t a, std::uint32_t b) {
    return std::lexicographical_compare(
      triangles[a].v, triangles[a].v + 3, triangles[b].v, triangles[b].v + 3);
  });
  return crossing;
}

// The near-plane triangles binned into the tiles their boxes touch, each tile's in event order.
void binNearPlane(NearPlaneFaces& near, const TileGrid& grid, int W, int H)
{
  for (std::size_t e = 0; e < near.triangles.size(); ++e)
  {
    const auto& v = near.triangles[e].v;
    const std::array<int, 4> box = pixelBox(v[0], v[1], v[2], W, H);
    near.box.push_back(box);
    near.event.push_back(std::min({ v[0].d, v[1].d, v[2].d }));
    if (box[0] > box[2] || box[1] > box[3])
    {
      continue;
    }
    for (int ty = box[1] / grid.S; ty <= box[3] / grid.S; ++ty)
    {
      for (int tx = box[0] / grid.S; tx <= box[2] / grid.S; ++tx)
      {
        near.perTile[static_cast<std::size_t>(ty) * grid.nx + tx].push_back(
          static_cast<std::uint32_t>(e));
      }
    }
  }
  for (auto& list : near.perTile)
  {
    std::stable_sort(list.begin(), list.end(),
      [&](std::uint32_t a, std::uint32_t b) { return near.event[a] < near.event[b]; });
  }
}

// What the sweep of every tile reads: the frame's triangles, their events and bins, and
// the settings.
struct SweepInput
{
  const ZSweepMesh& mesh;
  const std::vector<ZSweepTriangle>& triangles;
  const std::vector<ProjectedVertex>& proj;
  const std::vector<double>& scalars;
  const TriangleEvents& events;
  const TileBins& bins;
  const NearPlaneFaces& near;
  const OpticalModel& optics;
  const RayCamera& camera;
  const float* opaqueDepth;
  const ZSweepParameters& params;
  TileGrid grid;
  int W, H;
  bool cellData;
  bool curved;              // the curved cells' own fields (IsoparametricCell.h)
  double curvedTolerance;   // their linearization's, in scalar units
  double tieT;        // crossings closer than this along a ray are one crossing
  double termination; // the opacity that ends a ray
};

// A triangle as the scan conversion takes it: its corners, their keys (global ids, for the
// shared-edge fill rule), their scalars, and the cells the rays enter and leave through it.
struct ScanTriangle
{
  const ProjectedVertex* v[3];
  std::uint64_t key[3];
  double s[3];
  std::int32_t entered, exited;
};

// 3.-5. The sweep of one tile: its events in order, each event's triangles scan converted
// into the pixels' lists, the lists composited up to the sweep plane when delayed
// compositing says so (section 4.2), the pixels' light written to the frame at the end.
class TileSweep
{
public:
  TileSweep(const SweepInput& in, TileWork& work, int tileIndex);
  void run(Frame& frame);

private:
  void startPixels();
  bool gather(PixelState& px, std::vector<Entry>& list, double tLimit);
  void pushCurved(const PixelState& px, std::int32_t slot, double tEnd);
  void composite(PixelState& px, std::size_t begin, std::size_t end);
  std::size_t flush(double depthLimit);
  void rasterize(ScanTriangle t, const int bounds[4]);
  void insertEntry(std::size_t p, const Entry& entry);
  void beforeEvent(double zv, double zFar);
  void sweepNearPlaneTriangle(std::uint32_t n);
  void sweepEvent(std::size_t begin, std::size_t end);
  void writePixels(Frame& frame) const;

  const SweepInput& In;
  TileWork& Work;
  const std::size_t Tile;
  const int X0, Y0, TW, TH;
  std::size_t K;
  bool OverK = false;
  double ZTarget = -std::numeric_limits<double>::infinity();
};

TileSweep::TileSweep(const SweepInput& in, TileWork& work, int tileIndex)
  : In(in)
  , Work(work)
  , Tile(static_cast<std::size_t>(tileIndex))
  , X0(tileIndex % in.grid.nx * in.grid.S)
  , Y0(tileIndex / in.grid.nx * in.grid.S)
  , TW(std::min(in.grid.S, in.W - X0))
  , TH(std::min(in.grid.S, in.H - Y0))
  , K(static_cast<std::size_t>(std::max(2, in.params.listThreshold)))
{
  startPixels();
}

// Each pixel's ray (its depth map) and where opaque geometry ends it; empty lists.
void TileSweep::startPixels()
{
  const std::size_t numPixels = static_cast<std::size_t>(TW) * TH;
  Work.lists.resize(std::max(Work.lists.size(), numPixels));
  Work.pixels.assign(numPixels, PixelState());
  Work.isDirty.assign(numPixels, 0);
  Work.dirty.clear();
  Work.ranges.resize(FlushChunk);
  for (int j = 0; j < TH; ++j)
  {
    for (int i = 0; i < TW; ++i)
    {
      PixelState& px = Work.pixels[static_cast<std::size_t>(j) * TW + i];
      const Ray ray = In.camera.pixelRay(X0 + i, Y0 + j);
      px.map = In.camera.depthMap(ray);
      px.org = Vec3d(ray.org);
      px.dir = Vec3d(ray.dir);
      if (In.opaqueDepth)
      {
        const float d = In.opaqueDepth[static_cast<std::size_t>(Y0 + j) * In.W + X0 + i];
        if (d < 1.f)
        {
          px.tOpaque = px.map.distanceOf(d);
        }
      }
    }
  }
}

// 5. Moves the final crossings of a pixel's list (tie groups wholly before distance tLimit)
// into segments of the batch: from the pixel's last crossing to each group's first; returns
// whether opaque geometry ends the ray there. The segment lies in the cell the ray entered
// at its start; a tie group (a ray through a shared vertex or edge) leaves the ray in the
// cell some member entered and no member left.
bool TileSweep::gather(PixelState& px, std::vector<Entry>& list, double tLimit)
{
  const double tieT = In.tieT;
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
    const std::int32_t slot = In.curved && px.cell >= 0 ? In.mesh.curvedSlot(px.cell) : -1;
    if (slot >= 0 && L > 0)
    {
      pushCurved(px, slot, tEnd);
    }
    else if (px.cell >= 0 && L > 0)
    {
      const double s0 = In.cellData ? In.scalars[static_cast<std::size_t>(px.cell)] : px.prevS;
      Work.batch.push(s0, In.cellData ? s0 : sEnd, L);
    }
    std::int32_t cell = list[j - 1].entered;
    if (j - i > 1)
    {
      // The cell some member entered and no member left.
      ++Work.counts.tieGroups;
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
}

// 5. A segment [px.prevT, tEnd] inside a curved cell: its field's linear pieces into the
// batch (one transparent piece when the transfer function is transparent over the corners'
// range, which bounds the field).
void TileSweep::pushCurved(const PixelState& px, std::int32_t slot, double tEnd)
{
  const IsoparametricCell cell = curvedCell(In.mesh, slot);
  ++Work.counts.curvedSegments;
  if (In.optics.transparentBetween(cell.fMin, cell.fMax))
  {
    Work.batch.push(cell.fMin, cell.fMin, tEnd - px.prevT);
    return;
  }
  linearizeAlongRay(cell, px.org, px.dir, px.prevT, tEnd, In.curvedTolerance, Work.batch,
    Work.counts.curved);
}

// 5. Composites the batch's segments [begin, end) behind the pixel's light, in order, up to
// the termination opacity.
void TileSweep::composite(PixelState& px, std::size_t begin, std::size_t end)
{
  const SegmentBatch& batch = Work.batch;
  for (std::size_t q = begin; q < end && !px.done; ++q)
  {
    ++Work.counts.segments;
    const SegmentLight seg{ batch.r[q], batch.g[q], batch.b[q], batch.transmittance[q] };
    if (seg.transmittance == 1.0 && seg.r == 0.0 && seg.g == 0.0 && seg.b == 0.0)
    {
      ++Work.counts.transparentSegments; // no opacity over the segment's scalars
      continue;
    }
    compositeBehind(px.light, seg);
    px.done = 1.0 - px.light.transmittance >= In.termination;
  }
}

// 4. Composites the dirty pixels' lists up to window depth depthLimit (everything when it
// is >= 1); returns the longest list left. The pixels go in chunks: a chunk's segments are
// gathered, integrated as one batch (independent of each other), then composited pixel by
// pixel in order.
std::size_t TileSweep::flush(double depthLimit)
{
  ++Work.counts.flushes;
  std::size_t longest = 0;
  std::size_t keep = 0;
  for (std::size_t c0 = 0; c0 < Work.dirty.size(); c0 += FlushChunk)
  {
    const std::size_t c1 = std::min(Work.dirty.size(), c0 + FlushChunk);
    Work.batch.clear();
    for (std::size_t k = c0; k < c1; ++k)
    {
      const std::size_t p = static_cast<std::size_t>(Work.dirty[k]);
      PixelState& px = Work.pixels[p];
      const double tLimit = depthLimit >= 1.0 ? std::numeric_limits<double>::infinity()
                                              : px.map.distanceOf(depthLimit);
      FlushRange& chunkRange = Work.ranges[k - c0];
      chunkRange.pixel = p;
      chunkRange.begin = Work.batch.size();
      chunkRange.opaque = gather(px, Work.lists[p], tLimit);
      chunkRange.end = Work.batch.size();
    }
    if (In.cellData)
    {
      In.optics.integrateHomogeneous(Work.batch);
    }
    else
    {
      In.optics.integrate(In.params.integrator, Work.batch);
    }
    for (std::size_t k = c0; k < c1; ++k)
    {
      const FlushRange& chunkRange = Work.ranges[k - c0];
      PixelState& px = Work.pixels[chunkRange.pixel];
      std::vector<Entry>& list = Work.lists[chunkRange.pixel];
      composite(px, chunkRange.begin, chunkRange.end);
      px.done = px.done || chunkRange.opaque;
      if (px.done)
      {
        list.clear();
      }
      longest = std::max(longest, list.size());
      if (!list.empty())
      {
        Work.dirty[keep++] = static_cast<int>(chunkRange.pixel);
      }
      else
      {
        Work.isDirty[chunkRange.pixel] = 0;
      }
    }
  }
  Work.dirty.resize(keep);
  return longest;
}

// 3. Scan converts one triangle into the tile's pixel lists (bounds: its pixel box). Each
// covered pixel centre gets an entry: the distance along its ray (the window depth is
// affine in the window), the scalar (perspective-correct), the cells on both sides.
void TileSweep::rasterize(ScanTriangle t, const int bounds[4])
{
  double area = orient(*t.v[0], *t.v[1], t.v[2]->x, t.v[2]->y);
  if (area == 0)
  {
    return; // seen edge on: covers no pixel centre
  }
  if (area < 0)
  {
    std::swap(t.v[1], t.v[2]);
    std::swap(t.key[1], t.key[2]);
    std::swap(t.s[1], t.s[2]);
    area = -area;
  }
  const ProjectedVertex &a = *t.v[0], &b = *t.v[1], &c = *t.v[2];
  const EdgeEquation edges[3] = { EdgeEquation(b, t.key[1], c, t.key[2]),
    EdgeEquation(c, t.key[2], a, t.key[0]), EdgeEquation(a, t.key[0], b, t.key[1]) };
  const double invArea = 1.0 / area;
  const int x0 = std::max(bounds[0], X0), x1 = std::min(bounds[2], X0 + TW - 1);
  const int y0 = std::max(bounds[1], Y0), y1 = std::min(bounds[3], Y0 + TH - 1);
  for (int y = y0; y <= y1; ++y)
  {
    const double py = y + 0.5;
    double rows[3];
    // The row's span inside all three edges (with narrow's margin): the exact test below
    // decides each pixel of it.
    double lo = x0 + 0.5, hi = x1 + 0.5; // pixel centres
    bool empty = false;
    for (int q = 0; q < 3; ++q)
    {
      rows[q] = edges[q].row(py);
      edges[q].narrow(rows[q], lo, hi, empty);
    }
    if (empty || lo > hi)
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
      const PixelState& pxs = Work.pixels[p];
      if (pxs.done)
      {
        continue;
      }
      // Barycentrics; depth is affine in the window, the scalar perspective-correct.
      const double la = eBC * invArea, lb = eCA * invArea, lc = eAB * invArea;
      const double d = la * a.d + lb * b.d + lc * c.d;
      double s = 0;
      if (!In.cellData)
      {
        const double wa = la * a.invW, wb = lb * b.invW, wc = lc * c.invW;
        s = (wa * t.s[0] + wb * t.s[1] + wc * t.s[2]) / (wa + wb + wc);
      }
      insertEntry(p, Entry{ pxs.map.distanceOf(d), s, t.entered, t.exited });
    }
  }
}

// 3. Inserts an entry into pixel p's depth-sorted list. Usually the sweep order puts it at
// the end (section 4.2); when it does not, pending entries beyond it are found by bisection.
void TileSweep::insertEntry(std::size_t p, const Entry& entry)
{
  std::vector<Entry>& list = Work.lists[p];
  auto pos = list.end();
  if (!list.empty() && list.back().t > entry.t)
  {
    pos = std::upper_bound(list.begin(), list.end(), entry.t,
      [](double v, const Entry& en) { return v < en.t; });
  }
  list.insert(pos, entry);
  ++Work.counts.entries;
  Work.counts.maxList = std::max(Work.counts.maxList, list.size());
  OverK = OverK || list.size() > K;
  if (!Work.isDirty[p])
  {
    Work.isDirty[p] = 1;
    Work.dirty.push_back(static_cast<int>(p));
  }
}

// 4. Delayed compositing before an event at depth zv whose triangles reach zFar: at the
// z-target, or when a list is longer than K, every list up to zv; the next z-target is
// the farthest vertex of the event's triangles.
void TileSweep::beforeEvent(double zv, double zFar)
{
  if (zv >= ZTarget || OverK)
  {
    const std::size_t longest = flush(zv);
    OverK = false;
    if (longest > K)
    {
      K *= 2; // the lists cannot be flushed below K yet (section 4.2)
      ++Work.counts.kGrowths;
    }
    ZTarget = std::max(zv, zFar);
  }
}

// 3. The event of near-plane triangle n (a clipped face or a cap): one triangle.
void TileSweep::sweepNearPlaneTriangle(std::uint32_t n)
{
  const DrawTriangle& t = In.near.triangles[n];
  beforeEvent(In.near.event[n], std::max({ t.v[0].d, t.v[1].d, t.v[2].d }));
  rasterize(ScanTriangle{ { &t.v[0], &t.v[1], &t.v[2] }, { t.key[0], t.key[1], t.key[2] },
              { t.s[0], t.s[1], t.s[2] }, t.entered, t.exited },
    In.near.box[n].data());
}

// 3. The event of the tile's binned triangles [begin, end): the ones whose nearest vertex
// is the same.
void TileSweep::sweepEvent(std::size_t begin, std::size_t end)
{
  const std::vector<TriangleKey>& binned = In.bins.binned;
  const std::vector<ProjectedVertex>& proj = In.proj;
  double zFar = binned[begin].depth;
  for (std::size_t k = begin; k < end; ++k)
  {
    const ZSweepTriangle& t = In.triangles[binned[k].triangle];
    zFar = std::max({ zFar, proj[t.v[0]].d, proj[t.v[1]].d, proj[t.v[2]].d });
  }
  beforeEvent(binned[begin].depth, zFar);
  for (std::size_t k = begin; k < end; ++k)
  {
    const std::uint32_t f = binned[k].triangle;
    const ZSweepTriangle& t = In.triangles[f];
    const std::uint32_t ia = t.v[0], ib = t.v[1], ic = t.v[2];
    const bool forward = In.events.forward[f];
    rasterize(ScanTriangle{ { &proj[ia], &proj[ib], &proj[ic] }, { ia, ib, ic },
                { In.cellData ? 0.0 : In.scalars[ia], In.cellData ? 0.0 : In.scalars[ib],
                  In.cellData ? 0.0 : In.scalars[ic] },
                forward ? t.back : t.front, forward ? t.front : t.back },
      &In.events.box[4 * f]);
  }
}

// The events of the mesh's triangles and of the near-plane triangles, merged in order;
// then everything left is final.
void TileSweep::run(Frame& frame)
{
  const std::vector<TriangleKey>& binned = In.bins.binned;
  const std::vector<std::uint32_t>& near = In.near.perTile[Tile];
  const std::size_t end = In.bins.start[Tile + 1];
  std::size_t e = In.bins.start[Tile], n = 0;
  while (e < end || n < near.size())
  {
    if (n < near.size() && (e >= end || In.near.event[near[n]] <= binned[e].depth))
    {
      sweepNearPlaneTriangle(near[n++]);
      continue;
    }
    std::size_t g = e + 1;
    while (g < end && binned[g].vertex == binned[e].vertex)
    {
      ++g;
    }
    sweepEvent(e, g);
    e = g;
  }
  flush(2.0); // everything is final at the end of the sweep
  writePixels(frame);
}

void TileSweep::writePixels(Frame& frame) const
{
  for (int j = 0; j < TH; ++j)
  {
    for (int i = 0; i < TW; ++i)
    {
      const PixelState& px = Work.pixels[static_cast<std::size_t>(j) * TW + i];
      float* out = &frame.rgba[4 * frame.index(X0 + i, Y0 + j)];
      out[0] = static_cast<float>(px.light.r);
      out[1] = static_cast<float>(px.light.g);
      out[2] = static_cast<float>(px.light.b);
      out[3] = static_cast<float>(1.0 - px.light.transmittance);
    }
  }
}

// 3.-5. The tiles swept in parallel (TBB); returns their counters summed.
SweepCounters sweepTiles(const SweepInput& in, Frame& frame)
{
  tbb::enumerable_thread_specific<TileWork> works;
  const int numTiles = in.grid.nx * in.grid.ny;
  tbb::parallel_for(tbb::blocked_range<int>(0, numTiles, 1), [&](const tbb::blocked_range<int>& range) {
    TileWork& work = works.local();
    for (int tileIndex = range.begin(); tileIndex != range.end(); ++tileIndex)
    {
      TileSweep(in, work, tileIndex).run(frame);
    }
  });
  SweepCounters total;
  for (const TileWork& w : works)
  {
    total.add(w.counts);
  }
  return total;
}
} // namespace

void renderZSweep(const ZSweepScene& scene,
  const View& view,
  const ZSweepParameters& params,
  Frame& frame,
  RenderStatistics& stats)
{
  RAYMAPPERS_SIMD_FORWARD(renderZSweep, scene, view, params, frame, stats);
  const ZSweepMesh& mesh = scene.mesh;
  const OpticalModel& optics = scene.optics;
  const int W = view.width(), H = view.height();
  frame.resize(W, H);
  const bool cellData = mesh.cellScalars();
  stats.setEffect("cell_data", cellData);
  stats.setEffect("early_termination", params.terminationOpacity < 1.0);
  stats.setEffect("sparse_mesh", mesh.sparse());
  if (W <= 0 || H <= 0 || mesh.numTriangles() == 0 || optics.empty())
  {
    return;
  }
  std::vector<ZSweepTriangle> decoded;
  const std::vector<ZSweepTriangle>& triangles = frameTriangles(mesh, decoded, stats);
  const RayCamera& camera = view.camera();
  const std::array<double, 16>& M = view.originRelativeClip();

  std::vector<ProjectedVertex> proj(mesh.points().size());
  {
    ScopedPhase phase(stats, "project");
    projectVertices(mesh.points(), M, W, H, proj);
  }
  const int S = std::max(8, params.tileSize);
  const TileGrid grid{ S, (W + S - 1) / S, (H + S - 1) / S };
  TriangleEvents events(triangles.size());
  {
    ScopedPhase phase(stats, "bin");
    findEvents(triangles, proj, mesh.points(), camera, W, H, events);
  }
  std::vector<std::uint32_t> localOrder;
  std::vector<std::uint32_t>& order =
    scene.previousOrder ? scene.previousOrder->triangles : localOrder;
  std::array<std::int64_t, 2> sorting;
  {
    ScopedPhase phase(stats, "order");
    sorting = sortEvents(order, events);
  }
  stats.addCounter("order_moves", sorting[0]);
  stats.addCounter("order_sorts", sorting[1]);
  TileBins bins;
  {
    ScopedPhase phase(stats, "bin");
    bins = binIntoTiles(order, events, proj, grid);
  }

  // A camera close to or inside the grid: the faces across the near plane clipped, and the
  // caps of the cells they bound.
  NearPlaneFaces near;
  near.perTile.resize(grid.count());
  const std::vector<std::uint32_t> crossing = nearPlaneCrossings(triangles, events.crosses);
  if (!crossing.empty())
  {
    ScopedPhase phase(stats, "near_plane");
    near.openCaps =
      nearPlaneTriangles(mesh, triangles, M, W, H, crossing, events.forward, near.triangles);
    binNearPlane(near, grid, W, H);
  }

  // Ties: crossings closer than this along a ray are one crossing (a shared vertex or edge).
  const double tieT = 1e-9 * std::max(mesh.extent(), 1e-300);
  const bool curved = params.cellField == ZSweepCellField::Native && mesh.keepsCurvedCells();
  stats.setEffect("curved_cells", curved);
  const double curvedTolerance =
    std::max(params.curvedTolerance, 1e-12) * std::max(mesh.scalarMax() - mesh.scalarMin(), 1e-300);
  const SweepInput in{ mesh, triangles, proj, mesh.scalars(), events, bins, near, optics, camera,
    view.opaqueDepth(), params, grid, W, H, cellData, curved, curvedTolerance, tieT,
    std::clamp(params.terminationOpacity, 0.0, 1.0) };
  SweepCounters counts;
  {
    ScopedPhase phase(stats, "sweep");
    counts = sweepTiles(in, frame);
  }
  stats.addCounter("triangles", static_cast<std::int64_t>(triangles.size()));
  stats.addCounter("decoded_triangles", static_cast<std::int64_t>(decoded.size()));
  stats.addCounter("binned_triangles", static_cast<std::int64_t>(bins.binned.size()));
  stats.addCounter("entries", counts.entries);
  stats.addCounter("flushes", counts.flushes);
  stats.addCounter("k_growths", counts.kGrowths);
  stats.addCounter("segments", counts.segments);
  stats.addCounter("transparent_segments", counts.transparentSegments);
  stats.addCounter("near_plane_triangles", static_cast<std::int64_t>(near.triangles.size()));
  stats.addCounter("open_caps", static_cast<std::int64_t>(near.openCaps));
  stats.addCounter("max_list", static_cast<std::int64_t>(counts.maxList));
  stats.addCounter("tie_groups", counts.tieGroups);
  stats.addCounter("curved_segments", counts.curvedSegments);
  stats.addCounter("curved_pieces", counts.curved.pieces);
  stats.addCounter("curved_evaluations", counts.curved.evaluations);
  stats.addCounter("curved_inversion_failures", counts.curved.failures);
}

RAYMAPPERS_SIMD_END

} // namespace raymappers
