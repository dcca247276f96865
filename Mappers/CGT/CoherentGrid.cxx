#include "Mappers/CGT/CoherentGrid.h"
#include "Mappers/Common/PermuteInPlace.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

namespace raymappers
{

std::array<int, 3> CoherentGrid::cellOf(const Vec3f& p) const
{
  std::array<int, 3> c;
  for (int a = 0; a < 3; ++a)
  {
    const float g = (p[a] - Lower[a]) * InvCellSize; // as in build() and the traversal
    const int i = std::isfinite(g) ? static_cast<int>(std::floor(g)) : 0;
    c[a] = std::clamp(i, 0, Dims[a] - 1);
  }
  return c;
}

namespace
{
using Box = std::pair<Vec3f, Vec3f>;

// The bounds of the centres (a parallel reduction); a zero box without spheres.
Box centreBounds(const SphereSet& spheres)
{
  const std::size_t n = spheres.size();
  const float big = std::numeric_limits<float>::max();
  const Box empty(Vec3f(big, big, big), Vec3f(-big, -big, -big));
  const Box box = tbb::parallel_reduce(
    tbb::blocked_range<std::size_t>(0, n, 65536),
    empty,
    [&](const tbb::blocked_range<std::size_t>& range, Box b)
    {
      for (std::size_t i = range.begin(); i != range.end(); ++i)
      {
        const Vec3f& c = spheres.centers[i];
        for (int a = 0; a < 3; ++a)
        {
          b.first[a] = std::min(b.first[a], c[a]);
          b.second[a] = std::max(b.second[a], c[a]);
        }
      }
      return b;
    },
    [](Box a, const Box& b)
    {
      for (int k = 0; k < 3; ++k)
      {
        a.first[k] = std::min(a.first[k], b.first[k]);
        a.second[k] = std::max(a.second[k], b.second[k]);
      }
      return a;
    });
  return n == 0 ? Box(Vec3f(), Vec3f()) : box;
}

// The cell size (section 4.2): cubic cells of side h with about lambda * N cells over the
// extents that are not flat, h^d = (product of the d positive extents) / (lambda N).
double cellSide(const Box& box, std::size_t n, double lambda, float maxRadius)
{
  const Vec3f &lo = box.first, &hi = box.second;
  double volume = 1.0;
  int d = 0;
  double largest = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    const double e = static_cast<double>(hi[a]) - lo[a];
    largest = std::max(largest, e);
    if (e > 0)
    {
      volume *= e;
      ++d;
    }
  }
  double h = 1.0;
  if (d > 0 && n > 0)
  {
    h = std::pow(volume / (lambda * static_cast<double>(n)), 1.0 / d);
    // Never fewer cells along the largest extent than 1 (a single sphere: one cell).
    h = std::min(h, largest);
  }
  // Never cells smaller than the largest radius: each packet's cell range grows by r / h
  // cells on every side in a macrocell whose largest radius is r (the sphere-center method),
  // so a slice visits about (w + 2 r / h)^2 cells for a footprint of w cells, and cells much
  // smaller than r_max (spheres crowded far closer than their size, e.g. 10^7 centres in a
  // box of 1e-4 with r = 0.5) would make every packet walk the whole grid. With mixed radii
  // (large spheres in the sparse outskirts of a halo, small ones in its core) the floor r_max
  // rather than r_max / 2 halves the slices and the cells of each: measured at 1024^2, a
  // Plummer sphere of 10^7 with radii 0.0023 to 0.34 renders in 107 ms instead of 156 (and
  // a grid of 4.2 rather than 7.3 bytes per sphere), while 10^6 spheres crowded at radius 3 h
  // render alike (123-127 ms against 134-140).
  return std::max(h, static_cast<double>(maxRadius));
}

// The cells of side `side` that cover the box (at least one per axis).
std::array<int, 3> dimsFor(const Box& box, double side)
{
  std::array<int, 3> dims;
  for (int a = 0; a < 3; ++a)
  {
    const double e = static_cast<double>(box.second[a]) - box.first[a];
    dims[a] = std::max(1, static_cast<int>(std::ceil(e / side)));
  }
  return dims;
}

std::int64_t cellCount(const std::array<int, 3>& dims)
{
  return static_cast<std::int64_t>(dims[0]) * dims[1] * static_cast<std::int64_t>(dims[2]);
}

// Permutes the spheres into cell order, sphere i becoming input sphere perm[i], one array at
// a time: the build's peak holds one array twice, not the whole set.
void permute(SphereSet& spheres, const LargeBuffer<std::uint32_t>& perm)
{
  PermuteScratch scratch;
  permuteInPlace(spheres.centers, perm.data(), scratch);
  permuteInPlace(spheres.radii, perm.data(), scratch);
  permuteInPlace(spheres.colors, perm.data(), scratch);
  permuteInPlace(spheres.sourceIds, perm.data(), scratch);
  permuteInPlace(spheres.opacities, perm.data(), scratch);
  permuteInPlace(
    spheres.attributes, perm.data(), scratch, static_cast<std::size_t>(spheres.numAttributes));
}

// Widens the extrema mn, mx of the macrocell by the attributes of spheres [begin, end) (NaN
// values are left out).
void addExtrema(const SphereSet& spheres,
  std::uint32_t begin,
  std::uint32_t end,
  int numAttributes,
  float* mn,
  float* mx)
{
  for (std::uint32_t id = begin; id < end; ++id)
  {
    const float* v = spheres.attributesOf(id);
    for (int a = 0; a < numAttributes; ++a)
    {
      if (!std::isnan(v[a]))
      {
        mn[a] = std::min(mn[a], v[a]);
        mx[a] = std::max(mx[a], v[a]);
      }
    }
  }
}
}

void CoherentGrid::build(SphereSet& spheres, const CoherentGridParameters& params)
{
  NumSpheres = spheres.size();
  MaxRadius = spheres.maxRadius;
  MacroSize = std::max(1, params.macrocellSize);
  const Box box = centreBounds(spheres);
  Lower = box.first;
  const double lambda = params.lambda > 0 && std::isfinite(params.lambda) ? params.lambda : 1.0;
  double h = cellSide(box, NumSpheres, lambda, MaxRadius);
  Dims = dimsFor(box, h);
  while (cellCount(Dims) > params.maxCells)
  {
    h *= 1.25;
    Dims = dimsFor(box, h);
  }
  CellSize = static_cast<float>(h);
  InvCellSize = 1.f / CellSize;
  // Counting sort of the spheres by the cell of their centre, in parallel and stable (the
  // same order for any number of threads; see placeInCells).
  // The build's temporaries (sort pairs, permutation, one gathered array at a time) are
  // LargeBuffers, mapped on huge pages and freed when the build ends: between builds the grid
  // holds only its offsets and macrocells, and the SphereSet keeps its own memory (the
  // permutation copies back into it). The sort's (sphere, cell) pairs are freed before the
  // permutation, which holds one array twice.
  const LargeBuffer<std::uint32_t> perm = placeInCells(spheres);
  permute(spheres, perm);
  buildMacrocells(spheres);
  nestCrowdedCells(spheres, params);
}

const NestedCell* CoherentGrid::nestedCell(std::size_t macro, std::int64_t cell) const
{
  if (!MacroNested[macro])
  {
    return nullptr;
  }
  const auto it = std::lower_bound(Nested.begin(),
    Nested.end(),
    cell,
    [](const NestedCell& n, std::int64_t c) { return n.cell < c; });
  return it != Nested.end() && it->cell == cell ? &*it : nullptr;
}

std::uint64_t CoherentGrid::spheresInLeavesAbove(std::uint32_t limit) const
{
  std::uint64_t crowded = 0;
  // Only a macrocell holding more than `limit` spheres can hold such a leaf.
  for (std::size_t macro = 0; macro < MacroCount.size(); ++macro)
  {
    if (MacroCount[macro] <= limit)
    {
      continue;
    }
    forEachCell(macro,
      [&](std::int64_t c)
      {
        const std::uint32_t count = cellEnd(c) - cellBegin(c);
        const NestedCell* n = count > limit ? nestedCell(macro, c) : nullptr;
        if (n == nullptr)
        {
          crowded += count > limit ? count : 0;
          return;
        }
        const std::uint32_t* start = NestedStart.data() + n->offsets;
        for (std::size_t s = 0; s < static_cast<std::size_t>(n->m) * n->m * n->m; ++s)
        {
          const std::uint32_t inSubcell = start[s + 1] - start[s];
          crowded += inSubcell > limit ? inSubcell : 0;
        }
      });
  }
  return crowded;
}

namespace
{
// The subcells per side of a crowded cell of side h with `count` spheres: about lambda
// spheres' worth of subcells each (as the top level), never subcells smaller than half the
// cell's largest radius (a crowded cell's radii are alike: there the floor r / 2 and r
// measured the same on a Plummer sphere and a galpy halo), at most 64 per side.
int nestedSide(std::uint32_t count, double lambda, double h, float maxRadius)
{
  int m = static_cast<int>(std::lround(std::cbrt(lambda * static_cast<double>(count))));
  if (maxRadius > 0)
  {
    m = std::min(m, static_cast<int>(h / (0.5 * static_cast<double>(maxRadius))));
  }
  return std::min(m, 64);
}

// Reorders spheres [begin, begin + n) by a gather: new sphere begin + i is old sphere
// begin + from[i].
void gatherRange(SphereSet& spheres, std::uint32_t begin, const std::vector<std::uint32_t>& from)
{
  const std::size_t n = from.size();
  const int na = spheres.numAttributes;
  auto reorder = [&](auto& values, std::size_t width)
  {
    using T = typename std::decay_t<decltype(values)>::value_type;
    std::vector<T> copy(values.begin() + begin * width, values.begin() + (begin + n) * width);
    for (std::size_t i = 0; i < n; ++i)
    {
      for (std::size_t w = 0; w < width; ++w)
      {
        values[(begin + i) * width + w] = copy[from[i] * width + w];
      }
    }
  };
  reorder(spheres.centers, 1);
  reorder(spheres.radii, 1);
  reorder(spheres.colors, 1);
  reorder(spheres.sourceIds, 1);
  if (!spheres.opacities.empty())
  {
    reorder(spheres.opacities, 1);
  }
  if (na > 0)
  {
    reorder(spheres.attributes, static_cast<std::size_t>(na));
  }
}
}

void CoherentGrid::nestCrowdedCells(SphereSet& spheres, const CoherentGridParameters& params)
{
  MacroNested.assign(MacroCount.size(), 0);
  Nested = crowdedCells(spheres, params);
  std::size_t total = 0;
  for (NestedCell& n : Nested)
  {
    n.offsets = static_cast<std::uint32_t>(total);
    total += static_cast<std::size_t>(n.m) * n.m * n.m + 1;
  }
  NestedStart.assign(total, 0u);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, Nested.size(), 1),
    [&](const tbb::blocked_range<std::size_t>& range)
    {
      for (std::size_t q = range.begin(); q != range.end(); ++q)
      {
        sortIntoSubcells(spheres, Nested[q]);
      }
    });
}

std::vector<NestedCell> CoherentGrid::crowdedCells(const SphereSet& spheres,
  const CoherentGridParameters& params)
{
  std::vector<NestedCell> crowded;
  const std::uint32_t threshold = params.nestThreshold;
  const double lambda = params.lambda > 0 && std::isfinite(params.lambda) ? params.lambda : 1.0;
  // In cell order; only a macrocell holding more than the threshold can have one.
  for (std::size_t macro = 0; threshold > 0 && macro < MacroCount.size(); ++macro)
  {
    if (MacroCount[macro] <= threshold)
    {
      continue;
    }
    forEachCell(macro,
      [&](std::int64_t c)
      {
        const std::uint32_t count = cellEnd(c) - cellBegin(c);
        if (count <= threshold)
        {
          return;
        }
        float rMax = 0.f;
        for (std::uint32_t id = cellBegin(c); id < cellEnd(c); ++id)
        {
          rMax = std::max(rMax, spheres.radii[id]);
        }
        const int m = nestedSide(count, lambda, CellSize, rMax);
        if (m >= 2)
        {
          crowded.push_back({ c, m, rMax, 0 });
          MacroNested[macro] = 1;
        }
      });
  }
  std::sort(crowded.begin(),
    crowded.end(),
    [](const NestedCell& a, const NestedCell& b) { return a.cell < b.cell; });
  return crowded;
}

void CoherentGrid::sortIntoSubcells(SphereSet& spheres, const NestedCell& n)
{
  const std::int64_t c = n.cell;
  const std::array<int, 3> ijk{ static_cast<int>(c % Dims[0]),
    static_cast<int>((c / Dims[0]) % Dims[1]),
    static_cast<int>(c / Dims[0] / Dims[1]) };
  const std::uint32_t begin = cellBegin(c), end = cellEnd(c);
  const int m = n.m;
  const std::size_t subcells = static_cast<std::size_t>(m) * m * m;
  std::uint32_t* start = NestedStart.data() + n.offsets;
  // The subcell of each sphere: the traversal's grid coordinate (p - lower) / h, its
  // fraction inside the cell in subcells; then a counting sort in input order (stable).
  std::vector<std::uint32_t> sub(end - begin);
  for (std::uint32_t id = begin; id < end; ++id)
  {
    int a[3];
    for (int axis = 0; axis < 3; ++axis)
    {
      const float g = (spheres.centers[id][axis] - Lower[axis]) * InvCellSize;
      const float f = (g - static_cast<float>(ijk[axis])) * static_cast<float>(m);
      a[axis] = std::clamp(static_cast<int>(std::floor(f)), 0, m - 1);
    }
    sub[id - begin] = static_cast<std::uint32_t>((a[2] * m + a[1]) * m + a[0]);
    ++start[sub[id - begin] + 1];
  }
  start[0] = begin;
  for (std::size_t i = 0; i < subcells; ++i)
  {
    start[i + 1] += start[i];
  }
  std::vector<std::uint32_t> cursor(start, start + subcells);
  std::vector<std::uint32_t> from(end - begin);
  for (std::uint32_t i = 0; i < end - begin; ++i)
  {
    from[cursor[sub[i]]++ - begin] = i;
  }
  gatherRange(spheres, begin, from);
}

LargeBuffer<std::uint32_t> CoherentGrid::placeInCells(const SphereSet& spheres)
{
  // A stable counting sort by cell in two passes, neither with atomics nor with random
  // access to a cell-sized array: first into slabs, then each slab on its own into its
  // cells. A one-pass scatter touches a random cell counter and a random slot per sphere,
  // which at 10^7 cells is two cache misses per sphere (measured: 0.6 s of a 1.2 s build of
  // 10M spheres). A slab is a run of whole x rows of cells (rows j + Dims[1] k, each a
  // contiguous range of cells), about TargetSlabs of them: enough tasks for the threads
  // also when the grid is one z layer thick (slabs of whole z layers left the sort of the
  // flat 317,284-atom crack to one thread, 7.5 ms), and few enough output streams for the
  // scatter into slabs. A small set gets one slab per SpheresPerSlab spheres: 256 tasks of
  // a few spheres each were 30 of the 57 us of 2LYZ's grid (1,102 atoms). The order is the
  // same for any slab count (the sort is stable).
  const std::size_t rows = static_cast<std::size_t>(Dims[1]) * static_cast<std::size_t>(Dims[2]);
  const std::size_t targetSlabs =
    std::clamp<std::size_t>(NumSpheres / SpheresPerSlab, 1, TargetSlabs);
  const std::size_t rowsPerSlab = (rows + targetSlabs - 1) / targetSlabs;
  CellSlabs slabs;
  slabs.cells = rowsPerSlab * static_cast<std::size_t>(Dims[0]);
  slabs.count = static_cast<int>((rows + rowsPerSlab - 1) / rowsPerSlab);
  const LargeBuffer<CellOfSphere> bySlab = sortIntoSlabs(spheres, slabs);
  CellStart.assign(static_cast<std::size_t>(cellCount(Dims)) + 1, 0u);
  LargeBuffer<std::uint32_t> perm(NumSpheres);
  tbb::parallel_for(tbb::blocked_range<int>(0, slabs.count, 1),
    [&](const tbb::blocked_range<int>& range)
    {
      for (int s = range.begin(); s != range.end(); ++s)
      {
        sortSlab(bySlab, slabs, s, perm);
      }
    });
  return perm;
}

LargeBuffer<CoherentGrid::CellOfSphere> CoherentGrid::sortIntoSlabs(const SphereSet& spheres,
  CellSlabs& slabs) const
{
  // Fixed chunks of the input (the same for any number of threads), a histogram of slabs
  // per chunk, their exclusive prefix sum in (slab, chunk) order, and a scatter of each
  // chunk into its own offsets: the spheres of a slab stay in input order.
  const std::size_t n = NumSpheres;
  const std::size_t chunkSize = std::max<std::size_t>(65536, (n + 255) / 256);
  const std::size_t chunks = (n + chunkSize - 1) / chunkSize;
  const std::size_t cellsPerSlab = slabs.cells;
  auto slabOf = [&](std::uint32_t cell) { return static_cast<std::size_t>(cell / cellsPerSlab); };
  std::vector<std::uint32_t> offsets(chunks * slabs.count, 0u);
  auto eachChunk = [&](auto&& body)
  {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1),
      [&](const tbb::blocked_range<std::size_t>& range)
      {
        for (std::size_t t = range.begin(); t != range.end(); ++t)
        {
          std::uint32_t* own = offsets.data() + t * slabs.count;
          for (std::size_t i = t * chunkSize; i < std::min(n, (t + 1) * chunkSize); ++i)
          {
            body(own, static_cast<std::uint32_t>(i), cellOfCentre(spheres.centers[i]));
          }
        }
      });
  };
  eachChunk([&](std::uint32_t* own, std::uint32_t, std::uint32_t cell) { ++own[slabOf(cell)]; });
  slabs.start.assign(static_cast<std::size_t>(slabs.count) + 1, 0u);
  std::uint32_t total = 0;
  for (int s = 0; s < slabs.count; ++s)
  {
    slabs.start[s] = total;
    for (std::size_t t = 0; t < chunks; ++t)
    {
      const std::uint32_t count = offsets[t * slabs.count + s];
      offsets[t * slabs.count + s] = total;
      total += count;
    }
  }
  slabs.start[slabs.count] = total;
  LargeBuffer<CellOfSphere> bySlab(n);
  eachChunk([&](std::uint32_t* own, std::uint32_t i, std::uint32_t cell)
    { bySlab[own[slabOf(cell)]++] = { i, cell }; });
  return bySlab;
}

void CoherentGrid::sortSlab(const LargeBuffer<CellOfSphere>& bySlab,
  const CellSlabs& slabs,
  int s,
  LargeBuffer<std::uint32_t>& perm)
{
  // The slab's cells [first, last) are its own: counts in CellStart[c + 1], turned into the
  // cells' first slots from the slab's start, each advanced past its spheres by the scatter
  // (in input order), so that CellStart[c + 1] ends as cell c's end.
  const std::size_t first = static_cast<std::size_t>(s) * slabs.cells;
  const std::size_t last = std::min(first + slabs.cells, static_cast<std::size_t>(cellCount(Dims)));
  const CellOfSphere* begin = bySlab.data() + slabs.start[s];
  const CellOfSphere* end = bySlab.data() + slabs.start[s + 1];
  std::uint32_t* next = CellStart.data() + 1;
  for (const CellOfSphere* e = begin; e != end; ++e)
  {
    ++next[e->cell];
  }
  std::uint32_t run = slabs.start[s];
  for (std::size_t c = first; c < last; ++c)
  {
    const std::uint32_t count = next[c];
    next[c] = run;
    run += count;
  }
  for (const CellOfSphere* e = begin; e != end; ++e)
  {
    perm[next[e->cell]++] = e->sphere;
  }
}

void CoherentGrid::buildMacrocells(const SphereSet& spheres)
{
  for (int a = 0; a < 3; ++a)
  {
    MacroDims[a] = (Dims[a] + MacroSize - 1) / MacroSize;
  }
  const std::size_t macros =
    static_cast<std::size_t>(MacroDims[0]) * MacroDims[1] * static_cast<std::size_t>(MacroDims[2]);
  MacroCount.assign(macros, 0);
  MacroMaxRadius.assign(macros, 0.f);
  NumAttributes = spheres.numAttributes;
  MacroMin.assign(macros * NumAttributes, std::numeric_limits<float>::max());
  MacroMax.assign(macros * NumAttributes, -std::numeric_limits<float>::max());
  OccupiedWords = (static_cast<std::size_t>(MacroSize) * MacroSize * MacroSize + 63) / 64;
  MacroOccupied.assign(macros * OccupiedWords, 0);
  // One task per row of macrocells along x (macrocell rows mj + MacroDims[1] mk): each
  // macrocell is written by one task only, and a grid one macrocell thick (a flat crystal)
  // still has many rows. Within a macrocell, each x row of its cells is one contiguous run of
  // cells and of spheres. A task takes rows of about SpheresPerMacroTask spheres on average:
  // one task per row made 2LYZ's (1,102 atoms) macrocells cost 22-40 us instead of 4 us.
  const int rowCount = MacroDims[1] * MacroDims[2];
  const auto rowsPerTask = static_cast<int>(std::clamp<std::size_t>(
    SpheresPerMacroTask * static_cast<std::size_t>(rowCount) /
      std::max<std::size_t>(NumSpheres, 1),
    1,
    static_cast<std::size_t>(rowCount)));
  tbb::parallel_for(tbb::blocked_range<int>(0, rowCount, rowsPerTask),
    [&](const tbb::blocked_range<int>& macroRows)
    {
      for (int row = macroRows.begin(); row != macroRows.end(); ++row)
      {
        const int mj = row % MacroDims[1], mk = row / MacroDims[1];
        for (int k = mk * MacroSize; k < std::min(Dims[2], (mk + 1) * MacroSize); ++k)
        {
          for (int j = mj * MacroSize; j < std::min(Dims[1], (mj + 1) * MacroSize); ++j)
          {
            const int bitRow = ((k - mk * MacroSize) * MacroSize + (j - mj * MacroSize)) * MacroSize;
            for (int mi = 0; mi < MacroDims[0]; ++mi)
            {
              const int i = mi * MacroSize;
              addRunToMacrocell(spheres,
                macrocellIndex(mi, mj, mk),
                cellIndex(i, j, k),
                std::min(MacroSize, Dims[0] - i),
                bitRow);
            }
          }
        }
      }
    });
}

void CoherentGrid::addRunToMacrocell(const SphereSet& spheres,
  std::size_t m,
  std::int64_t first,
  int cells,
  int bitRow)
{
  const std::uint32_t begin = cellBegin(first), end = cellEnd(first + cells - 1);
  if (begin == end)
  {
    return;
  }
  MacroCount[m] += end - begin;
  for (int t = 0; t < cells; ++t)
  {
    if (cellEnd(first + t) != cellBegin(first + t))
    {
      const int bit = bitRow + t;
      MacroOccupied[m * OccupiedWords + bit / 64] |= std::uint64_t(1) << (bit % 64);
    }
  }
  for (std::uint32_t id = begin; id < end; ++id)
  {
    MacroMaxRadius[m] = std::max(MacroMaxRadius[m], spheres.radii[id]);
  }
  addExtrema(spheres,
    begin,
    end,
    NumAttributes,
    MacroMin.data() + m * NumAttributes,
    MacroMax.data() + m * NumAttributes);
}

} // namespace raymappers
