// An independent brute-force reference for unstructured-grid volume rendering, sharing no
// code with the ZSweep kernels: for one ray (double precision) it intersects every
// tetrahedron (clipping the ray by the four face planes), sorts the segments, and integrates
// each one numerically: the transfer function's nodes split it, the optical depth of each
// piece is integrated in closed form (tau is linear there) and the emitted light by
// composite Simpson's rule (512 intervals by default). For large grids a uniform grid of
// the tetrahedra's bounding boxes gives each ray its candidates (ReferenceTetraGrid).
//
// The model it integrates (the one ZSweep renders): tau = -ln(1 - alpha)/u and the color are
// linear in the scalar between the nodes; C = int c tau exp(-int tau).
//
// integrateSegments integrates segments found otherwise; clipToPolyhedron finds them in a
// cell bounded by triangles with the scalar linear between its crossings (ZSweep's model of
// a hexahedron, wedge or pyramid whose quadrilaterals are split into triangles), for cells
// that tetrahedra cannot represent (a non-convex cell).
#ifndef RayMappers_Test_UnstructuredReference_h
#define RayMappers_Test_UnstructuredReference_h

#include "Mappers/Common/Vec3.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

namespace raymappers::test
{

struct RefTetra
{
  std::array<Vec3d, 4> p;
  std::array<double, 4> s; // point scalars (point data)
  double cellScalar = 0;   // cell data
};

struct RefTransferFunction
{
  std::vector<double> s, rgb, alpha; // nodes
  double unitDistance = 1;

  void at(double v, double& tau, double c[3]) const
  {
    std::size_t k = 0;
    double f = 0;
    if (v <= s.front())
    {
      k = 0;
    }
    else if (v >= s.back())
    {
      k = s.size() - 1;
    }
    else
    {
      while (!(v >= s[k] && v <= s[k + 1]))
      {
        ++k;
      }
      f = (v - s[k]) / (s[k + 1] - s[k]);
    }
    auto tauOf = [&](std::size_t j) {
      return -std::log(1.0 - std::min(alpha[j], 1.0 - 1e-7)) / unitDistance;
    };
    const std::size_t k1 = std::min(k + 1, s.size() - 1);
    tau = tauOf(k) + f * (tauOf(k1) - tauOf(k));
    for (int ch = 0; ch < 3; ++ch)
    {
      c[ch] = rgb[3 * k + ch] + f * (rgb[3 * k1 + ch] - rgb[3 * k + ch]);
    }
  }
};

struct RefSegment
{
  double t0, t1, s0, s1;
};

/// The ray's part inside the tetrahedron, with the scalar at both ends (false: misses).
inline bool clipToTetra(const RefTetra& tet,
  const Vec3d& o,
  const Vec3d& d,
  bool cellData,
  RefSegment& seg)
{
  double t0 = -1e300, t1 = 1e300;
  // Face k is opposite vertex k; the plane's normal points towards vertex k (inside).
  std::array<Vec3d, 4> n;
  std::array<double, 4> c;
  for (int k = 0; k < 4; ++k)
  {
    const Vec3d& a = tet.p[(k + 1) % 4];
    const Vec3d& b = tet.p[(k + 2) % 4];
    const Vec3d& e = tet.p[(k + 3) % 4];
    Vec3d nk = cross(b - a, e - a);
    if (dot(nk, tet.p[k] - a) < 0)
    {
      nk = nk * -1.0;
    }
    n[k] = nk;
    c[k] = dot(nk, a);
    // Inside: n.x >= c; along the ray n.o + t n.d >= c. A ray in the plane (a ray along a
    // face shared by two cells) belongs to the side the normal's first non-zero component
    // points to, so exactly one of the two cells counts it.
    const double scale = length(nk);
    const double nd = dot(nk, d), no = dot(nk, o) - c[k];
    if (std::fabs(nd) <= 1e-12 * scale)
    {
      const double extent = length(b - a) + length(e - a);
      const bool onPlane = std::fabs(no) <= 1e-12 * scale * extent;
      const bool positive = nk.x != 0 ? nk.x > 0 : (nk.y != 0 ? nk.y > 0 : nk.z > 0);
      if (onPlane ? !positive : no < 0)
      {
        return false;
      }
      continue;
    }
    const double t = -no / nd;
    if (nd > 0)
    {
      t0 = std::max(t0, t);
    }
    else
    {
      t1 = std::min(t1, t);
    }
  }
  if (!(t0 < t1))
  {
    return false;
  }
  auto scalarAt = [&](double t) {
    if (cellData)
    {
      return tet.cellScalar;
    }
    const Vec3d x = o + d * t;
    double v = 0;
    for (int k = 0; k < 4; ++k)
    {
      v += tet.s[k] * (dot(n[k], x) - c[k]) / (dot(n[k], tet.p[k]) - c[k]);
    }
    return v;
  };
  seg = { t0, t1, scalarAt(t0), scalarAt(t1) };
  return true;
}

/// Premultiplied RGBA of a ray's segments (in any order; their interiors disjoint), each
/// with its scalar linear from s0 at t0 to s1 at t1: sorted, then integrated with the
/// transfer function's nodes splitting them, Simpson's rule with `intervals` (even)
/// intervals per piece.
inline std::array<double, 4> integrateSegments(std::vector<RefSegment> segs,
  const RefTransferFunction& tf,
  int intervals = 512)
{
  std::sort(segs.begin(), segs.end(), [](const RefSegment& a, const RefSegment& b) {
    return a.t0 < b.t0;
  });
  double rgb[3] = { 0, 0, 0 }, T = 1;
  for (const RefSegment& seg : segs)
  {
    // Pieces between the transfer function's nodes.
    std::vector<double> cuts = { seg.s0 };
    const double lo = std::min(seg.s0, seg.s1), hi = std::max(seg.s0, seg.s1);
    std::vector<double> inner;
    for (const double v : tf.s)
    {
      if (v > lo && v < hi)
      {
        inner.push_back(v);
      }
    }
    if (seg.s1 < seg.s0)
    {
      std::reverse(inner.begin(), inner.end());
    }
    cuts.insert(cuts.end(), inner.begin(), inner.end());
    cuts.push_back(seg.s1);
    const double L = seg.t1 - seg.t0;
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
    {
      const double l = seg.s1 == seg.s0 ? L : L * (cuts[k + 1] - cuts[k]) / (seg.s1 - seg.s0);
      if (!(l > 0))
      {
        continue;
      }
      double ta, tb, ca[3], cb[3];
      tf.at(cuts[k], ta, ca);
      tf.at(cuts[k + 1], tb, cb);
      // On the piece (x in [0, l]): tau = ta + (tb - ta) x / l, depth E(x) in closed form.
      auto depth = [&](double x) { return ta * x + 0.5 * (tb - ta) * x * x / l; };
      const int n = intervals;
      const double h = l / n;
      double acc[3] = { 0, 0, 0 };
      for (int i = 0; i <= n; ++i)
      {
        const double x = i * h;
        const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        const double tau = ta + (tb - ta) * x / l;
        const double att = std::exp(-depth(x));
        for (int ch = 0; ch < 3; ++ch)
        {
          const double c = ca[ch] + (cb[ch] - ca[ch]) * x / l;
          acc[ch] += w * c * tau * att;
        }
      }
      for (int ch = 0; ch < 3; ++ch)
      {
        rgb[ch] += T * acc[ch] * h / 3.0;
      }
      T *= std::exp(-depth(l));
    }
  }
  return { rgb[0], rgb[1], rgb[2], 1.0 - T };
}

/// Premultiplied RGBA of the ray o + t d (|d| = 1), t >= tMin, through the tetrahedra
/// `candidates` (indices into `tets`; all of them when null); Simpson's rule with
/// `intervals` (even) intervals per piece.
inline std::array<double, 4> traceReference(const std::vector<RefTetra>& tets,
  bool cellData,
  const RefTransferFunction& tf,
  const Vec3d& o,
  const Vec3d& d,
  double tMin,
  const std::vector<std::size_t>* candidates = nullptr,
  int intervals = 512)
{
  std::vector<RefSegment> segs;
  const std::size_t count = candidates ? candidates->size() : tets.size();
  for (std::size_t q = 0; q < count; ++q)
  {
    const RefTetra& tet = tets[candidates ? (*candidates)[q] : q];
    RefSegment s;
    if (clipToTetra(tet, o, d, cellData, s) && s.t1 > tMin)
    {
      if (s.t0 < tMin)
      {
        s.s0 = s.s0 + (s.s1 - s.s0) * (tMin - s.t0) / (s.t1 - s.t0);
        s.t0 = tMin;
      }
      segs.push_back(s);
    }
  }
  return integrateSegments(std::move(segs), tf, intervals);
}

/// A cell bounded by triangles, with a scalar per triangle corner (point data) or one for
/// the cell.
struct RefPolyhedron
{
  std::vector<std::array<Vec3d, 3>> triangles;
  std::vector<std::array<double, 3>> s;
  double cellScalar = 0;
};

/// Appends the ray's segments inside the polyhedron: its crossings with the triangles
/// (Moller-Trumbore in double, the scalar interpolated barycentrically), in order, bound the
/// inside between the first and the second, the third and the fourth ... (a closed surface
/// without self-intersections). False (nothing appended) when their count is odd: a ray
/// through an edge or a vertex, counted on two triangles.
inline bool clipToPolyhedron(const RefPolyhedron& cell,
  const Vec3d& o,
  const Vec3d& d,
  bool cellData,
  std::vector<RefSegment>& out)
{
  std::vector<std::pair<double, double>> crossings; // (t, scalar)
  for (std::size_t k = 0; k < cell.triangles.size(); ++k)
  {
    const auto& p = cell.triangles[k];
    const Vec3d e1 = p[1] - p[0], e2 = p[2] - p[0];
    const Vec3d pv = cross(d, e2);
    const double det = dot(e1, pv);
    if (!(std::fabs(det) > 1e-14 * length(e1) * length(e2)))
    {
      continue; // the ray runs along the triangle's plane
    }
    const Vec3d tv = o - p[0];
    const double u = dot(tv, pv) / det;
    const Vec3d qv = cross(tv, e1);
    const double v = dot(d, qv) / det;
    if (u < 0 || v < 0 || u + v > 1)
    {
      continue;
    }
    const double t = dot(e2, qv) / det;
    const double s = cellData
      ? cell.cellScalar
      : (1 - u - v) * cell.s[k][0] + u * cell.s[k][1] + v * cell.s[k][2];
    crossings.emplace_back(t, s);
  }
  if (crossings.size() % 2)
  {
    return false;
  }
  std::sort(crossings.begin(), crossings.end());
  for (std::size_t k = 0; k < crossings.size(); k += 2)
  {
    out.push_back({ crossings[k].first, crossings[k + 1].first, crossings[k].second,
      crossings[k + 1].second });
  }
  return true;
}

/// The cells (tetrahedra, or any cell type with its corners in `p`) binned by bounding box
/// into a uniform grid, walked along a ray (3D DDA) to collect the candidates the ray may
/// cross. A cell bounded by bilinear faces lies in its corners' box too (a bilinear patch is
/// a convex combination of its corners).
class ReferenceTetraGrid
{
public:
  template<typename Item>
  explicit ReferenceTetraGrid(const std::vector<Item>& tets)
  {
    Lo = Vec3d(1e300, 1e300, 1e300);
    Hi = Vec3d(-1e300, -1e300, -1e300);
    for (const Item& t : tets)
    {
      for (const Vec3d& p : t.p)
      {
        Lo = min(Lo, p);
        Hi = max(Hi, p);
      }
    }
    const int n = std::clamp(static_cast<int>(std::cbrt(static_cast<double>(tets.size()))), 1, 200);
    Res = { n, n, n };
    const Vec3d size = Hi - Lo;
    Cell = Vec3d(std::max(size.x, 1e-300) / n, std::max(size.y, 1e-300) / n,
      std::max(size.z, 1e-300) / n);
    std::vector<std::size_t> count(static_cast<std::size_t>(n) * n * n + 1, 0);
    auto each = [&](const Item& t, auto&& fn) {
      Vec3d lo = t.p[0], hi = t.p[0];
      for (const Vec3d& p : t.p)
      {
        lo = min(lo, p);
        hi = max(hi, p);
      }
      const auto a = cellOf(lo), b = cellOf(hi);
      for (int k = a[2]; k <= b[2]; ++k)
        for (int j = a[1]; j <= b[1]; ++j)
          for (int i = a[0]; i <= b[0]; ++i)
            fn(index(i, j, k));
    };
    for (const Item& t : tets)
    {
      each(t, [&](std::size_t c) { ++count[c + 1]; });
    }
    for (std::size_t c = 1; c < count.size(); ++c)
    {
      count[c] += count[c - 1];
    }
    Start = count;
    Items.resize(count.back());
    for (std::size_t q = 0; q < tets.size(); ++q)
    {
      each(tets[q], [&](std::size_t c) { Items[count[c]++] = q; });
    }
  }

  /// The cells whose boxes share a grid cell with the ray o + t d, t >= tMin.
  void candidates(const Vec3d& o, const Vec3d& d, double tMin, std::vector<std::size_t>& out) const
  {
    out.clear();
    double t0 = tMin, t1 = 1e300;
    const double od[3] = { o.x, o.y, o.z }, dd[3] = { d.x, d.y, d.z };
    const double lo[3] = { Lo.x, Lo.y, Lo.z }, hi[3] = { Hi.x, Hi.y, Hi.z };
    for (int a = 0; a < 3; ++a)
    {
      if (dd[a] == 0)
      {
        if (od[a] < lo[a] || od[a] > hi[a])
        {
          return;
        }
        continue;
      }
      double ta = (lo[a] - od[a]) / dd[a], tb = (hi[a] - od[a]) / dd[a];
      if (ta > tb)
      {
        std::swap(ta, tb);
      }
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    if (!(t0 <= t1))
    {
      return;
    }
    // Walk the cells the ray crosses between t0 and t1 (3D DDA).
    const Vec3d start = o + d * t0;
    auto c = cellOf(start);
    const double cs[3] = { Cell.x, Cell.y, Cell.z };
    int step[3];
    double next[3], delta[3];
    for (int a = 0; a < 3; ++a)
    {
      step[a] = dd[a] > 0 ? 1 : -1;
      const double boundary = lo[a] + (c[a] + (dd[a] > 0 ? 1 : 0)) * cs[a];
      next[a] = dd[a] != 0 ? (boundary - od[a]) / dd[a] : 1e300;
      delta[a] = dd[a] != 0 ? cs[a] / std::fabs(dd[a]) : 1e300;
    }
    while (true)
    {
      const std::size_t cell = index(c[0], c[1], c[2]);
      out.insert(out.end(), Items.begin() + static_cast<std::ptrdiff_t>(Start[cell]),
        Items.begin() + static_cast<std::ptrdiff_t>(Start[cell + 1]));
      const int a = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
      if (next[a] > t1)
      {
        break;
      }
      c[a] += step[a];
      if (c[a] < 0 || c[a] >= Res[a])
      {
        break;
      }
      next[a] += delta[a];
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

private:
  std::array<int, 3> cellOf(const Vec3d& p) const
  {
    const double v[3] = { (p.x - Lo.x) / Cell.x, (p.y - Lo.y) / Cell.y, (p.z - Lo.z) / Cell.z };
    std::array<int, 3> c;
    for (int a = 0; a < 3; ++a)
    {
      c[a] = std::clamp(static_cast<int>(std::floor(v[a])), 0, Res[a] - 1);
    }
    return c;
  }
  std::size_t index(int i, int j, int k) const
  {
    return (static_cast<std::size_t>(k) * Res[1] + j) * Res[0] + i;
  }

  Vec3d Lo, Hi, Cell;
  std::array<int, 3> Res;
  std::vector<std::size_t> Start, Items;
};

} // namespace raymappers::test

#endif
