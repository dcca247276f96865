// The emission-absorption model of the ZSweep renderer and its integrators along one ray
// segment (Farias 2001, section 2.2.2, equations 2-7).
//
// Model: the transfer function is piecewise linear in the scalar s between its nodes s_j,
// in the extinction tau (per unit length) and in the emitted color c:
//   tau_j = -ln(1 - alpha_j) / u     (alpha_j: the node's opacity per unit distance u),
// and the color reaching the eye from a segment [0, L] is
//   C = int_0^L c(t) tau(t) T(t) dt,   T(t) = exp(-int_0^t tau),
// accumulated front to back (C += T_front C_segment, T_front *= T_segment).
//
// Integrators of a segment on which s is linear in t (point data; s0 at the front):
// - Exact: the segment is split where s crosses a node; on each piece tau and c are linear
//   in t, T is exp(-(tau_a + tau_b) l / 2) and, by parts,
//     C = c_a - c_b T + (c_b - c_a) G,   G = int_0^1 exp(-A x - B x^2) dx,
//   A = tau_a l, B = (tau_b - tau_a) l / 2 (E(x) = A x + B x^2 is the optical depth, rising
//   since tau >= 0). G has no elementary closed form: it is evaluated by Gauss-Legendre
//   quadrature. Below an optical depth of 0.1 (most segments: one cell) 4 points with
//   1 - e^-E from its Taylor polynomial of degree 7 (no exp; error below 1e-11); up to depth
//   0.5, 4 points; above, 6 points on pieces of depth at most 1 (relative error about
//   1e-12), cut where the optical depth passes 40 (the rest is below 4e-18).
// - Farias: the dissertation's second-order closed form (equations 6 and 7), with o = tau
//   and c = emission density c tau at both ends, the accumulated opacity clamped to 1; the
//   transfer function is evaluated at the segment's ends only.
// - Midpoint: tau and c at the middle scalar, then the homogeneous formula.
// Cell data (s constant in a cell): the homogeneous formula, exact:
//   T = exp(-tau L),  C = c (1 - T).
//
// Segments are independent of each other until they are composited, so the renderer hands
// them over in batches (SegmentBatch); the exact integrator's common case, a segment inside
// one interval of the nodes with an optical depth below 0.1, runs in SIMD lanes over the
// batch, the others one by one.
#ifndef RayMappers_OpticalModel_h
#define RayMappers_OpticalModel_h

#include <vector>

namespace raymappers
{

enum class ZSweepIntegrator
{
  Exact,
  Farias,
  Midpoint
};

/// Premultiplied color and transmittance of a ray segment (or of a pixel so far).
struct SegmentLight
{
  double r = 0, g = 0, b = 0; // emitted light reaching the segment's front
  double transmittance = 1;
};

/// Ray segments integrated together: inputs s0 (front scalar), s1 (back scalar) and length;
/// outputs the light of each segment on its own (r, g, b premultiplied, transmittance).
struct SegmentBatch
{
  std::vector<double> s0, s1, length;
  std::vector<double> r, g, b, transmittance;

  std::size_t size() const { return Count; }
  void clear() { Count = 0; }
  void push(double front, double back, double L)
  {
    if (Count == s0.size())
    {
      grow();
    }
    s0[Count] = front;
    s1[Count] = back;
    length[Count] = L;
    ++Count;
  }

private:
  friend class OpticalModel;
  void grow();
  std::size_t Count = 0;
  // Scratch of the SIMD lanes: each end's interval index + 1, and whether the lanes left
  // the segment to integrateExact.
  std::vector<int> Interval0, Interval1;
  std::vector<unsigned char> Deferred;
};

class OpticalModel
{
public:
  struct Node
  {
    double s;       // scalar
    double rgb[3];  // emitted color
    double tau;     // extinction per unit length
  };

  /// Nodes in increasing s (at least one); below the first and above the last node the
  /// end nodes hold (as VTK clamps its transfer functions). `opacity` values are clamped to
  /// [0, 1 - 1e-7] before the conversion to tau with the unit distance.
  void assign(const std::vector<double>& s,
    const std::vector<double>& rgb,
    const std::vector<double>& opacity,
    double unitDistance);

  bool empty() const { return Nodes.empty(); }
  const std::vector<Node>& nodes() const { return Nodes; }

  /// tau and color at s (linear between nodes).
  void evaluate(double s, double& tau, double rgb[3]) const;

  /// Whether tau is zero all over [min(s0, s1), max(s0, s1)] (nothing to composite).
  bool transparentBetween(double s0, double s1) const;

  /// Light of a segment of length L whose scalar goes linearly from s0 (front) to s1.
  SegmentLight integrate(ZSweepIntegrator method, double s0, double s1, double L) const;

  /// Light of a segment of length L with the constant scalar s (cell data).
  SegmentLight integrateHomogeneous(double s, double L) const;

  /// Light of each segment of the batch (as integrate, one by one).
  void integrate(ZSweepIntegrator method, SegmentBatch& batch) const;
  /// Light of each segment of the batch with its constant scalar s0 (as integrateHomogeneous).
  void integrateHomogeneous(SegmentBatch& batch) const;

private:
  SegmentLight integrateExact(double s0, double s1, double L) const;
  SegmentLight integrateFarias(double s0, double s1, double L) const;

  /// The interval of s: k with s_k <= s < s_{k+1}; -1 below the first node, the last
  /// index at or above the last node.
  int intervalOf(double s) const;
  /// tau and color at s inside interval k (the end node's outside the nodes).
  void valueIn(int k, double s, double& tau, double rgb[3]) const;
  /// Whether a node with tau > 0 lies strictly between scalars in intervals k0 and k1.
  bool opaqueNodeBetween(int k0, int k1) const;

  /// The exact integrator's SIMD lanes over a batch: the segments inside one interval with
  /// an optical depth at most SeriesDepth; the others are left to integrateExact.
  void integrateExactLanes(SegmentBatch& batch) const;

  std::vector<Node> Nodes;
  // OpaqueBefore[j]: how many of the first j nodes have tau > 0 (for skipping).
  std::vector<int> OpaqueBefore;
  // The same model for SIMD lanes: node positions, and per interval k = -1 .. n-1 (index
  // k + 1) the values at its start From and their slopes in s (0 beyond the end nodes):
  // value(s) = Value[k + 1] + (s - From[k + 1]) Slope[k + 1], for tau, r, g, b.
  std::vector<double> NodeS;
  std::vector<double> From, Tau, TauSlope, R, RSlope, G, GSlope, B, BSlope;
};

/// G(A, B) = int_0^1 exp(-A x - B x^2) dx for A >= 0, A + 2B >= 0 (see above).
double gaussianDepthIntegral(double A, double B);

/// One piece on which tau and c are linear: front values (tau_a, c_a), back values
/// (tau_b, c_b), length l. Exact (see above).
SegmentLight integrateLinearPiece(double tauA,
  const double cA[3],
  double tauB,
  const double cB[3],
  double l);

/// Front-to-back: light = front then back.
inline void compositeBehind(SegmentLight& front, const SegmentLight& back)
{
  front.r += front.transmittance * back.r;
  front.g += front.transmittance * back.g;
  front.b += front.transmittance * back.b;
  front.transmittance *= back.transmittance;
}

} // namespace raymappers

#endif
