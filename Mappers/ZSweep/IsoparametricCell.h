// The cells' own interpolation inside hexahedra, wedges and pyramids, and a ray segment
// through such a cell cut into pieces on which that field is linear to a tolerance, for the
// ZSweep integrators (OpticalModel.h, which then handles the transfer function's nodes on
// each piece exactly).
//
// The field (VTK's shape functions; the reference cell's coordinates r = (r, s, t)):
//   x(r) = sum_i N_i(r) p_i,   f(r) = sum_i N_i(r) f_i,
// - hexahedron, r in [0, 1]^3: N_i = (r_i ? r : 1 - r)(s_i ? s : 1 - s)(t_i ? t : 1 - t),
//   the trilinear interpolant;
// - wedge, r, s >= 0, r + s <= 1, t in [0, 1]: N = ((1 - r - s), r, s) x ((1 - t), t), linear
//   on the triangles and along the edges between them;
// - pyramid, [0, 1]^3 with the apex at t = 1: the base's bilinear weights times (1 - t), and
//   N_4 = t (the hexahedron with its top face collapsed).
// Along the ray X(t) = o + t d the field is f(r(t)), r(t) solving x(r) = X(t): Newton's
// method, r <- r - J^-1 (x(r) - X), J = dx/dr by Cramer's rule: at the segment's front from
// the cell's centre, at its back from the tangent's prediction r(t0) + h dr/dt, at a midpoint
// from the mean of its ends' solutions (2 or 3 iterations there), in a pyramid each start
// clamped into the reference cell (near its apex a prediction can fall far outside, where
// Newton wanders), and the centre tried once when Newton fails; it stops after a step below
// 1e-7, which quadratic convergence leaves about 1e-14 from the solution; steps are
// shortened to 0.5 (a start far off does not jump away). The solution is clamped into the reference cell before f is evaluated: the
// renderer's cell is bounded by the split faces, which leave the curved cell's image where
// a face is not planar (by the face's bend); there f holds its value on the boundary, and
// f stays within the corners' range (the N_i are a partition of unity, >= 0 in the cell).
//
// Linearization: an interval [a, b] whose field at the midpoint m departs from the chord by
// at most the tolerance,
//   |f(m) - (f(a) + f(b)) / 2| <= tol,
// becomes the two pieces [a, m], [m, b] with f linear between the evaluated values; else it
// is halved. For a smooth f the chord's largest departure is h^2 |f''| / 8 on a piece of
// length h, 4 times the midpoint's departure of its parent: the pieces' error is about
// tol / 4. The midpoint alone misses an odd bend (a cubic through the chord's midpoint), so
// the whole segment [t0, t1] is accepted only when the end slopes f'(t0), f'(t1) (from the
// Jacobian: J w = d, f' = grad_r f . w) also bound the cubic with those ends' departure,
//   h x (1 - x) ((1 - x) (f'(t0) - k) - x (f'(t1) - k)) <= h / 4 max |f' - k| <= tol,
// k the chord's slope; its halves and theirs are then judged by their midpoints. At most
// 2^12 pieces a segment.
#ifndef RayMappers_IsoparametricCell_h
#define RayMappers_IsoparametricCell_h

#include "Mappers/Common/Vec3.h"
#include "Mappers/ZSweep/OpticalModel.h"
#include "Mappers/ZSweep/ZSweepMesh.h"

#include <cstdint>

namespace raymappers
{

struct IsoparametricCell
{
  ZSweepCellType type = ZSweepCellType::Hexahedron;
  int count = 8;  // corners
  Vec3d p[8];     // corners (origin-relative)
  double f[8];    // point scalars at the corners
  double fMin = 0, fMax = 0;
};

/// The curved cell of the mesh's slot (ZSweepMesh::curvedSlot).
IsoparametricCell curvedCell(const ZSweepMesh& mesh, std::int32_t slot);

/// The weights N_i(r) and their derivatives dN_i/dr (columns r, s, t) of the type.
void shapeFunctions(ZSweepCellType type, const Vec3d& r, double N[8], double dN[8][3]);

/// The reference cell's centre (Newton's first start).
Vec3d referenceCentre(ZSweepCellType type);

/// Newton's method on x(r) = X from r; false when the Jacobian is singular or 30
/// iterations do not bring the step below 1e-7 (r then holds the last iterate).
bool invertCellMap(const IsoparametricCell& cell, const Vec3d& X, Vec3d& r);

/// f at r clamped into the reference cell.
double cellField(const IsoparametricCell& cell, const Vec3d& r);

struct LinearizeCounts
{
  std::int64_t evaluations = 0, failures = 0, pieces = 0;
};

/// Appends to `batch` the pieces (front scalar, back scalar, length) of [t0, t1] along
/// o + t d inside the cell, front to back, linear to `tolerance` (see above).
void linearizeAlongRay(const IsoparametricCell& cell,
  const Vec3d& o,
  const Vec3d& d,
  double t0,
  double t1,
  double tolerance,
  SegmentBatch& batch,
  LinearizeCounts& counts);

} // namespace raymappers

#endif
