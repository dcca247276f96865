// The topology the ZSweep renderer sweeps (Farias 2001, section 4.3.1): the cells' faces
// as triangles, each stored once with the cells on its two sides.
//
// Cells: tetrahedra, hexahedra, wedges and pyramids (VTK's vertex orders), mixed freely.
// A quadrilateral face is split into two triangles along the diagonal through its vertex
// of smallest global index, so the two cells that share it split it the same way whatever
// their local vertex orders (the consistency section 4.3.2 asks for; a non-planar quad then
// stays watertight).
//
// Each triangle (v0, v1, v2) has the normal n = (v1 - v0) x (v2 - v0); `front` is the cell
// on the side n points away from and `back` the cell n points into (-1: outside the grid).
// The sides come from the cells' centroids, so the cells' own orientation (inverted cells)
// does not matter. A ray with direction d crosses the triangle from front to back when
// d . n > 0, else from back to front.
//
// Cells left out, each counted: a vertex index out of range, a vertex with a non-finite
// coordinate, a non-finite scalar (the cell's, or one of its vertices'), zero volume
// (nothing to integrate). Triangles of zero area are dropped (they cover no pixel centre).
#ifndef RayMappers_ZSweepMesh_h
#define RayMappers_ZSweepMesh_h

#include "Vec3.h"

#include <cstdint>
#include <vector>

namespace raymappers
{

enum class ZSweepCellType : std::uint8_t
{
  Tetra,
  Hexahedron,
  Wedge,
  Pyramid
};

/// The grid handed to ZSweepMesh::build: points, cells (type, offset into `connectivity`),
/// and the scalar either per point or per cell.
struct ZSweepGrid
{
  std::vector<Vec3d> points;
  std::vector<ZSweepCellType> cellTypes;
  std::vector<std::int64_t> cellOffsets; // size cells + 1
  std::vector<std::int64_t> connectivity;
  std::vector<double> scalars; // per point, or per cell when cellScalars
  bool cellScalars = false;
};

struct ZSweepTriangle
{
  std::uint32_t v[3];
  std::int32_t front; // cell against the normal, -1 outside
  std::int32_t back;  // cell on the normal's side, -1 outside
};

class ZSweepMesh
{
public:
  /// Builds the triangles (in parallel). Replaces any previous content.
  void build(const ZSweepGrid& grid);

  const Vec3d& origin() const { return Origin; }
  /// Largest coordinate of the points relative to origin() (half the bounds' longest side).
  double extent() const { return Extent; }
  /// Points relative to origin().
  const std::vector<Vec3d>& points() const { return Points; }
  const std::vector<ZSweepTriangle>& triangles() const { return Triangles; }
  bool cellScalars() const { return CellScalars; }
  /// Per point, or per cell (indexed like the grid's cells).
  const std::vector<double>& scalars() const { return Scalars; }
  std::size_t numCells() const { return NumCells; }
  double scalarMin() const { return ScalarMin; }
  double scalarMax() const { return ScalarMax; }
  std::size_t memoryBytes() const;

  struct Counts
  {
    std::size_t cellsUsed = 0;
    std::size_t badIndex = 0;
    std::size_t nonFinitePoint = 0;
    std::size_t nonFiniteScalar = 0;
    std::size_t zeroVolume = 0;
    std::size_t boundaryTriangles = 0;
    std::size_t nonManifoldTriangles = 0; // shared by more than two cells
  };
  const Counts& counts() const { return Stats; }

private:
  Vec3d Origin;
  double Extent = 0;
  std::vector<Vec3d> Points;
  std::vector<ZSweepTriangle> Triangles;
  std::vector<double> Scalars;
  bool CellScalars = false;
  std::size_t NumCells = 0;
  double ScalarMin = 0, ScalarMax = 0;
  Counts Stats;
};

/// The faces of a cell type in VTK's local vertex numbering: `count` faces, face f has
/// `sizes[f]` (3 or 4) vertices `local[f][0..sizes[f])`, listed with outward normals for a
/// positively oriented cell.
struct ZSweepCellFaces
{
  int count;
  int sizes[6];
  int local[6][4];
  int vertices;
};
const ZSweepCellFaces& cellFaces(ZSweepCellType type);

} // namespace raymappers

#endif
