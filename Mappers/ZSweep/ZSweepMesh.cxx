#include "Mappers/ZSweep/ZSweepMesh.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <bitset>
#include <cmath>
#include <limits>

namespace raymappers
{

namespace
{
// VTK's local faces of each cell type.
const ZSweepCellFaces TetraFaces = { 4,
  { 3, 3, 3, 3, 0, 0 },
  { { 0, 1, 3, 0 }, { 1, 2, 3, 0 }, { 2, 0, 3, 0 }, { 0, 2, 1, 0 }, {}, {} },
  4 };
const ZSweepCellFaces HexahedronFaces = { 6,
  { 4, 4, 4, 4, 4, 4 },
  { { 0, 4, 7, 3 }, { 1, 2, 6, 5 }, { 0, 1, 5, 4 }, { 3, 7, 6, 2 }, { 0, 3, 2, 1 }, { 4, 5, 6, 7 } },
  8 };
const ZSweepCellFaces WedgeFaces = { 5,
  { 3, 3, 4, 4, 4, 0 },
  { { 0, 1, 2, 0 }, { 3, 5, 4, 0 }, { 0, 3, 4, 1 }, { 1, 4, 5, 2 }, { 2, 5, 3, 0 }, {} },
  6 };
const ZSweepCellFaces PyramidFaces = { 5,
  { 4, 3, 3, 3, 3, 0 },
  { { 0, 3, 2, 1 }, { 0, 1, 4, 0 }, { 1, 2, 4, 0 }, { 2, 3, 4, 0 }, { 3, 0, 4, 0 }, {} },
  5 };

// Triangles a cell of each type yields (a quad gives two).
int trianglesOf(ZSweepCellType type)
{
  const ZSweepCellFaces& f = cellFaces(type);
  int n = 0;
  for (int i = 0; i < f.count; ++i)
  {
    n += f.sizes[i] - 2;
  }
  return n;
}

// Calls f(a, b, c) for each triangle of a cell (global vertex ids `ids` in VTK's order), in
// slot order: its faces in order, a quad split along the diagonal through its smallest
// global id into two triangles.
template <typename F>
void forEachTriangle(const ZSweepCellFaces& faces, const std::uint32_t* ids, F&& f)
{
  for (int i = 0; i < faces.count; ++i)
  {
    const int* l = faces.local[i];
    if (faces.sizes[i] == 3)
    {
      f(ids[l[0]], ids[l[1]], ids[l[2]]);
      continue;
    }
    const std::uint32_t q[4] = { ids[l[0]], ids[l[1]], ids[l[2]], ids[l[3]] };
    const int m = static_cast<int>(std::min_element(q, q + 4) - q);
    f(q[m], q[(m + 1) % 4], q[(m + 2) % 4]);
    f(q[m], q[(m + 2) % 4], q[(m + 3) % 4]);
  }
}

// The signed volume of a cell's surface as the renderer sees it (forEachTriangle's
// triangles, in their local winding: outward for a positively oriented cell), by the
// divergence theorem relative to the centroid c:
//   V = sum over the triangles (a, b, d) of (a - c) . ((b - c) x (d - c)) / 6,
// negative for an inverted cell (mirrored vertex order); and the surface's area. Unlike a
// test of each face against the centroid, the sign holds for cells that are not convex (a
// twisted frustum's centroid lies outside the planes of some of its triangles).
struct CellMeasure
{
  double volume = 0, area = 0;
};

CellMeasure measureCell(const ZSweepCellFaces& faces,
  const std::uint32_t* ids,
  const std::vector<Vec3d>& points,
  const Vec3d& centroid)
{
  CellMeasure m;
  forEachTriangle(faces, ids, [&](std::uint32_t a, std::uint32_t b, std::uint32_t d) {
    const Vec3d pa = points[a] - centroid, pb = points[b] - centroid, pd = points[d] - centroid;
    m.volume += dot(pa, cross(pb, pd));
    m.area += length(cross(pb - pa, pd - pa));
  });
  m.volume /= 6.0;
  m.area /= 2.0;
  return m;
}

// Whether sorting (a, b, d) ascending is an even permutation (keeps the triangle's winding).
bool sortKeepsWinding(std::uint32_t a, std::uint32_t b, std::uint32_t d)
{
  return ((a > b) + (a > d) + (b > d)) % 2 == 0;
}

// One cell's side of one triangle, keyed by the triangle's sorted vertex ids.
struct SideRecord
{
  std::uint32_t key[3];
  std::int32_t cell;
  std::int8_t side;   // +1: the cell is on the sorted triangle's normal side, -1: against it
  std::uint8_t slot;  // the triangle's slot in the cell (forEachTriangle's order)
};

bool keyLess(const SideRecord& a, const SideRecord& b)
{
  if (a.key[0] != b.key[0])
  {
    return a.key[0] < b.key[0];
  }
  if (a.key[1] != b.key[1])
  {
    return a.key[1] < b.key[1];
  }
  if (a.key[2] != b.key[2])
  {
    return a.key[2] < b.key[2];
  }
  return a.cell < b.cell;
}

bool sameKey(const SideRecord& a, const SideRecord& b)
{
  return a.key[0] == b.key[0] && a.key[1] == b.key[1] && a.key[2] == b.key[2];
}

constexpr double Big = std::numeric_limits<double>::max();

// The origin: the centre of the finite points' bounds (0 without any), and the extent: half
// the bounds' longest side. `relative`: the points relative to the origin.
void centreOnOrigin(
  const std::vector<Vec3d>& points, Vec3d& origin, double& extent, std::vector<Vec3d>& relative)
{
  Vec3d lo(Big, Big, Big), hi(-Big, -Big, -Big);
  for (const Vec3d& p : points)
  {
    if (isFinite(p))
    {
      lo = min(lo, p);
      hi = max(hi, p);
    }
  }
  origin = lo.x <= hi.x ? (lo + hi) * 0.5 : Vec3d(0, 0, 0);
  extent = lo.x <= hi.x ? 0.5 * std::max({ hi.x - lo.x, hi.y - lo.y, hi.z - lo.z }) : 0.0;
  relative.resize(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()),
    [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
      {
        relative[i] = points[i] - origin;
      }
    });
}

// Where each cell's side records go (fixed per type: one per triangle slot).
std::vector<std::size_t> sideRecordStarts(const std::vector<ZSweepCellType>& cellTypes)
{
  std::vector<std::size_t> start(cellTypes.size() + 1, 0);
  for (std::size_t c = 0; c < cellTypes.size(); ++c)
  {
    start[c + 1] = start[c] + static_cast<std::size_t>(trianglesOf(cellTypes[c]));
  }
  return start;
}

// What the checks of a cell find: the first problem, or that it is used.
enum class CellVerdict
{
  BadIndex,
  NonFinitePoint,
  NonFiniteScalar,
  ZeroVolume,
  Used
};

// Cell c's global vertex ids into `ids`; false when its size does not match its type or an
// id is out of range.
bool readCellIds(const ZSweepGrid& grid, std::size_t c, int vertices, std::uint32_t (&ids)[8])
{
  const std::int64_t begin = grid.cellOffsets[c];
  if (grid.cellOffsets[c + 1] - begin != vertices)
  {
    return false;
  }
  bool ok = true;
  for (int k = 0; k < vertices && ok; ++k)
  {
    const std::int64_t id = grid.connectivity[static_cast<std::size_t>(begin + k)];
    ok = id >= 0 && static_cast<std::size_t>(id) < grid.points.size();
    ids[k] = ok ? static_cast<std::uint32_t>(id) : 0;
  }
  return ok;
}

// Whether cell c's scalars (its own, or its vertices') are there and finite.
bool finiteScalars(const ZSweepGrid& grid, std::size_t c, int vertices, const std::uint32_t* ids)
{
  const std::vector<double>& scalars = grid.scalars;
  if (grid.cellScalars)
  {
    return c < scalars.size() && std::isfinite(scalars[c]);
  }
  bool ok = true;
  for (int k = 0; k < vertices && ok; ++k)
  {
    ok = ids[k] < scalars.size() && std::isfinite(scalars[ids[k]]);
  }
  return ok;
}

// The classification of cell c (ids: its vertex ids, read by readCellIds): finite points
// and scalars, and a volume that is not zero to the precision of its points (ZSweepMesh.h):
// |V| above both ZeroVolumeRatio D^3 (D: its bounding box's diagonal) and the rounding of
// the volume, sqrt(3) eps |p|max times its surface's area. `volume`: its signed volume.
CellVerdict classifyCell(const ZSweepGrid& grid,
  const std::vector<Vec3d>& points,
  std::size_t c,
  const ZSweepCellFaces& faces,
  const std::uint32_t* ids,
  double& volume)
{
  Vec3d centroid(0, 0, 0), cmin(Big, Big, Big), cmax(-Big, -Big, -Big);
  double magnitude = 0; // of the given coordinates
  bool ok = true;
  for (int k = 0; k < faces.vertices && ok; ++k)
  {
    const Vec3d& p = grid.points[ids[k]];
    ok = isFinite(p);
    magnitude = std::max({ magnitude, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z) });
    centroid = centroid + points[ids[k]];
    cmin = min(cmin, points[ids[k]]);
    cmax = max(cmax, points[ids[k]]);
  }
  if (!ok)
  {
    return CellVerdict::NonFinitePoint;
  }
  centroid = centroid * (1.0 / faces.vertices);
  if (!finiteScalars(grid, c, faces.vertices, ids))
  {
    return CellVerdict::NonFiniteScalar;
  }
  // A cell of zero volume adds nothing to any ray and is left out.
  const double extent = length(cmax - cmin);
  const CellMeasure measure = measureCell(faces, ids, points, centroid);
  volume = measure.volume;
  const double flat = std::max(ZSweepMesh::ZeroVolumeRatio * extent * extent * extent,
    std::sqrt(3.0) * grid.pointEpsilon * magnitude * measure.area);
  return std::fabs(volume) > flat ? CellVerdict::Used : CellVerdict::ZeroVolume;
}

// A used cell's side of each of its triangles, by slot into `out` (a triangle of zero area
// covers no pixel: its slot stays unused). `positive`: the cell's orientation.
void writeSideRecords(const ZSweepCellFaces& faces,
  const std::uint32_t* ids,
  const std::vector<Vec3d>& points,
  std::size_t c,
  bool positive,
  SideRecord* out)
{
  int slot = 0;
  forEachTriangle(faces, ids, [&](std::uint32_t a, std::uint32_t b, std::uint32_t d) {
    std::uint32_t k[3] = { a, b, d };
    std::sort(k, k + 3);
    const Vec3d& p0 = points[k[0]];
    const Vec3d e1 = points[k[1]] - p0, e2 = points[k[2]] - p0;
    SideRecord& rec = out[slot];
    rec.slot = static_cast<std::uint8_t>(slot++);
    if (!(length(cross(e1, e2)) > 1e-12 * length(e1) * length(e2)))
    {
      return;
    }
    std::copy(k, k + 3, rec.key);
    rec.cell = static_cast<std::int32_t>(c);
    // The sorted triangle's normal is the local winding's (outward for a positive cell) or,
    // after an odd permutation, its opposite.
    const bool normalOut = sortKeepsWinding(a, b, d) == positive;
    rec.side = normalOut ? -1 : 1;
  });
}

// The cells classified (in parallel): the side records of the used ones (`used[c]`), the
// others counted by their problem into `stats`.
void classifyCells(const ZSweepGrid& grid,
  const std::vector<Vec3d>& points,
  const std::vector<std::size_t>& recordStart,
  std::vector<SideRecord>& records,
  std::vector<char>& used,
  ZSweepMesh::Counts& stats)
{
  std::atomic<std::size_t> problems[4] = {}, inverted{ 0 }; // indexed by CellVerdict
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, used.size()),
    [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t c = r.begin(); c != r.end(); ++c)
      {
        SideRecord* out = records.data() + recordStart[c];
        for (std::size_t k = 0; k < recordStart[c + 1] - recordStart[c]; ++k)
        {
          out[k].cell = -1; // unused slot unless filled below
        }
        const ZSweepCellFaces& faces = cellFaces(grid.cellTypes[c]);
        std::uint32_t ids[8];
        double volume = 0;
        const CellVerdict verdict = readCellIds(grid, c, faces.vertices, ids)
          ? classifyCell(grid, points, c, faces, ids, volume)
          : CellVerdict::BadIndex;
        if (verdict != CellVerdict::Used)
        {
          ++problems[static_cast<int>(verdict)];
          continue;
        }
        inverted += !(volume > 0);
        used[c] = 1;
        writeSideRecords(faces, ids, points, c, volume > 0, out);
      }
    });
  stats.badIndex = problems[static_cast<int>(CellVerdict::BadIndex)];
  stats.nonFinitePoint = problems[static_cast<int>(CellVerdict::NonFinitePoint)];
  stats.nonFiniteScalar = problems[static_cast<int>(CellVerdict::NonFiniteScalar)];
  stats.zeroVolume = problems[static_cast<int>(CellVerdict::ZeroVolume)];
  stats.inverted = inverted;
  stats.cellsUsed = static_cast<std::size_t>(std::count(used.begin(), used.end(), 1));
}

// The end of the group of records with the key of records[i] (sorted by key).
std::size_t groupEnd(const std::vector<SideRecord>& records, std::size_t i)
{
  std::size_t j = i + 1;
  while (j < records.size() && sameKey(records[i], records[j]))
  {
    ++j;
  }
  return j;
}

// One triangle per key of the sorted records, with the cells on its two sides (the first
// of each side); counts the boundary and the non-manifold triangles.
void mergeSides(const std::vector<SideRecord>& records,
  std::vector<ZSweepTriangle>& triangles,
  ZSweepMesh::Counts& stats)
{
  triangles.clear();
  triangles.reserve(records.size() / 2 + 16);
  for (std::size_t i = 0; i < records.size();)
  {
    const std::size_t j = groupEnd(records, i);
    ZSweepTriangle t;
    std::copy(records[i].key, records[i].key + 3, t.v);
    t.front = -1;
    t.back = -1;
    for (std::size_t k = i; k < j; ++k)
    {
      std::int32_t& slot = records[k].side > 0 ? t.back : t.front;
      if (slot < 0)
      {
        slot = records[k].cell;
      }
    }
    if (j - i > 2 || (j - i == 2 && (t.front < 0 || t.back < 0)))
    {
      ++stats.nonManifoldTriangles;
    }
    if (t.front < 0 || t.back < 0)
    {
      ++stats.boundaryTriangles;
    }
    triangles.push_back(t);
    i = j;
  }
  triangles.shrink_to_fit();
}

// Sparsification's decision of each cell (section 4.3.5).
enum CellState : char
{
  Undecided,
  Essential,
  Dropped
};

// The dual graph: per cell, the cells across its triangles (CSR: cell c's are
// adjacent[start[c], start[c + 1])).
struct DualGraph
{
  std::vector<std::size_t> start;
  std::vector<std::int32_t> adjacent;
};

// The dual graph of the cells; a cell alone on a triangle (the boundary, or beside a
// skipped cell) is made essential in `state`.
DualGraph dualGraph(
  const std::vector<ZSweepTriangle>& triangles, std::size_t numCells, std::vector<char>& state)
{
  DualGraph g;
  g.start.assign(numCells + 1, 0);
  for (const ZSweepTriangle& t : triangles)
  {
    if (t.front >= 0 && t.back >= 0 && t.front != t.back)
    {
      ++g.start[static_cast<std::size_t>(t.front) + 1];
      ++g.start[static_cast<std::size_t>(t.back) + 1];
    }
    else
    {
      state[static_cast<std::size_t>(t.front >= 0 ? t.front : t.back)] = Essential;
    }
  }
  for (std::size_t c = 0; c < numCells; ++c)
  {
    g.start[c + 1] += g.start[c];
  }
  g.adjacent.resize(g.start[numCells]);
  std::vector<std::size_t> cursor(g.start.begin(), g.start.end() - 1);
  for (const ZSweepTriangle& t : triangles)
  {
    if (t.front >= 0 && t.back >= 0 && t.front != t.back)
    {
      g.adjacent[cursor[static_cast<std::size_t>(t.front)]++] = t.back;
      g.adjacent[cursor[static_cast<std::size_t>(t.back)]++] = t.front;
    }
  }
  return g;
}

// The greedy heuristic (section 4.3.5): drop an undecided cell and make its neighbours
// essential, until no cell is undecided. A neighbour is never one dropped before (that drop
// would have made this cell essential), so the dropped cells are independent, and every cell
// ends up dropped or essential (the dropped set is maximal). The next cell dropped is one
// with the fewest undecided neighbours (the minimum-degree greedy for independent sets: it
// removes the fewest candidates; in cell order, 68% of a lattice's tetrahedra stay), from
// buckets by that degree, entries made stale by a later change skipped.
void dropIndependentCells(const DualGraph& g, const std::vector<char>& used, std::vector<char>& state)
{
  const std::size_t numCells = used.size();
  std::vector<std::uint32_t> degree(numCells, 0);
  std::vector<std::vector<std::uint32_t>> buckets;
  auto push = [&](std::size_t c) {
    if (degree[c] >= buckets.size())
    {
      buckets.resize(degree[c] + 1);
    }
    buckets[degree[c]].push_back(static_cast<std::uint32_t>(c));
  };
  for (std::size_t c = 0; c < numCells; ++c)
  {
    if (used[c] && state[c] == Undecided)
    {
      for (std::size_t k = g.start[c]; k < g.start[c + 1]; ++k)
      {
        degree[c] += state[static_cast<std::size_t>(g.adjacent[k])] == Undecided;
      }
      push(c);
    }
  }
  for (std::size_t d = 0; d < buckets.size();)
  {
    if (buckets[d].empty())
    {
      ++d;
      continue;
    }
    const std::size_t c = buckets[d].back();
    buckets[d].pop_back();
    if (state[c] != Undecided || degree[c] != d)
    {
      continue; // decided, or its degree dropped since (it sits in a lower bucket too)
    }
    state[c] = Dropped;
    for (std::size_t k = g.start[c]; k < g.start[c + 1]; ++k)
    {
      const std::size_t n = static_cast<std::size_t>(g.adjacent[k]);
      if (state[n] != Undecided)
      {
        continue;
      }
      state[n] = Essential;
      for (std::size_t q = g.start[n]; q < g.start[n + 1]; ++q)
      {
        const std::size_t m = static_cast<std::size_t>(g.adjacent[q]);
        if (state[m] == Undecided)
        {
          --degree[m];
          push(m);
          d = std::min(d, static_cast<std::size_t>(degree[m]));
        }
      }
    }
  }
}

// Each cell's decision: the essential ones are kept, the dropped ones left out.
std::vector<char> decideCells(const std::vector<ZSweepTriangle>& triangles, const std::vector<char>& used)
{
  std::vector<char> state(used.size(), Undecided);
  const DualGraph g = dualGraph(triangles, used.size(), state);
  dropIndependentCells(g, used, state);
  return state;
}

// Who owns each triangle of a sparse mesh: per cell, the masks over its slots of the
// triangles it owns and of those it is the back cell of, and per slot the cell on the
// owned triangle's other side.
struct TriangleOwners
{
  std::vector<std::uint16_t> owned, back;
  std::vector<std::int32_t> otherAt; // indexed like the side records
};

// Each triangle is owned by a kept cell on one of its sides (the front one when both are
// kept); the owner's record in the triangle's group gives its slot.
TriangleOwners ownTriangles(const std::vector<SideRecord>& records,
  const std::vector<ZSweepTriangle>& triangles,
  const std::vector<char>& state,
  const std::vector<std::size_t>& recordStart)
{
  const std::size_t numCells = state.size();
  TriangleOwners o{ std::vector<std::uint16_t>(numCells, 0),
    std::vector<std::uint16_t>(numCells, 0), std::vector<std::int32_t>(recordStart[numCells], -1) };
  std::size_t tri = 0;
  for (std::size_t i = 0; i < records.size(); ++tri)
  {
    const std::size_t j = groupEnd(records, i);
    const ZSweepTriangle& t = triangles[tri];
    const bool frontOwns = t.front >= 0 && state[static_cast<std::size_t>(t.front)] == Essential;
    const std::int32_t owner = frontOwns ? t.front : t.back;
    const std::int8_t side = frontOwns ? -1 : 1;
    std::size_t k = i;
    while (records[k].cell != owner || records[k].side != side)
    {
      ++k; // the owner is the first cell of its side in the group: found before j
    }
    const std::uint16_t bit = static_cast<std::uint16_t>(1u << records[k].slot);
    o.owned[static_cast<std::size_t>(owner)] |= bit;
    if (!frontOwns)
    {
      o.back[static_cast<std::size_t>(owner)] |= bit;
    }
    o.otherAt[recordStart[static_cast<std::size_t>(owner)] + records[k].slot] =
      frontOwns ? t.back : t.front;
    i = j;
  }
  return o;
}
} // namespace

const ZSweepCellFaces& cellFaces(ZSweepCellType type)
{
  switch (type)
  {
    case ZSweepCellType::Hexahedron:
      return HexahedronFaces;
    case ZSweepCellType::Wedge:
      return WedgeFaces;
    case ZSweepCellType::Pyramid:
      return PyramidFaces;
    case ZSweepCellType::Tetra:
      break;
  }
  return TetraFaces;
}

std::size_t ZSweepMesh::memoryBytes() const
{
  return Points.capacity() * sizeof(Vec3d) + Triangles.capacity() * sizeof(ZSweepTriangle) +
    Scalars.capacity() * sizeof(double) + KeptIds.capacity() * sizeof(std::int32_t) +
    KeptTypes.capacity() * sizeof(ZSweepCellType) +
    KeptConnectivity.capacity() * sizeof(std::uint32_t) +
    (OwnedMask.capacity() + BackMask.capacity()) * sizeof(std::uint16_t) +
    Others.capacity() * sizeof(std::int32_t) + CurvedSlot.capacity() * sizeof(std::int32_t) +
    CurvedTypes.capacity() * sizeof(ZSweepCellType) +
    CurvedVertices.capacity() * sizeof(std::uint32_t);
}

const std::vector<ZSweepTriangle>& ZSweepMesh::triangles(std::vector<ZSweepTriangle>& scratch) const
{
  if (!Sparse)
  {
    return Triangles;
  }
  // Where each kept cell's vertices and owned triangles start.
  const std::size_t kept = KeptIds.size();
  std::vector<std::size_t> vertexStart(kept + 1, 0), triangleStart(kept + 1, 0);
  for (std::size_t k = 0; k < kept; ++k)
  {
    vertexStart[k + 1] = vertexStart[k] + static_cast<std::size_t>(cellFaces(KeptTypes[k]).vertices);
    triangleStart[k + 1] = triangleStart[k] + std::bitset<16>(OwnedMask[k]).count();
  }
  scratch.resize(NumTriangles);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kept),
    [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
      {
        std::size_t out = triangleStart[k];
        unsigned slot = 0;
        forEachTriangle(cellFaces(KeptTypes[k]), KeptConnectivity.data() + vertexStart[k],
          [&](std::uint32_t a, std::uint32_t b, std::uint32_t d) {
            const unsigned s = slot++;
            if (!(OwnedMask[k] >> s & 1u))
            {
              return;
            }
            ZSweepTriangle& t = scratch[out];
            t.v[0] = a;
            t.v[1] = b;
            t.v[2] = d;
            std::sort(t.v, t.v + 3);
            const bool isBack = BackMask[k] >> s & 1u;
            t.front = isBack ? Others[out] : KeptIds[k];
            t.back = isBack ? KeptIds[k] : Others[out];
            ++out;
          });
      }
    });
  return scratch;
}

void ZSweepMesh::build(const ZSweepGrid& grid, bool sparsify, bool keepCurved)
{
  Stats = Counts();
  CellScalars = grid.cellScalars;
  Scalars = grid.scalars;
  const std::size_t numCells = grid.cellTypes.size();
  NumCells = numCells;
  centreOnOrigin(grid.points, Origin, Extent, Points);

  // The faces: each used cell's side of each of its triangles, grouped by the triangle.
  const std::vector<std::size_t> recordStart = sideRecordStarts(grid.cellTypes);
  std::vector<SideRecord> records(recordStart[numCells]);
  std::vector<char> used(numCells, 0);
  classifyCells(grid, Points, recordStart, records, used, Stats);
  records.erase(std::remove_if(records.begin(), records.end(),
                  [](const SideRecord& r) { return r.cell < 0; }),
    records.end());
  tbb::parallel_sort(records.begin(), records.end(), keyLess);
  mergeSides(records, Triangles, Stats);
  NumTriangles = Triangles.size();
  Stats.cellsKept = Stats.cellsUsed;

  Sparse = false;
  KeptIds.clear();
  KeptTypes.clear();
  KeptConnectivity.clear();
  OwnedMask.clear();
  BackMask.clear();
  Others.clear();
  if (sparsify)
  {
    const std::vector<char> state = decideCells(Triangles, used);
    const TriangleOwners owners = ownTriangles(records, Triangles, state, recordStart);
    storeKeptCells(grid, used, state, recordStart, owners.owned, owners.back, owners.otherAt);
  }
  CurvedSlot.clear();
  CurvedTypes.clear();
  CurvedVertices.clear();
  if (keepCurved && !CellScalars)
  {
    keepCurvedCells(grid, used);
  }
  findScalarRange();
}

// The used hexahedra, wedges and pyramids: a slot each with the type and vertex ids.
void ZSweepMesh::keepCurvedCells(const ZSweepGrid& grid, const std::vector<char>& used)
{
  CurvedSlot.assign(grid.cellTypes.size(), -1);
  for (std::size_t c = 0; c < used.size(); ++c)
  {
    if (!used[c] || grid.cellTypes[c] == ZSweepCellType::Tetra)
    {
      continue;
    }
    CurvedSlot[c] = static_cast<std::int32_t>(CurvedTypes.size());
    CurvedTypes.push_back(grid.cellTypes[c]);
    const int n = cellFaces(grid.cellTypes[c]).vertices;
    for (int k = 0; k < 8; ++k)
    {
      CurvedVertices.push_back(static_cast<std::uint32_t>(
        grid.connectivity[static_cast<std::size_t>(grid.cellOffsets[c] + std::min(k, n - 1))]));
    }
  }
  CurvedTypes.shrink_to_fit();
  CurvedVertices.shrink_to_fit();
}

// The sparse store: the kept cells (used and essential) with their vertices, masks and
// owned triangles' other sides; the triangles themselves are let go.
void ZSweepMesh::storeKeptCells(const ZSweepGrid& grid,
  const std::vector<char>& used,
  const std::vector<char>& state,
  const std::vector<std::size_t>& recordStart,
  const std::vector<std::uint16_t>& owned,
  const std::vector<std::uint16_t>& back,
  const std::vector<std::int32_t>& otherAt)
{
  for (std::size_t c = 0; c < used.size(); ++c)
  {
    if (!used[c] || state[c] != Essential)
    {
      continue;
    }
    KeptIds.push_back(static_cast<std::int32_t>(c));
    KeptTypes.push_back(grid.cellTypes[c]);
    const int n = cellFaces(grid.cellTypes[c]).vertices;
    for (int k = 0; k < n; ++k)
    {
      KeptConnectivity.push_back(static_cast<std::uint32_t>(
        grid.connectivity[static_cast<std::size_t>(grid.cellOffsets[c] + k)]));
    }
    OwnedMask.push_back(owned[c]);
    BackMask.push_back(back[c]);
    for (std::size_t slot = 0; slot < recordStart[c + 1] - recordStart[c]; ++slot)
    {
      if (owned[c] >> slot & 1u)
      {
        Others.push_back(otherAt[recordStart[c] + slot]);
      }
    }
  }
  for (auto* v : { &KeptIds, &Others })
  {
    v->shrink_to_fit();
  }
  KeptTypes.shrink_to_fit();
  KeptConnectivity.shrink_to_fit();
  OwnedMask.shrink_to_fit();
  BackMask.shrink_to_fit();
  Triangles = std::vector<ZSweepTriangle>();
  Sparse = true;
  Stats.cellsKept = KeptIds.size();
}

// The range of the finite scalars (0, 0 without any).
void ZSweepMesh::findScalarRange()
{
  ScalarMin = std::numeric_limits<double>::max();
  ScalarMax = -std::numeric_limits<double>::max();
  for (const double s : Scalars)
  {
    if (std::isfinite(s))
    {
      ScalarMin = std::min(ScalarMin, s);
      ScalarMax = std::max(ScalarMax, s);
    }
  }
  if (ScalarMin > ScalarMax)
  {
    ScalarMin = ScalarMax = 0;
  }
}

} // namespace raymappers
