// The multi-level grid of the coherent grid traversal for spheres (Gribble et al. 2007,
// section 4.2), with the sphere-center method (section 4.1): every sphere is stored once,
// in the cell that holds its centre, so the grid holds no duplicated references and needs
// no mailboxes. The finest level has about lambda * N cubic cells (never smaller than half
// the largest radius, where crowded spheres would make them tiny); a second level of
// macrocells (M x M x M cells each) records which blocks are empty, their largest radius,
// and the extrema of each sphere attribute inside them, so traversal skips empty blocks and blocks
// whose spheres all fail a parameter range (section 4.3).
//
// The build sorts the spheres into cell order with a parallel counting sort that keeps the
// input order inside a cell (the same result for any number of threads): cell c
// owns the spheres [cellStart[c], cellStart[c + 1]) of the permuted SphereSet, whose
// sourceIds still name each sphere's input point. Besides the permuted
// spheres the grid costs one 32-bit offset per cell and one count per macrocell.
#ifndef RayMappers_CoherentGrid_h
#define RayMappers_CoherentGrid_h

#include "Mappers/CGT/SphereSet.h"
#include "Mappers/Common/LargeBuffer.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace raymappers
{

struct CoherentGridParameters
{
  double lambda = 1.0;                           // cells per sphere (the paper's finding: 1)
  int macrocellSize = 6;                         // cells per macrocell side (the paper's 6)
  std::int64_t maxCells = std::int64_t(1) << 27; // memory guard
  /// Cells holding more spheres than this get a nested grid of their own (0: never).
  std::uint32_t nestThreshold = 64;
};

/// A cell refined into m x m x m subcells of side h / m (clustered data: the cells of a
/// dense core hold far more than 1 / lambda spheres). Its spheres stay in the cell's range,
/// ordered by subcell: subcell (a, b, c) holds [start[i], start[i + 1]), i = (c m + b) m + a,
/// start = the grid's nested offsets from `offsets`.
struct NestedCell
{
  std::int64_t cell;     // the parent cell's index
  int m;                 // subcells per side
  float maxRadius;       // the cell's largest radius
  std::uint32_t offsets; // index of its m^3 + 1 offsets in CoherentGrid's nested offsets
};

class CoherentGrid
{
public:
  /// Builds the grid over `spheres`, permuting them into cell order in place.
  void build(SphereSet& spheres, const CoherentGridParameters& params);

  bool empty() const { return NumSpheres == 0; }
  const std::array<int, 3>& dims() const { return Dims; }
  const std::array<int, 3>& macroDims() const { return MacroDims; }
  int macrocellSize() const { return MacroSize; }
  const Vec3f& lower() const { return Lower; } // grid origin, origin-relative coordinates
  float cellSize() const { return CellSize; }
  float inverseCellSize() const { return InvCellSize; }
  float maxRadius() const { return MaxRadius; }

  std::int64_t cellIndex(int i, int j, int k) const
  {
    return (static_cast<std::int64_t>(k) * Dims[1] + j) * Dims[0] + i;
  }
  std::uint32_t cellBegin(std::int64_t c) const { return CellStart[static_cast<std::size_t>(c)]; }
  std::uint32_t cellEnd(std::int64_t c) const { return CellStart[static_cast<std::size_t>(c) + 1]; }
  std::size_t macrocellIndex(int mi, int mj, int mk) const
  {
    return (static_cast<std::size_t>(mk) * MacroDims[1] + mj) * MacroDims[0] + mi;
  }
  bool macrocellEmpty(std::size_t m) const { return MacroCount[m] == 0; }
  /// Whether cell (a, b, c) of macrocell m (its own coordinates, 0..M-1) holds spheres: one
  /// bit per cell beside the macrocell, so the traversal of a sparse macrocell reads neither
  /// the offsets of its empty cells nor their cache lines.
  bool cellOccupied(std::size_t m, int a, int b, int c) const
  {
    const std::size_t bit = (static_cast<std::size_t>(c) * MacroSize + b) * MacroSize + a;
    return (MacroOccupied[m * OccupiedWords + bit / 64] >> (bit % 64)) & 1u;
  }
  /// The largest radius of the macrocell's spheres (0 when empty): its own sphere-center
  /// shift, smaller than the grid's r_max where small spheres crowd (mixed radii).
  float macrocellMaxRadius(std::size_t m) const { return MacroMaxRadius[m]; }
  /// Whether some sphere of the macrocell can pass the filter (its stored extrema overlap
  /// the ranges: section 4.3's macrocell culling).
  bool macrocellInRange(std::size_t m, const RangeFilter& filter) const
  {
    return filter.overlaps(&MacroMin[m * NumAttributes], &MacroMax[m * NumAttributes]);
  }

  /// The nested grid of cell `cell` of macrocell `macro`, or nullptr when it has none.
  const NestedCell* nestedCell(std::size_t macro, std::int64_t cell) const;
  /// The spheres [first, second) of subcell (a, b, c) of nested cell n.
  std::pair<std::uint32_t, std::uint32_t> nestedRange(const NestedCell& n,
    int a,
    int b,
    int c) const
  {
    const std::size_t i = n.offsets + (static_cast<std::size_t>(c) * n.m + b) * n.m + a;
    return { NestedStart[i], NestedStart[i + 1] };
  }
  std::size_t nestedCellCount() const { return Nested.size(); }

  /// The spheres of the leaves (cells without a nested grid, and subcells) that hold more
  /// than `limit` spheres: every ray reaching such a leaf tests them all, so their share of
  /// the set measures how far this grid failed to separate the data (spheres of one point,
  /// or crowded far closer than their radius, where no subcell may be smaller than r / 2).
  std::uint64_t spheresInLeavesAbove(std::uint32_t limit) const;

  /// Cell of a point (origin-relative), clamped to the grid.
  std::array<int, 3> cellOf(const Vec3f& p) const;

  /// Bytes held by the grid itself (offsets and macrocells), not the spheres.
  std::size_t memoryBytes() const
  {
    return CellStart.size() * sizeof(std::uint32_t) + MacroCount.size() * sizeof(std::uint32_t) +
           (MacroMaxRadius.size() + MacroMin.size() + MacroMax.size()) * sizeof(float) +
           MacroNested.size() + MacroOccupied.size() * sizeof(std::uint64_t) +
           Nested.size() * sizeof(NestedCell) +
           NestedStart.size() * sizeof(std::uint32_t);
  }

private:
  // The phases of build() (section 4.2) after the cell size: the placement (the cells'
  // offsets and the permutation into cell order, by a counting sort into slabs of whole rows
  // of cells, then of each slab into its cells) and the macrocells with their attribute
  // extrema.
  struct CellOfSphere
  {
    std::uint32_t sphere, cell;
  };
  struct CellSlabs
  {
    std::size_t cells = 1;            // cells per slab (whole x rows)
    int count = 1;                    // slabs
    std::vector<std::uint32_t> start; // the spheres of slab s: [start[s], start[s + 1])
  };
  static constexpr int TargetSlabs = 256;
  // A small set gets fewer tasks: slabs of at least about SpheresPerSlab spheres, macrocell
  // rows of about SpheresPerMacroTask per task (a second task wakes a worker: 20-40 us).
  static constexpr std::size_t SpheresPerSlab = 1024;
  static constexpr std::size_t SpheresPerMacroTask = 4096;
  // The cell of a centre (finite, inside [Lower, Lower + Dims * h]; the clamp catches the
  // upper faces and rounding).
  std::uint32_t cellOfCentre(const Vec3f& p) const
  {
    const int ci = std::min(static_cast<int>((p.x - Lower.x) * InvCellSize), Dims[0] - 1);
    const int cj = std::min(static_cast<int>((p.y - Lower.y) * InvCellSize), Dims[1] - 1);
    const int ck = std::min(static_cast<int>((p.z - Lower.z) * InvCellSize), Dims[2] - 1);
    return static_cast<std::uint32_t>(
      cellIndex(std::max(ci, 0), std::max(cj, 0), std::max(ck, 0)));
  }
  LargeBuffer<std::uint32_t> placeInCells(const SphereSet& spheres);
  LargeBuffer<CellOfSphere> sortIntoSlabs(const SphereSet& spheres, CellSlabs& slabs) const;
  void sortSlab(const LargeBuffer<CellOfSphere>& bySlab,
    const CellSlabs& slabs,
    int s,
    LargeBuffer<std::uint32_t>& perm);
  void buildMacrocells(const SphereSet& spheres);
  // Adds the spheres of `cells` cells from cell `first` on, one x row of macrocell m whose
  // occupancy bits start at bitRow, to the macrocell: count, occupancy bits, largest radius,
  // attribute extrema.
  void addRunToMacrocell(const SphereSet& spheres,
    std::size_t m,
    std::int64_t first,
    int cells,
    int bitRow);
  // Calls f(c) for the index c of every cell of macrocell `macro`.
  template<typename F>
  void forEachCell(std::size_t macro, F&& f) const
  {
    const int mi = static_cast<int>(macro % MacroDims[0]);
    const int mj = static_cast<int>((macro / MacroDims[0]) % MacroDims[1]);
    const int mk = static_cast<int>(macro / MacroDims[0] / MacroDims[1]);
    for (int k = mk * MacroSize; k < std::min(Dims[2], (mk + 1) * MacroSize); ++k)
      for (int j = mj * MacroSize; j < std::min(Dims[1], (mj + 1) * MacroSize); ++j)
        for (int i = mi * MacroSize; i < std::min(Dims[0], (mi + 1) * MacroSize); ++i)
        {
          f(cellIndex(i, j, k));
        }
  }
  // The nested grids of the crowded cells, after the placement: each one's spheres are
  // ordered by subcell (a stable counting sort inside the cell's range).
  void nestCrowdedCells(SphereSet& spheres, const CoherentGridParameters& params);
  std::vector<NestedCell> crowdedCells(const SphereSet& spheres,
    const CoherentGridParameters& params);
  void sortIntoSubcells(SphereSet& spheres, const NestedCell& n);

  std::array<int, 3> Dims{ 0, 0, 0 };
  std::array<int, 3> MacroDims{ 0, 0, 0 };
  int MacroSize = 6;
  Vec3f Lower;
  float CellSize = 1.f;
  float InvCellSize = 1.f;
  float MaxRadius = 0.f;
  std::size_t NumSpheres = 0;
  std::vector<std::uint32_t> CellStart;  // size cells + 1
  std::vector<std::uint32_t> MacroCount; // spheres per macrocell
  std::vector<float> MacroMaxRadius;     // largest radius per macrocell
  int NumAttributes = 0;
  std::vector<float> MacroMin, MacroMax; // per macrocell and attribute
  std::vector<std::uint8_t> MacroNested; // whether a macrocell has nested cells
  std::vector<NestedCell> Nested;        // sorted by cell
  std::vector<std::uint32_t> NestedStart;
  std::size_t OccupiedWords = 0; // 64-bit words of cell bits per macrocell
  std::vector<std::uint64_t> MacroOccupied;
};

} // namespace raymappers

#endif
