// ZSweep kernels: the optical model's integrals against closed forms and quadrature; the
// mesh topology; the sweep's images against the independent brute-force ray caster of
// UnstructuredReference.h (rays through vertices and edges, perspective, cavities and
// disconnected parts, mixed cell types, inverted and bad cells, a forced growth of K); hard
// cases (thin cells at the volume threshold, half the cells inverted, cells that are not
// convex, zero-volume cells); the native hexahedra against the trilinear reference of
// TrilinearReference.h, and that reference's own checks.
#include "CameraFixtures.h"
#include "Mappers/ZSweep/OpticalModel.h"
#include "TrilinearReference.h"
#include "UnstructuredReference.h"
#include "Mappers/ZSweep/ZSweepMesh.h"
#include "Mappers/ZSweep/ZSweepRenderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <memory>
#include <random>

using namespace raymappers;
using namespace raymappers::test;

namespace
{
// ---------------------------------------------------------------------------------------
// Transfer function shared by the image tests (several nodes, varied colors).
RefTransferFunction testTransferFunction()
{
  RefTransferFunction tf;
  tf.s = { 0.0, 0.3, 0.6, 1.0 };
  tf.rgb = { 0.9, 0.1, 0.1, 0.1, 0.9, 0.2, 0.2, 0.3, 0.9, 1.0, 1.0, 0.4 };
  tf.alpha = { 0.05, 0.5, 0.1, 0.8 };
  tf.unitDistance = 0.5;
  return tf;
}

OpticalModel opticsOf(const RefTransferFunction& tf)
{
  OpticalModel m;
  m.assign(tf.s, tf.rgb, tf.alpha, tf.unitDistance);
  return m;
}

// ---------------------------------------------------------------------------------------
// Meshes: a lattice of n^3 cubes from `lo` with spacing h; each cube as a hexahedron or as
// the 6 tetrahedra of Freudenthal's split (all around the cube's main diagonal, so the
// split is conforming between cubes).
struct Lattice
{
  int n = 4;
  Vec3d lo{ -1, -1, -1 };
  double h = 0.5;
  double jitter = 0;  // interior points moved by up to jitter * h
  unsigned seed = 7;
  std::function<bool(int, int, int)> keep = [](int, int, int) { return true; };

  int id(int i, int j, int k) const { return (k * (n + 1) + j) * (n + 1) + i; }

  /// fn(i, j, k) for each kept cube, x fastest.
  template<typename Fn>
  void eachCube(Fn fn) const
  {
    for (int k = 0; k < n; ++k)
    {
      for (int j = 0; j < n; ++j)
      {
        for (int i = 0; i < n; ++i)
        {
          if (keep(i, j, k))
          {
            fn(i, j, k);
          }
        }
      }
    }
  }

  std::vector<Vec3d> points() const
  {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Vec3d> p;
    for (int k = 0; k <= n; ++k)
    {
      for (int j = 0; j <= n; ++j)
      {
        for (int i = 0; i <= n; ++i)
        {
          Vec3d q = lo + Vec3d(i * h, j * h, k * h);
          const bool interior = i > 0 && j > 0 && k > 0 && i < n && j < n && k < n;
          if (interior && jitter > 0)
          {
            q = q + Vec3d(u(rng), u(rng), u(rng)) * (jitter * h);
          }
          p.push_back(q);
        }
      }
    }
    return p;
  }

  // Global ids of cube (i, j, k)'s corners in VTK hexahedron order.
  std::array<int, 8> hex(int i, int j, int k) const
  {
    return { id(i, j, k),
      id(i + 1, j, k),
      id(i + 1, j + 1, k),
      id(i, j + 1, k),
      id(i, j, k + 1),
      id(i + 1, j, k + 1),
      id(i + 1, j + 1, k + 1),
      id(i, j + 1, k + 1) };
  }
};

// Freudenthal's 6 tetrahedra of a hexahedron given by its 8 corner ids (VTK order).
std::vector<std::array<int, 4>> freudenthal(const std::array<int, 8>& c)
{
  // VTK index of corner (a, b, e) (bits along x, y, z).
  auto corner = [&](int a, int b, int e) {
    static const int map[2][2][2] = { { { 0, 4 }, { 3, 7 } }, { { 1, 5 }, { 2, 6 } } };
    return c[map[a][b][e]];
  };
  const int perms[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 }, { 2, 1, 0 } };
  std::vector<std::array<int, 4>> out;
  for (const auto& p : perms)
  {
    int v[3] = { 0, 0, 0 };
    std::array<int, 4> t;
    t[0] = corner(0, 0, 0);
    for (int s = 0; s < 3; ++s)
    {
      v[p[s]] = 1;
      t[s + 1] = corner(v[0], v[1], v[2]);
    }
    out.push_back(t);
  }
  return out;
}

void addCell(ZSweepGrid& g, ZSweepCellType type, const std::vector<int>& ids)
{
  if (g.cellOffsets.empty())
  {
    g.cellOffsets.push_back(0);
  }
  g.cellTypes.push_back(type);
  for (const int i : ids)
  {
    g.connectivity.push_back(i);
  }
  g.cellOffsets.push_back(static_cast<std::int64_t>(g.connectivity.size()));
}

/// The lattice's points with the field's values, no cells yet.
ZSweepGrid latticePoints(const Lattice& L, const std::function<double(const Vec3d&)>& field)
{
  ZSweepGrid g;
  g.points = L.points();
  for (const Vec3d& p : g.points)
  {
    g.scalars.push_back(field(p));
  }
  return g;
}

ZSweepGrid tetLattice(const Lattice& L, const std::function<double(const Vec3d&)>& field)
{
  ZSweepGrid g = latticePoints(L, field);
  L.eachCube([&](int i, int j, int k) {
    for (const auto& t : freudenthal(L.hex(i, j, k)))
    {
      addCell(g, ZSweepCellType::Tetra, { t[0], t[1], t[2], t[3] });
    }
  });
  return g;
}

// The reference's tetrahedra of any grid: tetrahedra as they are, hexahedra by
// Freudenthal's split, wedges into 3 and pyramids into 2.
std::vector<RefTetra> referenceTetra(const ZSweepGrid& g)
{
  std::vector<RefTetra> out;
  for (std::size_t c = 0; c < g.cellTypes.size(); ++c)
  {
    const std::int64_t* v = g.connectivity.data() + g.cellOffsets[c];
    std::vector<std::array<int, 4>> tets;
    switch (g.cellTypes[c])
    {
      case ZSweepCellType::Tetra:
        tets.push_back({ int(v[0]), int(v[1]), int(v[2]), int(v[3]) });
        break;
      case ZSweepCellType::Hexahedron:
        tets = freudenthal({ int(v[0]), int(v[1]), int(v[2]), int(v[3]), int(v[4]), int(v[5]),
          int(v[6]), int(v[7]) });
        break;
      case ZSweepCellType::Wedge:
        tets = { { int(v[0]), int(v[1]), int(v[2]), int(v[3]) },
          { int(v[1]), int(v[2]), int(v[3]), int(v[4]) },
          { int(v[2]), int(v[3]), int(v[4]), int(v[5]) } };
        break;
      case ZSweepCellType::Pyramid:
        tets = { { int(v[0]), int(v[1]), int(v[2]), int(v[4]) },
          { int(v[0]), int(v[2]), int(v[3]), int(v[4]) } };
        break;
    }
    for (const auto& t : tets)
    {
      RefTetra r;
      for (int k = 0; k < 4; ++k)
      {
        r.p[k] = g.points[static_cast<std::size_t>(t[k])];
        r.s[k] = g.cellScalars ? 0 : g.scalars[static_cast<std::size_t>(t[k])];
      }
      r.cellScalar = g.cellScalars ? g.scalars[c] : 0;
      out.push_back(r);
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------
// A camera both the sweep (as a matrix) and the reference (as rays, from the same
// parameters, not from the matrix) use.
struct TestCamera
{
  Vec3d eye, at, up{ 0, 1, 0 };
  bool parallel = false;
  double fovy = 30, halfHeight = 1.5, nearD = 0.5, farD = 20;
  int width = 48, height = 48;

  Mat4 matrix() const
  {
    const double aspect = double(width) / height;
    const Mat4 proj = parallel ? orthographic(halfHeight * aspect, halfHeight, nearD, farD)
                               : perspective(fovy, aspect, nearD, farD);
    return multiply(proj, lookAt(eye, at, up));
  }

  void ray(int i, int j, Vec3d& o, Vec3d& d, double& tMin) const
  {
    const Vec3d f = normalize(at - eye);
    const Vec3d s = normalize(cross(f, up));
    const Vec3d u = cross(s, f);
    const double x = 2.0 * (i + 0.5) / width - 1.0, y = 2.0 * (j + 0.5) / height - 1.0;
    const double aspect = double(width) / height;
    if (parallel)
    {
      o = eye + s * (x * halfHeight * aspect) + u * (y * halfHeight);
      d = f;
      tMin = nearD;
      return;
    }
    const double th = std::tan(fovy * M_PI / 360.0);
    d = normalize(f + s * (x * th * aspect) + u * (y * th));
    o = eye;
    tMin = nearD / dot(d, f);
  }
};

struct Image
{
  Frame frame;
  RenderStatistics stats;
};

Image sweep(const ZSweepGrid& g,
  const RefTransferFunction& tf,
  const TestCamera& cam,
  ZSweepParameters params = ZSweepParameters(),
  bool sparse = false)
{
  ZSweepMesh mesh;
  mesh.build(g, sparse, params.cellField == ZSweepCellField::Native);
  Image im;
  im.frame.resize(cam.width, cam.height);
  renderZSweep({ mesh, opticsOf(tf) }, View(cam.matrix(), cam.width, cam.height, mesh.origin()), params, im.frame, im.stats);
  return im;
}

// The split-triangle model's parameters (the field linear between the split faces).
ZSweepParameters splitFaces()
{
  ZSweepParameters params;
  params.cellField = ZSweepCellField::SplitFaces;
  return params;
}

// Largest per-channel difference between the sweep and the reference over all pixels.
double maxErrorToReference(const Image& im,
  const ZSweepGrid& g,
  const RefTransferFunction& tf,
  const TestCamera& cam,
  int* coveredPixels = nullptr,
  const std::function<bool(const Vec3d&)>& skip = nullptr)
{
  const std::vector<RefTetra> tets = referenceTetra(g);
  double worst = 0;
  int covered = 0;
  for (int j = 0; j < cam.height; ++j)
  {
    for (int i = 0; i < cam.width; ++i)
    {
      Vec3d o, d;
      double tMin;
      cam.ray(i, j, o, d, tMin);
      if (skip && skip(o))
      {
        continue;
      }
      const auto ref = traceReference(tets, g.cellScalars, tf, o, d, tMin);
      const float* px = &im.frame.rgba[4 * im.frame.index(i, j)];
      covered += ref[3] > 1e-3;
      if (std::getenv("ZSWEEP_DEBUG") && std::fabs(px[3] - ref[3]) > 1e-4)
      {
        std::printf("pixel %d %d: sweep a %g reference a %g\n", i, j, px[3], ref[3]);
      }
      for (int c = 0; c < 4; ++c)
      {
        EXPECT_TRUE(std::isfinite(px[c]));
        worst = std::max(worst, std::fabs(double(px[c]) - ref[static_cast<std::size_t>(c)]));
      }
    }
  }
  if (coveredPixels)
  {
    *coveredPixels = covered;
  }
  return worst;
}

double maxDifference(const Frame& a, const Frame& b)
{
  double worst = 0;
  for (std::size_t k = 0; k < a.rgba.size(); ++k)
  {
    worst = std::max(worst, std::fabs(double(a.rgba[k]) - double(b.rgba[k])));
  }
  return worst;
}

// The cube of corners c (VTK's hexahedron order) as 2 wedges, cut along the plane through
// corners 0, 2, 6, 4.
void addWedgePair(ZSweepGrid& g, const std::array<int, 8>& c)
{
  addCell(g, ZSweepCellType::Wedge, { c[0], c[1], c[2], c[4], c[5], c[6] });
  addCell(g, ZSweepCellType::Wedge, { c[0], c[2], c[3], c[4], c[6], c[7] });
}

// The cube of corners c as 6 pyramids, one on each face, their apex a new point there.
void addPyramidsAround(ZSweepGrid& g, const std::array<int, 8>& c, const Vec3d& apexPoint)
{
  const int apex = static_cast<int>(g.points.size());
  g.points.push_back(apexPoint);
  const int faces[6][4] = { { 0, 3, 2, 1 }, { 4, 5, 6, 7 }, { 0, 1, 5, 4 }, { 1, 2, 6, 5 },
    { 2, 3, 7, 6 }, { 3, 0, 4, 7 } };
  for (const auto& f : faces)
  {
    addCell(g, ZSweepCellType::Pyramid, { c[f[0]], c[f[1]], c[f[2]], c[f[3]], apex });
  }
}

// Hexahedra, wedges (a cube cut in 2), pyramids (a cube cut in 6 around its centre) and
// tetrahedra in one grid of 3^3 cubes, with a linear point field (which every cell type
// interpolates exactly).
ZSweepGrid mixedGrid()
{
  Lattice L;
  L.n = 3;
  L.lo = { -1.5, -1.5, -1.5 };
  L.h = 1.0;
  const auto linear = [](const Vec3d& p) { return 0.5 + 0.2 * p.x - 0.1 * p.y + 0.15 * p.z; };
  ZSweepGrid g;
  g.points = L.points();
  L.eachCube([&](int i, int j, int k) {
    const auto c = L.hex(i, j, k);
    switch ((i + j + k) % 4)
    {
      case 0:
        addCell(g, ZSweepCellType::Hexahedron, { c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7] });
        break;
      case 1:
        addWedgePair(g, c);
        break;
      case 2:
        addPyramidsAround(g, c, L.lo + Vec3d(i + 0.5, j + 0.5, k + 0.5) * L.h);
        break;
      default:
        for (const auto& t : freudenthal(c))
        {
          addCell(g, ZSweepCellType::Tetra, { t[0], t[1], t[2], t[3] });
        }
    }
  });
  for (const Vec3d& p : g.points)
  {
    g.scalars.push_back(linear(p));
  }
  return g;
}

ZSweepGrid hexLattice(const Lattice& L, const std::function<double(const Vec3d&)>& field)
{
  ZSweepGrid g = latticePoints(L, field);
  L.eachCube([&](int i, int j, int k) {
    const auto c = L.hex(i, j, k);
    addCell(g, ZSweepCellType::Hexahedron, { c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7] });
  });
  return g;
}

// The grid with cell data instead: a scalar per cell, varied.
ZSweepGrid withCellData(ZSweepGrid g)
{
  g.cellScalars = true;
  g.scalars.clear();
  for (std::size_t c = 0; c < g.cellTypes.size(); ++c)
  {
    g.scalars.push_back(0.15 + 0.7 * double((c * 37) % 11) / 10.0);
  }
  return g;
}

double smoothField(const Vec3d& p)
{
  return 0.5 + 0.45 * std::sin(1.7 * p.x + 0.4) * std::cos(1.3 * p.y - 0.2) * (0.6 + 0.4 * p.z);
}
} // namespace

// =======================================================================================
// Optical model.

TEST(ZSweepOptics, GaussianDepthIntegralMatchesQuadrature)
{
  // G(A, B) = int_0^1 exp(-A x - B x^2) dx against composite Simpson with 20000 intervals.
  const double cases[][2] = { { 0, 0 }, { 1e-9, 0 }, { 0.02, 0.01 }, { 0.045, -0.02 }, { 0, 0.024 },
    { 0.3, 0 }, { 0.3, 0.2 }, { 2, -0.9 },
    { 5, 3 }, { 0, 12 }, { 50, -20 }, { 300, 100 }, { 1e-6, 1e-6 }, { 80, -39.9 } };
  for (const auto& c : cases)
  {
    const double A = c[0], B = c[1];
    const int n = 20000;
    double sum = 0;
    for (int i = 0; i <= n; ++i)
    {
      const double x = double(i) / n;
      const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
      sum += w * std::exp(-A * x - B * x * x);
    }
    sum /= 3.0 * n;
    EXPECT_NEAR(gaussianDepthIntegral(A, B), sum, 1e-10 * std::max(1.0, sum))
      << "A " << A << " B " << B;
  }
}

TEST(ZSweepOptics, HomogeneousSegmentIsBeerLambert)
{
  RefTransferFunction tf;
  tf.s = { 0, 1 };
  tf.rgb = { 0.2, 0.4, 0.8, 0.2, 0.4, 0.8 };
  tf.alpha = { 0.3, 0.3 };
  tf.unitDistance = 2.0;
  const OpticalModel m = opticsOf(tf);
  const double tau = -std::log(0.7) / 2.0;
  for (const double L : { 1e-8, 0.01, 1.0, 7.0, 400.0 })
  {
    for (const auto method : { ZSweepIntegrator::Exact, ZSweepIntegrator::Midpoint })
    {
      const SegmentLight a = m.integrate(method, 0.2, 0.7, L);
      EXPECT_NEAR(a.transmittance, std::exp(-tau * L), 1e-14);
      EXPECT_NEAR(a.b, 0.8 * -std::expm1(-tau * L), 1e-14 + 1e-12 * 0.8 * -std::expm1(-tau * L));
    }
    const SegmentLight h = m.integrateHomogeneous(0.4, L);
    EXPECT_NEAR(h.transmittance, std::exp(-tau * L), 1e-14);
  }
}

namespace
{
// Direct quadrature of the model along a segment of length L whose scalar goes linearly from
// s0 to s1: 200,000 homogeneous steps at the midpoints.
SegmentLight quadratureOf(const RefTransferFunction& tf, double s0, double s1, double L)
{
  const int n = 200000;
  const double h = L / n;
  SegmentLight out;
  double* rgb[3] = { &out.r, &out.g, &out.b };
  for (int i = 0; i < n; ++i)
  {
    const double s = s0 + (s1 - s0) * (i + 0.5) / n;
    double tau, col[3];
    tf.at(s, tau, col);
    const double a = -std::expm1(-tau * h);
    for (int ch = 0; ch < 3; ++ch)
    {
      *rgb[ch] += out.transmittance * col[ch] * a;
    }
    out.transmittance *= 1 - a;
  }
  return out;
}
} // namespace

TEST(ZSweepOptics, ExactSegmentMatchesReferenceAcrossNodes)
{
  const RefTransferFunction tf = testTransferFunction();
  const OpticalModel m = opticsOf(tf);
  // Segments inside one node interval, across several, backwards, beyond the end nodes,
  // constant, and tiny; each also scaled down into the SIMD lanes' series range (L / 400:
  // optical depth below 0.1) and integrated one by one and through a batch.
  for (const auto& c : std::vector<std::array<double, 3>>{ { 0.1, 0.9, 1.3 }, { 0.95, 0.05, 0.7 },
         { 0.3, 0.6, 2.0 }, { -0.5, 1.5, 3.0 }, { 0.45, 0.45, 1.0 }, { 0.2, 0.25, 1e-5 } })
  {
    for (const double scale : { 1.0, 1.0 / 400 })
    {
      const double s0 = c[0], s1 = c[1], L = c[2] * scale;
      const SegmentLight q = quadratureOf(tf, s0, s1, L);
      SegmentBatch batch;
      batch.push(s0, s1, L);
      m.integrate(ZSweepIntegrator::Exact, batch);
      const SegmentLight one = m.integrate(ZSweepIntegrator::Exact, s0, s1, L);
      const SegmentLight batched{ batch.r[0], batch.g[0], batch.b[0], batch.transmittance[0] };
      for (const SegmentLight& e : { one, batched })
      {
        EXPECT_NEAR(e.transmittance, q.transmittance, 1e-7) << s0 << " " << s1 << " " << L;
        EXPECT_NEAR(e.r, q.r, 1e-7);
        EXPECT_NEAR(e.g, q.g, 1e-7);
        EXPECT_NEAR(e.b, q.b, 1e-7);
      }
    }
  }
}

TEST(ZSweepOptics, BatchMatchesSegmentBySegment)
{
  // Random segments (inside one interval, across nodes, beyond the end nodes, constant,
  // shallow and deep) through a batch against integrate() one at a time, with 4 nodes and
  // 40 nodes (SIMD lanes) and 100 nodes (the batch goes one by one).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const int nodes : { 4, 40, 100 })
  {
    RefTransferFunction tf;
    for (int j = 0; j < nodes; ++j)
    {
      tf.s.push_back(double(j) / (nodes - 1));
      tf.alpha.push_back(j % 3 == 1 ? 0.0 : 0.9 * u(rng));
      for (int c = 0; c < 3; ++c)
      {
        tf.rgb.push_back(u(rng));
      }
    }
    tf.unitDistance = 0.5;
    const OpticalModel m = opticsOf(tf);
    SegmentBatch batch;
    std::vector<std::array<double, 3>> segments;
    for (int i = 0; i < 3000; ++i)
    {
      const double s0 = -0.2 + 1.4 * u(rng);
      const double s1 =
        i % 5 == 0 ? s0 : (i % 2 ? s0 + 0.02 * (u(rng) - 0.5) : -0.2 + 1.4 * u(rng));
      const double L = std::pow(10.0, -6 + 7 * u(rng));
      segments.push_back({ s0, s1, L });
      batch.push(s0, s1, L);
    }
    for (const auto method : { ZSweepIntegrator::Exact, ZSweepIntegrator::Farias })
    {
      m.integrate(method, batch);
      for (std::size_t i = 0; i < segments.size(); ++i)
      {
        const auto& c = segments[i];
        const SegmentLight e = m.integrate(method, c[0], c[1], c[2]);
        const double tol = 1e-11;
        EXPECT_NEAR(batch.transmittance[i], e.transmittance, tol)
          << nodes << " " << c[0] << " " << c[1] << " " << c[2];
        EXPECT_NEAR(batch.r[i], e.r, tol);
        EXPECT_NEAR(batch.g[i], e.g, tol);
        EXPECT_NEAR(batch.b[i], e.b, tol);
      }
    }
    SegmentBatch homogeneous;
    homogeneous.push(0.45, 0.45, 2.0);
    m.integrateHomogeneous(homogeneous);
    const SegmentLight h = m.integrateHomogeneous(0.45, 2.0);
    EXPECT_EQ(homogeneous.transmittance[0], h.transmittance);
    EXPECT_EQ(homogeneous.r[0], h.r);
  }
}

TEST(ZSweepOptics, FariasAndMidpointConvergeOnShortSegments)
{
  const OpticalModel m = opticsOf(testTransferFunction());
  // Second-order formulas: in a field of fixed gradient (ds/dt = 1), the error of a
  // segment shrinks at least like L^2 with its length: 8 times shorter, 16 times smaller.
  for (const auto method : { ZSweepIntegrator::Farias, ZSweepIntegrator::Midpoint })
  {
    double err[2];
    int k = 0;
    for (const double L : { 0.2, 0.025 })
    {
      const SegmentLight e = m.integrate(ZSweepIntegrator::Exact, 0.35, 0.35 + L, L);
      const SegmentLight f = m.integrate(method, 0.35, 0.35 + L, L);
      err[k++] = std::fabs(e.r - f.r) + std::fabs(e.transmittance - f.transmittance);
    }
    EXPECT_GT(err[0], 0);
    EXPECT_LT(err[1], err[0] / 16);
  }
  EXPECT_TRUE(m.transparentBetween(-1, -0.5) == false); // alpha 0.05 below the first node
  RefTransferFunction holes = testTransferFunction();
  holes.alpha = { 0, 0, 0.5, 0.5 };
  const OpticalModel h = opticsOf(holes);
  EXPECT_TRUE(h.transparentBetween(0.1, 0.25));
  EXPECT_TRUE(h.transparentBetween(0.3, 0.0));
  EXPECT_FALSE(h.transparentBetween(0.1, 0.35));
}

// =======================================================================================
// Topology.

TEST(ZSweepMesh, TrianglesOfALatticeAreSharedOnce)
{
  Lattice L;
  L.n = 3;
  const ZSweepGrid g = tetLattice(L, smoothField);
  ZSweepMesh mesh;
  mesh.build(g);
  // 27 cubes * 6 tets; each tet has 4 faces: interior triangles are shared by 2 tets.
  const std::size_t tets = 27 * 6;
  const std::size_t boundary = 6 * 9 * 2; // 6 sides, 9 squares each, 2 triangles
  EXPECT_EQ(mesh.counts().cellsUsed, tets);
  EXPECT_EQ(mesh.counts().boundaryTriangles, boundary);
  EXPECT_EQ(mesh.numTriangles(), (4 * tets + boundary) / 2);
  EXPECT_EQ(mesh.counts().nonManifoldTriangles, 0u);
  std::vector<ZSweepTriangle> scratch;
  for (const ZSweepTriangle& t : mesh.triangles(scratch))
  {
    EXPECT_NE(t.front, t.back);
  }
}

TEST(ZSweepMesh, HexahedraSplitSharedQuadsTheSameWay)
{
  // Two hexahedra sharing a (non-planar) quad, listed with different local orders: the quad
  // must become the same two triangles from both sides (no boundary inside).
  ZSweepGrid g;
  g.points = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0.2 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 },
    { 1, 1, 1 }, { 0, 1, 1 }, { 2, 0, 0 }, { 2, 1, 0 }, { 2, 0, 1 }, { 2, 1, 1 } };
  g.scalars.assign(g.points.size(), 0.5);
  addCell(g, ZSweepCellType::Hexahedron, { 0, 1, 2, 3, 4, 5, 6, 7 });
  // The second cell starts at a different corner of the shared face (1, 2, 6, 5).
  addCell(g, ZSweepCellType::Hexahedron, { 5, 10, 11, 6, 1, 8, 9, 2 });
  ZSweepMesh mesh;
  mesh.build(g);
  EXPECT_EQ(mesh.counts().cellsUsed, 2u);
  EXPECT_EQ(mesh.numTriangles(), 22u); // 11 quads, 2 triangles each
  EXPECT_EQ(mesh.counts().boundaryTriangles, 20u);
}

TEST(ZSweepMesh, BadCellsAreCountedAndLeftOut)
{
  Lattice L;
  L.n = 2;
  ZSweepGrid g = tetLattice(L, smoothField);
  const std::size_t good = g.cellTypes.size();
  const int nanPoint = static_cast<int>(g.points.size());
  g.points.push_back({ std::nan(""), 0, 0 });
  g.scalars.push_back(0.5);
  addCell(g, ZSweepCellType::Tetra, { 0, 1, 4, nanPoint });
  const int nanScalar = static_cast<int>(g.points.size());
  g.points.push_back({ 5, 5, 5 });
  g.scalars.push_back(std::numeric_limits<double>::quiet_NaN());
  addCell(g, ZSweepCellType::Tetra, { 0, 1, 3, nanScalar });
  addCell(g, ZSweepCellType::Tetra, { 0, 1, 2, 99999 });
  addCell(g, ZSweepCellType::Tetra, { 0, 1, 2, 1 }); // repeated vertex: zero volume
  ZSweepMesh mesh;
  mesh.build(g);
  EXPECT_EQ(mesh.counts().cellsUsed, good);
  EXPECT_EQ(mesh.counts().nonFinitePoint, 1u);
  EXPECT_EQ(mesh.counts().nonFiniteScalar, 1u);
  EXPECT_EQ(mesh.counts().badIndex, 1u);
  EXPECT_EQ(mesh.counts().zeroVolume, 1u);
}

// Overlapping cells are not a valid grid: a duplicated tetrahedron puts two cells on the
// same side of each of its 4 faces, and a third cell on an interior face makes it shared by
// three; both are counted (the mapper warns) and the valid lattice counts none.
TEST(ZSweepMesh, OverlappingCellsAreCounted)
{
  Lattice L;
  L.n = 2;
  ZSweepGrid g = tetLattice(L, smoothField);
  ZSweepMesh mesh;
  mesh.build(g);
  EXPECT_EQ(mesh.counts().nonManifoldTriangles, 0u);
  const std::int64_t first = g.cellOffsets[0];
  const std::vector<int> cell(g.connectivity.begin() + first, g.connectivity.begin() + first + 4);
  addCell(g, ZSweepCellType::Tetra, cell);
  mesh.build(g);
  EXPECT_EQ(mesh.counts().nonManifoldTriangles, 4u);
}

// =======================================================================================
// Images against the reference ray caster.

TEST(ZSweepImage, HomogeneousCubeTransmittanceIsExact)
{
  Lattice L; // [-1, 1]^3
  ZSweepGrid g = tetLattice(L, smoothField);
  g.cellScalars = true;
  g.scalars.assign(g.cellTypes.size(), 0.45);
  RefTransferFunction tf;
  tf.s = { 0, 1 };
  tf.rgb = { 1, 0.5, 0.25, 1, 0.5, 0.25 };
  tf.alpha = { 0.4, 0.4 };
  tf.unitDistance = 1.0;
  TestCamera cam;
  cam.parallel = true;
  cam.eye = { 0.013, -0.021, 6 };
  cam.at = { 0.013, -0.021, 0 };
  const Image im = sweep(g, tf, cam);
  const double expected = 1 - std::exp(std::log(0.6) * 2.0); // L = 2 through the cube
  int inside = 0;
  for (int j = 0; j < cam.height; ++j)
  {
    for (int i = 0; i < cam.width; ++i)
    {
      Vec3d o, d;
      double tMin;
      cam.ray(i, j, o, d, tMin);
      const bool in = std::fabs(o.x) < 1 && std::fabs(o.y) < 1;
      const float a = im.frame.rgba[4 * im.frame.index(i, j) + 3];
      if (in)
      {
        ++inside;
        EXPECT_NEAR(a, expected, 2e-6) << i << " " << j;
      }
      else
      {
        EXPECT_EQ(a, 0.f) << i << " " << j;
      }
    }
  }
  EXPECT_GT(inside, 100);
  EXPECT_TRUE(im.stats.effect("cell_data"));
}

TEST(ZSweepImage, LinearFieldAlongTheRayIntegratesInClosedForm)
{
  // s = (z + 1) / 2 through the cube [-1, 1]^3 seen along -z: tau rises linearly from tau0
  // to tau1 over L = 2, so T = exp(-(tau0 + tau1)), and with one color c, C = c (1 - T).
  Lattice L;
  const ZSweepGrid g = tetLattice(L, [](const Vec3d& p) { return 0.5 * (p.z + 1); });
  RefTransferFunction tf;
  tf.s = { 0, 1 };
  tf.rgb = { 0.3, 0.6, 0.9, 0.3, 0.6, 0.9 };
  tf.alpha = { 0.1, 0.7 };
  tf.unitDistance = 1.0;
  TestCamera cam;
  cam.parallel = true;
  cam.eye = { 0.0, 0.0, 6 };
  cam.at = { 0.0, 0.0, 0 };
  const Image im = sweep(g, tf, cam);
  const double tau0 = -std::log(0.9), tau1 = -std::log(0.3);
  const double T = std::exp(-(tau0 + tau1));
  const float* centre = &im.frame.rgba[4 * im.frame.index(cam.width / 2, cam.height / 2)];
  EXPECT_NEAR(centre[3], 1 - T, 1e-6);
  EXPECT_NEAR(centre[1], 0.6 * (1 - T), 1e-6);
}

TEST(ZSweepImage, RaysThroughVerticesAndEdgesMatchTheReference)
{
  // Lattice points and the split's diagonals fall exactly on pixel centres: pixel size
  // 0.05, centres at -1.475 + 0.05 i, lattice at -1.025 + 0.5 k. Rays exactly on the outer
  // silhouette (x or y on the grid's bounds) graze the grid: whether they count is a
  // convention (the top-left rule here), so they are not compared.
  Lattice L;
  L.lo = { -1.025, -1.025, -1.0 };
  const ZSweepGrid g = tetLattice(L, smoothField);
  const RefTransferFunction tf = testTransferFunction();
  TestCamera cam;
  cam.parallel = true;
  cam.width = cam.height = 60;
  cam.halfHeight = 1.5;
  cam.eye = { 0, 0, 6 };
  cam.at = { 0, 0, 0 };
  const Image im = sweep(g, tf, cam);
  int covered = 0;
  const auto onSilhouette = [](const Vec3d& o) {
    const auto on = [](double v) {
      return std::fabs(v + 1.025) < 1e-9 || std::fabs(v - 0.975) < 1e-9;
    };
    return on(o.x) || on(o.y);
  };
  EXPECT_LT(maxErrorToReference(im, g, tf, cam, &covered, onSilhouette), 1e-5);
  EXPECT_GT(covered, 1000);
  EXPECT_GT(im.stats.counter("tie_groups"), 0);
}

TEST(ZSweepImage, PerspectiveJitteredTetrahedraMatchTheReference)
{
  Lattice L;
  L.jitter = 0.3;
  const ZSweepGrid g = tetLattice(L, smoothField);
  const RefTransferFunction tf = testTransferFunction();
  TestCamera cam;
  cam.eye = { 3.1, 2.3, 4.2 };
  cam.at = { 0.1, -0.1, 0.05 };
  const Image im = sweep(g, tf, cam);
  int covered = 0;
  EXPECT_LT(maxErrorToReference(im, g, tf, cam, &covered), 1e-5);
  EXPECT_GT(covered, 300);
  for (const auto method : { ZSweepIntegrator::Farias, ZSweepIntegrator::Midpoint })
  {
    ZSweepParameters p;
    p.integrator = method;
    const Image approx = sweep(g, tf, cam, p);
    const double err = maxErrorToReference(approx, g, tf, cam);
    EXPECT_GT(err, 1e-5); // a different (approximate) integral ...
    EXPECT_LT(err, 0.5);  // ... of the same picture (big cells: coarse approximations)
  }
}

TEST(ZSweepImage, CavityAndDisconnectedPartsMatchTheReference)
{
  Lattice L;
  L.n = 5;
  L.lo = { -1.25, -1.25, -1.25 };
  L.jitter = 0.2;
  // A hollow centre and a gap splitting the grid into two parts along x.
  L.keep = [](int i, int j, int k) {
    const bool centre = i >= 1 && i <= 3 && j >= 1 && j <= 3 && k == 2;
    return !centre && i != 2;
  };
  const ZSweepGrid g = tetLattice(L, smoothField);
  const RefTransferFunction tf = testTransferFunction();
  for (const bool parallel : { true, false })
  {
    TestCamera cam;
    cam.parallel = parallel;
    cam.halfHeight = 2.0;
    cam.eye = { 5.5, 1.2, 2.1 };
    cam.at = { 0, 0, 0 };
    const Image im = sweep(g, tf, cam);
    EXPECT_LT(maxErrorToReference(im, g, tf, cam), 1e-5) << "parallel " << parallel;
  }
}

TEST(ZSweepImage, MixedCellTypesWithALinearFieldMatchTheReference)
{
  const ZSweepGrid g = mixedGrid();
  const RefTransferFunction tf = testTransferFunction();
  TestCamera cam;
  cam.eye = { 4.2, 3.3, 5.0 };
  cam.at = { 0.05, 0.1, 0 };
  const Image im = sweep(g, tf, cam);
  int covered = 0;
  EXPECT_LT(maxErrorToReference(im, g, tf, cam, &covered), 1e-5);
  EXPECT_GT(covered, 500);
}

// A jittered 6 x 6 x 6 lattice of tetrahedralized cubes around the origin.
ZSweepGrid jitteredLattice()
{
  Lattice L;
  L.n = 6;
  L.lo = { -1.2, -1.2, -1.2 };
  L.h = 0.4;
  L.jitter = 0.25;
  return tetLattice(L, smoothField);
}

TEST(ZSweepImage, ParametersAndCellOrientationDoNotChangeThePicture)
{
  ZSweepGrid g = jitteredLattice();
  const RefTransferFunction tf = testTransferFunction();
  TestCamera cam;
  cam.eye = { 2.5, -3.0, 3.5 };
  cam.at = { 0, 0, 0 };
  const Image base = sweep(g, tf, cam);

  // Tiny lists: K must grow, the picture must not change.
  ZSweepParameters small;
  small.listThreshold = 2;
  small.tileSize = 8;
  const Image grown = sweep(g, tf, cam, small);
  EXPECT_GT(grown.stats.counter("k_growths"), 0);
  EXPECT_LT(maxDifference(base.frame, grown.frame), 1e-6);

  // Inverted cells (two vertices swapped): same picture.
  for (std::size_t c = 0; c < g.cellTypes.size(); ++c)
  {
    std::swap(g.connectivity[static_cast<std::size_t>(g.cellOffsets[c])],
      g.connectivity[static_cast<std::size_t>(g.cellOffsets[c]) + 1]);
  }
  const Image inverted = sweep(g, tf, cam);
  EXPECT_LT(maxDifference(base.frame, inverted.frame), 1e-6);
}

// The event order kept between frames is only the start of the next frame's sort: the
// pictures equal those of a fresh sort; a camera that stays costs no move, one that moves a
// little some moves and no full sort, one that moves far a full sort.
TEST(ZSweepImage, TheEventOrderKeptBetweenFramesChangesNoPicture)
{
  const ZSweepGrid g = jitteredLattice();
  const RefTransferFunction tf = testTransferFunction();
  ZSweepMesh mesh;
  mesh.build(g, false);
  ZSweepEventOrder order;
  auto render = [&](const TestCamera& cam, ZSweepEventOrder* kept) {
    Image im;
    im.frame.resize(cam.width, cam.height);
    renderZSweep({ mesh, opticsOf(tf), kept }, View(cam.matrix(), cam.width, cam.height, mesh.origin()), ZSweepParameters(), im.frame, im.stats);
    return im;
  };
  TestCamera cam;
  cam.eye = { 2.5, -3.0, 3.5 };
  cam.at = { 0, 0, 0 };
  const Image first = render(cam, &order);
  EXPECT_EQ(first.stats.counter("order_sorts"), 1); // nothing kept yet
  EXPECT_EQ(maxDifference(first.frame, render(cam, nullptr).frame), 0.0);
  const Image still = render(cam, &order);
  EXPECT_EQ(still.stats.counter("order_sorts"), 0);
  EXPECT_EQ(still.stats.counter("order_moves"), 0);
  EXPECT_EQ(maxDifference(still.frame, first.frame), 0.0);

  TestCamera moved = cam;
  moved.eye = { 2.51, -3.0, 3.5 };
  const Image near = render(moved, &order);
  EXPECT_EQ(near.stats.counter("order_sorts"), 0);
  EXPECT_GT(near.stats.counter("order_moves"), 0);
  EXPECT_EQ(maxDifference(near.frame, render(moved, nullptr).frame), 0.0);
  EXPECT_LT(maxErrorToReference(near, g, tf, moved), 1e-5);

  TestCamera behind = cam;
  behind.eye = { -2.5, 3.0, -3.5 };
  const Image far = render(behind, &order);
  EXPECT_EQ(far.stats.counter("order_sorts"), 1);
  EXPECT_EQ(maxDifference(far.frame, render(behind, nullptr).frame), 0.0);
}

TEST(ZSweepImage, BadCellsLeaveTheRestOfThePictureAndNoNaN)
{
  Lattice L;
  const ZSweepGrid clean = tetLattice(L, smoothField);
  ZSweepGrid g = clean;
  const int nanPoint = static_cast<int>(g.points.size());
  g.points.push_back({ std::nan(""), 0, 0 });
  g.scalars.push_back(0.5);
  addCell(g, ZSweepCellType::Tetra, { 0, 1, 4, nanPoint });
  const int far = static_cast<int>(g.points.size());
  g.points.push_back({ 0.5, 0.5, 3 });
  g.scalars.push_back(std::numeric_limits<double>::infinity());
  addCell(g, ZSweepCellType::Tetra, { 0, 1, 3, far });
  const RefTransferFunction tf = testTransferFunction();
  TestCamera cam;
  cam.eye = { 2, 3, 5 };
  cam.at = { 0, 0, 0 };
  const Image bad = sweep(g, tf, cam);
  const Image good = sweep(clean, tf, cam);
  EXPECT_LT(maxDifference(bad.frame, good.frame), 1e-6);
  for (const float v : bad.frame.rgba)
  {
    ASSERT_TRUE(std::isfinite(v));
  }
}

TEST(ZSweepReference, GridCandidatesGiveTheSameRaysAsAllCells)
{
  // The bench's reference walks a grid of the cells: it must see every cell a ray meets.
  Lattice L;
  L.n = 5;
  L.jitter = 0.3;
  const ZSweepGrid g = tetLattice(L, smoothField);
  const std::vector<RefTetra> tets = referenceTetra(g);
  const ReferenceTetraGrid grid(tets);
  const RefTransferFunction tf = testTransferFunction();
  TestCamera cam;
  cam.eye = { 2.9, -1.7, 3.6 };
  cam.at = { 0.1, 0.2, -0.1 };
  std::vector<std::size_t> candidates;
  double worst = 0;
  for (int j = 0; j < cam.height; j += 3)
  {
    for (int i = 0; i < cam.width; i += 3)
    {
      Vec3d o, d;
      double tMin;
      cam.ray(i, j, o, d, tMin);
      grid.candidates(o, d, tMin, candidates);
      const auto all = traceReference(tets, false, tf, o, d, tMin, nullptr, 64);
      const auto some = traceReference(tets, false, tf, o, d, tMin, &candidates, 64);
      for (int c = 0; c < 4; ++c)
      {
        worst = std::max(worst, std::fabs(all[static_cast<std::size_t>(c)] - some[static_cast<std::size_t>(c)]));
      }
    }
  }
  EXPECT_EQ(worst, 0.0);
}

TEST(ZSweepImage, CameraInsideTheGridMatchesTheReference)
{
  // The eye inside the grid: the near plane cuts cells; each ray starts in the cell its
  // cap belongs to. Also the eye outside with the near plane cutting the grid.
  Lattice L;
  L.n = 5;
  L.lo = { -1.25, -1.25, -1.25 };
  L.jitter = 0.2;
  for (const bool cellData : { false, true })
  {
    ZSweepGrid g = tetLattice(L, smoothField);
    if (cellData)
    {
      g.cellScalars = true;
      g.scalars.clear();
      for (std::size_t c = 0; c < g.cellTypes.size(); ++c)
      {
        g.scalars.push_back(0.2 + 0.6 * double(c % 7) / 6.0);
      }
    }
    const RefTransferFunction tf = testTransferFunction();
    for (const auto& eye : { Vec3d(0.13, 0.21, 0.37), Vec3d(0.4, -0.3, 1.3) })
    {
      TestCamera cam;
      cam.eye = eye;
      cam.at = { 1.0, 0.45, -0.2 };
      cam.fovy = 70;
      cam.nearD = 0.3;
      const Image im = sweep(g, tf, cam);
      int covered = 0;
      EXPECT_LT(maxErrorToReference(im, g, tf, cam, &covered), 1e-5)
        << "cell data " << cellData << " eye " << eye.x;
      EXPECT_GT(covered, 1500);
      EXPECT_GT(im.stats.counter("near_plane_triangles"), 0);
      EXPECT_EQ(im.stats.counter("open_caps"), 0);
    }
  }
}

// =======================================================================================
// Sparsification (section 4.3.5).

namespace
{
// Builds `g` dense and sparse and checks the sparse mesh against the dense one exactly: the
// same counts, the same triangles (vertex ids and the cells on both sides) once both lists
// are in vertex-id order, and kept cells that cover every triangle (at least one of its
// cells kept) and of which none can be dropped (each is the only kept cell of one of its
// triangles: the dropped set is a maximal independent set of the dual graph). Returns the
// number of kept cells.
std::size_t checkSparsification(const ZSweepGrid& g)
{
  ZSweepMesh dense, sparse;
  dense.build(g);
  sparse.build(g, true);
  EXPECT_FALSE(dense.sparse());
  EXPECT_TRUE(sparse.sparse());
  const auto& a = dense.counts();
  const auto& b = sparse.counts();
  EXPECT_EQ(a.cellsUsed, b.cellsUsed);
  EXPECT_EQ(a.cellsKept, a.cellsUsed);
  EXPECT_EQ(b.cellsKept, sparse.keptCells().size());
  EXPECT_EQ(a.boundaryTriangles, b.boundaryTriangles);
  EXPECT_EQ(a.badIndex + a.nonFinitePoint + a.nonFiniteScalar + a.zeroVolume,
    b.badIndex + b.nonFinitePoint + b.nonFiniteScalar + b.zeroVolume);
  EXPECT_EQ(dense.numTriangles(), sparse.numTriangles());

  std::vector<ZSweepTriangle> none, decoded;
  const std::vector<ZSweepTriangle>& expected = dense.triangles(none);
  std::vector<ZSweepTriangle> got = sparse.triangles(decoded);
  std::sort(got.begin(), got.end(), [](const ZSweepTriangle& x, const ZSweepTriangle& y) {
    return std::lexicographical_compare(x.v, x.v + 3, y.v, y.v + 3);
  });
  EXPECT_EQ(got.size(), expected.size());
  std::size_t same = 0;
  for (std::size_t k = 0; k < std::min(got.size(), expected.size()); ++k)
  {
    const ZSweepTriangle& x = got[k];
    const ZSweepTriangle& y = expected[k];
    same += std::equal(x.v, x.v + 3, y.v) && x.front == y.front && x.back == y.back;
  }
  EXPECT_EQ(same, expected.size());

  std::vector<char> kept(g.cellTypes.size(), 0);
  for (const std::int32_t c : sparse.keptCells())
  {
    kept[static_cast<std::size_t>(c)] = 1;
  }
  EXPECT_TRUE(std::is_sorted(sparse.keptCells().begin(), sparse.keptCells().end()));
  std::vector<char> needed(g.cellTypes.size(), 0); // the only kept cell of some triangle
  std::size_t uncovered = 0;
  for (const ZSweepTriangle& t : expected)
  {
    const bool f = t.front >= 0 && kept[static_cast<std::size_t>(t.front)];
    const bool k = t.back >= 0 && kept[static_cast<std::size_t>(t.back)];
    uncovered += !f && !k;
    if (f != k)
    {
      needed[static_cast<std::size_t>(f ? t.front : t.back)] = 1;
    }
  }
  EXPECT_EQ(uncovered, 0u);
  std::size_t droppable = 0;
  for (const std::int32_t c : sparse.keptCells())
  {
    droppable += !needed[static_cast<std::size_t>(c)];
  }
  EXPECT_EQ(droppable, 0u);
  EXPECT_LT(sparse.memoryBytes(), dense.memoryBytes());
  return sparse.keptCells().size();
}
} // namespace

TEST(ZSweepSparsification, KeptCellsCoverEveryFaceAndNoneCanBeDropped)
{
  Lattice L;
  L.jitter = 0.3;
  const ZSweepGrid tets = tetLattice(L, smoothField); // 384 tetrahedra
  EXPECT_EQ(checkSparsification(tets), 276u);
  const ZSweepGrid hexes = hexLattice(L, smoothField); // 64 hexahedra, 56 on the boundary
  EXPECT_EQ(checkSparsification(hexes), 60u);
  EXPECT_EQ(checkSparsification(mixedGrid()), 81u); // of 101 cells
  EXPECT_EQ(checkSparsification(withCellData(tets)), checkSparsification(tets));

  Lattice holes = L;
  holes.n = 5;
  holes.keep = [](int i, int j, int k) { return !(i >= 1 && i <= 3 && j >= 1 && j <= 3 && k == 2) && i != 2; };
  EXPECT_EQ(checkSparsification(tetLattice(holes, smoothField)), 446u); // of 552
}

TEST(ZSweepSparsification, KeepsAtMostTheFractionThePaperReports)
{
  // The dissertation keeps at most 56% of the cells (Table 5) of grids of 13K to 1M
  // tetrahedra. Every cell with a boundary face is kept, so small grids keep more.
  Lattice L;
  L.n = 20;
  L.h = 2.0 / 20;
  L.jitter = 0.3;
  const ZSweepGrid tets = tetLattice(L, smoothField); // 48,000 tetrahedra
  const std::size_t kept = checkSparsification(tets);
  EXPECT_EQ(kept, 26379u); // 55.0%
  EXPECT_LE(double(kept) / tets.cellTypes.size(), 0.56);
  // Hexahedra: the 20^3 - 18^3 = 2168 on the boundary are kept, and of the 5832 inside at
  // least half (a dropped hexahedron's 6 neighbours are kept; a kept one has at most 6), so
  // the chessboard's 2168 + 2916 = 5084 is the least possible, and the greedy finds it.
  // (Before the cells were oriented by their volume, 85 faces of this lattice had wrong
  // sides, counted as boundary faces, and made 28 more cells essential.)
  const ZSweepGrid hexes = hexLattice(L, smoothField);
  const std::size_t keptHexes = checkSparsification(hexes);
  EXPECT_EQ(keptHexes, 5084u); // 63.6%
}

TEST(ZSweepSparsification, SkippedCellsStayOutAndTheirNeighboursKeepTheirFaces)
{
  // Bad cells are skipped before sparsification: a face beside a skipped cell is a boundary
  // face, so the cell on its other side is kept.
  Lattice L;
  L.n = 3;
  ZSweepGrid g = tetLattice(L, smoothField);
  g.scalars[static_cast<std::size_t>(L.id(1, 1, 1))] = std::numeric_limits<double>::quiet_NaN();
  addCell(g, ZSweepCellType::Tetra, { 0, 1, 2, 1 });     // zero volume
  addCell(g, ZSweepCellType::Tetra, { 0, 1, 2, 99999 }); // bad index
  ZSweepMesh mesh;
  mesh.build(g, true);
  EXPECT_EQ(mesh.counts().nonFiniteScalar, 24u); // the tetrahedra around the NaN vertex
  EXPECT_EQ(mesh.counts().zeroVolume, 1u);
  EXPECT_EQ(mesh.counts().badIndex, 1u);
  for (const std::int32_t c : mesh.keptCells())
  {
    EXPECT_LT(static_cast<std::size_t>(c), g.cellTypes.size() - 2);
  }
  checkSparsification(g);
}

TEST(ZSweepSparsification, SameImageWithAndWithoutSparsification)
{
  const RefTransferFunction tf = testTransferFunction();
  Lattice L;
  L.jitter = 0.3;
  TestCamera cam;
  cam.eye = { 3.1, 2.3, 4.2 };
  cam.at = { 0.1, -0.1, 0.05 };
  TestCamera inside = cam;
  inside.eye = { 0.13, 0.21, 0.37 };
  inside.at = { 1.0, 0.45, -0.2 };
  inside.fovy = 70;
  inside.nearD = 0.3;
  Lattice edges; // rays through vertices and edges (see RaysThroughVerticesAndEdges...)
  edges.lo = { -1.025, -1.025, -1.0 };
  TestCamera straight;
  straight.parallel = true;
  straight.width = straight.height = 60;
  straight.eye = { 0, 0, 6 };
  straight.at = { 0, 0, 0 };
  const ZSweepGrid tets = tetLattice(L, smoothField);
  const ZSweepGrid hexes = hexLattice(L, smoothField);
  const struct
  {
    const char* name;
    ZSweepGrid grid;
    TestCamera camera;
  } cases[] = { { "tetrahedra", tets, cam }, { "tetrahedra, cell data", withCellData(tets), cam },
    { "hexahedra", hexes, cam }, { "hexahedra, cell data", withCellData(hexes), cam },
    { "mixed", mixedGrid(), cam }, { "mixed, cell data", withCellData(mixedGrid()), cam },
    { "inside, cell data", withCellData(tets), inside }, { "inside, hexahedra", hexes, inside },
    { "vertices and edges", tetLattice(edges, smoothField), straight },
    { "vertices and edges, cell data", withCellData(tetLattice(edges, smoothField)), straight } };
  for (const auto& c : cases)
  {
    const Image dense = sweep(c.grid, tf, c.camera);
    const Image sparse = sweep(c.grid, tf, c.camera, ZSweepParameters(), true);
    EXPECT_LE(maxDifference(dense.frame, sparse.frame), 1e-6) << c.name;
    EXPECT_EQ(maxDifference(dense.frame, sparse.frame), 0.0) << c.name;
    EXPECT_TRUE(sparse.stats.effect("sparse_mesh"));
    EXPECT_FALSE(dense.stats.effect("sparse_mesh"));
    EXPECT_EQ(sparse.stats.counter("decoded_triangles"), sparse.stats.counter("triangles"));
    EXPECT_EQ(dense.stats.counter("decoded_triangles"), 0);
  }
}

// =======================================================================================
// Hard cases: thin cells at the volume threshold, inverted and non-convex cells, warped
// hexahedra against a trilinear reference, zero-volume cells.

namespace
{
// The sweep's image against a reference per pixel ray: the largest and the root mean square
// difference over all pixels and channels (premultiplied RGBA in [0, 1]), and whether every
// value of the image is finite.
struct ImageError
{
  double max = 0, rmse = 0;
  bool finite = true;
  int covered = 0; // pixels whose reference opacity exceeds 1e-3
};

using PixelReference = std::function<std::array<double, 4>(const Vec3d&, const Vec3d&, double)>;

ImageError errorTo(const Frame& frame, const TestCamera& cam, const PixelReference& reference)
{
  ImageError e;
  double sum = 0;
  for (int j = 0; j < cam.height; ++j)
  {
    for (int i = 0; i < cam.width; ++i)
    {
      Vec3d o, d;
      double tMin;
      cam.ray(i, j, o, d, tMin);
      const auto ref = reference(o, d, tMin);
      const float* px = &frame.rgba[4 * frame.index(i, j)];
      e.covered += ref[3] > 1e-3;
      for (int c = 0; c < 4; ++c)
      {
        e.finite = e.finite && std::isfinite(px[c]);
        const double diff = double(px[c]) - ref[static_cast<std::size_t>(c)];
        e.max = std::max(e.max, std::fabs(diff));
        if (std::getenv("ZSWEEP_DEBUG") && std::fabs(diff) > 1e-5)
        {
          std::printf("pixel %d %d channel %d: sweep %g reference %g\n", i, j, c, px[c],
            ref[static_cast<std::size_t>(c)]);
        }
        sum += diff * diff;
      }
    }
  }
  e.rmse = std::sqrt(sum / (4.0 * cam.width * cam.height));
  return e;
}

bool allFinite(const Frame& frame)
{
  return std::all_of(
    frame.rgba.begin(), frame.rgba.end(), [](float v) { return std::isfinite(v); });
}

PixelReference tetraReference(const ZSweepGrid& g, const RefTransferFunction& tf)
{
  auto tets = std::make_shared<std::vector<RefTetra>>(referenceTetra(g));
  const bool cellData = g.cellScalars;
  return [tets, cellData, tf](const Vec3d& o, const Vec3d& d, double tMin) {
    return traceReference(*tets, cellData, tf, o, d, tMin);
  };
}

// The reference's polyhedra of any grid: each cell's faces in VTK's local order (restated
// here), quadrilaterals split along the diagonal through their smallest global id (the
// split ZSweep documents), each triangle with its corners' scalars.
std::vector<RefPolyhedron> referencePolyhedra(const ZSweepGrid& g)
{
  using Faces = std::vector<std::vector<int>>;
  static const Faces tetra = { { 0, 1, 3 }, { 1, 2, 3 }, { 2, 0, 3 }, { 0, 2, 1 } };
  static const Faces hexahedron = { { 0, 4, 7, 3 }, { 1, 2, 6, 5 }, { 0, 1, 5, 4 }, { 3, 7, 6, 2 },
    { 0, 3, 2, 1 }, { 4, 5, 6, 7 } };
  static const Faces wedge = { { 0, 1, 2 }, { 3, 5, 4 }, { 0, 3, 4, 1 }, { 1, 4, 5, 2 },
    { 2, 5, 3, 0 } };
  static const Faces pyramid = { { 0, 3, 2, 1 }, { 0, 1, 4 }, { 1, 2, 4 }, { 2, 3, 4 },
    { 3, 0, 4 } };
  std::vector<RefPolyhedron> out;
  for (std::size_t c = 0; c < g.cellTypes.size(); ++c)
  {
    const std::int64_t* v = g.connectivity.data() + g.cellOffsets[c];
    const Faces& faces = g.cellTypes[c] == ZSweepCellType::Tetra ? tetra
      : g.cellTypes[c] == ZSweepCellType::Hexahedron             ? hexahedron
      : g.cellTypes[c] == ZSweepCellType::Wedge                  ? wedge
                                                                 : pyramid;
    RefPolyhedron cell;
    cell.cellScalar = g.cellScalars ? g.scalars[c] : 0;
    auto add = [&](std::int64_t a, std::int64_t b, std::int64_t e) {
      cell.triangles.push_back({ g.points[static_cast<std::size_t>(a)],
        g.points[static_cast<std::size_t>(b)], g.points[static_cast<std::size_t>(e)] });
      const auto s = [&](std::int64_t i) {
        return g.cellScalars ? 0.0 : g.scalars[static_cast<std::size_t>(i)];
      };
      cell.s.push_back({ s(a), s(b), s(e) });
    };
    for (const auto& f : faces)
    {
      if (f.size() == 3)
      {
        add(v[f[0]], v[f[1]], v[f[2]]);
        continue;
      }
      int m = 0;
      for (int k = 1; k < 4; ++k)
      {
        m = v[f[static_cast<std::size_t>(k)]] < v[f[static_cast<std::size_t>(m)]] ? k : m;
      }
      const auto q = [&](int k) { return v[f[static_cast<std::size_t>((m + k) % 4)]]; };
      add(q(0), q(1), q(2));
      add(q(0), q(2), q(3));
    }
    out.push_back(cell);
  }
  return out;
}

// The reference of the split-triangle model: the cells' segments (each cell on its own,
// by the parity of its crossings), integrated in depth order. `odd` counts the rays whose
// crossings of some cell were odd (through an edge: left out of that cell).
PixelReference polyhedronReference(const ZSweepGrid& g,
  const RefTransferFunction& tf,
  int* odd = nullptr)
{
  auto cells = std::make_shared<std::vector<RefPolyhedron>>(referencePolyhedra(g));
  const bool cellData = g.cellScalars;
  return [cells, cellData, tf, odd](const Vec3d& o, const Vec3d& d, double tMin) {
    std::vector<RefSegment> segs, clipped;
    for (const RefPolyhedron& cell : *cells)
    {
      if (!clipToPolyhedron(cell, o, d, cellData, segs) && odd)
      {
        ++*odd;
      }
    }
    for (RefSegment s : segs)
    {
      if (s.t1 > tMin)
      {
        if (s.t0 < tMin)
        {
          s.s0 = s.s0 + (s.s1 - s.s0) * (tMin - s.t0) / (s.t1 - s.t0);
          s.t0 = tMin;
        }
        clipped.push_back(s);
      }
    }
    return integrateSegments(clipped, tf);
  };
}

// ---------------------------------------------------------------------------------------
// Thin tetrahedra. ZSweepMesh drops a cell whose volume V is at most 1e-12 D^3, D the
// diagonal of the cell's bounding box (ZSweepMesh.cxx). The grids below put each thin
// tetrahedron in a bipyramid of normal tetrahedra that share all its faces, one bipyramid
// every 2.5 along x, the i-th thin cell with V = ratio[i] 1e-12 D^3; the thin cells are the
// grid's last cells (the normal cells' ids do not depend on which thin cells are there).
constexpr double VolumeThreshold = 1e-12;

struct ThinCells
{
  ZSweepGrid grid;
  std::size_t normalCells = 0;
};

double bipyramidOffset(std::size_t k, std::size_t count)
{
  return 2.5 * (double(k) - 0.5 * double(count - 1));
}

// Flat slivers: a over the square [-1, 1]^2 (around x0), a = (-1, -1, -e/2),
// b = (1, -1, e/2), c = (1, 1, -e/2), d = (-1, 1, e/2) are four nearly coplanar points; the
// tetrahedron abcd has V = 4 e / 3 (det(b - a, c - a, d - a) = 8 e) and D = sqrt(8 + e^2).
// Its upper faces abd, cbd (on the high edge bd) are shared with the tetrahedra to the apex
// P = (0, 0, 1.2), its lower faces abc, acd with those to Q = (0, 0, -1.2).
ThinCells sliverGrid(const std::vector<double>& ratios,
  const std::function<bool(std::size_t)>& include)
{
  ThinCells out;
  ZSweepGrid& g = out.grid;
  std::vector<std::array<int, 4>> thin;
  for (std::size_t k = 0; k < ratios.size(); ++k)
  {
    const double x0 = bipyramidOffset(k, ratios.size());
    const double e = ratios[k] * VolumeThreshold * std::pow(8.0, 1.5) * 0.75;
    const double h = 0.5 * e;
    const int base = static_cast<int>(g.points.size());
    for (const Vec3d& p : { Vec3d(-1, -1, -h), Vec3d(1, -1, h), Vec3d(1, 1, -h), Vec3d(-1, 1, h),
           Vec3d(0, 0, 1.2), Vec3d(0, 0, -1.2) })
    {
      g.points.push_back(p + Vec3d(x0, 0, 0));
    }
    const int a = base, b = base + 1, c = base + 2, d = base + 3, P = base + 4, Q = base + 5;
    for (const auto& t :
      { std::array<int, 4>{ a, b, d, P }, { c, b, d, P }, { a, b, c, Q }, { a, c, d, Q } })
    {
      addCell(g, ZSweepCellType::Tetra, { t[0], t[1], t[2], t[3] });
    }
    if (include(k))
    {
      thin.push_back({ a, b, c, d });
    }
  }
  out.normalCells = g.cellTypes.size();
  for (const auto& t : thin)
  {
    addCell(g, ZSweepCellType::Tetra, { t[0], t[1], t[2], t[3] });
  }
  for (const Vec3d& p : g.points)
  {
    g.scalars.push_back(smoothField(p * 0.5));
  }
  return out;
}

// Needles: a = (-1, 0, 0), c = (0, w, 0), b = (1, 0, 0) are three nearly collinear points;
// with the points d = (0, 1, 0) and e = (0, -1, 0) they triangulate the square ebd a into
// acd, cbd, abe and the thin triangle abc, and each triangle is the base of a tetrahedron to
// P = (0, 0, 1) and one to Q = (0, 0, -1). The two needles abcP and abcQ have V = w / 3 and
// D = sqrt(5 + w^2).
ThinCells needleGrid(const std::vector<double>& ratios,
  const std::function<bool(std::size_t)>& include)
{
  ThinCells out;
  ZSweepGrid& g = out.grid;
  std::vector<std::array<int, 4>> thin;
  for (std::size_t k = 0; k < ratios.size(); ++k)
  {
    const double x0 = bipyramidOffset(k, ratios.size());
    const double w = ratios[k] * VolumeThreshold * std::pow(5.0, 1.5) * 3.0;
    const int base = static_cast<int>(g.points.size());
    for (const Vec3d& p : { Vec3d(-1, 0, 0), Vec3d(1, 0, 0), Vec3d(0, w, 0), Vec3d(0, 1, 0),
           Vec3d(0, -1, 0), Vec3d(0, 0, 1), Vec3d(0, 0, -1) })
    {
      g.points.push_back(p + Vec3d(x0, 0, 0));
    }
    const int a = base, b = base + 1, c = base + 2, d = base + 3, e = base + 4, P = base + 5,
              Q = base + 6;
    for (const auto& t : { std::array<int, 3>{ a, c, d }, { c, b, d }, { a, b, e } })
    {
      addCell(g, ZSweepCellType::Tetra, { t[0], t[1], t[2], P });
      addCell(g, ZSweepCellType::Tetra, { t[0], t[1], t[2], Q });
    }
    if (include(k))
    {
      thin.push_back({ a, b, c, P });
      thin.push_back({ a, b, c, Q });
    }
  }
  out.normalCells = g.cellTypes.size();
  for (const auto& t : thin)
  {
    addCell(g, ZSweepCellType::Tetra, { t[0], t[1], t[2], t[3] });
  }
  for (const Vec3d& p : g.points)
  {
    g.scalars.push_back(smoothField(p * 0.5));
  }
  return out;
}

// V / (1e-12 D^3) of a tetrahedron, computed here (the triple product and the box).
double thresholdRatio(const ZSweepGrid& g, std::size_t c)
{
  const std::int64_t* v = g.connectivity.data() + g.cellOffsets[c];
  const auto p = [&](int k) { return g.points[static_cast<std::size_t>(v[k])]; };
  const double volume = std::fabs(dot(p(1) - p(0), cross(p(2) - p(0), p(3) - p(0)))) / 6;
  Vec3d lo = p(0), hi = p(0);
  for (int k = 1; k < 4; ++k)
  {
    lo = min(lo, p(k));
    hi = max(hi, p(k));
  }
  return volume / (VolumeThreshold * std::pow(length(hi - lo), 3));
}

// The thin cells' checks: the ratios as built; the cells at or below the threshold
// counted and dropped, the image exactly that of the grid without them; the image finite
// and within 1e-6 of the reference of the cells kept (float's rounding: 4e-8); the kept
// thin cells changing the picture by less than 1e-6 (they hold almost nothing).
void checkThinCells(const std::function<ThinCells(const std::vector<double>&,
                      const std::function<bool(std::size_t)>&)>& build,
  std::size_t thinPerRatio)
{
  // From above down to the threshold, then just below it and far below.
  const std::vector<double> ratios = { 1e4, 10, 1.001, 0.999, 0.1 };
  const auto kept = [&](std::size_t k) { return ratios[k] > 1; };
  const ThinCells all = build(ratios, [](std::size_t) { return true; });
  const ThinCells above = build(ratios, kept);
  const ThinCells none = build(ratios, [](std::size_t) { return false; });
  for (std::size_t k = 0; k < ratios.size(); ++k)
  {
    for (std::size_t q = 0; q < thinPerRatio; ++q)
    {
      EXPECT_NEAR(thresholdRatio(all.grid, all.normalCells + k * thinPerRatio + q), ratios[k],
        1e-6 * ratios[k]);
    }
  }
  ZSweepMesh mesh;
  mesh.build(all.grid);
  EXPECT_EQ(mesh.counts().zeroVolume, 2 * thinPerRatio);
  EXPECT_EQ(mesh.counts().cellsUsed, all.normalCells + 3 * thinPerRatio);
  EXPECT_EQ(mesh.counts().nonManifoldTriangles, 0u);

  const RefTransferFunction tf = testTransferFunction();
  TestCamera cam;
  cam.parallel = true;
  cam.width = 120;
  cam.height = 48;
  cam.halfHeight = 2.6;
  cam.eye = { 0.9, -2.1, 6 };
  cam.at = { 0, 0, 0 };
  const Image withAll = sweep(all.grid, tf, cam);
  const Image withAbove = sweep(above.grid, tf, cam);
  const Image withNone = sweep(none.grid, tf, cam);
  EXPECT_EQ(maxDifference(withAll.frame, withAbove.frame), 0.0);
  const ImageError e = errorTo(withAll.frame, cam, tetraReference(above.grid, tf));
  std::printf("to the reference: max %.3g, rmse %.3g; kept thin cells change the picture by %.3g\n",
    e.max, e.rmse, maxDifference(withAbove.frame, withNone.frame));
  EXPECT_TRUE(e.finite);
  EXPECT_LT(e.max, 1e-6);
  EXPECT_GT(e.covered, 600);
  EXPECT_LT(maxDifference(withAbove.frame, withNone.frame), 1e-6);
  EXPECT_GT(withAll.stats.counter("segments"), 1000);
}
} // namespace

// Flat slivers (four nearly coplanar points) from 1e4 times the volume threshold down to
// 1.001 times it are drawn; at 0.999 and 0.1 times it they are dropped.
TEST(ZSweepHardCases, SliversAtTheVolumeThreshold)
{
  checkThinCells(sliverGrid, 1);
}

// Needles (three nearly collinear points), the same ratios.
TEST(ZSweepHardCases, NeedlesAtTheVolumeThreshold)
{
  checkThinCells(needleGrid, 2);
}

namespace
{
// Cell c with its vertices in mirrored order: the same cell, of negative orientation.
void invertCell(ZSweepGrid& g, std::size_t c)
{
  std::int64_t* v = g.connectivity.data() + g.cellOffsets[c];
  switch (g.cellTypes[c])
  {
    case ZSweepCellType::Tetra:
      std::swap(v[0], v[1]);
      break;
    case ZSweepCellType::Hexahedron:
      std::swap_ranges(v, v + 4, v + 4); // the top face for the bottom one
      break;
    case ZSweepCellType::Wedge:
      std::swap_ranges(v, v + 3, v + 3);
      break;
    case ZSweepCellType::Pyramid:
      std::swap(v[1], v[3]); // the base the other way round
      break;
  }
}

// How many cells have a negative volume: their reference polyhedra's triangles (VTK's
// faces, outward for a positive cell) enclose V = sum p0 . (p1 x p2) / 6 < 0.
std::size_t negativeCells(const ZSweepGrid& g)
{
  std::size_t n = 0;
  for (const RefPolyhedron& cell : referencePolyhedra(g))
  {
    const Vec3d c = cell.triangles[0][0];
    double volume = 0;
    for (const auto& t : cell.triangles)
    {
      volume += dot(t[0] - c, cross(t[1] - c, t[2] - c)) / 6;
    }
    n += volume < 0;
  }
  return n;
}

ZSweepGrid invertedCells(ZSweepGrid g, const std::function<bool(std::size_t)>& which)
{
  for (std::size_t c = 0; c < g.cellTypes.size(); ++c)
  {
    if (which(c))
    {
      invertCell(g, c);
    }
  }
  return g;
}
} // namespace

// Half the cells inverted (every other one: tetrahedra, hexahedra, wedges, pyramids), and
// all of them: the mesh counts the cells of negative volume (the fixtures' own grids have
// some: half of Freudenthal's tetrahedra) and orients every cell by its own volume, so the
// triangles and hence the picture are exactly those of the grid as given (no warning: the
// picture is right).
TEST(ZSweepHardCases, HalfTheCellsInvertedGiveTheSamePicture)
{
  Lattice warped;
  warped.jitter = 0.3;
  const RefTransferFunction tf = testTransferFunction();
  TestCamera cam;
  cam.eye = { 3.1, 2.3, 4.2 };
  cam.at = { 0.1, -0.1, 0.05 };
  const struct
  {
    const char* name;
    ZSweepGrid grid;
  } cases[] = { { "mixed", mixedGrid() }, { "tetrahedra", jitteredLattice() },
    { "warped hexahedra", hexLattice(warped, smoothField) } };
  for (const auto& c : cases)
  {
    const std::size_t n = c.grid.cellTypes.size();
    const Image oriented = sweep(c.grid, tf, cam);
    for (const bool all : { false, true })
    {
      const ZSweepGrid g = invertedCells(c.grid, [&](std::size_t k) { return all || k % 2 == 1; });
      ZSweepMesh mesh;
      mesh.build(g);
      EXPECT_EQ(mesh.counts().inverted, negativeCells(g)) << c.name;
      if (all)
      {
        EXPECT_EQ(negativeCells(g), n - negativeCells(c.grid));
      }
      EXPECT_EQ(mesh.counts().cellsUsed, n);
      EXPECT_EQ(mesh.counts().nonManifoldTriangles, 0u);
      const Image im = sweep(g, tf, cam);
      EXPECT_EQ(maxDifference(im.frame, oriented.frame), 0.0)
        << c.name << (all ? ", all" : ", half");
    }
  }
  // The mixed grid's linear field is exact in every cell type: the reference decides.
  const ZSweepGrid half = invertedCells(mixedGrid(), [](std::size_t k) { return k % 2 == 1; });
  const ImageError e = errorTo(sweep(half, tf, cam).frame, cam, tetraReference(mixedGrid(), tf));
  EXPECT_LT(e.max, 1e-5);
  EXPECT_GT(e.covered, 500);
}

namespace
{
// A column of two twisted frusta: square layers at z = -1, 0, 1 of half-sides 1, 0.5, 0.25,
// each turned 80 degrees from the one below. Valid hexahedra (det dx/d(u, v, w) > 0 over
// the cube; a simple surface once their side quadrilaterals are split), but not convex:
// the centroid lies outside the planes of three of each cell's triangles.
ZSweepGrid twistedFrusta(bool cellData)
{
  ZSweepGrid g;
  const double corners[4][2] = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
  for (int layer = 0; layer < 3; ++layer)
  {
    const double turn = 80.0 * M_PI / 180.0 * layer, scale = std::pow(0.5, layer);
    for (const auto& q : corners)
    {
      g.points.push_back({ scale * (q[0] * std::cos(turn) - q[1] * std::sin(turn)),
        scale * (q[0] * std::sin(turn) + q[1] * std::cos(turn)), -1.0 + layer });
    }
  }
  for (int cell = 0; cell < 2; ++cell)
  {
    const int b = 4 * cell, t = 4 * cell + 4;
    addCell(g, ZSweepCellType::Hexahedron, { b, b + 1, b + 2, b + 3, t, t + 1, t + 2, t + 3 });
  }
  g.cellScalars = cellData;
  if (cellData)
  {
    g.scalars = { 0.35, 0.8 };
  }
  else
  {
    for (const Vec3d& p : g.points)
    {
      g.scalars.push_back(smoothField(p));
    }
  }
  return g;
}
} // namespace

// Cells that are not convex: the twisted frusta (point and cell data, as given and
// inverted) against the reference of their split-triangle model (each cell on its own,
// inside by the parity of its crossings); and the faces of jittered hexahedra, each with
// its two cells on opposite sides. Sides taken from the centroid (the mesh's former rule)
// were wrong on 3 triangles of each frustum (the picture off by up to 0.64), and 85 faces of
// the 20^3 lattice had both cells on one side (counted as overlaps and as boundary faces).
TEST(ZSweepHardCases, NonConvexHexahedraAreOrientedByTheirVolume)
{
  const RefTransferFunction tf = testTransferFunction();
  TestCamera cam;
  cam.eye = { 2.4, -3.3, 2.6 };
  cam.at = { 0, 0, -0.1 };
  for (const bool cellData : { false, true })
  {
    const ZSweepGrid g = twistedFrusta(cellData);
    for (const bool inverted : { false, true })
    {
      const ZSweepGrid h = inverted ? invertedCells(g, [](std::size_t) { return true; }) : g;
      int odd = 0;
      const ImageError e =
        errorTo(sweep(h, tf, cam, splitFaces()).frame, cam, polyhedronReference(h, tf, &odd));
      EXPECT_EQ(odd, 0);
      EXPECT_LT(e.max, 1e-5) << "cell data " << cellData << " inverted " << inverted;
      EXPECT_GT(e.covered, 300);
    }
  }
  Lattice L;
  L.n = 20;
  L.h = 2.0 / 20;
  L.jitter = 0.3;
  ZSweepMesh large;
  large.build(hexLattice(L, smoothField));
  EXPECT_EQ(large.counts().nonManifoldTriangles, 0u);
  EXPECT_EQ(large.counts().boundaryTriangles, 6u * 20 * 20 * 2);
}

// Zero-volume cells added to the mixed grid: a tetrahedron of four coplanar points inside
// it (rounded: their volume is not exactly 0), a tetrahedron with a repeated point id on
// one of its faces, a hexahedron collapsed to one of its quadrilaterals (its ids repeated)
// and one collapsed onto four new points (the top's coordinates those of the bottom), a
// wedge collapsed to its triangle, a pyramid with its apex in its base's plane. Each is
// counted and left out: the picture is exactly the grid's alone, with no NaN. Repeated ids
// that leave a volume (a hexahedron with two edges collapsed, a wedge to VTK's users) are
// drawn: the picture is exactly the wedge's.
TEST(ZSweepHardCases, ZeroVolumeCellsAreLeftOutAndTheRestIsDrawnAsWithoutThem)
{
  const ZSweepGrid clean = mixedGrid();
  ZSweepGrid g = clean;
  const auto field = [](const Vec3d& p) { return 0.5 + 0.2 * p.x - 0.1 * p.y + 0.15 * p.z; };
  const auto point = [&](const Vec3d& p) {
    g.points.push_back(p);
    g.scalars.push_back(field(p));
    return static_cast<int>(g.points.size() - 1);
  };
  const auto cellIds = [&](ZSweepCellType type) {
    for (std::size_t c = 0; c < clean.cellTypes.size(); ++c)
    {
      if (clean.cellTypes[c] == type)
      {
        return std::vector<int>(clean.connectivity.begin() + clean.cellOffsets[c],
          clean.connectivity.begin() + clean.cellOffsets[c + 1]);
      }
    }
    return std::vector<int>();
  };
  const std::vector<int> tet = cellIds(ZSweepCellType::Tetra);
  const std::vector<int> hex = cellIds(ZSweepCellType::Hexahedron);
  const std::vector<int> wedge = cellIds(ZSweepCellType::Wedge);
  // Four points of a tilted plane, rounded: a volume of rounding noise, not exactly 0.
  const Vec3d u = normalize(Vec3d(0.6, 0.7, 0.2)), v = normalize(cross(Vec3d(0.1, -0.3, 1), u));
  std::vector<int> flat;
  for (const auto& ab :
    { std::array<double, 2>{ -0.3, -0.2 }, { 0.4, -0.1 }, { 0.1, 0.5 }, { -0.2, 0.3 } })
  {
    flat.push_back(point(Vec3d(0.05, 0.1, 0.1) + u * ab[0] + v * ab[1]));
  }
  addCell(g, ZSweepCellType::Tetra, flat);
  const auto at = [&](std::size_t k) { return g.points[static_cast<std::size_t>(flat[k])]; };
  const double noise = std::fabs(dot(at(1) - at(0), cross(at(2) - at(0), at(3) - at(0))));
  EXPECT_GT(noise, 0.0);
  EXPECT_LT(noise, 1e-15);
  addCell(g, ZSweepCellType::Tetra, { tet[0], tet[1], tet[2], tet[1] });
  addCell(g, ZSweepCellType::Hexahedron,
    { hex[0], hex[1], hex[2], hex[3], hex[0], hex[1], hex[2], hex[3] });
  std::vector<int> quad;
  for (const Vec3d& p : { Vec3d(-0.6, -0.5, -0.2), Vec3d(0.3, -0.6, -0.2), Vec3d(0.4, 0.2, -0.2),
         Vec3d(-0.5, 0.3, -0.2) })
  {
    quad.push_back(point(p));
  }
  for (const Vec3d& p : { Vec3d(-0.6, -0.5, -0.2), Vec3d(0.3, -0.6, -0.2), Vec3d(0.4, 0.2, -0.2),
         Vec3d(-0.5, 0.3, -0.2) })
  {
    quad.push_back(point(p));
  }
  addCell(g, ZSweepCellType::Hexahedron, quad);
  addCell(g, ZSweepCellType::Wedge, { wedge[0], wedge[1], wedge[2], wedge[0], wedge[1], wedge[2] });
  const Vec3d centre =
    (g.points[static_cast<std::size_t>(hex[0])] + g.points[static_cast<std::size_t>(hex[2])]) * 0.5;
  addCell(g, ZSweepCellType::Pyramid, { hex[0], hex[1], hex[2], hex[3], point(centre) });

  ZSweepMesh mesh;
  mesh.build(g);
  EXPECT_EQ(mesh.counts().zeroVolume, 6u);
  EXPECT_EQ(mesh.counts().cellsUsed, clean.cellTypes.size());
  EXPECT_EQ(mesh.counts().nonManifoldTriangles, 0u);
  const RefTransferFunction tf = testTransferFunction();
  TestCamera cam;
  cam.eye = { 4.2, 3.3, 5.0 };
  cam.at = { 0.05, 0.1, 0 };
  const Image im = sweep(g, tf, cam);
  EXPECT_TRUE(allFinite(im.frame));
  EXPECT_EQ(maxDifference(im.frame, sweep(clean, tf, cam).frame), 0.0);

  // The flat tetrahedron's points rounded to float, as VTK's float points hold them: flat
  // to float's precision only (their volume is float's rounding), left out when the grid
  // says its points were floats, a real (thin) cell when they were doubles.
  ZSweepGrid rounded = clean;
  std::vector<int> roundedIds;
  for (std::size_t k = 0; k < 4; ++k)
  {
    const Vec3d& q = g.points[static_cast<std::size_t>(flat[k])];
    rounded.points.push_back(Vec3d(Vec3f(q)));
    rounded.scalars.push_back(field(q));
    roundedIds.push_back(static_cast<int>(rounded.points.size() - 1));
  }
  addCell(rounded, ZSweepCellType::Tetra, roundedIds);
  rounded.pointEpsilon = std::numeric_limits<float>::epsilon() / 2;
  mesh.build(rounded);
  EXPECT_EQ(mesh.counts().zeroVolume, 1u);
  EXPECT_EQ(maxDifference(sweep(rounded, tf, cam).frame, sweep(clean, tf, cam).frame), 0.0);
  rounded.pointEpsilon = std::numeric_limits<double>::epsilon() / 2;
  mesh.build(rounded);
  EXPECT_EQ(mesh.counts().zeroVolume, 0u);

  // A wedge given as a hexahedron whose ids repeat along two edges.
  ZSweepGrid asWedge, asHexahedron;
  asWedge.points = asHexahedron.points = { { -1, -1, -1 }, { 1, -1, -1 }, { -1, 1, -1 },
    { -1, -1, 1 }, { 1, -1, 1 }, { -1, 1, 1 } };
  for (const Vec3d& p : asWedge.points)
  {
    asWedge.scalars.push_back(smoothField(p));
  }
  asHexahedron.scalars = asWedge.scalars;
  addCell(asWedge, ZSweepCellType::Wedge, { 0, 1, 2, 3, 4, 5 });
  addCell(asHexahedron, ZSweepCellType::Hexahedron, { 0, 1, 2, 2, 3, 4, 5, 5 });
  const Image collapsed = sweep(asHexahedron, tf, cam, splitFaces());
  EXPECT_EQ(maxDifference(collapsed.frame, sweep(asWedge, tf, cam, splitFaces()).frame), 0.0);
  EXPECT_LT(errorTo(collapsed.frame, cam, polyhedronReference(asWedge, tf)).max, 1e-5);
  // The cells' own fields: the collapsed hexahedron's trilinear map is singular along its
  // collapsed edges, yet its field is the wedge's (measured 3e-8: Newton's rounding).
  const Image nativeCollapsed = sweep(asHexahedron, tf, cam);
  EXPECT_LT(maxDifference(nativeCollapsed.frame, sweep(asWedge, tf, cam).frame), 1e-6);
  EXPECT_TRUE(errorTo(nativeCollapsed.frame, cam, polyhedronReference(asWedge, tf)).finite);

  // A pyramid given as a hexahedron with its top face in one point: the trilinear field
  // of that hexahedron is VTK's pyramid field (the base's bilinear weights times 1 - w,
  // the apex w), computed by other shape functions. Made to fail: the pyramid's apex
  // weight as 1 - t instead of t (0.51).
  ZSweepGrid asPyramid, asTopless;
  asPyramid.points = asTopless.points = { { -1, -1, -1 }, { 1, -1, -1 }, { 1, 1, -0.8 },
    { -1, 1, -1 }, { 0.2, -0.1, 1 } };
  for (const Vec3d& p : asPyramid.points)
  {
    asPyramid.scalars.push_back(smoothField(p));
  }
  asTopless.scalars = asPyramid.scalars;
  addCell(asPyramid, ZSweepCellType::Pyramid, { 0, 1, 2, 3, 4 });
  addCell(asTopless, ZSweepCellType::Hexahedron, { 0, 1, 2, 3, 4, 4, 4, 4 });
  const Image pyramid = sweep(asPyramid, tf, cam), topless = sweep(asTopless, tf, cam);
  const double pyramidDifference = maxDifference(pyramid.frame, topless.frame);
  const ImageError toSplit = errorTo(pyramid.frame, cam, polyhedronReference(asPyramid, tf));
  std::printf("pyramid as a collapsed hexahedron: max difference %.2e, %lld and %lld curved "
              "segments, %lld pieces; to the split faces' field %.3f, %d pixels\n",
    pyramidDifference, static_cast<long long>(pyramid.stats.counter("curved_segments")),
    static_cast<long long>(topless.stats.counter("curved_segments")),
    static_cast<long long>(pyramid.stats.counter("curved_pieces")), toSplit.max, toSplit.covered);
  EXPECT_LT(pyramidDifference, 1e-6);
  EXPECT_GT(topless.stats.counter("curved_pieces"), 1000);
  EXPECT_GT(toSplit.covered, 300);
}

// =======================================================================================
// Warped hexahedra: the sweep's cells, with the split faces' linear field and with the
// cells' own (trilinear) field, against the trilinear reference of TrilinearReference.h.

namespace
{
// The grid's hexahedra, wedges and pyramids as the reference's cells.
std::vector<RefCurvedCell> referenceCells(const ZSweepGrid& g)
{
  std::vector<RefCurvedCell> out;
  for (std::size_t c = 0; c < g.cellTypes.size(); ++c)
  {
    RefCurvedCell h;
    h.shape = g.cellTypes[c] == ZSweepCellType::Wedge ? RefShape::Wedge
      : g.cellTypes[c] == ZSweepCellType::Pyramid     ? RefShape::Pyramid
                                                      : RefShape::Hexahedron;
    const int corners = h.shape == RefShape::Wedge ? 6 : h.shape == RefShape::Pyramid ? 5 : 8;
    for (int k = 0; k < corners; ++k)
    {
      const auto id =
        static_cast<std::size_t>(g.connectivity[static_cast<std::size_t>(g.cellOffsets[c] + k)]);
      h.p[static_cast<std::size_t>(k)] = g.points[id];
      h.s[static_cast<std::size_t>(k)] = g.scalars[id];
    }
    out.push_back(h);
  }
  return out;
}

PixelReference trilinearReference(const ZSweepGrid& g,
  const RefTransferFunction& tf,
  double step,
  TrilinearTraceCounts* counts = nullptr)
{
  auto cells = std::make_shared<std::vector<RefCurvedCell>>(referenceCells(g));
  return [cells, tf, step, counts](const Vec3d& o, const Vec3d& d, double tMin) {
    return traceTrilinearReference(*cells, tf, o, d, tMin, step, counts);
  };
}

// One hexahedron from its 8 corners (VTK order), with the field
//   s = 0.45 + 0.1 X + 0.08 Y + 0.3 X Y Z   (X, Y, Z = 2 (u, v, w) - 1, +-1 at the corners),
// trilinear in the cell's parametric coordinates, not linear.
ZSweepGrid singleHexahedron(const std::array<Vec3d, 8>& corners)
{
  ZSweepGrid g;
  for (int k = 0; k < 8; ++k)
  {
    g.points.push_back(corners[static_cast<std::size_t>(k)]);
    const double X = 2.0 * HexCorner[k][0] - 1, Y = 2.0 * HexCorner[k][1] - 1,
                 Z = 2.0 * HexCorner[k][2] - 1;
    g.scalars.push_back(0.45 + 0.1 * X + 0.08 * Y + 0.3 * X * Y * Z);
  }
  addCell(g, ZSweepCellType::Hexahedron, { 0, 1, 2, 3, 4, 5, 6, 7 });
  return g;
}

std::array<Vec3d, 8> cubeCorners()
{
  std::array<Vec3d, 8> c;
  for (int k = 0; k < 8; ++k)
  {
    c[static_cast<std::size_t>(k)] =
      Vec3d(2.0 * HexCorner[k][0] - 1, 2.0 * HexCorner[k][1] - 1, 2.0 * HexCorner[k][2] - 1);
  }
  return c;
}

// The cube [-1, 1]^3 with each corner moved by up to 0.3 along each axis (fixed seed).
ZSweepGrid jitteredCube()
{
  std::array<Vec3d, 8> c = cubeCorners();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (Vec3d& p : c)
  {
    p = p + Vec3d(u(rng), u(rng), u(rng));
  }
  return singleHexahedron(c);
}

// The cube with its top face turned by `degrees` about z.
ZSweepGrid twistedHexahedron(double degrees)
{
  std::array<Vec3d, 8> c = cubeCorners();
  const double a = degrees * M_PI / 180;
  for (std::size_t k = 4; k < 8; ++k)
  {
    c[k] = Vec3d(c[k].x * std::cos(a) - c[k].y * std::sin(a),
      c[k].x * std::sin(a) + c[k].y * std::cos(a), c[k].z);
  }
  return singleHexahedron(c);
}

// The cube sheared and stretched by a fixed matrix: planar faces, an affine map.
ZSweepGrid parallelepiped()
{
  std::array<Vec3d, 8> c = cubeCorners();
  for (Vec3d& p : c)
  {
    p = Vec3d(1.1 * p.x + 0.35 * p.y - 0.2 * p.z, 0.9 * p.y + 0.25 * p.z, 0.15 * p.x + 0.95 * p.z);
  }
  return singleHexahedron(c);
}

// The grid with the point field 0.5 + 0.2 x - 0.15 y + 0.1 z: its trilinear interpolant in a
// cell is that linear field, and so is the split-triangle model's (the two differ only by
// the cells' shapes, bilinear faces or triangles).
ZSweepGrid withLinearField(ZSweepGrid g)
{
  for (std::size_t k = 0; k < g.points.size(); ++k)
  {
    g.scalars[k] = 0.5 + 0.2 * g.points[k].x - 0.15 * g.points[k].y + 0.1 * g.points[k].z;
  }
  return g;
}

// A view of [-1.3, 1.3]^3 whole.
TestCamera warpedCamera()
{
  TestCamera cam;
  cam.eye = { 2.6, -3.1, 3.4 };
  cam.at = { 0, 0, 0 };
  cam.fovy = 44;
  return cam;
}
} // namespace

// The reference's parts on warped cells (a jittered cube, a twisted hexahedron, a twisted
// frustum): the map's inversion returns the parametric point it came from; along rays
// (random ones through the cell, and rays through the middle of each edge and through each
// corner towards the cell's centre, which cross two or three faces at once) the intervals'
// ends lie on the cell's boundary (a parametric coordinate at 0 or 1 within 1e-12), their
// middles inside, and their total length is the inside length found by marching the ray in
// steps of 1e-3 with the inside test (within a step at each of its ends); and rays grazing
// a face cross it where they touch it.
TEST(ZSweepTrilinearReference, InvertsTheMapAndFindsTheBilinearFaces)
{
  const ZSweepGrid frusta = twistedFrusta(false);
  const std::vector<RefCurvedCell> cells = { referenceCells(jitteredCube())[0],
    referenceCells(twistedHexahedron(60))[0], referenceCells(frusta)[0] };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u01(0, 1);
  const auto at = [](const RefCurvedCell& h, const Vec3d& u) {
    Vec3d J[3];
    return shapePoint(h, u, J);
  };
  for (const RefCurvedCell& h : cells)
  {
    double worst = 0;
    for (int k = 0; k < 200; ++k)
    {
      const Vec3d u(u01(rng), u01(rng), u01(rng));
      Vec3d back(0.5, 0.5, 0.5);
      ASSERT_TRUE(invertShapeMap(h, at(h, u), back));
      worst = std::max(worst, length(back - u));
    }
    EXPECT_LT(worst, 1e-12);

    // Rays o + t d through a point of the cell 4 from o (the cells are at most 4.5 across:
    // t in [0, 9]).
    std::vector<std::array<Vec3d, 2>> rays;
    for (int k = 0; k < 20; ++k)
    {
      const Vec3d d = normalize(Vec3d(u01(rng) - 0.5, u01(rng) - 0.5, u01(rng) - 0.5));
      rays.push_back({ at(h, Vec3d(u01(rng), u01(rng), u01(rng))), d });
    }
    const Vec3d centre = at(h, Vec3d(0.5, 0.5, 0.5));
    for (int a = 0; a < 8; ++a)
    {
      const Vec3d corner = h.p[static_cast<std::size_t>(a)];
      rays.push_back({ corner, normalize(centre - corner) });
      for (int b = a + 1; b < 8; ++b)
      {
        const int differ = (HexCorner[a][0] != HexCorner[b][0]) +
          (HexCorner[a][1] != HexCorner[b][1]) + (HexCorner[a][2] != HexCorner[b][2]);
        if (differ == 1) // an edge
        {
          const Vec3d middle = (corner + h.p[static_cast<std::size_t>(b)]) * 0.5;
          rays.push_back({ middle, normalize(centre - middle) });
        }
      }
    }
    EXPECT_EQ(rays.size(), 20u + 8 + 12);
    double lengthError = 0, offBoundary = 0;
    int hits = 0;
    constexpr double dt = 1e-3;
    for (const auto& ray : rays)
    {
      const Vec3d d = ray[1], o = ray[0] - d * 4.0;
      const auto intervals = cellIntervals(h, o, d);
      hits += !intervals.empty();
      double inside = 0;
      for (const auto& iv : intervals)
      {
        inside += iv[1] - iv[0];
        for (const double t : { iv[0], iv[1] })
        {
          Vec3d q(0.5, 0.5, 0.5);
          ASSERT_TRUE(invertShapeMap(h, o + d * t, q));
          const double off = std::min({ q.x, 1 - q.x, q.y, 1 - q.y, q.z, 1 - q.z });
          offBoundary = std::max(offBoundary, std::fabs(off));
        }
        EXPECT_TRUE(insideCell(h, o + d * (0.5 * (iv[0] + iv[1]))));
      }
      double marched = 0;
      for (double t = 0.5 * dt; t < 9.0; t += dt)
      {
        marched += insideCell(h, o + d * t) ? dt : 0;
      }
      lengthError = std::max(lengthError, std::fabs(marched - inside));
    }
    std::printf("interval ends off the boundary by %.2g, lengths off the marched ones by %.2g\n",
      offBoundary, lengthError);
    EXPECT_EQ(hits, static_cast<int>(rays.size()));
    EXPECT_LT(offBoundary, 1e-12);
    EXPECT_LT(lengthError, 2 * dt);

    // Grazing rays: through a point P(a, b) of a face nearly along its straight line of
    // constant b (the ray within an angle of 1e-3 to 1e-6 of the face), each crosses the
    // face at that point.
    int found = 0, grazing = 0;
    for (const auto& f : HexFace)
    {
      const auto corner = [&](int k) { return h.p[static_cast<std::size_t>(f[k])]; };
      const Vec3d q00 = corner(0), q10 = corner(1), q11 = corner(2), q01 = corner(3);
      for (int k = 0; k < 25; ++k, ++grazing)
      {
        const double a = 0.1 + 0.8 * u01(rng), b = 0.1 + 0.8 * u01(rng);
        const Vec3d g = q00 - q10 + q11 - q01;
        const Vec3d P = q00 + (q10 - q00) * a + (q01 - q00) * b + g * (a * b);
        const Vec3d along = q10 - q00 + g * b, across = q01 - q00 + g * a;
        const double angle = std::pow(10.0, -3 - k % 4);
        const Vec3d d = normalize(normalize(along) + normalize(cross(along, across)) * angle);
        std::vector<double> ts;
        intersectBilinearPatch(q00, q10, q11, q01, P - d * 3.0, d, ts);
        found +=
          std::any_of(ts.begin(), ts.end(), [](double t) { return std::fabs(t - 3.0) < 1e-6; });
      }
    }
    EXPECT_EQ(found, grazing);
  }
}

namespace
{
// A 2^3 lattice over [-1, 1]^3 (its interior point jittered by `jitter` of a cell) of wedges
// (each cube cut in 2 along its diagonal plane through corners 0, 2, 6, 4) or of pyramids
// (each cube cut in 6 around the mean of its corners), with the point field smoothField:
// their bilinear faces are not planar, and their own fields are not linear. (Not both in
// one grid: a wedge's triangles against a pyramid's bilinear base would not be conforming.)
ZSweepGrid warpedLatticeOf(ZSweepCellType type, double jitter = 0.3)
{
  Lattice L;
  L.n = 2;
  L.h = 1.0;
  L.jitter = jitter;
  ZSweepGrid g;
  g.points = L.points();
  L.eachCube([&](int i, int j, int k) {
    const auto c = L.hex(i, j, k);
    if (type == ZSweepCellType::Wedge)
    {
      addWedgePair(g, c);
      return;
    }
    Vec3d centre;
    for (const int v : c)
    {
      centre += g.points[static_cast<std::size_t>(v)] * 0.125;
    }
    addPyramidsAround(g, c, centre);
  });
  for (const Vec3d& p : g.points)
  {
    g.scalars.push_back(smoothField(p));
  }
  return g;
}

} // namespace

// Where both references are exact, they agree: a parallelepiped (planar faces, an affine
// map) with a linear field, whose trilinear interpolant is that linear field, against the
// tetrahedra of its Freudenthal split; lattices of unjittered wedges and pyramids (planar
// faces) with a linear field, against their tetrahedra (3 a wedge, 2 a pyramid). Made to
// fail: the pyramid's base weights taken for corners 0, 1, 3, 2, or the wedge's triangle
// weights for corners 1, 0, 2, each give 0.97 here (and 219 to 224 levels of 255 in
// WarpedHexahedraAgainstTheTrilinearReference, with no pixel left covered by the wedges).
TEST(ZSweepTrilinearReference, AgreesWithTheTetrahedraWhereBothAreExact)
{
  for (const ZSweepGrid& g : { withLinearField(parallelepiped()),
         withLinearField(warpedLatticeOf(ZSweepCellType::Wedge, 0)),
         withLinearField(warpedLatticeOf(ZSweepCellType::Pyramid, 0)) })
  {
  const RefTransferFunction tf = testTransferFunction();
  const TestCamera cam = warpedCamera();
  const auto trilinear = trilinearReference(g, tf, 0.01);
  const auto tetra = tetraReference(g, tf);
  double worst = 0;
  int covered = 0;
  for (int j = 0; j < cam.height; ++j)
  {
    for (int i = 0; i < cam.width; ++i)
    {
      Vec3d o, d;
      double tMin;
      cam.ray(i, j, o, d, tMin);
      const auto a = trilinear(o, d, tMin), b = tetra(o, d, tMin);
      covered += b[3] > 1e-3;
      for (std::size_t c = 0; c < 4; ++c)
      {
        worst = std::max(worst, std::fabs(a[c] - b[c]));
      }
    }
  }
  std::printf("trilinear against tetrahedra: max %.3g\n", worst);
  EXPECT_LT(worst, 1e-7);
  EXPECT_GT(covered, 500);
  }
}

namespace
{
// A 3^3 lattice of hexahedra over [-1, 1]^3, interior points jittered by up to 0.3 of a
// cell, the point field smoothField (so the cells' trilinear interpolant of it).
ZSweepGrid warpedLattice()
{
  Lattice L;
  L.n = 3;
  L.h = 2.0 / 3;
  L.jitter = 0.3;
  return hexLattice(L, smoothField);
}

// The step of the trilinear reference in these tests (the cells are 0.7 to 2.6 across).
constexpr double TrilinearStep = 0.01;
} // namespace

// Halving the step changes the reference's picture by less than 1e-5 (RK4 on pieces without
// kinks: the change falls like step^4).
TEST(ZSweepTrilinearReference, ConvergesWhenTheStepIsHalved)
{
  const RefTransferFunction tf = testTransferFunction();
  const TestCamera cam = warpedCamera();
  for (const ZSweepGrid& g : { warpedLattice(), twistedHexahedron(45),
         warpedLatticeOf(ZSweepCellType::Wedge), warpedLatticeOf(ZSweepCellType::Pyramid) })
  {
    TrilinearTraceCounts counts;
    const auto coarse = trilinearReference(g, tf, 2 * TrilinearStep);
    const auto fine = trilinearReference(g, tf, TrilinearStep, &counts);
    double change[2] = { 0, 0 }; // step 2h to h, h to h / 2
    const auto finer = trilinearReference(g, tf, 0.5 * TrilinearStep);
    for (int j = 0; j < cam.height; j += 2)
    {
      for (int i = 0; i < cam.width; i += 2)
      {
        Vec3d o, d;
        double tMin;
        cam.ray(i, j, o, d, tMin);
        const auto a = coarse(o, d, tMin), b = fine(o, d, tMin), c = finer(o, d, tMin);
        for (std::size_t k = 0; k < 4; ++k)
        {
          change[0] = std::max(change[0], std::fabs(a[k] - b[k]));
          change[1] = std::max(change[1], std::fabs(b[k] - c[k]));
        }
      }
    }
    std::printf("step %g to %g: change %.3g; %g to %g: %.3g (%ld inversions, %ld failed)\n",
      2 * TrilinearStep, TrilinearStep, change[0], TrilinearStep, 0.5 * TrilinearStep, change[1],
      counts.evaluations, counts.failures);
    EXPECT_LT(change[1], 1e-5);
    EXPECT_EQ(counts.failures, 0);
  }
}

// Far from the coordinates' origin the reference draws the same picture: the lattice shrunk
// to cells 0.1 across and moved to z = 30 (as the Combustion Chamber's 0.3-wide cells at z =
// 23 to 36), traced along the same rays moved with it, against the lattice where it is,
// with no inversion failing. Made to fail: inverting until a step below 1e-14 only (the
// rounding of x(u) - X there moves u by more) fails 12,372 of 73,895 inversions, and the
// pictures differ by up to 0.79.
TEST(ZSweepTrilinearReference, FarFromTheOriginDrawsTheSamePicture)
{
  const RefTransferFunction tf = testTransferFunction();
  const TestCamera cam = warpedCamera();
  constexpr double scale = 0.15;
  const Vec3d shift(0, 0, 30);
  ZSweepGrid moved = warpedLattice();
  for (Vec3d& p : moved.points)
  {
    p = p * scale + shift;
  }
  RefTransferFunction movedTf = tf;
  movedTf.unitDistance *= scale; // the same optical depth along the shrunk rays
  TrilinearTraceCounts counts;
  const auto here = trilinearReference(warpedLattice(), tf, TrilinearStep);
  const auto there = trilinearReference(moved, movedTf, scale * TrilinearStep, &counts);
  double change = 0;
  long rays = 0;
  for (int j = 0; j < cam.height; j += 2)
  {
    for (int i = 0; i < cam.width; i += 2, ++rays)
    {
      Vec3d o, d;
      double tMin;
      cam.ray(i, j, o, d, tMin);
      const auto a = here(o, d, tMin), b = there(o * scale + shift, d, tMin * scale);
      for (std::size_t k = 0; k < 4; ++k)
      {
        change = std::max(change, std::fabs(a[k] - b[k]));
      }
    }
  }
  std::printf("moved to z = 30: change %.3g over %ld rays (%ld inversions, %ld failed)\n", change,
    rays, counts.evaluations, counts.failures);
  EXPECT_LT(change, 1e-9);
  EXPECT_EQ(counts.failures, 0);
}

// The error of the sweep's native hexahedra (faces split into triangles, the scalar linear
// between them along a ray) against the trilinear reference, in levels of 255 over all
// pixels and channels (premultiplied RGBA; 48 x 48 pixels), bounded by the values measured
// (rounded up by at most 0.015, so that a change of the native path shows): a jittered cube
// with a linear field (only the shapes differ: bilinear faces or triangles), warped cells
// with the trilinear field of singleHexahedron (0.3 X Y Z: a strong trilinear term), the
// twisted frusta and the jittered lattice with smoothField, and a parallelepiped (planar
// faces: only the field differs) with the trilinear field. Against the reference of the
// split-triangle model the sweep is exact (below 1e-5, float's rounding): the error is
// the model's.
// The split faces' field departs from the trilinear one by up to 155 levels of 255; the
// cells' own field brings cells with planar faces (the parallelepiped, the lattice's mildly
// jittered cells) within 1/255 of the reference. What remains on the single strongly warped
// cells is their bounds: the sweep's cell is bounded by its split faces, the reference's by
// bilinear patches (the linear field's case, where both fields agree, shows that error
// alone: 25.6 levels at the silhouette of the jittered cube).
// Jittered lattices of wedges and of pyramids (their own fields: 0.60 and 0.99 levels)
// check those cells' maps. Made to fail (parallelepiped, lattice; levels of 255):
// linearizing to 0.1 of the range (6.2, 1.2), the pieces constant at their front value
// (6.0, 8.9), corners 2 and 3 of the parametric cube swapped (128, 17.5, with inversion
// failures); Newton started from the predicted solution unclamped (as before 2026-12-08):
// the pyramids 27.9 levels, 49 inversions failing near the apices.
TEST(ZSweepHardCases, WarpedHexahedraAgainstTheTrilinearReference)
{
  const RefTransferFunction tf = testTransferFunction();
  const TestCamera cam = warpedCamera();
  const struct
  {
    const char* name;
    ZSweepGrid grid;
    double splitMax, splitRmse; // measured, levels of 255, with the split faces' field
    double nativeMax, nativeRmse; // with the cells' own field
  } cases[] = { { "jittered cube, linear field", withLinearField(jitteredCube()), 25.64, 3.91, 25.63, 3.89 },
    { "jittered cube", jitteredCube(), 143.42, 19.35, 35.58, 3.04 },
    { "twisted hexahedron (45 degrees)", twistedHexahedron(45), 154.96, 18.69, 142.06, 13.25 },
    { "twisted frusta", twistedFrusta(false), 144.52, 8.98, 139.45, 8.32 },
    { "jittered 3^3 lattice", warpedLattice(), 19.60, 1.61, 0.58, 0.022 },
    { "jittered 2^3 lattice of wedges", warpedLatticeOf(ZSweepCellType::Wedge), 19.31, 2.34, 0.61, 0.05 },
    { "jittered 2^3 lattice of pyramids", warpedLatticeOf(ZSweepCellType::Pyramid), 15.52, 1.34, 1.00, 0.045 },
    { "parallelepiped, trilinear field", parallelepiped(), 120.23, 18.89, 0.035, 0.0016 } };
  for (const auto& c : cases)
  {
    const PixelReference reference = trilinearReference(c.grid, tf, TrilinearStep);
    const Image split = sweep(c.grid, tf, cam, splitFaces());
    const ImageError toModel = errorTo(split.frame, cam, polyhedronReference(c.grid, tf));
    const ImageError e = errorTo(split.frame, cam, reference);
    const Image native = sweep(c.grid, tf, cam);
    const ImageError n = errorTo(native.frame, cam, reference);
    std::printf("%s: split faces max %.4f, rmse %.4f (to the split-triangle model %.1e); own "
                "field max %.4f, rmse %.4f levels of 255 (%lld pieces, %lld inversion "
                "failures); %d pixels\n",
      c.name, 255 * e.max, 255 * e.rmse, toModel.max, 255 * n.max, 255 * n.rmse,
      static_cast<long long>(native.stats.counter("curved_pieces")),
      static_cast<long long>(native.stats.counter("curved_inversion_failures")), e.covered);
    EXPECT_TRUE(e.finite && n.finite);
    EXPECT_LT(toModel.max, 1e-5) << c.name;
    EXPECT_LE(255 * e.max, c.splitMax) << c.name;
    EXPECT_LE(255 * e.rmse, c.splitRmse) << c.name;
    EXPECT_LE(255 * n.max, c.nativeMax) << c.name;
    EXPECT_LE(255 * n.rmse, c.nativeRmse) << c.name;
    EXPECT_GT(e.covered, 300) << c.name;
    EXPECT_EQ(split.stats.counter("curved_segments"), 0) << c.name;
    EXPECT_GT(native.stats.counter("curved_segments"), 0) << c.name;
    EXPECT_EQ(native.stats.counter("curved_inversion_failures"), 0) << c.name;
  }
}

namespace
{
// The cell refined into m^3 sub-cubes of its parametric cube, each split into Freudenthal's
// 6 tetrahedra, their corners at x(u) with the scalar s(u): a piecewise-linear model that
// tends to the trilinear cell like 1 / m^2 (built from the map's formula, not from the
// reference's code).
std::vector<RefTetra> refinedTetrahedra(const ZSweepGrid& g, int m)
{
  std::vector<RefTetra> out;
  const auto corner = [&](int k) { return g.points[static_cast<std::size_t>(k)]; };
  const auto at = [&](double u, double v, double w, double& s) {
    const double f[8] = { (1 - u) * (1 - v) * (1 - w), u * (1 - v) * (1 - w), u * v * (1 - w),
      (1 - u) * v * (1 - w), (1 - u) * (1 - v) * w, u * (1 - v) * w, u * v * w, (1 - u) * v * w };
    Vec3d x;
    s = 0;
    for (int k = 0; k < 8; ++k)
    {
      x += corner(k) * f[k];
      s += g.scalars[static_cast<std::size_t>(k)] * f[k];
    }
    return x;
  };
  for (int k = 0; k < m; ++k)
  {
    for (int j = 0; j < m; ++j)
    {
      for (int i = 0; i < m; ++i)
      {
        // The sub-cube's corners as a hexahedron in VTK order (ids 0..7 of its own).
        ZSweepGrid sub;
        for (int c = 0; c < 8; ++c)
        {
          double s;
          sub.points.push_back(at(double(i + HexCorner[c][0]) / m, double(j + HexCorner[c][1]) / m,
            double(k + HexCorner[c][2]) / m, s));
          sub.scalars.push_back(s);
        }
        addCell(sub, ZSweepCellType::Hexahedron, { 0, 1, 2, 3, 4, 5, 6, 7 });
        for (const RefTetra& t : referenceTetra(sub))
        {
          out.push_back(t);
        }
      }
    }
  }
  return out;
}
} // namespace

// On single warped cells with a trilinear field the reference is the limit of refined
// piecewise-linear models (the tetrahedra reference on m^3 sub-cubes): the difference falls
// like 1 / m^2, from m = 8 to m = 16 by about 4.
TEST(ZSweepTrilinearReference, IsTheLimitOfRefinedTetrahedra)
{
  const RefTransferFunction tf = testTransferFunction();
  const TestCamera cam = warpedCamera();
  for (const ZSweepGrid& g : { jitteredCube(), twistedHexahedron(45) })
  {
    const auto trilinear = trilinearReference(g, tf, TrilinearStep);
    double err[2] = { 0, 0 };
    int n = 0;
    for (const int m : { 8, 16 })
    {
      const std::vector<RefTetra> tets = refinedTetrahedra(g, m);
      const ReferenceTetraGrid grid(tets);
      std::vector<std::size_t> candidates;
      for (int j = 1; j < cam.height; j += 3)
      {
        for (int i = 1; i < cam.width; i += 3)
        {
          Vec3d o, d;
          double tMin;
          cam.ray(i, j, o, d, tMin);
          grid.candidates(o, d, tMin, candidates);
          const auto a = trilinear(o, d, tMin);
          const auto b = traceReference(tets, false, tf, o, d, tMin, &candidates, 16);
          for (std::size_t c = 0; c < 4; ++c)
          {
            err[n] = std::max(err[n], std::fabs(a[c] - b[c]));
          }
        }
      }
      ++n;
    }
    std::printf(
      "refined tetrahedra to the trilinear reference: m = 8 %.3g, m = 16 %.3g\n", err[0], err[1]);
    EXPECT_LT(err[1], err[0] / 3);
    EXPECT_LT(err[1], 0.02);
  }
}
