// ZSweep volume rendering of an unstructured grid (Farias 2001, chapters 4 and 5).
//
// Per frame:
// 1. The vertices are projected (window x, y, depth; 1/w for perspective-correct scalars).
// 2. The triangles are sorted by the depth of their nearest vertex: the sweep's event order
//    (section 4.2), sorted from the previous frame's order when the caller keeps it (an
//    insertion sort, linear when the camera stayed or moved a little). Every triangle is
//    binned into the screen tiles its projection touches (chapter 5: a tile sweeps only the
//    faces in its shaft), in that order. Each face is projected once per tile: the mesh
//    stores every face once.
// 3. Each tile (in parallel, TBB) sweeps its events: the triangles whose nearest vertex is
//    the event vertex are scan converted exactly (pixel centres, a top-left fill rule whose
//    edge functions are evaluated identically by both faces sharing an edge, so a ray
//    through an edge or a vertex is counted once on each side of the surface it crosses);
//    each covered pixel gets an entry (distance t along its ray, scalar, the cells on both
//    sides) inserted from the back of its depth-sorted list.
// 4. Delayed compositing (section 4.2): when the sweep reaches the z-target, or some list is
//    longer than K, every list is composited up to the current sweep depth z_v, which is
//    safe: a face not yet projected has its nearest vertex at or beyond z_v, so all its
//    intersections are too. The z-target is then the farthest vertex of the faces just
//    projected. When lists cannot shrink below K, K doubles (K, 2K, 4K ...).
// 5. Compositing walks the entries in order: the segment between two entries lies in the
//    cell the ray entered at the first (none: outside the grid, a cavity or a gap between
//    parts) and is integrated with the optical model (point data: the scalar varies
//    linearly, or in a curved cell with the Native field as the cell's own interpolation,
//    cut into linear pieces; cell data: constant). Entries closer than a tie tolerance (a ray through a
//    shared vertex or edge) form one crossing: the ray ends up in the cell that some
//    member entered and no member left.
// A sparse mesh (ZSweepMesh.h) is decoded into its triangles first (phase decode), in
// another order than the dense mesh's. The order matters only among the triangles of one
// event whose entries in a pixel tie exactly (inserted in triangle order) and for the caps
// (their fans start at the first face across the near plane: these faces are taken in
// vertex-id order); the kernel tests find the images of both identical.
// A camera close to or inside the grid: faces across the near plane are clipped and the
// cells across it get caps (ZSweepNearPlane.h). Opaque geometry (a window depth per pixel)
// ends the rays; a pixel stops collecting entries once its opacity reaches the termination
// threshold.
#ifndef RayMappers_ZSweepRenderer_h
#define RayMappers_ZSweepRenderer_h

#include "Mappers/Common/Frame.h"
#include "Mappers/ZSweep/OpticalModel.h"
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/Common/View.h"
#include "Mappers/ZSweep/ZSweepMesh.h"

#include <array>
#include <cstdint>
#include <vector>

namespace raymappers
{

/// The field inside hexahedra, wedges and pyramids (point data): Native, the cell's own
/// interpolation (trilinear in a hexahedron; IsoparametricCell.h), linearized along each ray
/// to `curvedTolerance` times the scalar range, needs a mesh built with its curved cells;
/// SplitFaces, linear between the crossings of the triangles the faces are split into (what
/// a tetrahedralization of the cell gives at its faces, exact for tetrahedra only).
enum class ZSweepCellField
{
  Native,
  SplitFaces
};

struct ZSweepParameters
{
  ZSweepIntegrator integrator = ZSweepIntegrator::Exact;
  ZSweepCellField cellField = ZSweepCellField::Native;
  double curvedTolerance = 1e-4;
  int tileSize = 32;
  int listThreshold = 16;           // K
  double terminationOpacity = 1.0;  // stop a pixel once its opacity reaches this
};

/// The event order of a mesh's triangles from the previous frame, kept by the caller
/// between frames as the start of the next frame's sort (a permutation of the triangles;
/// any permutation gives the same image, the previous one only a faster sort).
struct ZSweepEventOrder
{
  std::vector<std::uint32_t> triangles;
};

/// What ZSweep draws: the mesh, classified by `optics`, and the event order of its
/// triangles from the previous frame (`previousOrder`, when not null, is read and replaced
/// by this frame's).
struct ZSweepScene
{
  const ZSweepMesh& mesh;
  const OpticalModel& optics;
  ZSweepEventOrder* previousOrder = nullptr;
};

/// Renders the scene into `frame` (resized to the view's grid; premultiplied RGBA, the
/// depth stays at the far plane). The view's origin must be the mesh's (its float
/// coordinates are relative to it); the sweep stops at the view's opaque depth. Counters: triangles, binned_triangles, entries, flushes,
/// k_growths, segments, transparent_segments, near_plane_triangles (clipped faces and
/// caps), open_caps, max_list, tie_groups, decoded_triangles (0 for a dense mesh),
/// order_moves (the insertion sort's moves from `previousOrder`), order_sorts (1 when the
/// frame took a full sort instead), curved_segments, curved_pieces, curved_evaluations,
/// curved_inversion_failures (the Native field's). Effects: cell_data, early_termination,
/// sparse_mesh, curved_cells.
void renderZSweep(const ZSweepScene& scene,
  const View& view,
  const ZSweepParameters& params,
  Frame& frame,
  RenderStatistics& stats);

} // namespace raymappers

#endif
