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
// The sides come from each cell's orientation, the sign of the volume its triangles
// enclose in their local winding (VTK's faces list it outward): an inverted cell (its
// vertices in mirrored order, negative volume) is used like the others and counted, and a
// cell that is not convex (a twisted frustum) gets the right sides. A ray with direction d
// crosses the triangle from front to back when d . n > 0, else from back to front.
//
// Cells left out, each counted: a vertex index out of range, a vertex with a non-finite
// coordinate, a non-finite scalar (the cell's, or one of its vertices'), zero volume:
//   |V| <= max(ZeroVolumeRatio D^3, sqrt(3) eps X S),
// D the diagonal of the cell's bounding box, S the area of its triangles, X the largest
// magnitude of its points' coordinates, eps the rounding of the given coordinates
// (ZSweepGrid::pointEpsilon). Below the first bound the volume is within a factor 1e4 of its
// rounding error (a few 1e-16 D^3), so its sign, the cell's orientation, is not known. Below
// the second the cell is flat to the precision of its points: rounding a coordinate moves a
// vertex by at most sqrt(3) eps X, and that changes V by at most its product with S
// (dV/dp_i has at most the area of the triangles at p_i over 3, each triangle counted at
// its 3 corners), so four coplanar points stored as floats, no longer exactly coplanar, are
// still of zero volume. Nothing to integrate either. Triangles of zero area are dropped
// (they cover no pixel centre).
//
// Sparsification (Farias 2001, section 4.3.5, "Sparse Data Representation"): the faces can
// be stored through a subset of the cells that contains every face. In the dual graph
// (nodes: the cells; an edge: a triangle with a cell on each side) a set D of cells may be
// dropped when no triangle loses both of its cells, i.e. when D is an independent set; the
// kept cells K = the rest. The paper's greedy heuristic: a cell with a triangle on the
// boundary (a triangle with no cell on its other side, also beside a skipped cell) is
// essential; then each cell not yet essential is dropped and its neighbours become
// essential, the next cell dropped being one with the fewest undecided neighbours.
// Every kept cell is then essential: it has a triangle whose other side is outside or a
// dropped cell, so none can be dropped without uncovering a triangle (the set D is maximal).
//
// Here the dense mesh already stores each face once (the sort dedupes the shared faces the
// paper's sweep would project twice), so what sparsification buys is the store: a sparse
// mesh keeps, instead of the triangles (3 vertex ids and 2 cells, 20 bytes each), the kept
// cells' vertices, and per triangle one kept cell owns it and stores only the cell on the
// triangle's other side (4 bytes). A tetrahedron's 4 ids serve its 4 triangles, a
// hexahedron's 8 ids its 12. The renderer decodes the triangles per frame (same vertex ids,
// same cells on both sides, in another order, so the same image: ZSweepRenderer.h); the
// dropped cells stay known as those other sides (the tie rule at shared vertices and
// edges, ZSweepRenderer.h, compares cells; cell data integrates the dropped cell's scalar,
// so all cells' scalars are kept).
// The build runs the dense build first (the dual graph comes from its sort), so it takes
// longer; the gain is the memory the mesh holds between frames.
//
// Curved cells (hexahedra, wedges, pyramids with point data): on request the mesh also keeps
// each used one's type and vertex ids (one slot per such cell, 8 ids), so the renderer can
// evaluate the cell's own interpolation inside it (IsoparametricCell.h) instead of the
// linear field of its split faces: 4 bytes per cell and 33 per curved cell, nothing
// without the request.
#ifndef RayMappers_ZSweepMesh_h
#define RayMappers_ZSweepMesh_h

#include "Mappers/Common/Vec3.h"

#include <cstdint>
#include <limits>
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
  /// The relative rounding of the points as given: double's 2^-53 (default), float's 2^-24
  /// for points that were stored as floats.
  double pointEpsilon = std::numeric_limits<double>::epsilon() / 2;
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
  /// A cell of volume |V| <= ZeroVolumeRatio D^3 is left out, as one flat to the precision
  /// of its points (see above).
  static constexpr double ZeroVolumeRatio = 1e-12;

  /// Builds the triangles (in parallel). Replaces any previous content. With `sparsify`,
  /// stores them through the kept cells (see above).
  /// With `keepCurvedCells` (and point scalars), also keeps the used curved cells' vertices.
  void build(const ZSweepGrid& grid, bool sparsify = false, bool keepCurvedCells = false);

  const Vec3d& origin() const { return Origin; }
  /// Largest coordinate of the points relative to origin() (half the bounds' longest side).
  double extent() const { return Extent; }
  /// Points relative to origin().
  const std::vector<Vec3d>& points() const { return Points; }
  /// Whether the triangles are stored through the kept cells.
  bool sparse() const { return Sparse; }
  std::size_t numTriangles() const { return NumTriangles; }
  /// The triangles, in the dense mesh's order for a dense mesh (sorted by vertex ids), in
  /// kept-cell order for a sparse one: the stored list, or for a sparse mesh the list
  /// decoded from the kept cells (in parallel) into `scratch`.
  const std::vector<ZSweepTriangle>& triangles(std::vector<ZSweepTriangle>& scratch) const;
  /// A sparse mesh's kept cells (ascending ids); empty for a dense mesh.
  const std::vector<std::int32_t>& keptCells() const { return KeptIds; }
  bool cellScalars() const { return CellScalars; }
  /// Per point, or per cell (indexed like the grid's cells).
  const std::vector<double>& scalars() const { return Scalars; }
  std::size_t numCells() const { return NumCells; }
  double scalarMin() const { return ScalarMin; }
  double scalarMax() const { return ScalarMax; }
  /// Whether the curved cells' vertices are kept (build's keepCurvedCells with point data).
  bool keepsCurvedCells() const { return !CurvedSlot.empty(); }
  /// Cell c's slot among the kept curved cells, -1 for a tetrahedron, an unused cell or
  /// when none are kept.
  std::int32_t curvedSlot(std::int32_t c) const
  {
    return CurvedSlot.empty() ? -1 : CurvedSlot[static_cast<std::size_t>(c)];
  }
  ZSweepCellType curvedType(std::int32_t slot) const { return CurvedTypes[static_cast<std::size_t>(slot)]; }
  /// The slot's vertex ids (VTK's order; 8 entries, the first as many as the type has).
  const std::uint32_t* curvedVertices(std::int32_t slot) const
  {
    return CurvedVertices.data() + 8 * static_cast<std::size_t>(slot);
  }
  /// What the mesh holds: points, scalars, and the triangles or the sparse cell store.
  std::size_t memoryBytes() const;

  struct Counts
  {
    std::size_t cellsUsed = 0;
    std::size_t badIndex = 0;
    std::size_t nonFinitePoint = 0;
    std::size_t nonFiniteScalar = 0;
    std::size_t zeroVolume = 0;
    std::size_t inverted = 0; // used, of negative orientation (mirrored vertex order)
    std::size_t boundaryTriangles = 0;
    std::size_t nonManifoldTriangles = 0; // shared by more than two cells
    std::size_t cellsKept = 0;            // sparse: the kept cells; dense: cellsUsed
  };
  const Counts& counts() const { return Stats; }

private:
  void storeKeptCells(const ZSweepGrid& grid,
    const std::vector<char>& used,
    const std::vector<char>& state,
    const std::vector<std::size_t>& recordStart,
    const std::vector<std::uint16_t>& owned,
    const std::vector<std::uint16_t>& back,
    const std::vector<std::int32_t>& otherAt);
  void findScalarRange();
  void keepCurvedCells(const ZSweepGrid& grid, const std::vector<char>& used);

  Vec3d Origin;
  double Extent = 0;
  std::vector<Vec3d> Points;
  std::vector<ZSweepTriangle> Triangles; // dense
  std::size_t NumTriangles = 0;
  bool Sparse = false;
  // The sparse store, one entry per kept cell: its id, type, vertex ids (KeptConnectivity,
  // consecutive), and two masks over its triangle slots (the order of forEachTriangle):
  // the triangles it owns, and of those the ones it is on the normal side of (the back
  // cell). Others: per owned triangle, in kept-cell and slot order, the cell on the
  // triangle's other side (-1: outside).
  std::vector<std::int32_t> KeptIds;
  std::vector<ZSweepCellType> KeptTypes;
  std::vector<std::uint32_t> KeptConnectivity;
  std::vector<std::uint16_t> OwnedMask, BackMask;
  std::vector<std::int32_t> Others;
  std::vector<std::int32_t> CurvedSlot; // per cell (empty: none kept)
  std::vector<ZSweepCellType> CurvedTypes;
  std::vector<std::uint32_t> CurvedVertices; // 8 per slot
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
