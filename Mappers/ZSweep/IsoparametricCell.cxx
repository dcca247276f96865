// The cells' own interpolation and the linearization of a ray segment (IsoparametricCell.h).
#include "Mappers/ZSweep/IsoparametricCell.h"

#include <algorithm>
#include <cmath>

namespace raymappers
{

namespace
{
// Parametric corners of VTK's hexahedron (also the pyramid's base, corners 0-3).
constexpr int HexCorner[8][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
  { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } };

constexpr int MaxDepth = 12;

// x solving J x = b (J's columns J[0..2]) by Cramer's rule; false when J is singular or not
// finite.
bool solveColumns(const Vec3d J[3], const Vec3d& b, Vec3d& x)
{
  const Vec3d j12 = cross(J[1], J[2]);
  const double det = dot(J[0], j12);
  if (!(std::fabs(det) > 0) || !std::isfinite(det))
  {
    return false;
  }
  x = Vec3d(dot(b, j12) / det, dot(J[0], cross(b, J[2])) / det, dot(J[0], cross(J[1], b)) / det);
  return true;
}

void hexahedronWeights(const Vec3d& r, double N[8], double dN[8][3])
{
  const double u[3] = { r.x, r.y, r.z };
  for (int i = 0; i < 8; ++i)
  {
    double w[3], dw[3];
    for (int a = 0; a < 3; ++a)
    {
      w[a] = HexCorner[i][a] ? u[a] : 1.0 - u[a];
      dw[a] = HexCorner[i][a] ? 1.0 : -1.0;
    }
    N[i] = w[0] * w[1] * w[2];
    dN[i][0] = dw[0] * w[1] * w[2];
    dN[i][1] = w[0] * dw[1] * w[2];
    dN[i][2] = w[0] * w[1] * dw[2];
  }
}

// N = (1 - r - s, r, s) x (1 - t, t).
void wedgeWeights(const Vec3d& r, double N[8], double dN[8][3])
{
  const double tri[3] = { 1.0 - r.x - r.y, r.x, r.y };
  const double dTri[3][2] = { { -1, -1 }, { 1, 0 }, { 0, 1 } };
  const double lin[2] = { 1.0 - r.z, r.z };
  const double dLin[2] = { -1, 1 };
  for (int level = 0; level < 2; ++level)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int i = 3 * level + k;
      N[i] = tri[k] * lin[level];
      dN[i][0] = dTri[k][0] * lin[level];
      dN[i][1] = dTri[k][1] * lin[level];
      dN[i][2] = tri[k] * dLin[level];
    }
  }
}

// The base's bilinear weights times (1 - t), the apex t.
void pyramidWeights(const Vec3d& r, double N[8], double dN[8][3])
{
  for (int i = 0; i < 4; ++i)
  {
    const double wu = HexCorner[i][0] ? r.x : 1.0 - r.x, du = HexCorner[i][0] ? 1.0 : -1.0;
    const double wv = HexCorner[i][1] ? r.y : 1.0 - r.y, dv = HexCorner[i][1] ? 1.0 : -1.0;
    N[i] = wu * wv * (1.0 - r.z);
    dN[i][0] = du * wv * (1.0 - r.z);
    dN[i][1] = wu * dv * (1.0 - r.z);
    dN[i][2] = -wu * wv;
  }
  N[4] = r.z;
  dN[4][0] = dN[4][1] = 0;
  dN[4][2] = 1;
}

// r moved to the nearest point of the reference cell (per coordinate; for the wedge's
// triangle, r + s > 1 scaled back onto r + s = 1).
Vec3d clampToCell(ZSweepCellType type, const Vec3d& r)
{
  Vec3d c(std::clamp(r.x, 0.0, 1.0), std::clamp(r.y, 0.0, 1.0), std::clamp(r.z, 0.0, 1.0));
  if (type == ZSweepCellType::Wedge && c.x + c.y > 1.0)
  {
    const double sum = c.x + c.y;
    c.x /= sum;
    c.y /= sum;
  }
  return c;
}

// The field at X, by Newton from r (in a pyramid clamped into the reference cell; r is
// updated when the inversion converges), and once more from the cell's centre when that
// fails. Near a pyramid's apex (t -> 1) the map's r and s columns shrink like 1 - t, so a
// start predicted from neighbouring solutions can lie far outside the cell (r, s of -2 to
// -7 at t = 0.99), where Newton's steps wander without converging; the clamped start is
// within the cell's own coordinate range. (Hexahedra and wedges, whose maps do not
// degenerate in the cell, keep their start: clamping it there cost 3-4 % of a Blunt Fin
// frame for the same image.)
double fieldAt(const IsoparametricCell& cell, const Vec3d& X, Vec3d& r, LinearizeCounts& counts)
{
  ++counts.evaluations;
  Vec3d next = cell.type == ZSweepCellType::Pyramid ? clampToCell(cell.type, r) : r;
  bool converged = invertCellMap(cell, X, next);
  if (!converged)
  {
    next = referenceCentre(cell.type);
    converged = invertCellMap(cell, X, next);
  }
  if (converged)
  {
    r = next;
  }
  else
  {
    ++counts.failures;
    const bool finite = std::isfinite(next.x) && std::isfinite(next.y) && std::isfinite(next.z);
    r = finite ? clampToCell(cell.type, next) : referenceCentre(cell.type);
  }
  return cellField(cell, r);
}

// A point of the ray in the cell: t, the field, the map's solution.
struct RayPoint
{
  double t, f;
  Vec3d r;
};

// The two halves of [a, b] as linear pieces through the midpoint m.
void pushHalves(const RayPoint& a, const RayPoint& m, const RayPoint& b, SegmentBatch& batch,
  LinearizeCounts& counts)
{
  batch.push(a.f, m.f, m.t - a.t);
  batch.push(m.f, b.f, b.t - m.t);
  counts.pieces += 2;
}

// The midpoint of [a, b], Newton started from the mean of the ends' solutions (off by
// O(h^2)).
RayPoint midpoint(const IsoparametricCell& cell, const Vec3d& o, const Vec3d& d,
  const RayPoint& a, const RayPoint& b, LinearizeCounts& counts)
{
  RayPoint m{ 0.5 * (a.t + b.t), 0, (a.r + b.r) * 0.5 };
  m.f = fieldAt(cell, o + d * m.t, m.r, counts);
  return m;
}

// The halving of [a, b] into the batch's pieces.
void linearizeInterval(const IsoparametricCell& cell,
  const Vec3d& o,
  const Vec3d& d,
  const RayPoint& a,
  const RayPoint& b,
  double tolerance,
  int depth,
  SegmentBatch& batch,
  LinearizeCounts& counts)
{
  const RayPoint m = midpoint(cell, o, d, a, b, counts);
  if (std::fabs(m.f - 0.5 * (a.f + b.f)) <= tolerance || depth >= MaxDepth)
  {
    pushHalves(a, m, b, batch, counts);
    return;
  }
  linearizeInterval(cell, o, d, a, m, tolerance, depth + 1, batch, counts);
  linearizeInterval(cell, o, d, m, b, tolerance, depth + 1, batch, counts);
}
// df/dt along the direction d at r: J w = d (w = dr/dt, Cramer's rule), df/dt = grad_r f . w;
// 0 (and w = 0) where the Jacobian is singular.
double slopeAlong(const IsoparametricCell& cell, const Vec3d& r, const Vec3d& d, Vec3d& w)
{
  double N[8], dN[8][3];
  shapeFunctions(cell.type, clampToCell(cell.type, r), N, dN);
  Vec3d J[3];
  double grad[3] = { 0, 0, 0 };
  for (int i = 0; i < cell.count; ++i)
  {
    for (int a = 0; a < 3; ++a)
    {
      J[a] += cell.p[i] * dN[i][a];
      grad[a] += cell.f[i] * dN[i][a];
    }
  }
  if (!solveColumns(J, d, w))
  {
    w = Vec3d();
    return 0;
  }
  return grad[0] * w.x + grad[1] * w.y + grad[2] * w.z;
}
} // namespace

IsoparametricCell curvedCell(const ZSweepMesh& mesh, std::int32_t slot)
{
  IsoparametricCell cell;
  cell.type = mesh.curvedType(slot);
  cell.count = cellFaces(cell.type).vertices;
  const std::uint32_t* ids = mesh.curvedVertices(slot);
  cell.fMin = cell.fMax = mesh.scalars()[ids[0]];
  for (int i = 0; i < cell.count; ++i)
  {
    cell.p[i] = mesh.points()[ids[i]];
    cell.f[i] = mesh.scalars()[ids[i]];
    cell.fMin = std::min(cell.fMin, cell.f[i]);
    cell.fMax = std::max(cell.fMax, cell.f[i]);
  }
  return cell;
}

void shapeFunctions(ZSweepCellType type, const Vec3d& r, double N[8], double dN[8][3])
{
  switch (type)
  {
    case ZSweepCellType::Wedge:
      wedgeWeights(r, N, dN);
      return;
    case ZSweepCellType::Pyramid:
      pyramidWeights(r, N, dN);
      return;
    case ZSweepCellType::Hexahedron:
    case ZSweepCellType::Tetra:
      break;
  }
  hexahedronWeights(r, N, dN);
}

Vec3d referenceCentre(ZSweepCellType type)
{
  switch (type)
  {
    case ZSweepCellType::Wedge:
      return Vec3d(1.0 / 3, 1.0 / 3, 0.5);
    case ZSweepCellType::Pyramid:
      return Vec3d(0.5, 0.5, 0.2);
    case ZSweepCellType::Hexahedron:
    case ZSweepCellType::Tetra:
      break;
  }
  return Vec3d(0.5, 0.5, 0.5);
}

bool invertCellMap(const IsoparametricCell& cell, const Vec3d& X, Vec3d& r)
{
  for (int iteration = 0; iteration < 30; ++iteration)
  {
    double N[8], dN[8][3];
    shapeFunctions(cell.type, r, N, dN);
    Vec3d F = X * -1.0, J[3];
    for (int i = 0; i < cell.count; ++i)
    {
      F += cell.p[i] * N[i];
      for (int a = 0; a < 3; ++a)
      {
        J[a] += cell.p[i] * dN[i][a];
      }
    }
    Vec3d delta;
    if (!solveColumns(J, F, delta))
    {
      return false;
    }
    const double size = std::max({ std::fabs(delta.x), std::fabs(delta.y), std::fabs(delta.z) });
    if (!std::isfinite(size))
    {
      return false;
    }
    if (size > 0.5)
    {
      delta = delta * (0.5 / size);
    }
    r = r - delta;
    if (size < 1e-7)
    {
      return true;
    }
  }
  return false;
}

double cellField(const IsoparametricCell& cell, const Vec3d& r)
{
  double N[8], dN[8][3];
  shapeFunctions(cell.type, clampToCell(cell.type, r), N, dN);
  double f = 0;
  for (int i = 0; i < cell.count; ++i)
  {
    f += N[i] * cell.f[i];
  }
  return std::clamp(f, cell.fMin, cell.fMax);
}

void linearizeAlongRay(const IsoparametricCell& cell,
  const Vec3d& o,
  const Vec3d& d,
  double t0,
  double t1,
  double tolerance,
  SegmentBatch& batch,
  LinearizeCounts& counts)
{
  RayPoint a{ t0, 0, referenceCentre(cell.type) };
  a.f = fieldAt(cell, o + d * t0, a.r, counts);
  Vec3d wa, wb;
  const double slopeA = slopeAlong(cell, a.r, d, wa);
  // The far end's Newton started from the tangent's prediction r(t0) + h dr/dt.
  const double h = t1 - t0;
  RayPoint b{ t1, 0, a.r + wa * h };
  b.f = fieldAt(cell, o + d * t1, b.r, counts);
  const double slopeB = slopeAlong(cell, b.r, d, wb);
  const RayPoint m = midpoint(cell, o, d, a, b, counts);
  // The whole segment's two halves, when the midpoint and the end slopes' bound agree.
  const double k = (b.f - a.f) / h;
  const double bend = 0.25 * h * std::max(std::fabs(slopeA - k), std::fabs(slopeB - k));
  if (std::fabs(m.f - 0.5 * (a.f + b.f)) <= tolerance && bend <= tolerance)
  {
    pushHalves(a, m, b, batch, counts);
    return;
  }
  linearizeInterval(cell, o, d, a, m, tolerance, 1, batch, counts);
  linearizeInterval(cell, o, d, m, b, tolerance, 1, batch, counts);
}

} // namespace raymappers
