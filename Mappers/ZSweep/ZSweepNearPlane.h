// The part of a frame's geometry at the near plane, for a camera close to or inside the grid
// (Farias 2001 renders from outside; a volume mapper must also render from inside).
//
// A face crossing the near plane is clipped to the part beyond it (Sutherland-Hodgman in
// clip space, against z + w >= 0) and drawn as a fan of triangles. Each cell crossing the
// near plane gets a cap: its cross-section with the plane, whose edges are the crossing
// segments of its faces, drawn as a fan with the ray entering the cell there from outside.
// A ray starting inside a cell thus meets the cap first, and the sweep needs nothing else.
//
// The point where an edge crosses the plane is computed from the edge's endpoints in a
// fixed order and gets a key derived from the two endpoint ids, so every face and cap that
// shares the edge has bit-identical coordinates and the same key: the fill rule stays
// consistent across them. Keys of mesh vertices are their ids; keys of crossing points are
// 2^32 (min + 1) + max.
#ifndef RayMappers_ZSweepNearPlane_h
#define RayMappers_ZSweepNearPlane_h

#include "Mappers/ZSweep/ZSweepMesh.h"

#include <array>
#include <cstdint>
#include <vector>

namespace raymappers
{

struct ProjectedVertex
{
  double x, y; // window position (pixels; pixel (i, j) has its centre at (i + .5, j + .5))
  double d;    // window depth
  double invW; // 1 / w_clip, for perspective-correct interpolation
  bool valid;  // in front of the eye and not before the near plane
};

/// A triangle to scan convert that is not one of the mesh's (a clipped face or a cap).
struct DrawTriangle
{
  std::array<ProjectedVertex, 3> v;
  std::array<std::uint64_t, 3> key;
  std::array<double, 3> s; // point scalars (unused for cell data)
  std::int32_t entered, exited;
};

/// The clipped parts of the `crossing` triangles (indices into `triangles`, the mesh's, with
/// vertices on both sides of the near plane) and the caps of the cells they bound. `M`:
/// origin-relative model to clip;
/// `forward[f]`: whether the rays cross triangle f from its front cell to its back cell.
/// Returns the number of caps that could not be closed (a degenerate cross-section; left
/// out).
std::size_t nearPlaneTriangles(const ZSweepMesh& mesh,
  const std::vector<ZSweepTriangle>& triangles,
  const std::array<double, 16>& M,
  int width,
  int height,
  const std::vector<std::uint32_t>& crossing,
  const std::vector<char>& forward,
  std::vector<DrawTriangle>& out);

} // namespace raymappers

#endif
