#include "RBFVolumeRenderer.h"

#include "FastExp.h"
#include "TileScheduler.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace raymappers
{

namespace
{
// The transfer function of a field with its opacities corrected for the step dt
// (1 - (1 - alpha)^(dt / unit distance)), sampled as the original table and looked up in
// float as TransferFunctionTable::lookup does in double (linear interpolation between the
// samples, clamped to the range).
struct RGBA
{
  float r, g, b, a;
};

struct StepTable
{
  // n >= 2 samples: a constant table holds its sample twice, an empty one transparent black.
  std::vector<float> rgba;
  float lo = 0.f;
  float scale = 0.f; // (n - 1) / (hi - lo), 0 for a constant table

  int size() const { return static_cast<int>(rgba.size() / 4); }

  /// The RGBA of value v (not NaN).
  RGBA lookup(float v) const { return lookupIn(rgba.data(), size(), v); }

  /// The lookup on this table's n samples at `table`, written for SIMD lanes (selects,
  /// integer indices, a value returned: what the vectorizer turns into gathers).
  RGBA lookupIn(const float* table, int n, float v) const
  {
    const float xMax = static_cast<float>(n - 1);
    float x = (v - lo) * scale;
    x = x < 0.f ? 0.f : x;
    x = x > xMax ? xMax : x;
    std::int32_t k = static_cast<std::int32_t>(x);
    k = k > n - 2 ? n - 2 : k;
    const float f = x - static_cast<float>(k);
    const std::int32_t j = 4 * k;
    return { table[j] + f * (table[j + 4] - table[j]),
      table[j + 1] + f * (table[j + 5] - table[j + 1]),
      table[j + 2] + f * (table[j + 6] - table[j + 2]),
      table[j + 3] + f * (table[j + 7] - table[j + 3]) };
  }
};

std::vector<StepTable> correctForStep(const std::vector<TransferFunctionTable>& fields, double dt)
{
  std::vector<StepTable> out;
  for (const TransferFunctionTable& tf : fields)
  {
    const int n = tf.size();
    StepTable t;
    t.rgba.assign(4 * static_cast<std::size_t>(std::max(n, 2)), 0.f);
    for (int k = 0; k < n; ++k)
    {
      const double v =
        n > 1 ? tf.rangeMin() + (tf.rangeMax() - tf.rangeMin()) * k / (n - 1) : tf.rangeMin();
      const auto c = tf.lookup(v);
      t.rgba[4 * k] = c[0];
      t.rgba[4 * k + 1] = c[1];
      t.rgba[4 * k + 2] = c[2];
      t.rgba[4 * k + 3] =
        static_cast<float>(TransferFunctionTable::correctOpacity(c[3], dt, tf.unitDistance()));
    }
    if (n == 1)
    {
      std::copy(t.rgba.begin(), t.rgba.begin() + 4, t.rgba.begin() + 4);
    }
    t.lo = static_cast<float>(tf.rangeMin());
    t.scale = n > 1 && tf.rangeMax() > tf.rangeMin()
                ? static_cast<float>((n - 1) / (tf.rangeMax() - tf.rangeMin()))
                : 0.f;
    out.push_back(std::move(t));
  }
  return out;
}

inline Vec3d mul3(const double* m, int stride, const Vec3d& v)
{
  return { m[0] * v.x + m[1] * v.y + m[2] * v.z,
    m[stride] * v.x + m[stride + 1] * v.y + m[stride + 2] * v.z,
    m[2 * stride] * v.x + m[2 * stride + 1] * v.y + m[2 * stride + 2] * v.z };
}

// Front-to-back state of one ray.
struct RayAccumulator
{
  float r = 0, g = 0, b = 0, a = 0;
};

// Everything a sample's classification needs.
struct Classifier
{
  const std::vector<StepTable>* tables; // per field (missing fields use the last table)
  const RBFRenderParameters* params;
  Vec3d origin;
  int numFields;
  bool emptyIsClear; // every field's opacity at 0 is 0: samples no particle reaches are skipped

  /// Blends the sample at t of ray (o, d) with field values phi[] and field-sum gradient
  /// grad (used only when shading) into acc, sequentially per field (section 5.5).
  inline void blend(const float* phi,
    const float* grad,
    const Vec3f& o,
    const Vec3f& d,
    float t,
    RayAccumulator& acc) const
  {
    const std::vector<StepTable>& tf = *tables;
    for (int m = 0; m < numFields; ++m)
    {
      if (std::isnan(phi[m]))
      {
        continue; // classified as transparent black
      }
      RGBA c = tf[std::min<std::size_t>(m, tf.size() - 1)].lookup(phi[m]);
      if (!(c.a > 0.f))
      {
        continue;
      }
      if (params->shade && grad)
      {
        shadeColor(grad, o, d, t, c);
      }
      const float w = (1.f - acc.a) * c.a;
      acc.r += w * c.r;
      acc.g += w * c.g;
      acc.b += w * c.b;
      acc.a += w;
    }
  }

  /// Replaces the colour of c with its shaded colour at the sample (a separate function, so
  /// that the unshaded blend stays small enough to inline).
  void shadeColor(const float* grad, const Vec3f& o, const Vec3f& d, float t, RGBA& c) const
  {
    const Vec3d gm(grad[0], grad[1], grad[2]);
    const double len = length(gm);
    if (!(len > 0) || !std::isfinite(len))
    {
      return;
    }
    // The surface normal points down the gradient (out of the denser region).
    Vec3d n = mul3(params->normalToWorld, 3, gm * (-1.0 / len));
    const double nl = length(n);
    n = n * (1.0 / nl);
    const Vec3d pRel = Vec3d(o) + Vec3d(d) * static_cast<double>(t);
    const Vec3d pModel = pRel + origin;
    const double* M = params->modelToWorld;
    const Vec3d pw(M[0] * pModel.x + M[1] * pModel.y + M[2] * pModel.z + M[3],
      M[4] * pModel.x + M[5] * pModel.y + M[6] * pModel.z + M[7],
      M[8] * pModel.x + M[9] * pModel.y + M[10] * pModel.z + M[11]);
    Vec3d dw = mul3(params->modelToWorld, 4, Vec3d(d));
    dw = dw * (1.0 / length(dw));
    if (dot(n, dw) > 0)
    {
      n = -n; // two-sided: light the side facing the viewer
    }
    const Vec3d s = shade(params->lights, params->material, Vec3d(c.r, c.g, c.b), pw, n, -dw);
    c.r = static_cast<float>(std::clamp(s.x, 0.0, 1.0));
    c.g = static_cast<float>(std::clamp(s.y, 0.0, 1.0));
    c.b = static_cast<float>(std::clamp(s.z, 0.0, 1.0));
  }
};

// The rays of a packet in structure-of-arrays form, so that a particle or a node is tested
// against all of them in SIMD lanes (section 5.3: "a packet is simply a varying Ray").
// Lanes are padded to a multiple of 16 (the widest SIMD width); a padding lane, like a ray
// without samples in the pass, has an empty interval and an empty sample range.
constexpr int MaxPacketRays = MaxRBFPacketSide * MaxRBFPacketSide;
static_assert(MaxPacketRays <= 64, "a packet's rays fit a 64-bit mask");
constexpr int LaneMultiple = 16;

struct PacketLanes
{
  alignas(64) float ox[MaxPacketRays];
  alignas(64) float oy[MaxPacketRays];
  alignas(64) float oz[MaxPacketRays];
  alignas(64) float dx[MaxPacketRays];
  alignas(64) float dy[MaxPacketRays];
  alignas(64) float dz[MaxPacketRays];
  alignas(64) float ix[MaxPacketRays]; // 1 / d per axis
  alignas(64) float iy[MaxPacketRays];
  alignas(64) float iz[MaxPacketRays];
  // This pass: the t interval of the ray's samples (empty: t0 > t1) and their indices
  // relative to the pass's first sample, [first, last] (empty: first > last).
  alignas(64) float t0[MaxPacketRays];
  alignas(64) float t1[MaxPacketRays];
  alignas(64) std::int32_t first[MaxPacketRays];
  alignas(64) std::int32_t last[MaxPacketRays];
  // For the particle being deposited: b = f.d, h^2, and the samples in its support
  // [ka, kb] (pass-relative, empty when the ray misses the support).
  alignas(64) float b[MaxPacketRays];
  alignas(64) float h2[MaxPacketRays];
  alignas(64) std::int32_t ka[MaxPacketRays];
  alignas(64) std::int32_t kb[MaxPacketRays];
  // The pass's samples some particle reached, [touchedFirst, touchedLast] (empty: first >
  // last).
  alignas(64) std::int32_t touchedFirst[MaxPacketRays];
  alignas(64) std::int32_t touchedLast[MaxPacketRays];
  // Front-to-back state (premultiplied colour and opacity), and for the pass's
  // integration the samples to blend [from, to] and whether the ray is still open.
  alignas(64) float cr[MaxPacketRays];
  alignas(64) float cg[MaxPacketRays];
  alignas(64) float cb[MaxPacketRays];
  alignas(64) float ca[MaxPacketRays];
  alignas(64) std::int32_t from[MaxPacketRays];
  alignas(64) std::int32_t to[MaxPacketRays];
  alignas(64) std::int32_t open[MaxPacketRays];
};

// Integrates a pass's buffer front to back for the n rays of the packet, without shading
// (section 5.3: "all samples for the packet are integrated, iterating using a uniform t
// variable spanning minimum and maximum sample positions"): ray r blends its samples
// [from[r], to[r]] while open[r], with the arithmetic of Classifier::blend, and closes when
// its opacity reaches the threshold. The loop runs per SIMD block of LaneMultiple rays, and
// a block with no open ray costs nothing. Step i of a block blends, in each ray, either the
// block's sample kLo + i (the uniform t over the block's span) or the ray's own sample
// from[r] + i (read by a gather): the latter when the rays' spans are staggered, as where
// they cross a thin layer obliquely, so that the block takes as many steps as its longest
// ray has samples instead of its whole span. The buffer holds the value of field m at
// sample k of ray r at base[m fieldStride + k sampleStride + r]. Returns the samples
// blended; the rays closed are added to `terminated`, the staggered blocks to
// `staggeredBlocks`.
std::int64_t integrateLanes(const std::vector<StepTable>& tables,
  int numFields,
  const float* base,
  std::ptrdiff_t fieldStride,
  std::ptrdiff_t sampleStride,
  int n,
  float threshold,
  PacketLanes& P,
  std::int64_t& terminated,
  std::int64_t& staggeredBlocks)
{
  std::int64_t blended = 0, closed = 0;
  for (int b0 = 0; b0 < n; b0 += LaneMultiple)
  {
    // (The block's lanes past n are padding, closed with empty ranges.)
    const int b1 = std::min(n, b0 + LaneMultiple);
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
    const bool staggered = kHi - kLo + 1 > longest;
    staggeredBlocks += staggered;
    const std::int32_t steps = staggered ? longest : kHi - kLo + 1;
    // Step i's sample of lane r is first[r] + i.
    alignas(64) std::int32_t first[LaneMultiple];
    for (int r = 0; r < LaneMultiple; ++r)
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
        const std::int32_t rowStride = static_cast<std::int32_t>(sampleStride);
        const std::int32_t lastRow = static_cast<std::int32_t>(fieldStride / sampleStride) - 1;
#pragma omp simd
        for (int r = 0; r < LaneMultiple; ++r)
        {
          const int q = b0 + r;
          const std::int32_t k = first[r] + i;
          // (Read in every lane, at a row of the buffer: a gather the loop can vectorize.)
          const float v = field[(k < lastRow ? k : lastRow) * rowStride + r];
          const bool on = (P.open[q] != 0) & (k >= P.from[q]) & (k <= P.to[q]);
          const bool valid = on & (v == v); // off, or NaN: transparent black
          const RGBA c = table.lookupIn(rgba, size, valid ? v : 0.f);
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
      for (int r = 0; r < LaneMultiple; ++r)
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

// Whether some ray of the packet meets the box grown by `grow` within its pass interval
// (a SIMD block of LaneMultiple rays at a time, all of its lanes at once: a block costs
// about one ray; the first block with a hit answers).
inline bool packetMeetsBox(const PacketLanes& P,
  int lanes,
  const float lo[3],
  const float hi[3],
  float grow)
{
  const float lx = lo[0] - grow, ly = lo[1] - grow, lz = lo[2] - grow;
  const float hx = hi[0] + grow, hy = hi[1] + grow, hz = hi[2] + grow;
  for (int b0 = 0; b0 < lanes; b0 += LaneMultiple)
  {
    int hit = 0;
#pragma omp simd reduction(| : hit)
    for (int r = b0; r < b0 + LaneMultiple; ++r)
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

// The sample range [k0, k1] of a ray: t in [tEnter, tExit] with t = k dt.
struct SampleRange
{
  std::int64_t k0 = 1, k1 = 0; // empty when k0 > k1
};

// Where a ray meets the box grown by `grow`, within [t0, t1]; false when it misses.
bool clipToBox(const Vec3f& o,
  const Vec3f& d,
  const float lo[3],
  const float hi[3],
  float grow,
  float& t0,
  float& t1)
{
  for (int a = 0; a < 3; ++a)
  {
    const float l = lo[a] - grow, h = hi[a] + grow;
    if (d[a] == 0.f)
    {
      if (o[a] < l || o[a] > h)
      {
        return false;
      }
      continue;
    }
    const float inv = 1.f / d[a];
    float ta = (l - o[a]) * inv, tb = (h - o[a]) * inv;
    if (ta > tb)
    {
      std::swap(ta, tb);
    }
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}
}

void renderRBF(const RBFParticles& particles,
  const ParticleBVH& bvh,
  const RayCamera& camera,
  const RBFRenderParameters& params,
  const std::vector<TransferFunctionTable>& fields,
  const float* opaqueDepth,
  Frame& frame,
  RenderStatistics& stats)
{
  const int width = camera.width(), height = camera.height();
  // Every pixel's colour is written below (or cleared here); the depth stays 1.
  frame.reshape(width, height);
  stats.declareCounter("rays");
  stats.declareCounter("packets");
  stats.declareCounter("passes");
  stats.declareCounter("samples");
  stats.declareCounter("node_visits");
  stats.declareCounter("deposits");
  stats.declareCounter("terminated_rays");
  stats.declareCounter("culled_packets");
  stats.declareCounter("staggered_blocks");
  const int numFields = std::max(1, particles.numFields);
  stats.setEffect("shading", params.shade);
  stats.setEffect("multi_field", numFields > 1);
  stats.setEffect("early_termination", params.terminationOpacity < 1.0);
  const double dtD = params.sampleDistance;
  if (bvh.empty() || fields.empty() || !(dtD > 0) || !std::isfinite(dtD))
  {
    std::fill(frame.rgba.begin(), frame.rgba.end(), 0.f);
    return;
  }
  const float dt = static_cast<float>(dtD);
  const float kappa = static_cast<float>(params.kappa);
  const float sigma = static_cast<float>(std::max(0.0, params.sigma));
  const float threshold = static_cast<float>(std::clamp(params.terminationOpacity, 0.0, 1.0));
  const bool grads = params.shade;
  const std::vector<StepTable> tables = correctForStep(fields, dtD);
  const bool emptyIsClear = std::all_of(
    tables.begin(), tables.end(), [](const StepTable& t) { return t.lookup(0.f).a == 0.f; });
  stats.setEffect("empty_space_skipping", emptyIsClear);
  const Classifier classifier{ &tables, &params, particles.origin, numFields, emptyIsClear };
  const std::vector<BVHNode>& nodes = bvh.nodes();
  const BVHNode& root = nodes[0];
  const int side = std::clamp(params.packetSide, 1, MaxRBFPacketSide);
  const int K = std::clamp(params.samplesPerPass, 1, MaxRBFSamplesPerPass);

  std::atomic<std::int64_t> rays{ 0 }, packets{ 0 }, passes{ 0 }, samples{ 0 }, visits{ 0 },
    deposits{ 0 }, terminated{ 0 }, culled{ 0 }, staggered{ 0 };

  const bool regionBounded = params.region.bounded();
  // A ray of the grid: its samples lie in the root's grown box (and the region), before
  // opaque geometry.
  // (The ray of pixel (i, j) made by the caller: one by one, or a packet's in SIMD lanes.)
  auto setUp = [&](int i, int j, const Ray& ray, SampleRange& range)
  {
    float t0 = ray.tnear, t1 = ray.tfar;
    if (opaqueDepth)
    {
      const float depth = opaqueDepth[frame.index(i, j)];
      if (depth < 1.f)
      {
        t1 = std::min(
          t1, static_cast<float>(camera.depthMap(ray).distanceOf(static_cast<double>(depth))));
      }
    }
    range = SampleRange();
    if (!clipToBox(ray.org, ray.dir, root.lo, root.hi, sigma * root.rMax, t0, t1))
    {
      return;
    }
    if (!regionBounded)
    {
      range.k0 = static_cast<std::int64_t>(std::ceil(t0 / dt));
      range.k1 = static_cast<std::int64_t>(std::floor(t1 / dt));
      return;
    }
    // The region's samples: k dt in [entry, exit), so that neighbouring regions never
    // both take a sample on their common face.
    double r0 = t0, r1 = t1;
    if (params.region.clip(Vec3d(ray.org), Vec3d(ray.dir), particles.origin, r0, r1))
    {
      range.k0 = static_cast<std::int64_t>(std::ceil(r0 / dt));
      range.k1 = static_cast<std::int64_t>(std::ceil(r1 / dt)) - 1;
    }
  };

  auto store = [&](int i, int j, const RayAccumulator& acc)
  {
    float* px = &frame.rgba[4 * frame.index(i, j)];
    px[0] = acc.r;
    px[1] = acc.g;
    px[2] = acc.b;
    px[3] = acc.a;
  };

  if (params.direct)
  {
    // The direct method: one BVH point query per sample.
    forEachTile(width,
      height,
      params.tileSize,
      [&](const Tile& tile)
      {
        std::int64_t tileRays = 0, tileSamples = 0, tileVisits = 0, tileDeposits = 0,
                     tileTerminated = 0;
        std::vector<std::uint32_t> stack;
        stack.reserve(128);
        for (int j = tile.y0; j < tile.y1; ++j)
        {
          for (int i = tile.x0; i < tile.x1; ++i)
          {
            ++tileRays;
            const Ray ray = camera.pixelRay(i, j);
            SampleRange range;
            setUp(i, j, ray, range);
            RayAccumulator acc;
            for (std::int64_t k = range.k0; k <= range.k1; ++k)
            {
              const float t = static_cast<float>(k) * dt;
              const Vec3f x = ray.org + ray.dir * t;
              float phi[MaxRBFFields] = { 0, 0, 0, 0 };
              float grad[3] = { 0, 0, 0 };
              stack.assign(1, 0u);
              while (!stack.empty())
              {
                const BVHNode& node = nodes[stack.back()];
                stack.pop_back();
                ++tileVisits;
                const float g = sigma * node.rMax;
                if (x.x < node.lo[0] - g || x.x > node.hi[0] + g || x.y < node.lo[1] - g ||
                    x.y > node.hi[1] + g || x.z < node.lo[2] - g || x.z > node.hi[2] + g)
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
                  const Vec3f e = x - particles.centers[p];
                  const float d2 = dot(e, e);
                  const float r = particles.radii[p];
                  if (d2 > sigma * sigma * r * r)
                  {
                    continue;
                  }
                  ++tileDeposits;
                  const float v = kappa * particles.values[p] * std::exp(-d2 / (2.f * r * r));
                  phi[particles.fields[p]] += v;
                  if (grads)
                  {
                    const float s = -v / (r * r);
                    grad[0] += s * e.x;
                    grad[1] += s * e.y;
                    grad[2] += s * e.z;
                  }
                }
              }
              if (emptyIsClear && phi[0] == 0.f && phi[1] == 0.f && phi[2] == 0.f && phi[3] == 0.f)
              {
                continue; // no particle reaches this sample
              }
              ++tileSamples;
              classifier.blend(phi, grads ? grad : nullptr, ray.org, ray.dir, t, acc);
              if (acc.a >= threshold)
              {
                ++tileTerminated;
                break;
              }
            }
            store(i, j, acc);
          }
        }
        rays += tileRays;
        samples += tileSamples;
        visits += tileVisits;
        deposits += tileDeposits;
        terminated += tileTerminated;
      });
  }
  else
  {
    forEachTile(width,
      height,
      params.tileSize,
      [&](const Tile& tile)
      {
        std::int64_t tileRays = 0, tilePackets = 0, tilePasses = 0, tileSamples = 0, tileVisits = 0,
                     tileDeposits = 0, tileTerminated = 0, tileCulled = 0, tileStaggered = 0;
        const int maxRays = side * side;
        // The packet's sample buffer, reused for every pass: per field (and per gradient
        // component when shading) K rows, one per sample of the pass, of the packet's
        // rays side by side, so that a particle deposits one sample into a SIMD block of
        // rays at a time and the integration reads a block's samples in one load.
        const int laneStride = (maxRays + LaneMultiple - 1) / LaneMultiple * LaneMultiple;
        const std::ptrdiff_t fieldStride = static_cast<std::ptrdiff_t>(K) * laneStride;
        std::vector<float> phiBuf(static_cast<std::size_t>(numFields) * fieldStride);
        std::vector<float> gradBuf(grads ? static_cast<std::size_t>(3) * fieldStride : 0);
        auto phiAt = [&](int m, std::int32_t k)
        { return &phiBuf[static_cast<std::size_t>(m * fieldStride + k * laneStride)]; };
        auto gradAt = [&](int axis, std::int32_t k)
        { return &gradBuf[static_cast<std::size_t>(axis * fieldStride + k * laneStride)]; };
        std::vector<float> tPass(K); // t of the pass's samples
        std::vector<std::uint32_t> stack;
        stack.reserve(128);
        PacketLanes P;
        Ray ray[MaxPacketRays];
        SampleRange range[MaxPacketRays];
        bool active[MaxPacketRays];
        int pi[MaxPacketRays], pj[MaxPacketRays];
        float tFar[MaxPacketRays];
        for (int by = tile.y0; by < tile.y1; by += side)
        {
          for (int bx = tile.x0; bx < tile.x1; bx += side)
          {
            // A packet whose rays cannot reach the root's grown box takes no ray set-up.
            const int i1 = std::min(bx + side, tile.x1) - 1, j1 = std::min(by + side, tile.y1) - 1;
            const Ray corners[4] = { camera.pixelRay(bx, by), camera.pixelRay(i1, by),
              camera.pixelRay(i1, j1), camera.pixelRay(bx, j1) };
            if (!packetMayMeetBox(corners, root.lo, root.hi, sigma * root.rMax))
            {
              for (int j = by; j <= j1; ++j)
              {
                for (int i = bx; i <= i1; ++i)
                {
                  store(i, j, RayAccumulator{});
                }
              }
              tileRays += (i1 - bx + 1) * (j1 - by + 1);
              ++tilePackets;
              ++tileCulled;
              continue;
            }
            int n = 0;
            for (int q = 0; q < side * side; ++q)
            {
              const int i = bx + q % side, j = by + q / side;
              if (i < tile.x1 && j < tile.y1)
              {
                pi[n] = i;
                pj[n] = j;
                ++n;
              }
            }
            tileRays += n;
            ++tilePackets;
            const int lanes = (n + LaneMultiple - 1) / LaneMultiple * LaneMultiple;
            // The packet's rays in SIMD lanes (a padding lane: origin and direction 0).
            float* const org[3] = { P.ox, P.oy, P.oz };
            float* const dir[3] = { P.dx, P.dy, P.dz };
            camera.pixelRays(pi, pj, n, org, dir, tFar);
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
            std::int64_t kFirst = std::numeric_limits<std::int64_t>::max(),
                         kLast = std::numeric_limits<std::int64_t>::min();
            for (int r = 0; r < n; ++r)
            {
              ray[r].org = Vec3f(P.ox[r], P.oy[r], P.oz[r]);
              ray[r].dir = Vec3f(P.dx[r], P.dy[r], P.dz[r]);
              ray[r].tnear = 0.f;
              ray[r].tfar = tFar[r];
              setUp(pi[r], pj[r], ray[r], range[r]);
              P.cr[r] = P.cg[r] = P.cb[r] = P.ca[r] = 0.f;
              active[r] = range[r].k0 <= range[r].k1;
              if (active[r])
              {
                kFirst = std::min(kFirst, range[r].k0);
                kLast = std::max(kLast, range[r].k1);
              }
            }
            for (int r = 0; r < lanes; ++r)
            {
              const bool real = r < n;
              P.t0[r] = 1.f;
              P.t1[r] = 0.f;
              P.first[r] = K;
              P.last[r] = -1;
              if (!real)
              {
                // A padding lane stays closed, transparent and without samples.
                P.cr[r] = P.cg[r] = P.cb[r] = P.ca[r] = 0.f;
                P.open[r] = 0;
                P.from[r] = 0;
                P.to[r] = -1;
              }
            }
            // Passes of K samples (section 4.2) until every ray is opaque or done.
            for (std::int64_t s0 = kFirst; s0 <= kLast; s0 += K)
            {
              const std::int64_t s1 = std::min(kLast, s0 + K - 1);
              int live = 0;
              for (int r = 0; r < n; ++r)
              {
                active[r] = active[r] && range[r].k1 >= s0;
                live += active[r] && range[r].k0 <= s1;
              }
              if (live == 0)
              {
                if (std::none_of(active, active + n, [](bool a) { return a; }))
                {
                  break;
                }
                continue;
              }
              ++tilePasses;
              // This pass's samples of each ray and their t interval; the samples of the
              // pass some particle reached, per ray.
              for (int r = 0; r < n; ++r)
              {
                const bool in = active[r] && range[r].k0 <= s1;
                const std::int64_t passFirst = std::max(s0, range[r].k0);
                const std::int64_t passLast = std::min(s1, range[r].k1);
                P.first[r] = in ? static_cast<std::int32_t>(passFirst - s0) : K;
                P.last[r] = in ? static_cast<std::int32_t>(passLast - s0) : -1;
                P.t0[r] = in ? static_cast<float>(passFirst) * dt : 1.f;
                P.t1[r] = in ? static_cast<float>(passLast) * dt : 0.f;
              }
              for (int r = 0; r < lanes; ++r)
              {
                P.touchedFirst[r] = K;
                P.touchedLast[r] = -1;
              }
              for (int k = 0; k < K; ++k)
              {
                tPass[k] = static_cast<float>(s0 + k) * dt;
              }
              // (Locals, not the captured references: read through a reference, the SIMD
              // loops below would gather them from memory in every lane.)
              const float invStep = 1.f / dt, s0f = static_cast<float>(s0);
              const std::int32_t slots = K;
              const float lastSlot = static_cast<float>(K);
              // Coherent BVH traversal: a node is entered when any ray's pass interval
              // meets its box grown by sigma r_max.
              stack.assign(1, 0u);
              while (!stack.empty())
              {
                const BVHNode& node = nodes[stack.back()];
                stack.pop_back();
                ++tileVisits;
                if (!packetMeetsBox(P, lanes, node.lo, node.hi, sigma * node.rMax))
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
                  const Vec3f c = particles.centers[p];
                  const float rad = particles.radii[p];
                  const float R = sigma * rad;
                  const float R2 = R * R;
                  const float inv2r2 = 0.5f / (rad * rad);
                  // Every ray at once, in two steps. First only h^2: whether some ray
                  // passes within the support at all (where the particles are small on
                  // the screen, most particles of a leaf the packet reaches meet none of
                  // its rays). Then the samples inside the support, t = k dt in
                  // [-b - w, -b + w], w = sqrt(R^2 - h^2), as indices relative to the pass
                  // (clamped to the pass and the ray's samples). (t / dt - s0 is taken as
                  // t (1 / dt) - s0: a sample within an ulp of the support's edge may fall
                  // either way, as its own t = k dt may.)
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
                  if (!near)
                  {
                    continue;
                  }
                  int any = 0;
#pragma omp simd reduction(| : any)
                  for (int r = 0; r < lanes; ++r)
                  {
                    const float b = P.b[r], h2 = P.h2[r];
                    const float w = std::sqrt(h2 < R2 ? R2 - h2 : 0.f);
                    float qa = (-b - w) * invStep - s0f, qb = (-b + w) * invStep - s0f;
                    // (Clamped for the conversion to int, with one select each: a nested
                    // one keeps the loop from vectorizing.)
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
                  if (!any)
                  {
                    continue;
                  }
                  const float amp = kappa * particles.values[p];
                  const int field = particles.fields[p];
                  // Deposit into each SIMD block of rays the support reaches, sample by
                  // sample over the block's samples in the support: the Gaussian
                  // g = kappa k_i exp(-(u^2 + h^2) / 2r^2) with u = t + b (section 3.1) in
                  // the rays whose own support samples hold k, zero in the others.
                  const float s = -2.f * inv2r2;
                  for (int b0 = 0; b0 < lanes; b0 += LaneMultiple)
                  {
                    std::int32_t kLo = slots, kHi = -1;
                    int reached = 0;
#pragma omp simd reduction(min : kLo) reduction(max : kHi) reduction(+ : reached)
                    for (int r = b0; r < b0 + LaneMultiple; ++r)
                    {
                      const bool in = P.ka[r] <= P.kb[r];
                      kLo = std::min(kLo, P.ka[r]);
                      kHi = std::max(kHi, P.kb[r]);
                      reached += in;
                      const std::int32_t first = P.touchedFirst[r], last = P.touchedLast[r];
                      P.touchedFirst[r] = in && P.ka[r] < first ? P.ka[r] : first;
                      P.touchedLast[r] = in && P.kb[r] > last ? P.kb[r] : last;
                    }
                    if (reached == 0)
                    {
                      continue;
                    }
                    tileDeposits += reached;
                    for (std::int32_t k = kLo; k <= kHi; ++k)
                    {
                      const float t = tPass[k];
                      float* phi = phiAt(field, k);
                      if (!grads)
                      {
#pragma omp simd
                        for (int r = b0; r < b0 + LaneMultiple; ++r)
                        {
                          const float u = t + P.b[r];
                          const float g = amp * fastExp(-(u * u + P.h2[r]) * inv2r2);
                          phi[r] += (k >= P.ka[r]) & (k <= P.kb[r]) ? g : 0.f;
                        }
                        continue;
                      }
                      // Equation 4: grad phi = -phi (x - x_i) / r^2, x - x_i = f + t d.
                      float *gx = gradAt(0, k), *gy = gradAt(1, k), *gz = gradAt(2, k);
#pragma omp simd
                      for (int r = b0; r < b0 + LaneMultiple; ++r)
                      {
                        const float u = t + P.b[r];
                        const bool on = (k >= P.ka[r]) & (k <= P.kb[r]);
                        const float g = on ? amp * fastExp(-(u * u + P.h2[r]) * inv2r2) : 0.f;
                        phi[r] += g;
                        gx[r] += s * g * (P.ox[r] - c.x + t * P.dx[r]);
                        gy[r] += s * g * (P.oy[r] - c.y + t * P.dy[r]);
                        gz[r] += s * g * (P.oz[r] - c.z + t * P.dz[r]);
                      }
                    }
                  }
                }
              }
              // Integrate the buffer front to back (section 4.1, step 5).
              for (int r = 0; r < n; ++r)
              {
                // With a clear empty field only the reached samples can add anything.
                P.from[r] = emptyIsClear ? P.touchedFirst[r] : P.first[r];
                P.to[r] = emptyIsClear ? P.touchedLast[r] : P.last[r];
                P.open[r] = active[r];
              }
              if (!grads)
              {
                tileSamples +=
                  integrateLanes(tables, numFields, phiBuf.data(), fieldStride, laneStride, n,
                    threshold, P, tileTerminated, tileStaggered);
              }
              else
              {
                // Shading: ray by ray, through the classifier.
                for (int r = 0; r < n; ++r)
                {
                  RayAccumulator sum{ P.cr[r], P.cg[r], P.cb[r], P.ca[r] };
                  for (std::int32_t k = P.from[r]; P.open[r] && k <= P.to[r]; ++k)
                  {
                    float phi[MaxRBFFields] = { 0, 0, 0, 0 };
                    for (int m = 0; m < numFields; ++m)
                    {
                      phi[m] = phiAt(m, k)[r];
                    }
                    const float grad[3] = { gradAt(0, k)[r], gradAt(1, k)[r], gradAt(2, k)[r] };
                    ++tileSamples;
                    classifier.blend(phi, grad, ray[r].org, ray[r].dir, tPass[k], sum);
                    if (sum.a >= threshold)
                    {
                      P.open[r] = 0;
                      ++tileTerminated;
                    }
                  }
                  P.cr[r] = sum.r;
                  P.cg[r] = sum.g;
                  P.cb[r] = sum.b;
                  P.ca[r] = sum.a;
                }
              }
              int stillActive = 0;
              std::int32_t clearFirst = K, clearLast = -1;
              for (int r = 0; r < n; ++r)
              {
                active[r] = P.open[r] != 0;
                stillActive += active[r];
                clearFirst = std::min(clearFirst, P.touchedFirst[r]);
                clearLast = std::max(clearLast, P.touchedLast[r]);
              }
              // Leave the buffer zero for the next pass: only the reached samples changed.
              if (clearFirst <= clearLast)
              {
                const std::size_t rows = static_cast<std::size_t>(clearLast - clearFirst + 1);
                for (int m = 0; m < numFields; ++m)
                {
                  std::fill_n(phiAt(m, clearFirst), rows * laneStride, 0.f);
                }
                for (int axis = 0; grads && axis < 3; ++axis)
                {
                  std::fill_n(gradAt(axis, clearFirst), rows * laneStride, 0.f);
                }
              }
              if (stillActive == 0)
              {
                break; // every ray of the packet is opaque or past its samples
              }
            }
            for (int r = 0; r < n; ++r)
            {
              store(pi[r], pj[r], RayAccumulator{ P.cr[r], P.cg[r], P.cb[r], P.ca[r] });
            }
          }
        }
        rays += tileRays;
        packets += tilePackets;
        culled += tileCulled;
        staggered += tileStaggered;
        passes += tilePasses;
        samples += tileSamples;
        visits += tileVisits;
        deposits += tileDeposits;
        terminated += tileTerminated;
      });
  }
  stats.addCounter("rays", rays);
  stats.addCounter("packets", packets);
  stats.addCounter("passes", passes);
  stats.addCounter("samples", samples);
  stats.addCounter("node_visits", visits);
  stats.addCounter("deposits", deposits);
  stats.addCounter("terminated_rays", terminated);
  stats.addCounter("culled_packets", culled);
  stats.addCounter("staggered_blocks", staggered);
}

} // namespace raymappers
