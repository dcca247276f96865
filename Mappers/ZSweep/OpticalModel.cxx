#include "Mappers/ZSweep/OpticalModel.h"

#include "Mappers/Common/SimdTarget.h"

#include <algorithm>
#include <cmath>

namespace raymappers
{

namespace
{
// The 4- and 6-point Gauss-Legendre rules on [-1, 1].
constexpr double GL4x[4] = { -0.8611363115940526,
  -0.3399810435848563,
  0.3399810435848563,
  0.8611363115940526 };
constexpr double GL4w[4] = { 0.3478548451374538,
  0.6521451548625461,
  0.6521451548625461,
  0.3478548451374538 };
constexpr double GL6x[6] = { -0.9324695142031521,
  -0.6612093864662645,
  -0.2386191860831969,
  0.2386191860831969,
  0.6612093864662645,
  0.9324695142031521 };
constexpr double GL6w[6] = { 0.1713244923791704,
  0.3607615730481386,
  0.4679139345726910,
  0.4679139345726910,
  0.3607615730481386,
  0.1713244923791704 };

// Beyond this optical depth the remaining light is below exp(-40) = 4e-18.
constexpr double DepthCutoff = 40.0;

// I1 = int_0^1 (1 - exp(-E(x))) dx and I2 = int_0^1 (exp(-E(x)) - exp(-E(1))) dx with
// E(x) = A x + B x^2, written so that neither cancels when E is tiny (expm1):
// G = 1 - I1 and 1 - T = I1 + I2, T = exp(-E(1)).
struct DepthIntegrals
{
  double oneMinusG = 0;
  double gMinusT = 0;
  double transmittance = 1;
};

// Below this optical depth (E <= 0.1 all over [0, 1]) the integrals come from 4-point
// Gauss-Legendre quadrature of 1 - e^-E with 1 - e^-E from its Taylor polynomial of degree
// 7 (relative remainder below E^7 / 8! = 2.5e-12), without exp. The rule is exact for
// polynomials of degree 7 in x; of 1 - e^-E(x) = sum_k (-1)^(k+1) E^k / k! with
// E = A x + B x^2, |A| <= 0.1, |B| <= 0.05, only the terms k >= 4 reach degree 8, and
// they leave an error below 1e-11.
constexpr double SeriesDepth = 0.1;

// 1 - e^-E for 0 <= E <= 0.1: Horner's scheme of its Taylor polynomial of degree 7.
inline double oneMinusExpSmall(double E)
{
  return E * (1.0 -
               E * (1.0 / 2 -
                     E * (1.0 / 6 -
                           E * (1.0 / 24 - E * (1.0 / 120 - E * (1.0 / 720 - E * (1.0 / 5040)))))));
}

// The integrals below SeriesDepth (E' <= SeriesDepth on [0, 1]); inlined into the SIMD
// lanes of a batch too.
inline DepthIntegrals seriesDepthIntegrals(double A, double B)
{
  double oneMinusG = 0;
  for (int k = 0; k < 4; ++k)
  {
    const double x = 0.5 * (1.0 + GL4x[k]);
    oneMinusG += 0.5 * GL4w[k] * oneMinusExpSmall(x * (A + B * x));
  }
  const double oneMinusT = oneMinusExpSmall(A + B);
  DepthIntegrals out;
  out.oneMinusG = oneMinusG;
  out.gMinusT = oneMinusT - oneMinusG;
  out.transmittance = 1.0 - oneMinusT;
  return out;
}

inline DepthIntegrals depthIntegrals(double A, double B)
{
  DepthIntegrals out;
  const double total = A + B;
  if (!(total > 0))
  {
    return out;
  }
  const double slope = std::max(A, A + 2.0 * B); // E' is affine: largest at an end
  if (slope <= SeriesDepth)
  {
    return seriesDepthIntegrals(A, B);
  }
  // Integrate up to xmax, where E reaches the cutoff (E rises monotonically), and count
  // the rest as fully absorbed (1 - e^-E = 1 there, e^-E - e^-E(1) = 0).
  double xmax = 1.0;
  if (total > DepthCutoff)
  {
    // Root of B x^2 + A x - 40 = 0 in (0, 1), in the form without cancellation.
    xmax = 2.0 * DepthCutoff / (A + std::sqrt(std::max(0.0, A * A + 4.0 * B * DepthCutoff)));
    xmax = std::clamp(xmax, 0.0, 1.0);
  }
  const double depth = xmax * std::max(A, A + 2.0 * B * xmax); // bounds E's rise on [0, xmax]
  // 4 points while the depth is at most 0.5, else 6 points on pieces of depth at most 1
  // (relative error about 1e-12 either way).
  const bool shallow = depth <= 0.5;
  const int pieces = shallow ? 1 : std::clamp(static_cast<int>(std::ceil(depth)), 1, 64);
  const int nodes = shallow ? 4 : 6;
  const double* xs = shallow ? GL4x : GL6x;
  const double* ws = shallow ? GL4w : GL6w;
  const double width = xmax / pieces;
  out.transmittance = std::exp(-total);
  for (int p = 0; p < pieces; ++p)
  {
    const double a = p * width;
    for (int k = 0; k < nodes; ++k)
    {
      const double x = a + 0.5 * width * (1.0 + xs[k]);
      const double w = 0.5 * width * ws[k];
      // Here E > 0.1 somewhere, so 1 - e^-E loses at most a few digits of 16 where E is
      // small: one exp per node.
      const double attenuation = std::exp(-(A * x + B * x * x));
      out.oneMinusG += w * (1.0 - attenuation);
      out.gMinusT += w * (attenuation - out.transmittance);
    }
  }
  out.oneMinusG += 1.0 - xmax;
  return out;
}
// The light of one linear piece (see integrateLinearPiece), inlined into the integrators.
inline SegmentLight linearPiece(double tauA,
  const double cA[3],
  double tauB,
  const double cB[3],
  double l)
{
  SegmentLight out;
  if (!(l > 0) || (tauA <= 0 && tauB <= 0))
  {
    return out;
  }
  // C = c_a - c_b T + (c_b - c_a) G = c_a (1 - G) + c_b (G - T).
  const double A = tauA * l;
  const double B = 0.5 * (tauB - tauA) * l;
  const DepthIntegrals d = depthIntegrals(A, B);
  out.transmittance = d.transmittance;
  out.r = cA[0] * d.oneMinusG + cB[0] * d.gMinusT;
  out.g = cA[1] * d.oneMinusG + cB[1] * d.gMinusT;
  out.b = cA[2] * d.oneMinusG + cB[2] * d.gMinusT;
  return out;
}

} // namespace

// The arrays of a batch and the piecewise-linear transfer function that the exact
// integrator's SIMD lanes read and write (OpticalModel::integrateExactLanes).
struct ExactLaneArrays
{
  std::size_t count;
  int nodes;
  const double *nodeS, *from, *tau, *tauSlope, *red, *redSlope, *green, *greenSlope, *blue,
    *blueSlope;
  const double *in0, *in1, *len;
  double *outR, *outG, *outB, *outT;
  unsigned char* deferred;
  int *interval0, *interval1;
};

void integrateLinearPieceLanes(const ExactLaneArrays& a);
RAYMAPPERS_SIMD_VARIANTS(integrateLinearPieceLanes)

#if RAYMAPPERS_SIMD_TARGET == 0 // (everything but the SIMD lanes: once)
double gaussianDepthIntegral(double A, double B)
{
  return 1.0 - depthIntegrals(A, B).oneMinusG;
}

SegmentLight integrateLinearPiece(double tauA,
  const double cA[3],
  double tauB,
  const double cB[3],
  double l)
{
  return linearPiece(tauA, cA, tauB, cB, l);
}

void OpticalModel::assign(const std::vector<double>& s,
  const std::vector<double>& rgb,
  const std::vector<double>& opacity,
  double unitDistance)
{
  Nodes.clear();
  const double u = unitDistance > 0 && std::isfinite(unitDistance) ? unitDistance : 1.0;
  for (std::size_t j = 0; j < s.size(); ++j)
  {
    Node node;
    node.s = s[j];
    for (int c = 0; c < 3; ++c)
    {
      node.rgb[c] = std::clamp(rgb[3 * j + c], 0.0, 1.0);
    }
    const double a = std::clamp(std::isfinite(opacity[j]) ? opacity[j] : 0.0, 0.0, 1.0 - 1e-7);
    node.tau = -std::log1p(-a) / u;
    Nodes.push_back(node);
  }
  OpaqueBefore.assign(Nodes.size() + 1, 0);
  for (std::size_t j = 0; j < Nodes.size(); ++j)
  {
    OpaqueBefore[j + 1] = OpaqueBefore[j] + (Nodes[j].tau > 0);
  }
  // The interval tables of the SIMD lanes (see the header), as valueIn evaluates them.
  const std::size_t n = Nodes.size();
  NodeS.resize(n);
  for (auto* table : { &From, &Tau, &TauSlope, &R, &RSlope, &G, &GSlope, &B, &BSlope })
  {
    table->assign(n + 1, 0.0);
  }
  for (std::size_t j = 0; j < n; ++j)
  {
    NodeS[j] = Nodes[j].s;
  }
  for (std::size_t i = 0; i <= n && n > 0; ++i)
  {
    // Index i: interval k = i - 1; the end nodes hold outside.
    const bool inner = i >= 1 && i < n;
    const Node& a = Nodes[i == 0 ? 0 : i - 1];
    const double span = inner ? Nodes[i].s - a.s : 0.0;
    auto slope = [&](double va, double vb) { return span > 0 ? (vb - va) / span : 0.0; };
    From[i] = a.s;
    Tau[i] = a.tau;
    R[i] = a.rgb[0];
    G[i] = a.rgb[1];
    B[i] = a.rgb[2];
    if (inner)
    {
      const Node& b = Nodes[i];
      TauSlope[i] = slope(a.tau, b.tau);
      RSlope[i] = slope(a.rgb[0], b.rgb[0]);
      GSlope[i] = slope(a.rgb[1], b.rgb[1]);
      BSlope[i] = slope(a.rgb[2], b.rgb[2]);
    }
  }
}

void SegmentBatch::grow()
{
  const std::size_t n = std::max<std::size_t>(64, 2 * s0.size());
  for (auto* v : { &s0, &s1, &length, &r, &g, &b, &transmittance })
  {
    v->resize(n);
  }
  Interval0.resize(n);
  Interval1.resize(n);
  Deferred.resize(n);
}

inline int OpticalModel::intervalOf(double s) const
{
  // Few nodes (the usual transfer function): a linear scan beats a binary search.
  const int n = static_cast<int>(Nodes.size());
  if (n <= 8)
  {
    int k = -1;
    while (k + 1 < n && Nodes[static_cast<std::size_t>(k + 1)].s <= s)
    {
      ++k;
    }
    return k;
  }
  const auto it = std::upper_bound(
    Nodes.begin(), Nodes.end(), s, [](double v, const Node& node) { return v < node.s; });
  return static_cast<int>(it - Nodes.begin()) - 1;
}

inline void OpticalModel::valueIn(int k, double s, double& tau, double rgb[3]) const
{
  const int last = static_cast<int>(Nodes.size()) - 1;
  if (k < 0 || k >= last)
  {
    const Node& n = Nodes[k < 0 ? 0 : static_cast<std::size_t>(last)];
    tau = n.tau;
    std::copy(n.rgb, n.rgb + 3, rgb);
    return;
  }
  const Node& a = Nodes[static_cast<std::size_t>(k)];
  const Node& b = Nodes[static_cast<std::size_t>(k) + 1];
  const double f = (b.s > a.s) ? (s - a.s) / (b.s - a.s) : 0.0;
  tau = a.tau + f * (b.tau - a.tau);
  for (int c = 0; c < 3; ++c)
  {
    rgb[c] = a.rgb[c] + f * (b.rgb[c] - a.rgb[c]);
  }
}

void OpticalModel::evaluate(double s, double& tau, double rgb[3]) const
{
  valueIn(intervalOf(s), s, tau, rgb);
}

bool OpticalModel::opaqueNodeBetween(int k0, int k1) const
{
  // The nodes strictly between s0 (in interval k0) and s1 (in k1): min(k0, k1) + 1 ..
  // max(k0, k1).
  const int lo = std::min(k0, k1) + 1, hi = std::max(k0, k1);
  return lo <= hi && OpaqueBefore[static_cast<std::size_t>(hi) + 1] !=
                       OpaqueBefore[static_cast<std::size_t>(lo)];
}

bool OpticalModel::transparentBetween(double s0, double s1) const
{
  const int k0 = intervalOf(s0), k1 = intervalOf(s1);
  double tau0 = 0, tau1 = 0, rgb[3];
  valueIn(k0, s0, tau0, rgb);
  valueIn(k1, s1, tau1, rgb);
  return !(tau0 > 0) && !(tau1 > 0) && !opaqueNodeBetween(k0, k1);
}

SegmentLight OpticalModel::integrateHomogeneous(double s, double L) const
{
  SegmentLight out;
  double tau = 0, c[3];
  evaluate(s, tau, c);
  if (!(L > 0) || !(tau > 0))
  {
    return out;
  }
  const double oneMinusT = -std::expm1(-tau * L);
  out.transmittance = 1.0 - oneMinusT;
  out.r = c[0] * oneMinusT;
  out.g = c[1] * oneMinusT;
  out.b = c[2] * oneMinusT;
  return out;
}

SegmentLight OpticalModel::integrate(ZSweepIntegrator method, double s0, double s1, double L) const
{
  if (method == ZSweepIntegrator::Exact)
  {
    return integrateExact(s0, s1, L); // skips transparent scalar ranges itself
  }
  if (transparentBetween(s0, s1))
  {
    return SegmentLight();
  }
  return method == ZSweepIntegrator::Farias ? integrateFarias(s0, s1, L)
                                            : integrateHomogeneous(0.5 * (s0 + s1), L);
}

void OpticalModel::integrate(ZSweepIntegrator method, SegmentBatch& batch) const
{
  // The lanes count the nodes at or below s one by one: for the usual few nodes.
  constexpr std::size_t MaxLaneNodes = 64;
  if (method == ZSweepIntegrator::Exact && !Nodes.empty() && Nodes.size() <= MaxLaneNodes)
  {
    integrateExactLanes(batch);
    return;
  }
  for (std::size_t i = 0; i < batch.size(); ++i)
  {
    const SegmentLight l = integrate(method, batch.s0[i], batch.s1[i], batch.length[i]);
    batch.r[i] = l.r;
    batch.g[i] = l.g;
    batch.b[i] = l.b;
    batch.transmittance[i] = l.transmittance;
  }
}

void OpticalModel::integrateHomogeneous(SegmentBatch& batch) const
{
  for (std::size_t i = 0; i < batch.size(); ++i)
  {
    const SegmentLight l = integrateHomogeneous(batch.s0[i], batch.length[i]);
    batch.r[i] = l.r;
    batch.g[i] = l.g;
    batch.b[i] = l.b;
    batch.transmittance[i] = l.transmittance;
  }
}

void OpticalModel::integrateExactLanes(SegmentBatch& batch) const
{
  const std::size_t count = batch.size();
  const ExactLaneArrays a{ count, static_cast<int>(NodeS.size()), NodeS.data(), From.data(),
    Tau.data(), TauSlope.data(), R.data(), RSlope.data(), G.data(), GSlope.data(), B.data(),
    BSlope.data(), batch.s0.data(), batch.s1.data(), batch.length.data(), batch.r.data(),
    batch.g.data(), batch.b.data(), batch.transmittance.data(), batch.Deferred.data(),
    batch.Interval0.data(), batch.Interval1.data() };
  integrateLinearPieceLanes(a);
  for (std::size_t i = 0; i < count; ++i)
  {
    if (a.deferred[i])
    {
      const SegmentLight l = integrateExact(a.in0[i], a.in1[i], a.len[i]);
      a.outR[i] = l.r;
      a.outG[i] = l.g;
      a.outB[i] = l.b;
      a.outT[i] = l.transmittance;
    }
  }
}

SegmentLight OpticalModel::integrateExact(double s0, double s1, double L) const
{
  SegmentLight out;
  if (!(L > 0))
  {
    return out;
  }
  const int k0 = intervalOf(s0), k1 = intervalOf(s1);
  double sa = s0, tauA = 0, cA[3], tauEnd = 0, cEnd[3];
  valueIn(k0, s0, tauA, cA);
  valueIn(k1, s1, tauEnd, cEnd);
  if (!(tauA > 0) && !(tauEnd > 0) && !opaqueNodeBetween(k0, k1))
  {
    return out; // no opacity over [s0, s1]
  }
  if (s0 == s1)
  {
    return integrateHomogeneous(s0, L);
  }
  if (k0 == k1)
  {
    return linearPiece(tauA, cA, tauEnd, cEnd, L); // no node between: one linear piece
  }
  // Pieces between the nodes the ray meets strictly between s0 and s1, in its order.
  const double ds = s1 - s0;
  auto piece = [&](double sb, double tauB, const double cB[3])
  {
    const double l = L * ((sb - sa) / ds);
    if (tauA > 0 || tauB > 0)
    {
      compositeBehind(out, linearPiece(tauA, cA, tauB, cB, l));
    }
    sa = sb;
    tauA = tauB;
    std::copy(cB, cB + 3, cA);
  };
  if (ds > 0)
  {
    for (int k = k0 + 1; k <= k1; ++k)
    {
      const Node& n = Nodes[static_cast<std::size_t>(k)];
      if (n.s > s0 && n.s < s1)
      {
        piece(n.s, n.tau, n.rgb);
      }
    }
  }
  else
  {
    for (int k = k0; k > k1; --k)
    {
      const Node& n = Nodes[static_cast<std::size_t>(k)];
      if (n.s < s0 && n.s > s1)
      {
        piece(n.s, n.tau, n.rgb);
      }
    }
  }
  piece(s1, tauEnd, cEnd);
  return out;
}

SegmentLight OpticalModel::integrateFarias(double s0, double s1, double L) const
{
  // Equations 6 and 7 for one segment (accumulated opacity 0 at its front), o = tau and
  // emission density e = c tau:
  //   O = (o_c + o_n) L / 2,
  //   C = (e_c + e_n) L / 2 - (3 e_c o_c + 5 e_n o_c + e_c o_n + 3 e_n o_n) L^2 / 24.
  SegmentLight out;
  if (!(L > 0))
  {
    return out;
  }
  double oc = 0, on = 0, cc[3], cn[3];
  evaluate(s0, oc, cc);
  evaluate(s1, on, cn);
  const double opacity = std::min(1.0, 0.5 * (oc + on) * L);
  out.transmittance = 1.0 - opacity;
  double* channel[3] = { &out.r, &out.g, &out.b };
  for (int c = 0; c < 3; ++c)
  {
    const double ec = cc[c] * oc, en = cn[c] * on;
    const double value =
      0.5 * (ec + en) * L - (3 * ec * oc + 5 * en * oc + ec * on + 3 * en * on) * L * L / 24.0;
    *channel[c] = std::clamp(value, 0.0, opacity);
  }
  return out;
}
#endif

RAYMAPPERS_SIMD_BEGIN

// The SIMD lanes of integrateExactLanes: each segment's interval, then one linear piece
// (integrateLinearPiece) when no node lies between the ends, with the series branch of
// depthIntegrals when E' <= SeriesDepth all along; the other segments are marked deferred.
void integrateLinearPieceLanes(const ExactLaneArrays& a)
{
  RAYMAPPERS_SIMD_FORWARD(integrateLinearPieceLanes, a);
  const std::size_t count = a.count;
  const double* nodeS = a.nodeS;
  const double *from = a.from, *tau = a.tau, *tauSlope = a.tauSlope;
  const double *red = a.red, *redSlope = a.redSlope, *green = a.green,
               *greenSlope = a.greenSlope, *blue = a.blue, *blueSlope = a.blueSlope;
  const double *in0 = a.in0, *in1 = a.in1, *len = a.len;
  double *outR = a.outR, *outG = a.outG, *outB = a.outB, *outT = a.outT;
  unsigned char* deferred = a.deferred;
  // Interval index + 1 of each end: the number of nodes at or below it.
  int *interval0 = a.interval0, *interval1 = a.interval1;
  std::fill(interval0, interval0 + count, 0);
  std::fill(interval1, interval1 + count, 0);
  for (int j = 0; j < a.nodes; ++j)
  {
    const double sj = nodeS[j];
#pragma omp simd
    for (std::size_t i = 0; i < count; ++i)
    {
      interval0[i] += sj <= in0[i];
      interval1[i] += sj <= in1[i];
    }
  }
#pragma omp simd
  for (std::size_t i = 0; i < count; ++i)
  {
    const double s0 = in0[i], s1 = in1[i], L = len[i];
    const int c0 = interval0[i], c1 = interval1[i];
    const double f0 = s0 - from[c0], f1 = s1 - from[c0];
    const double tauA = tau[c0] + f0 * tauSlope[c0], tauB = tau[c0] + f1 * tauSlope[c0];
    const double A = tauA * L, Bq = 0.5 * (tauB - tauA) * L;
    const bool lane = c0 == c1 && std::max(A, A + 2.0 * Bq) <= SeriesDepth;
    deferred[i] = !lane;
    const DepthIntegrals d = seriesDepthIntegrals(lane ? A : 0.0, lane ? Bq : 0.0);
    outT[i] = d.transmittance;
    outR[i] = (red[c0] + f0 * redSlope[c0]) * d.oneMinusG + (red[c0] + f1 * redSlope[c0]) * d.gMinusT;
    outG[i] = (green[c0] + f0 * greenSlope[c0]) * d.oneMinusG +
      (green[c0] + f1 * greenSlope[c0]) * d.gMinusT;
    outB[i] =
      (blue[c0] + f0 * blueSlope[c0]) * d.oneMinusG + (blue[c0] + f1 * blueSlope[c0]) * d.gMinusT;
  }
}

RAYMAPPERS_SIMD_END

} // namespace raymappers
