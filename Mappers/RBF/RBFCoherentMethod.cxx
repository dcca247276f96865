// The coherent method of RBF volume rendering (Knoll et al. 2014, section 4): rays in square
// packets whose frustum is culled against the data first; the samples of a packet taken in
// passes of K samples per ray (section 4.2); in each pass the packet walks the BVH once,
// nodes grown by sigma r_max, and every particle of a leaf adds its Gaussian to each
// buffered sample of each ray within its support (section 4.1, step 4); the buffer is then
// integrated front to back (step 5) and the packet stops when every ray is opaque. The
// packet's rays sit in SIMD lanes (section 5.3): a node's slabs, a particle's support and
// the deposits are computed for all of them at once.
//
// Every SIMD loop reads its scalars from locals or by-value parameters: read through a
// reference, GCC would load them from memory in every lane.
#include "Mappers/RBF/RBFMethods.h"

#include "Mappers/RBF/FastExp.h"
#include "Mappers/Common/SimdLanes.h"
#include "Mappers/Common/TileScheduler.h"
#include "Mappers/Common/SimdTarget.h"

#include <limits>

namespace raymappers
{
namespace rbf
{

RAYMAPPERS_SIMD_VARIANTS(renderCoherent)

RAYMAPPERS_SIMD_BEGIN

namespace
{
// The rays of a packet in structure-of-arrays form, so that a particle or a node is tested
// against all of them in SIMD lanes (section 5.3: "a packet is simply a varying Ray").
// Lanes are padded to a multiple of SimdLaneWidth (SimdLanes.h); a padding lane, like a ray
// without samples in the pass, has an empty interval and an empty sample range. At most 64
// rays (CGT's packets take up to 256): a packet's active rays are a 64-bit mask.
constexpr int MaxRBFPacketRays = MaxRBFPacketSide * MaxRBFPacketSide;
static_assert(MaxRBFPacketRays <= 64, "a packet's rays fit a 64-bit mask");

struct PacketLanes : RayLaneArrays<MaxRBFPacketRays>
{
  alignas(64) float ix[MaxRBFPacketRays]; // 1 / d per axis
  alignas(64) float iy[MaxRBFPacketRays];
  alignas(64) float iz[MaxRBFPacketRays];
  // This pass: the t interval of the ray's samples (empty: t0 > t1) and their indices
  // relative to the pass's first sample, [first, last] (empty: first > last).
  alignas(64) float t0[MaxRBFPacketRays];
  alignas(64) float t1[MaxRBFPacketRays];
  alignas(64) std::int32_t first[MaxRBFPacketRays];
  alignas(64) std::int32_t last[MaxRBFPacketRays];
  // For the particle being deposited: b = f.d, h^2, and the samples in its support
  // [ka, kb] (pass-relative, empty when the ray misses the support).
  alignas(64) float b[MaxRBFPacketRays];
  alignas(64) float h2[MaxRBFPacketRays];
  alignas(64) std::int32_t ka[MaxRBFPacketRays];
  alignas(64) std::int32_t kb[MaxRBFPacketRays];
  // The pass's samples some particle reached, [touchedFirst, touchedLast] (empty: first >
  // last).
  alignas(64) std::int32_t touchedFirst[MaxRBFPacketRays];
  alignas(64) std::int32_t touchedLast[MaxRBFPacketRays];
  // For the pass's integration the samples to blend [from, to] and whether the ray is
  // still open, and the front-to-back state (premultiplied colour and opacity).
  alignas(64) std::int32_t from[MaxRBFPacketRays];
  alignas(64) std::int32_t to[MaxRBFPacketRays];
  alignas(64) std::int32_t open[MaxRBFPacketRays];
  alignas(64) float cr[MaxRBFPacketRays];
  alignas(64) float cg[MaxRBFPacketRays];
  alignas(64) float cb[MaxRBFPacketRays];
  alignas(64) float ca[MaxRBFPacketRays];
};

// A packet: its lanes, and per ray its pixel, its ray (for shading), its samples and whether
// it still takes samples.
struct Packet
{
  PacketLanes P;
  Ray ray[MaxRBFPacketRays];
  SampleRange range[MaxRBFPacketRays];
  bool active[MaxRBFPacketRays];
  int pi[MaxRBFPacketRays], pj[MaxRBFPacketRays];
  int n = 0;     // rays
  int lanes = 0; // n padded to a multiple of SimdLaneWidth
  // The samples of all rays, [kFirst, kLast].
  std::int64_t kFirst = 0, kLast = -1;
};

// The packet's sample buffer (section 4.1, step 3), reused for every pass: per field (and
// per field's weight sum with normalized weights, per gradient component when shading) K
// rows, one per sample of the pass, of the packet's
// rays side by side, so that a particle deposits one sample into a SIMD block of rays at a
// time and the integration reads a block's samples in one load. Zero between passes.
struct SampleBuffer
{
  int laneStride;
  std::ptrdiff_t fieldStride;
  std::vector<float> phi, weight, grad;
  std::vector<float> t; // t of the pass's samples

  SampleBuffer(int maxRays, int K, int numFields, bool normalize, bool grads)
    : laneStride(paddedLaneCount(maxRays))
    , fieldStride(static_cast<std::ptrdiff_t>(K) * laneStride)
    , phi(static_cast<std::size_t>(numFields) * fieldStride)
    , weight(normalize ? static_cast<std::size_t>(numFields) * fieldStride : 0)
    , grad(grads ? static_cast<std::size_t>(3) * fieldStride : 0)
    , t(K)
  {
  }

  float* phiAt(int m, std::int32_t k)
  {
    return &phi[static_cast<std::size_t>(m * fieldStride + k * laneStride)];
  }
  float* weightAt(int m, std::int32_t k)
  {
    return &weight[static_cast<std::size_t>(m * fieldStride + k * laneStride)];
  }
  float* gradAt(int axis, std::int32_t k)
  {
    return &grad[static_cast<std::size_t>(axis * fieldStride + k * laneStride)];
  }

  /// Zeroes samples [first, last] of every row (the only ones a pass changed).
  void clearSamples(std::int32_t first, std::int32_t last, int numFields)
  {
    const std::size_t rows = static_cast<std::size_t>(last - first + 1);
    for (int m = 0; m < numFields; ++m)
    {
      std::fill_n(phiAt(m, first), rows * laneStride, 0.f);
      if (!weight.empty())
      {
        std::fill_n(weightAt(m, first), rows * laneStride, 0.f);
      }
    }
    for (int axis = 0; !grad.empty() && axis < 3; ++axis)
    {
      std::fill_n(gradAt(axis, first), rows * laneStride, 0.f);
    }
  }
};

// Whether some ray of a packet can meet the box [lo - grow, hi + grow], from the packet's
// four corner rays in order around it. A pixel's ray is affine in the pixel's position (its
// points on the near and on the far plane are), so every ray of the packet lies in the cone
// (perspective: the corner rays meet at the eye) or slab (parallel) bounded by the four
// planes that each hold two adjacent corner rays: the plane of rays a and b holds o_a and
// the directions d_a and o_b - o_a. The box is out of reach when it lies wholly outside one
// of them, by a margin far above the rounding of the float rays (1e-4 of the box's and the
// rays' scale). A packet one pixel wide or high spans no cone: never culled.
bool packetMayMeetBox(const Ray corner[4], const float lo[3], const float hi[3], float grow)
{
  const Vec3d bl(lo[0] - grow, lo[1] - grow, lo[2] - grow);
  const Vec3d bh(hi[0] + grow, hi[1] + grow, hi[2] + grow);
  // A point in the cone, as far along the rays as the box (so that its distance to the
  // planes, the packet's width there, is measured at the scale of the margin): the mean of
  // the corners' o + D d.
  const double D = length((bl + bh) * 0.5 - Vec3d(corner[0].org)) + length(bh - bl);
  Vec3d inside(0.0, 0.0, 0.0);
  for (int c = 0; c < 4; ++c)
  {
    inside = inside + (Vec3d(corner[c].org) + Vec3d(corner[c].dir) * D) * 0.25;
  }
  const double scale = length(bh - bl) + length(Vec3d(corner[0].org)) + length(inside);
  for (int e = 0; e < 4; ++e)
  {
    const Vec3d oa(corner[e].org), da(corner[e].dir), ob(corner[(e + 1) % 4].org);
    Vec3d n = cross(da, ob - oa);
    const double norm = length(n);
    if (!(norm > 0))
    {
      return true;
    }
    n = n * (1.0 / norm);
    const double in = dot(n, inside - oa);
    if (!(std::abs(in) > 1e-4 * scale))
    {
      return true; // degenerate: no cone to cull by
    }
    const double side = in > 0 ? 1.0 : -1.0;
    bool outside = true;
    for (int k = 0; k < 8 && outside; ++k)
    {
      const Vec3d x((k & 1) ? bh.x : bl.x, (k & 2) ? bh.y : bl.y, (k & 4) ? bh.z : bl.z);
      outside = side * dot(n, x - oa) < -1e-4 * scale;
    }
    if (outside)
    {
      return false;
    }
  }
  return true;
}

// Frustum culling of the packet at (bx, by): a packet whose rays cannot reach the root's
// grown box takes no ray set-up; its pixels are cleared. Returns whether it was culled.
bool cullPacket(const RBFFrameInputs& in, const Tile& tile, int bx, int by, RBFCounts& counts)
{
  const int side = in.side;
  const int i1 = std::min(bx + side, tile.x1) - 1, j1 = std::min(by + side, tile.y1) - 1;
  const RayCamera& camera = in.camera;
  const Ray corners[4] = { camera.pixelRay(bx, by),
    camera.pixelRay(i1, by),
    camera.pixelRay(i1, j1),
    camera.pixelRay(bx, j1) };
  const BVHNode& root = in.nodes[0];
  if (packetMayMeetBox(corners, root.lo, root.hi, in.sigma * root.rMax))
  {
    return false;
  }
  for (int j = by; j <= j1; ++j)
  {
    for (int i = bx; i <= i1; ++i)
    {
      in.store(i, j, RayAccumulator{});
    }
  }
  counts[Rays] += (i1 - bx + 1) * (j1 - by + 1);
  ++counts[Packets];
  ++counts[CulledPackets];
  return true;
}

// Packet set-up, the rays: the packet's pixels inside the tile, their rays made in SIMD
// lanes (a padding lane: origin and direction 0) and their inverse directions.
void makePacketRays(const RBFFrameInputs& in, const Tile& tile, int bx, int by, Packet& pk)
{
  const int side = in.side;
  int n = 0;
  for (int q = 0; q < side * side; ++q)
  {
    const int i = bx + q % side, j = by + q / side;
    if (i < tile.x1 && j < tile.y1)
    {
      pk.pi[n] = i;
      pk.pj[n] = j;
      ++n;
    }
  }
  const int lanes = paddedLaneCount(n);
  pk.n = n;
  pk.lanes = lanes;
  PacketLanes& P = pk.P;
  float* const org[3] = { P.ox, P.oy, P.oz };
  float* const dir[3] = { P.dx, P.dy, P.dz };
  float tFar[MaxRBFPacketRays];
  in.camera.pixelRays(pk.pi, pk.pj, n, org, dir, tFar);
  for (int r = n; r < lanes; ++r)
  {
    P.ox[r] = P.oy[r] = P.oz[r] = P.dx[r] = P.dy[r] = P.dz[r] = 0.f;
  }
#pragma omp simd
  for (int r = 0; r < lanes; ++r)
  {
    const bool real = r < n;
    P.ix[r] = real ? 1.f / P.dx[r] : 0.f;
    P.iy[r] = real ? 1.f / P.dy[r] : 0.f;
    P.iz[r] = real ? 1.f / P.dz[r] : 0.f;
  }
  for (int r = 0; r < n; ++r)
  {
    pk.ray[r].org = Vec3f(P.ox[r], P.oy[r], P.oz[r]);
    pk.ray[r].dir = Vec3f(P.dx[r], P.dy[r], P.dz[r]);
    pk.ray[r].tnear = 0.f;
    pk.ray[r].tfar = tFar[r];
  }
}

// Packet set-up, the samples (section 4.1, steps 1-2): each ray's sample range, the
// packet's [kFirst, kLast], transparent accumulators, and padding lanes that stay closed,
// transparent and without samples.
void setUpSamples(const RBFFrameInputs& in, Packet& pk)
{
  PacketLanes& P = pk.P;
  const int n = pk.n, K = in.K;
  std::int64_t kFirst = std::numeric_limits<std::int64_t>::max(),
               kLast = std::numeric_limits<std::int64_t>::min();
  for (int r = 0; r < n; ++r)
  {
    pk.range[r] = in.sampleRange(pk.pi[r], pk.pj[r], pk.ray[r]);
    P.cr[r] = P.cg[r] = P.cb[r] = P.ca[r] = 0.f;
    pk.active[r] = pk.range[r].k0 <= pk.range[r].k1;
    if (pk.active[r])
    {
      kFirst = std::min(kFirst, pk.range[r].k0);
      kLast = std::max(kLast, pk.range[r].k1);
    }
  }
  pk.kFirst = kFirst;
  pk.kLast = kLast;
  for (int r = 0; r < pk.lanes; ++r)
  {
    P.t0[r] = 1.f;
    P.t1[r] = 0.f;
    P.first[r] = K;
    P.last[r] = -1;
    if (r >= n)
    {
      P.cr[r] = P.cg[r] = P.cb[r] = P.ca[r] = 0.f;
      P.open[r] = 0;
      P.from[r] = 0;
      P.to[r] = -1;
    }
  }
}

// The rays that take samples in the pass [s0, s1]: rays past their last sample leave the
// packet's active set for good. Returns how many rays have samples in the pass.
int raysInPass(Packet& pk, std::int64_t s0, std::int64_t s1)
{
  int live = 0;
  for (int r = 0; r < pk.n; ++r)
  {
    pk.active[r] = pk.active[r] && pk.range[r].k1 >= s0;
    live += pk.active[r] && pk.range[r].k0 <= s1;
  }
  return live;
}

// The pass's samples of each ray, as pass-relative indices and a t interval, none reached
// yet, and the t of the pass's samples.
void beginPass(const RBFFrameInputs& in,
  Packet& pk,
  SampleBuffer& buffer,
  std::int64_t s0,
  std::int64_t s1)
{
  PacketLanes& P = pk.P;
  const int K = in.K;
  const float dt = in.dt;
  for (int r = 0; r < pk.n; ++r)
  {
    const bool on = pk.active[r] && pk.range[r].k0 <= s1;
    const std::int64_t passFirst = std::max(s0, pk.range[r].k0);
    const std::int64_t passLast = std::min(s1, pk.range[r].k1);
    P.first[r] = on ? static_cast<std::int32_t>(passFirst - s0) : K;
    P.last[r] = on ? static_cast<std::int32_t>(passLast - s0) : -1;
    P.t0[r] = on ? static_cast<float>(passFirst) * dt : 1.f;
    P.t1[r] = on ? static_cast<float>(passLast) * dt : 0.f;
  }
  for (int r = 0; r < pk.lanes; ++r)
  {
    P.touchedFirst[r] = K;
    P.touchedLast[r] = -1;
  }
  for (int k = 0; k < K; ++k)
  {
    buffer.t[k] = static_cast<float>(s0 + k) * dt;
  }
}

// One slab of the ray-box test: [t0, t1] shrinks to where the ray is between l and h on
// this axis (inv = 1 / d). A zero direction component gives an infinite inverse; the NaN
// of 0 * inf then drops out of the comparisons, which keeps the test conservative.
inline void clipToSlab(float l, float h, float o, float inv, float& t0, float& t1)
{
  const float ta = (l - o) * inv, tb = (h - o) * inv;
  const bool swap = ta > tb;
  const float near = swap ? tb : ta, far = swap ? ta : tb;
  t0 = t0 < near ? near : t0;
  t1 = far < t1 ? far : t1;
}

// The node test of the BVH pass: whether some ray of the packet meets the box grown by
// `grow` within its pass interval (a SIMD block of SimdLaneWidth rays at a time, all of its
// lanes at once: a block costs about one ray; the first block with a hit answers).
inline bool packetMeetsBox(const PacketLanes& P,
  int lanes,
  const float lo[3],
  const float hi[3],
  float grow)
{
  const float lx = lo[0] - grow, ly = lo[1] - grow, lz = lo[2] - grow;
  const float hx = hi[0] + grow, hy = hi[1] + grow, hz = hi[2] + grow;
  for (int b0 = 0; b0 < lanes; b0 += SimdLaneWidth)
  {
    int hit = 0;
#pragma omp simd reduction(| : hit)
    for (int r = b0; r < b0 + SimdLaneWidth; ++r)
    {
      float t0 = P.t0[r], t1 = P.t1[r];
      clipToSlab(lx, hx, P.ox[r], P.ix[r], t0, t1);
      clipToSlab(ly, hy, P.oy[r], P.iy[r], t0, t1);
      clipToSlab(lz, hz, P.oz[r], P.iz[r], t0, t1);
      hit |= t0 <= t1;
    }
    if (hit)
    {
      return true;
    }
  }
  return false;
}

// ceil(q) and floor(q) for q in [-2^31, 2^31) (callers clamp first): std::ceil and
// std::floor would keep the loop from vectorizing (without -fno-trapping-math).
inline std::int32_t ceilToInt(float q)
{
  const std::int32_t c = static_cast<std::int32_t>(q); // towards zero
  return c + (static_cast<float>(c) < q);
}
inline std::int32_t floorToInt(float q)
{
  const std::int32_t c = static_cast<std::int32_t>(q);
  return c - (static_cast<float>(c) > q);
}

// The pass's sample indices as the lane tests need them: t / dt - s0 is taken as
// t (1 / dt) - s0 (a sample within an ulp of a support's edge may fall either way, as its
// own t = k dt may), clamped to [-1, K] for the conversion to int.
struct PassIndexing
{
  float invStep;      // 1 / dt
  float s0f;          // the pass's first sample
  std::int32_t slots; // K
  float lastSlot;     // K
};

// First lane test: h^2, the squared distance from the centre c to each ray's line, and
// b = f.d (f = o - c); whether some ray passes within the support R at all (where the
// particles are small on the screen, most particles of a leaf the packet reaches meet none
// of its rays).
bool raysNearParticle(PacketLanes& P, int lanes, const Vec3f c, float R2)
{
  int near = 0;
#pragma omp simd reduction(| : near)
  for (int r = 0; r < lanes; ++r)
  {
    const float fx = P.ox[r] - c.x, fy = P.oy[r] - c.y, fz = P.oz[r] - c.z;
    const float b = fx * P.dx[r] + fy * P.dy[r] + fz * P.dz[r];
    const float lx = fx - P.dx[r] * b, ly = fy - P.dy[r] * b, lz = fz - P.dz[r] * b;
    const float h2 = lx * lx + ly * ly + lz * lz;
    P.b[r] = b;
    P.h2[r] = h2;
    near |= h2 <= R2;
  }
  return near != 0;
}

// Second lane test: each ray's samples inside the support, t = k dt in [-b - w, -b + w],
// w = sqrt(R^2 - h^2), as pass-relative indices [ka, kb] clamped to the ray's samples of the
// pass (empty: [K, -1]). Returns whether some ray has one.
bool supportSamples(PacketLanes& P, int lanes, float R2, const PassIndexing ix)
{
  const float invStep = ix.invStep, s0f = ix.s0f, lastSlot = ix.lastSlot;
  const std::int32_t slots = ix.slots;
  int any = 0;
#pragma omp simd reduction(| : any)
  for (int r = 0; r < lanes; ++r)
  {
    const float b = P.b[r], h2 = P.h2[r];
    const float w = std::sqrt(h2 < R2 ? R2 - h2 : 0.f);
    float qa = (-b - w) * invStep - s0f, qb = (-b + w) * invStep - s0f;
    // (Clamped for the conversion to int, with one select each: a nested one keeps the
    // loop from vectorizing.)
    qa = qa < -1.f ? -1.f : qa;
    qa = qa > lastSlot ? lastSlot : qa;
    qb = qb < -1.f ? -1.f : qb;
    qb = qb > lastSlot ? lastSlot : qb;
    const std::int32_t ka = std::max(P.first[r], ceilToInt(qa));
    const std::int32_t kb = std::min(P.last[r], floorToInt(qb));
    const bool in = h2 <= R2 && ka <= kb;
    P.ka[r] = in ? ka : slots;
    P.kb[r] = in ? kb : -1;
    any |= in;
  }
  return any != 0;
}

// The samples a SIMD block's rays take from the particle, [kLo, kHi] over the block, and
// how many rays they are; the block's reached samples grow by them.
struct BlockReach
{
  std::int32_t kLo, kHi;
  int reached;
};

BlockReach reachBlock(PacketLanes& P, int b0, std::int32_t slots)
{
  std::int32_t kLo = slots, kHi = -1;
  int reached = 0;
#pragma omp simd reduction(min : kLo) reduction(max : kHi) reduction(+ : reached)
  for (int r = b0; r < b0 + SimdLaneWidth; ++r)
  {
    const bool in = P.ka[r] <= P.kb[r];
    kLo = std::min(kLo, P.ka[r]);
    kHi = std::max(kHi, P.kb[r]);
    reached += in;
    const std::int32_t first = P.touchedFirst[r], last = P.touchedLast[r];
    P.touchedFirst[r] = in && P.ka[r] < first ? P.ka[r] : first;
    P.touchedLast[r] = in && P.kb[r] > last ? P.kb[r] : last;
  }
  return { kLo, kHi, reached };
}

// A particle's Gaussian and its gradient, as the deposits need them: amplitude kappa k_i,
// the weight's amplitude kappa, 1 / 2r^2, -1 / r^2 (the gradient's factor), the centre and
// the field.
struct Deposit
{
  Vec3f c;
  float amp, weightAmp, inv2r2, s;
  int field;
};

// Deposits into a SIMD block of rays, sample by sample over the block's samples in the
// support [kLo, kHi]: the Gaussian g = kappa k_i e, e = exp(-(u^2 + h^2) / 2r^2) with
// u = t + b (section 3.1) in the rays whose own support samples hold k, zero in the
// others; with Normalize also the weight kappa e.
template<bool Normalize>
void depositBlock(const PacketLanes& P,
  SampleBuffer& buffer,
  int b0,
  const BlockReach reach,
  const Deposit d)
{
  const float amp = d.amp, weightAmp = d.weightAmp, inv2r2 = d.inv2r2;
  for (std::int32_t k = reach.kLo; k <= reach.kHi; ++k)
  {
    const float t = buffer.t[k];
    float* phi = buffer.phiAt(d.field, k);
    float* weight = Normalize ? buffer.weightAt(d.field, k) : nullptr;
#pragma omp simd
    for (int r = b0; r < b0 + SimdLaneWidth; ++r)
    {
      const float u = t + P.b[r];
      const bool on = (k >= P.ka[r]) & (k <= P.kb[r]);
      const float e = on ? fastExp(-(u * u + P.h2[r]) * inv2r2) : 0.f;
      phi[r] += amp * e;
      if constexpr (Normalize)
      {
        weight[r] += weightAmp * e;
      }
    }
  }
}

// The same deposits with the gradient of equation 4: grad phi = -phi (x - x_i) / r^2,
// x - x_i = f + t d; with Normalize that of the weight, -kappa e (x - x_i) / r^2.
template<bool Normalize>
void depositBlockWithGradient(const PacketLanes& P,
  SampleBuffer& buffer,
  int b0,
  const BlockReach reach,
  const Deposit d)
{
  const float amp = d.amp, weightAmp = d.weightAmp, inv2r2 = d.inv2r2, s = d.s;
  const float gradAmp = Normalize ? weightAmp : amp;
  const Vec3f c = d.c;
  for (std::int32_t k = reach.kLo; k <= reach.kHi; ++k)
  {
    const float t = buffer.t[k];
    float* phi = buffer.phiAt(d.field, k);
    float* weight = Normalize ? buffer.weightAt(d.field, k) : nullptr;
    float *gx = buffer.gradAt(0, k), *gy = buffer.gradAt(1, k), *gz = buffer.gradAt(2, k);
#pragma omp simd
    for (int r = b0; r < b0 + SimdLaneWidth; ++r)
    {
      const float u = t + P.b[r];
      const bool on = (k >= P.ka[r]) & (k <= P.kb[r]);
      const float e = on ? fastExp(-(u * u + P.h2[r]) * inv2r2) : 0.f;
      phi[r] += amp * e;
      if constexpr (Normalize)
      {
        weight[r] += weightAmp * e;
      }
      const float g = gradAmp * e;
      gx[r] += s * g * (P.ox[r] - c.x + t * P.dx[r]);
      gy[r] += s * g * (P.oy[r] - c.y + t * P.dy[r]);
      gz[r] += s * g * (P.oz[r] - c.z + t * P.dz[r]);
    }
  }
}

// A leaf's particle p against the packet (section 4.1, step 4): the two lane tests, then
// the deposits into each SIMD block of rays the support reaches.
void depositParticle(const RBFFrameInputs& in,
  Packet& pk,
  SampleBuffer& buffer,
  std::uint32_t p,
  const PassIndexing ix,
  RBFCounts& counts)
{
  const RBFParticles& particles = in.particles;
  const Vec3f c = particles.centers[p];
  const float rad = particles.radii[p];
  const float R = in.sigma * rad;
  const float R2 = R * R;
  const float inv2r2 = 0.5f / (rad * rad);
  PacketLanes& P = pk.P;
  const int lanes = pk.lanes;
  if (!raysNearParticle(P, lanes, c, R2) || !supportSamples(P, lanes, R2, ix))
  {
    return;
  }
  const Deposit d{
    c, in.kappa * particles.values[p], in.kappa, inv2r2, -2.f * inv2r2, particles.fields[p]
  };
  for (int b0 = 0; b0 < lanes; b0 += SimdLaneWidth)
  {
    const BlockReach reach = reachBlock(P, b0, ix.slots);
    if (reach.reached == 0)
    {
      continue;
    }
    counts[Deposits] += reach.reached;
    if (in.grads)
    {
      (in.normalize ? depositBlockWithGradient<true> : depositBlockWithGradient<false>)(
        P, buffer, b0, reach, d);
    }
    else
    {
      (in.normalize ? depositBlock<true> : depositBlock<false>)(P, buffer, b0, reach, d);
    }
  }
}

// The BVH pass (section 4.1, step 4; Listing 2): the packet walks the BVH once, entering a
// node when any ray's pass interval meets its box grown by sigma r_max, and every particle
// of a leaf it enters deposits into the buffer.
void walkBVH(const RBFFrameInputs& in,
  Packet& pk,
  SampleBuffer& buffer,
  std::int64_t s0,
  std::vector<std::uint32_t>& stack,
  RBFCounts& counts)
{
  const PassIndexing ix{ 1.f / in.dt, static_cast<float>(s0), in.K, static_cast<float>(in.K) };
  const std::vector<BVHNode>& nodes = in.nodes;
  const float sigma = in.sigma;
  stack.assign(1, 0u);
  while (!stack.empty())
  {
    const BVHNode& node = nodes[stack.back()];
    stack.pop_back();
    ++counts[NodeVisits];
    if (!packetMeetsBox(pk.P, pk.lanes, node.lo, node.hi, sigma * node.rMax))
    {
      continue;
    }
    if (node.count == 0)
    {
      stack.push_back(node.first + 1);
      stack.push_back(node.first);
      continue;
    }
    for (std::uint32_t p = node.first; p < node.first + node.count; ++p)
    {
      depositParticle(in, pk, buffer, p, ix, counts);
    }
  }
}

// The span of a SIMD block's open rays' samples to blend, [kLo, kHi], and the most samples
// one of them has.
struct BlockSpan
{
  std::int32_t kLo, kHi, longest;
};

BlockSpan blockSpan(const PacketLanes& P, int b0, int b1)
{
  std::int32_t kLo = std::numeric_limits<std::int32_t>::max(), kHi = -1, longest = 0;
  for (int r = b0; r < b1; ++r)
  {
    if (P.open[r] && P.from[r] <= P.to[r])
    {
      kLo = std::min(kLo, P.from[r]);
      kHi = std::max(kHi, P.to[r]);
      longest = std::max(longest, P.to[r] - P.from[r] + 1);
    }
  }
  return { kLo, kHi, longest };
}

// Integrates a pass's buffer front to back for the n rays of the packet, without shading
// (section 5.3: "all samples for the packet are integrated, iterating using a uniform t
// variable spanning minimum and maximum sample positions"): ray r blends its samples
// [from[r], to[r]] while open[r], with the arithmetic of Classifier::blend, and closes when
// its opacity reaches the threshold. The loop runs per SIMD block of SimdLaneWidth rays, and
// a block with no open ray costs nothing. Step i of a block blends, in each ray, either the
// block's sample kLo + i (the uniform t over the block's span) or the ray's own sample
// from[r] + i (read by a gather): the latter when the rays' spans are staggered, as where
// they cross a thin layer obliquely, so that the block takes as many steps as its longest
// ray has samples instead of its whole span. The buffer holds the value of field m at
// sample k of ray r at base[m fieldStride + k sampleStride + r] (with Normalize its weight
// sum at the same place of weights, and the value Phi / W is classified with the covered
// opacity). Returns the samples blended; the rays closed are added to `terminated`, the
// staggered blocks to `staggeredBlocks`.
template<bool Normalize>
std::int64_t integrateLanes(const std::vector<StepTable>& tables,
  int numFields,
  const float* base,
  const float* weights,
  std::ptrdiff_t fieldStride,
  std::ptrdiff_t sampleStride,
  int n,
  float threshold,
  PacketLanes& P,
  std::int64_t& terminated,
  std::int64_t& staggeredBlocks)
{
  std::int64_t blended = 0, closed = 0;
  for (int b0 = 0; b0 < n; b0 += SimdLaneWidth)
  {
    // (The block's lanes past n are padding, closed with empty ranges.)
    const BlockSpan span = blockSpan(P, b0, std::min(n, b0 + SimdLaneWidth));
    const std::int32_t kLo = span.kLo, kHi = span.kHi, longest = span.longest;
    const bool staggered = kHi - kLo + 1 > longest;
    staggeredBlocks += staggered;
    const std::int32_t steps = staggered ? longest : kHi - kLo + 1;
    // Step i's sample of lane r is first[r] + i.
    alignas(64) std::int32_t first[SimdLaneWidth];
    for (int r = 0; r < SimdLaneWidth; ++r)
    {
      first[r] = staggered ? P.from[b0 + r] : kLo;
    }
    for (std::int32_t i = 0; i < steps; ++i)
    {
      for (int m = 0; m < numFields; ++m)
      {
        const StepTable& table = tables[std::min<std::size_t>(m, tables.size() - 1)];
        const float* rgba = table.rgba.data();
        const int size = table.size();
        const float* field = base + m * fieldStride + b0;
        const float* fieldWeight = Normalize ? weights + m * fieldStride + b0 : nullptr;
        const std::int32_t rowStride = static_cast<std::int32_t>(sampleStride);
        const std::int32_t lastRow = static_cast<std::int32_t>(fieldStride / sampleStride) - 1;
#pragma omp simd
        for (int r = 0; r < SimdLaneWidth; ++r)
        {
          const int q = b0 + r;
          const std::int32_t k = first[r] + i;
          // (Read in every lane, at a row of the buffer: a gather the loop can vectorize.)
          const std::int32_t at = (k < lastRow ? k : lastRow) * rowStride + r;
          float v = field[at];
          float cover = 1.f;
          if constexpr (Normalize)
          {
            cover = fieldWeight[at];
            v = cover > 0.f ? v / cover : 0.f;
          }
          const bool on = (P.open[q] != 0) & (k >= P.from[q]) & (k <= P.to[q]);
          // Off, NaN, or (Normalize) reached by no particle: transparent black.
          const bool valid = on & (v == v) & (cover > 0.f);
          RGBA c = table.lookupIn(rgba, size, valid ? v : 0.f);
          if constexpr (Normalize)
          {
            c.a = coveredOpacity(c.a, cover);
          }
          const float w = (1.f - P.ca[q]) * c.a;
          const bool add = valid & (c.a > 0.f);
          P.cr[q] = add ? P.cr[q] + w * c.r : P.cr[q];
          P.cg[q] = add ? P.cg[q] + w * c.g : P.cg[q];
          P.cb[q] = add ? P.cb[q] + w * c.b : P.cb[q];
          P.ca[q] = add ? P.ca[q] + w : P.ca[q];
        }
      }
      int stillOpen = 0;
#pragma omp simd reduction(+ : blended, closed, stillOpen)
      for (int r = 0; r < SimdLaneWidth; ++r)
      {
        const int q = b0 + r;
        const std::int32_t k = first[r] + i;
        const bool on = (P.open[q] != 0) & (k >= P.from[q]) & (k <= P.to[q]);
        const bool stop = on & (P.ca[q] >= threshold);
        blended += on;
        closed += stop;
        P.open[q] = stop ? 0 : P.open[q];
        stillOpen += (P.open[q] != 0) & (P.to[q] > k);
      }
      if (stillOpen == 0)
      {
        break;
      }
    }
  }
  terminated += closed;
  return blended;
}

// Integration with shading: ray by ray, each sample classified, shaded with its gradient
// and blended through the classifier, until the ray's opacity reaches the threshold.
void integrateShaded(const RBFFrameInputs& in, Packet& pk, SampleBuffer& buffer, RBFCounts& counts)
{
  PacketLanes& P = pk.P;
  for (int r = 0; r < pk.n; ++r)
  {
    RayAccumulator sum{ P.cr[r], P.cg[r], P.cb[r], P.ca[r] };
    for (std::int32_t k = P.from[r]; P.open[r] && k <= P.to[r]; ++k)
    {
      float phi[MaxRBFFields] = { 0, 0, 0, 0 }, weight[MaxRBFFields] = { 0, 0, 0, 0 };
      for (int m = 0; m < in.numFields; ++m)
      {
        phi[m] = buffer.phiAt(m, k)[r];
        weight[m] = in.normalize ? buffer.weightAt(m, k)[r] : 0.f;
      }
      const float grad[3] = {
        buffer.gradAt(0, k)[r], buffer.gradAt(1, k)[r], buffer.gradAt(2, k)[r]
      };
      ++counts[Samples];
      in.classifier.blend(
        phi, in.normalize ? weight : nullptr, grad, pk.ray[r].org, pk.ray[r].dir, buffer.t[k], sum);
      if (sum.a >= in.threshold)
      {
        P.open[r] = 0;
        ++counts[TerminatedRays];
      }
    }
    P.cr[r] = sum.r;
    P.cg[r] = sum.g;
    P.cb[r] = sum.b;
    P.ca[r] = sum.a;
  }
}

// Integration of the pass (section 4.1, step 5): each open ray blends its samples, with a
// clear empty field only those some particle reached (nothing else can add anything).
void integratePass(const RBFFrameInputs& in, Packet& pk, SampleBuffer& buffer, RBFCounts& counts)
{
  PacketLanes& P = pk.P;
  const bool emptyIsClear = in.emptyIsClear;
  for (int r = 0; r < pk.n; ++r)
  {
    P.from[r] = emptyIsClear ? P.touchedFirst[r] : P.first[r];
    P.to[r] = emptyIsClear ? P.touchedLast[r] : P.last[r];
    P.open[r] = pk.active[r];
  }
  if (in.grads)
  {
    integrateShaded(in, pk, buffer, counts);
    return;
  }
  counts[Samples] += (in.normalize ? integrateLanes<true> : integrateLanes<false>)(in.tables,
    in.numFields,
    buffer.phi.data(),
    buffer.weight.data(),
    buffer.fieldStride,
    buffer.laneStride,
    pk.n,
    in.threshold,
    P,
    counts[TerminatedRays],
    counts[StaggeredBlocks]);
}

// Early termination (section 4.2): the rays still open stay active; the buffer's reached
// samples are zeroed for the next pass. Returns whether some ray is still active.
bool endPass(const RBFFrameInputs& in, Packet& pk, SampleBuffer& buffer)
{
  PacketLanes& P = pk.P;
  int stillActive = 0;
  std::int32_t clearFirst = in.K, clearLast = -1;
  for (int r = 0; r < pk.n; ++r)
  {
    pk.active[r] = P.open[r] != 0;
    stillActive += pk.active[r];
    clearFirst = std::min(clearFirst, P.touchedFirst[r]);
    clearLast = std::max(clearLast, P.touchedLast[r]);
  }
  if (clearFirst <= clearLast)
  {
    buffer.clearSamples(clearFirst, clearLast, in.numFields);
  }
  return stillActive > 0;
}

// The passes of K samples (section 4.2, Listing 3) until every ray of the packet is opaque
// or past its samples.
void tracePasses(const RBFFrameInputs& in,
  Packet& pk,
  SampleBuffer& buffer,
  std::vector<std::uint32_t>& stack,
  RBFCounts& counts)
{
  const int K = in.K;
  for (std::int64_t s0 = pk.kFirst; s0 <= pk.kLast; s0 += K)
  {
    const std::int64_t s1 = std::min(pk.kLast, s0 + K - 1);
    if (raysInPass(pk, s0, s1) == 0)
    {
      if (std::none_of(pk.active, pk.active + pk.n, [](bool a) { return a; }))
      {
        break;
      }
      continue;
    }
    ++counts[Passes];
    beginPass(in, pk, buffer, s0, s1);
    walkBVH(in, pk, buffer, s0, stack, counts);
    integratePass(in, pk, buffer, counts);
    if (!endPass(in, pk, buffer))
    {
      break;
    }
  }
}

// A tile's packets: culled, or set up, traced and stored.
void renderTile(const RBFFrameInputs& in, const Tile& tile, RBFCounts& counts)
{
  const int side = in.side;
  SampleBuffer buffer(side * side, in.K, in.numFields, in.normalize, in.grads);
  std::vector<std::uint32_t> stack;
  stack.reserve(128);
  Packet pk;
  for (int by = tile.y0; by < tile.y1; by += side)
  {
    for (int bx = tile.x0; bx < tile.x1; bx += side)
    {
      if (cullPacket(in, tile, bx, by, counts))
      {
        continue;
      }
      makePacketRays(in, tile, bx, by, pk);
      counts[Rays] += pk.n;
      ++counts[Packets];
      setUpSamples(in, pk);
      tracePasses(in, pk, buffer, stack, counts);
      for (int r = 0; r < pk.n; ++r)
      {
        const PacketLanes& P = pk.P;
        in.store(pk.pi[r], pk.pj[r], RayAccumulator{ P.cr[r], P.cg[r], P.cb[r], P.ca[r] });
      }
    }
  }
}
}

void renderCoherent(const RBFFrameInputs& in, RBFCounters& counters)
{
  RAYMAPPERS_SIMD_FORWARD(renderCoherent, in, counters);
  forEachTile(in.camera.width(),
    in.camera.height(),
    in.params.tileSize,
    [&](const Tile& tile)
    {
      RBFCounts counts{};
      renderTile(in, tile, counts);
      counters.add(counts);
    });
}

RAYMAPPERS_SIMD_END

} // namespace rbf
} // namespace raymappers
