// A converged reference for volume rendering hexahedra with a trilinear point field,
// sharing no code with the ZSweep kernels (nor with UnstructuredReference.h's tetrahedra
// beyond its transfer function): the hexahedron is the image of the unit cube under its
// trilinear map, bounded by bilinear faces, and the scalar is the trilinear interpolant of
// its corner values, evaluated along the ray by inverting the map point by point. Wedges
// and pyramids likewise with their own maps (VTK's shape functions, below): a wedge is
// (1 - u - v, u, v) x (1 - w, w) on u, v >= 0, u + v <= 1, w in [0, 1], bounded by two
// triangles and three bilinear faces; a pyramid the base's bilinear weights times (1 - w)
// and w for the apex on [0, 1]^3, bounded by its bilinear base and four triangles.
//
// The cell (VTK's vertex order; corner i at parametric (u_i, v_i, w_i) = HexCorner[i]):
//   x(u, v, w) = sum_i N_i(u, v, w) p_i,   s(u, v, w) = sum_i N_i(u, v, w) s_i,
//   N_i = (u_i ? u : 1 - u) (v_i ? v : 1 - v) (w_i ? w : 1 - w).
// The map must be one-to-one on the cube (det dx/d(u, v, w) > 0 there; a cell of the
// other orientation is given with its corners mirrored): then a point X is inside the cell
// iff the solution u of x(u) = X lies in [0, 1]^3.
//
// Along a ray o + t d (|d| = 1), through cells whose interiors are disjoint:
// 1. Entry and exit: each face is the bilinear patch of its 4 corners, crossed where a
//    quadratic vanishes (intersectBilinearPatch), the root polished by Newton's method on
//    P(a, b) = o + t d to rounding (a residual below 1e-12 of the face's size; without the
//    polish a ray grazing a face at an angle of 1e-5 loses a third of its crossings, with
//    it they are found down to 1e-6). The crossings cut the ray into intervals; an interval
//    lies in the cell iff its midpoint does (a warped cell is not convex: a ray may enter
//    it more than once; a ray through an edge or a corner crosses two or three faces at
//    the same t, which this test makes harmless).
// 2. The scalar at a point: Newton's method on x(u) = X, u <- u - J^-1 (x(u) - X), J the
//    Jacobian (Cramer's rule, in double), started from the previous point's solution, to
//    a step below 1e-14 (quadratic convergence: 2 or 3 iterations a point).
// 3. The transfer function's kinks: an interval is cut where s(t) crosses a node (sampled
//    at the step, the root bisected to rounding; a node touched and left within one step
//    is missed, an error of the order of step^2 on that step).
// 4. On each piece, where the integrand is smooth, the transport equation of the model of
//    UnstructuredReference.h (tau and the color linear in s between the nodes),
//      dT/dt = -tau(s(t)) T,   dC/dt = c(s(t)) tau(s(t)) T,
//    is integrated by the classical 4th-order Runge-Kutta method with steps of at most
//    `step`, from the front's (T, C); the pieces of all cells in depth order.
// The result converges like step^4: on cells 0.7 to 2.6 across, halving the step from 0.01
// changes a picture by 5e-10, from 0.02 by 8e-9 (TestZSweep.cxx); the refined
// piecewise-linear models of a cell tend to it like 1 / m^2.
#ifndef RayMappers_Test_TrilinearReference_h
#define RayMappers_Test_TrilinearReference_h

#include "UnstructuredReference.h"
#include "Mappers/Common/Vec3.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace raymappers::test
{

/// Parametric coordinates of a VTK hexahedron's corners.
constexpr int HexCorner[8][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
  { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } };

/// VTK's faces of a hexahedron, each in cyclic order.
constexpr int HexFace[6][4] = { { 0, 4, 7, 3 }, { 1, 2, 6, 5 }, { 0, 1, 5, 4 }, { 3, 7, 6, 2 },
  { 0, 3, 2, 1 }, { 4, 5, 6, 7 } };

enum class RefShape
{
  Hexahedron,
  Wedge,
  Pyramid
};

/// A wedge's bilinear faces, each in cyclic order (its triangles are 0, 1, 2 and 3, 4, 5).
constexpr int WedgeQuad[3][4] = { { 0, 1, 4, 3 }, { 1, 2, 5, 4 }, { 2, 0, 3, 5 } };

struct RefCurvedCell
{
  std::array<Vec3d, 8> p{};  // corners, VTK order (8, 6 or 5 of them)
  std::array<double, 8> s{}; // point scalars
  RefShape shape = RefShape::Hexahedron;
};

/// The trilinear weights N_i at (u, v, w) and their derivatives dN_i/du, dv, dw.
inline void trilinearWeights(const Vec3d& u, double N[8], double dN[8][3])
{
  for (int i = 0; i < 8; ++i)
  {
    double f[3], df[3];
    for (int a = 0; a < 3; ++a)
    {
      f[a] = HexCorner[i][a] ? u[a] : 1.0 - u[a];
      df[a] = HexCorner[i][a] ? 1.0 : -1.0;
    }
    N[i] = f[0] * f[1] * f[2];
    dN[i][0] = df[0] * f[1] * f[2];
    dN[i][1] = f[0] * df[1] * f[2];
    dN[i][2] = f[0] * f[1] * df[2];
  }
}

/// The wedge's N_i = L_(i mod 3) (i < 3 ? 1 - w : w), L = (1 - u - v, u, v); the pyramid's
/// N_i = B_i(u, v) (1 - w) (i < 4, B the bilinear weights of the base 0, 1, 2, 3 at (0, 0),
/// (1, 0), (1, 1), (0, 1)), N_4 = w; the entries past the cell's corners are 0.
inline void shapeWeights(RefShape shape, const Vec3d& u, double N[8], double dN[8][3])
{
  if (shape == RefShape::Hexahedron)
  {
    trilinearWeights(u, N, dN);
    return;
  }
  for (int i = 0; i < 8; ++i)
  {
    N[i] = dN[i][0] = dN[i][1] = dN[i][2] = 0;
  }
  const double w = u.z;
  if (shape == RefShape::Wedge)
  {
    const double L[3] = { 1 - u.x - u.y, u.x, u.y };
    const double dL[3][2] = { { -1, -1 }, { 1, 0 }, { 0, 1 } };
    for (int i = 0; i < 6; ++i)
    {
      const double f = i < 3 ? 1 - w : w, df = i < 3 ? -1 : 1;
      N[i] = L[i % 3] * f;
      dN[i][0] = dL[i % 3][0] * f;
      dN[i][1] = dL[i % 3][1] * f;
      dN[i][2] = L[i % 3] * df;
    }
    return;
  }
  for (int i = 0; i < 4; ++i)
  {
    const double fu = HexCorner[i][0] ? u.x : 1 - u.x, fv = HexCorner[i][1] ? u.y : 1 - u.y;
    const double du = HexCorner[i][0] ? 1 : -1, dv = HexCorner[i][1] ? 1 : -1;
    N[i] = fu * fv * (1 - w);
    dN[i][0] = du * fv * (1 - w);
    dN[i][1] = fu * dv * (1 - w);
    dN[i][2] = -fu * fv;
  }
  N[4] = w;
  dN[4][2] = 1;
}

/// The parametric centre (Newton's first start).
inline Vec3d parametricCentre(const RefCurvedCell& h)
{
  return h.shape == RefShape::Wedge ? Vec3d(1.0 / 3, 1.0 / 3, 0.5) : Vec3d(0.5, 0.5, 0.5);
}

/// Whether u lies in the cell's parametric domain.
inline bool inParametricDomain(const RefCurvedCell& h, const Vec3d& u)
{
  const bool w = u.z >= 0 && u.z <= 1;
  if (h.shape == RefShape::Wedge)
  {
    return w && u.x >= 0 && u.y >= 0 && u.x + u.y <= 1;
  }
  return w && u.x >= 0 && u.x <= 1 && u.y >= 0 && u.y <= 1;
}

/// x(u) and the Jacobian's columns dx/du, dx/dv, dx/dw.
inline Vec3d shapePoint(const RefCurvedCell& h, const Vec3d& u, Vec3d J[3])
{
  double N[8], dN[8][3];
  shapeWeights(h.shape, u, N, dN);
  Vec3d x;
  J[0] = J[1] = J[2] = Vec3d();
  for (int i = 0; i < 8; ++i)
  {
    x += h.p[i] * N[i];
    for (int a = 0; a < 3; ++a)
    {
      J[a] += h.p[i] * dN[i][a];
    }
  }
  return x;
}

/// s(u), the cell's interpolant of the corner scalars (trilinear in a hexahedron).
inline double shapeScalar(const RefCurvedCell& h, const Vec3d& u)
{
  double N[8], dN[8][3];
  shapeWeights(h.shape, u, N, dN);
  double s = 0;
  for (int i = 0; i < 8; ++i)
  {
    s += N[i] * h.s[i];
  }
  return s;
}

/// Solves x(u) = X by Newton's method from the given u (steps longer than 0.5 in the
/// parametric space are shortened to 0.5: a start far off does not jump away). Converged
/// when a step is below 1e-14, or below 1e-9 and no shorter than the one before: far from
/// the coordinates' origin (the Combustion Chamber at z = 23 to 36, cells 0.3 across) the
/// rounding of x(u) - X alone moves u by more than 1e-14, and Newton's steps, which shrink
/// quadratically until then, stall there. False when the Jacobian is singular or 50
/// iterations do not converge.
inline bool invertShapeMap(const RefCurvedCell& h, const Vec3d& X, Vec3d& u)
{
  double previous = 1e300;
  for (int iteration = 0; iteration < 50; ++iteration)
  {
    Vec3d J[3];
    const Vec3d F = shapePoint(h, u, J) - X;
    // J delta = F by Cramer's rule.
    const double det = dot(J[0], cross(J[1], J[2]));
    if (!(std::fabs(det) > 0))
    {
      return false;
    }
    Vec3d delta(dot(F, cross(J[1], J[2])) / det, dot(J[0], cross(F, J[2])) / det,
      dot(J[0], cross(J[1], F)) / det);
    const double size = std::max({ std::fabs(delta.x), std::fabs(delta.y), std::fabs(delta.z) });
    if (size > 0.5)
    {
      delta = delta * (0.5 / size);
    }
    u = u - delta;
    if (size < 1e-14 || (size < 1e-9 && size >= previous))
    {
      return true;
    }
    previous = size;
  }
  return false;
}

/// Appends the t of every crossing of the ray o + t d with the bilinear patch
///   P(a, b) = q00 + a (q10 - q00) + b (q01 - q00) + a b (q00 - q10 + q11 - q01),
/// (a, b) in [0, 1]^2. Two planes through the ray (normals n1, n2 orthogonal to d) give
/// D_k + B_k a + C_k b + A_k a b = 0 (k = 1, 2); eliminating a leaves the quadratic
///   (C1 A2 - C2 A1) b^2 + (D1 A2 + C1 B2 - D2 A1 - C2 B1) b + (D1 B2 - D2 B1) = 0,
/// then a = -(D_k + C_k b) / (B_k + A_k b) with the better conditioned k. Each root is
/// polished by two Newton steps on P(a, b) - o - t d = 0 and kept when (a, b) lies in the
/// patch (within 1e-10: a ray through an edge may count on both faces; the caller's
/// midpoint test makes that harmless).
inline void intersectBilinearPatch(const Vec3d& q00,
  const Vec3d& q10,
  const Vec3d& q11,
  const Vec3d& q01,
  const Vec3d& o,
  const Vec3d& d,
  std::vector<double>& out)
{
  const Vec3d e10 = q10 - q00, e01 = q01 - q00, g = q00 - q10 + q11 - q01;
  const Vec3d axis = std::fabs(d.x) < 0.6 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
  const Vec3d n1 = normalize(cross(d, axis));
  const Vec3d n2 = cross(d, n1);
  const double A1 = dot(n1, g), B1 = dot(n1, e10), C1 = dot(n1, e01), D1 = dot(n1, q00 - o);
  const double A2 = dot(n2, g), B2 = dot(n2, e10), C2 = dot(n2, e01), D2 = dot(n2, q00 - o);
  const double qa = C1 * A2 - C2 * A1;
  const double qb = D1 * A2 + C1 * B2 - D2 * A1 - C2 * B1;
  const double qc = D1 * B2 - D2 * B1;
  double roots[2];
  int count = 0;
  const double scale = std::fabs(qa) + std::fabs(qb) + std::fabs(qc);
  if (!(scale > 0))
  {
    return; // the ray lies in the patch's plane: no crossing
  }
  if (std::fabs(qa) <= 1e-14 * scale)
  {
    if (qb != 0)
    {
      roots[count++] = -qc / qb;
    }
  }
  else
  {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc < 0)
    {
      return;
    }
    // The stable pair of roots: q / qa and qc / q.
    const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
    roots[count++] = q / qa;
    if (q != 0)
    {
      roots[count++] = qc / q;
    }
  }
  const double size = length(e10) + length(e01);
  for (int r = 0; r < count; ++r)
  {
    double b = roots[r];
    const double den1 = B1 + A1 * b, den2 = B2 + A2 * b;
    double a = std::fabs(den1) > std::fabs(den2) ? -(D1 + C1 * b) / den1 : -(D2 + C2 * b) / den2;
    if (!std::isfinite(a) || !std::isfinite(b) || a < -0.1 || a > 1.1 || b < -0.1 || b > 1.1)
    {
      continue;
    }
    double t = dot(q00 + e10 * a + e01 * b + g * (a * b) - o, d);
    // Newton on F(a, b, t) = P(a, b) - o - t d, columns dP/da, dP/db, -d.
    for (int it = 0; it < 2; ++it)
    {
      const Vec3d F = q00 + e10 * a + e01 * b + g * (a * b) - o - d * t;
      const Vec3d ca = e10 + g * b, cb = e01 + g * a, ct = d * -1.0;
      const double det = dot(ca, cross(cb, ct));
      if (!(std::fabs(det) > 0))
      {
        break;
      }
      a -= dot(F, cross(cb, ct)) / det;
      b -= dot(ca, cross(F, ct)) / det;
      t -= dot(ca, cross(cb, F)) / det;
    }
    const double residual = length(q00 + e10 * a + e01 * b + g * (a * b) - o - d * t);
    const double tol = 1e-10;
    if (a >= -tol && a <= 1 + tol && b >= -tol && b <= 1 + tol && residual <= 1e-12 * size)
    {
      out.push_back(t);
    }
  }
}

/// Appends the t of the crossing of the ray o + t d with the triangle a, b, c (a wedge's or
/// a pyramid's flat faces), solving o + t d = a + beta (b - a) + gamma (c - a) by Cramer's
/// rule; kept within 1e-10 of the triangle, like the patches' crossings.
inline void intersectTriangle(const Vec3d& a,
  const Vec3d& b,
  const Vec3d& c,
  const Vec3d& o,
  const Vec3d& d,
  std::vector<double>& out)
{
  const Vec3d e1 = b - a, e2 = c - a, r = o - a;
  // [e1 e2 -d] (beta, gamma, t) = r.
  const Vec3d md = d * -1.0;
  const double det = dot(e1, cross(e2, md));
  if (!(std::fabs(det) > 0))
  {
    return; // the ray is parallel to the triangle's plane
  }
  const double beta = dot(r, cross(e2, md)) / det, gamma = dot(e1, cross(r, md)) / det;
  const double t = dot(e1, cross(e2, r)) / det;
  const double tol = 1e-10;
  if (beta >= -tol && gamma >= -tol && beta + gamma <= 1 + tol)
  {
    out.push_back(t);
  }
}

/// Whether X lies inside the cell (the map inverted from the cell's centre); an inversion
/// that fails counts in `failures` (when given) and answers false.
inline bool insideCell(const RefCurvedCell& h, const Vec3d& X, long* failures = nullptr)
{
  Vec3d u = parametricCentre(h);
  if (!invertShapeMap(h, X, u))
  {
    if (failures)
    {
      ++*failures;
    }
    return false;
  }
  return inParametricDomain(h, u);
}

/// The intervals [t0, t1] of the ray o + t d inside the cell, in order (the midpoint tests'
/// failed inversions counted in `failures`, when given).
inline std::vector<std::array<double, 2>> cellIntervals(const RefCurvedCell& h,
  const Vec3d& o,
  const Vec3d& d,
  long* failures = nullptr)
{
  std::vector<double> ts;
  if (h.shape == RefShape::Hexahedron)
  {
    for (const auto& f : HexFace)
    {
      intersectBilinearPatch(h.p[f[0]], h.p[f[1]], h.p[f[2]], h.p[f[3]], o, d, ts);
    }
  }
  else if (h.shape == RefShape::Wedge)
  {
    for (const auto& f : WedgeQuad)
    {
      intersectBilinearPatch(h.p[f[0]], h.p[f[1]], h.p[f[2]], h.p[f[3]], o, d, ts);
    }
    intersectTriangle(h.p[0], h.p[1], h.p[2], o, d, ts);
    intersectTriangle(h.p[3], h.p[4], h.p[5], o, d, ts);
  }
  else
  {
    intersectBilinearPatch(h.p[0], h.p[1], h.p[2], h.p[3], o, d, ts);
    for (int k = 0; k < 4; ++k)
    {
      intersectTriangle(h.p[k], h.p[(k + 1) % 4], h.p[4], o, d, ts);
    }
  }
  std::sort(ts.begin(), ts.end());
  std::vector<std::array<double, 2>> out;
  for (std::size_t k = 0; k + 1 < ts.size(); ++k)
  {
    if (ts[k + 1] > ts[k] && insideCell(h, o + d * (0.5 * (ts[k] + ts[k + 1])), failures))
    {
      if (!out.empty() && out.back()[1] == ts[k])
      {
        out.back()[1] = ts[k + 1]; // a duplicated crossing (an edge) split one interval
      }
      else
      {
        out.push_back({ ts[k], ts[k + 1] });
      }
    }
  }
  return out;
}

/// Counters of a trace: the points whose map was inverted, and the inversions that failed
/// (0 for a valid cell; a failure leaves the previous point's scalar).
struct TrilinearTraceCounts
{
  long evaluations = 0;
  long failures = 0;
};

namespace detail
{
// One interval of one cell along the ray, and the scalar along it by inversion.
struct TrilinearPath
{
  const RefCurvedCell* cell;
  double t0, t1;
  Vec3d o, d;
  Vec3d u{ 0.5, 0.5, 0.5 }; // the last inversion's solution (the next one's start)

  double scalar(double t, TrilinearTraceCounts& counts)
  {
    ++counts.evaluations;
    Vec3d v = u;
    if (invertShapeMap(*cell, o + d * t, v))
    {
      u = v;
    }
    else
    {
      ++counts.failures;
    }
    return shapeScalar(*cell, u);
  }
};

// The t in [t0, t1] where s(t) crosses one of the nodes, sampled every `step` and bisected.
inline std::vector<double> nodeCrossings(TrilinearPath& path,
  const RefTransferFunction& tf,
  double step,
  TrilinearTraceCounts& counts)
{
  std::vector<double> cuts;
  const int n = std::max(1, static_cast<int>(std::ceil((path.t1 - path.t0) / step)));
  double ta = path.t0, sa = path.scalar(ta, counts);
  for (int k = 1; k <= n; ++k)
  {
    const double tb = path.t0 + (path.t1 - path.t0) * k / n;
    const double sb = path.scalar(tb, counts);
    for (const double node : tf.s)
    {
      if ((sa - node) * (sb - node) < 0)
      {
        double lo = ta, hi = tb; // s - node changes sign on [lo, hi]
        const Vec3d keep = path.u;
        for (int it = 0; it < 200 && hi - lo > 1e-15 * std::max(1.0, std::fabs(hi)); ++it)
        {
          const double mid = 0.5 * (lo + hi);
          ((path.scalar(mid, counts) - node) * (sa - node) > 0 ? lo : hi) = mid;
        }
        path.u = keep;
        cuts.push_back(0.5 * (lo + hi));
      }
    }
    ta = tb;
    sa = sb;
  }
  std::sort(cuts.begin(), cuts.end());
  return cuts;
}

// RK4 on y = (T, C) over [a, b] in n steps, y' = (-tau T, c tau T).
inline void transport(TrilinearPath& path,
  const RefTransferFunction& tf,
  double a,
  double b,
  double step,
  double light[4],
  TrilinearTraceCounts& counts)
{
  const int n = std::max(1, static_cast<int>(std::ceil((b - a) / step)));
  const double h = (b - a) / n;
  auto rates = [&](double t, double& tau, double c[3]) { tf.at(path.scalar(t, counts), tau, c); };
  auto derivative = [](double tau, const double c[3], const double y[4], double dy[4]) {
    dy[0] = -tau * y[0];
    for (int ch = 0; ch < 3; ++ch)
    {
      dy[ch + 1] = c[ch] * tau * y[0];
    }
  };
  double tau0, c0[3];
  rates(a, tau0, c0);
  for (int k = 0; k < n; ++k)
  {
    const double t = a + h * k;
    double tauM, cM[3], tau1, c1[3];
    rates(t + 0.5 * h, tauM, cM);
    rates(t + h, tau1, c1);
    double k1[4], k2[4], k3[4], k4[4], y[4];
    derivative(tau0, c0, light, k1);
    for (int q = 0; q < 4; ++q)
    {
      y[q] = light[q] + 0.5 * h * k1[q];
    }
    derivative(tauM, cM, y, k2);
    for (int q = 0; q < 4; ++q)
    {
      y[q] = light[q] + 0.5 * h * k2[q];
    }
    derivative(tauM, cM, y, k3);
    for (int q = 0; q < 4; ++q)
    {
      y[q] = light[q] + h * k3[q];
    }
    derivative(tau1, c1, y, k4);
    for (int q = 0; q < 4; ++q)
    {
      light[q] += h / 6 * (k1[q] + 2 * k2[q] + 2 * k3[q] + k4[q]);
    }
    tau0 = tau1;
    std::copy(c1, c1 + 3, c0);
  }
}
} // namespace detail

/// Premultiplied RGBA of the ray o + t d (|d| = 1), t >= tMin, through the cells (their
/// interiors disjoint), integrated with steps of at most `step`; only the cells of
/// `candidates` when given (a superset of those the ray meets, as ReferenceTetraGrid finds).
inline std::array<double, 4> traceTrilinearReference(const std::vector<RefCurvedCell>& cells,
  const RefTransferFunction& tf,
  const Vec3d& o,
  const Vec3d& d,
  double tMin,
  double step,
  TrilinearTraceCounts* counts = nullptr,
  const std::vector<std::size_t>* candidates = nullptr)
{
  TrilinearTraceCounts local;
  TrilinearTraceCounts& c = counts ? *counts : local;
  std::vector<detail::TrilinearPath> paths;
  const std::size_t n = candidates ? candidates->size() : cells.size();
  for (std::size_t k = 0; k < n; ++k)
  {
    const RefCurvedCell& cell = cells[candidates ? (*candidates)[k] : k];
    for (const auto& interval : cellIntervals(cell, o, d, &c.failures))
    {
      if (interval[1] > tMin)
      {
        paths.push_back({ &cell, std::max(interval[0], tMin), interval[1], o, d });
      }
    }
  }
  std::sort(paths.begin(), paths.end(),
    [](const detail::TrilinearPath& a, const detail::TrilinearPath& b) { return a.t0 < b.t0; });
  // (T, C): transmittance and the light so far.
  double light[4] = { 1, 0, 0, 0 };
  for (detail::TrilinearPath& path : paths)
  {
    path.u = parametricCentre(*path.cell);
    std::vector<double> cuts = detail::nodeCrossings(path, tf, step, c);
    cuts.insert(cuts.begin(), path.t0);
    cuts.push_back(path.t1);
    path.u = parametricCentre(*path.cell);
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
    {
      detail::transport(path, tf, cuts[k], cuts[k + 1], step, light, c);
    }
  }
  return { light[1], light[2], light[3], 1.0 - light[0] };
}

} // namespace raymappers::test

#endif
