// What the two methods of RBFVolumeRenderer share (internal to Mappers/RBF): the frame's
// inputs as renderRBF sets them up, the sample range of a pixel's ray (section 4.1, steps
// 1-2: the root's box grown by sigma r_max, opaque geometry, the region), the transfer
// functions corrected for the step dt, and the classification and front-to-back blending of
// one sample (section 3.2, Listing 1). The direct method (RBFDirectMethod.cxx) gathers
// each sample's particles (section 3.3); the coherent method (RBFCoherentMethod.cxx)
// scatters each particle into a packet's sample buffer (section 4).
#ifndef RayMappers_RBFMethods_h
#define RayMappers_RBFMethods_h

#include "Mappers/RBF/RBFVolumeRenderer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <vector>

namespace raymappers
{
namespace rbf
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

// The opacity of a step with normalized weights (RBFVolumeRenderer.h): the step's opacity
// alpha of the value, for the coverage c = min(1, W) of the medium, 1 - (1 - alpha)^c
// (0 where W = 0).
inline float coveredOpacity(float alpha, float w)
{
  return w >= 1.f ? alpha : (w > 0.f ? 1.f - std::pow(1.f - alpha, w) : 0.f);
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
  // Every field's opacity at 0 is 0, or the weights are normalized: samples no particle
  // reaches are skipped.
  bool emptyIsClear;

  /// Blends the sample at t of ray (o, d) with field values phi[] (with normalized weights
  /// also the fields' weight sums weight[], else null) and gradient grad (used only when
  /// shading) into acc, sequentially per field (section 5.5). One out-of-line function
  /// (RBFVolumeRenderer.cxx) for both methods, with the shading inlined in it.
  void blend(const float* phi,
    const float* weight,
    const float* grad,
    const Vec3f& o,
    const Vec3f& d,
    float t,
    RayAccumulator& acc) const;

  /// Replaces the colour of c with its shaded colour at the sample.
  void shadeColor(const float* grad, const Vec3f& o, const Vec3f& d, float t, RGBA& c) const;
};

// The sample range [k0, k1] of a ray: t in [tEnter, tExit] with t = k dt.
struct SampleRange
{
  std::int64_t k0 = 1, k1 = 0; // empty when k0 > k1
};

// Where a ray meets the box grown by `grow`, within [t0, t1]; false when it misses.
inline bool clipToBox(const Vec3f& o,
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

// The inputs of one frame, set up once by renderRBF for either method.
struct RBFFrameInputs
{
  const RBFParticles& particles;
  const std::vector<BVHNode>& nodes; // not empty
  const RayCamera& camera;
  const RBFRenderParameters& params;
  const std::vector<StepTable>& tables; // per field, corrected for dt
  const Classifier& classifier;
  const float* opaqueDepth; // window depth per pixel, or null
  Frame& frame;
  float dt, kappa, sigma, threshold;
  int numFields;
  bool grads;         // gradients accumulated (shading)
  bool normalize;     // params.normalizeWeights: weight sums accumulated beside phi
  bool emptyIsClear;  // see Classifier
  bool regionBounded; // params.region clips the rays
  int side;           // packets of side x side rays
  int K;              // samples per pass

  /// The samples of pixel (i, j)'s ray (made by the caller: one by one, or a packet's in
  /// SIMD lanes): those in the root's box grown by sigma r_max (and the region), before
  /// opaque geometry.
  SampleRange sampleRange(int i, int j, const Ray& ray) const
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
    SampleRange range;
    const BVHNode& root = nodes[0];
    if (!clipToBox(ray.org, ray.dir, root.lo, root.hi, sigma * root.rMax, t0, t1))
    {
      return range;
    }
    if (!regionBounded)
    {
      range.k0 = static_cast<std::int64_t>(std::ceil(t0 / dt));
      range.k1 = static_cast<std::int64_t>(std::floor(t1 / dt));
      return range;
    }
    // The region's samples: k dt in [entry, exit), so that neighbouring regions never
    // both take a sample on their common face.
    double r0 = t0, r1 = t1;
    if (params.region.clip(Vec3d(ray.org), Vec3d(ray.dir), particles.origin, r0, r1))
    {
      range.k0 = static_cast<std::int64_t>(std::ceil(r0 / dt));
      range.k1 = static_cast<std::int64_t>(std::ceil(r1 / dt)) - 1;
    }
    return range;
  }

  /// Writes a ray's premultiplied colour and opacity to pixel (i, j).
  void store(int i, int j, const RayAccumulator& acc) const
  {
    float* px = &frame.rgba[4 * frame.index(i, j)];
    px[0] = acc.r;
    px[1] = acc.g;
    px[2] = acc.b;
    px[3] = acc.a;
  }
};

// The frame's counters, indexed as their statistics' names in RBFCounterNames: a tile's
// counts (RBFCounts) are summed into the frame's (RBFCounters).
enum RBFCounter
{
  Rays,
  Packets,
  Passes,
  Samples,
  NodeVisits,
  Deposits,
  TerminatedRays,
  CulledPackets,
  StaggeredBlocks,
  NumRBFCounters
};

constexpr const char* RBFCounterNames[NumRBFCounters] = { "rays",
  "packets",
  "passes",
  "samples",
  "node_visits",
  "deposits",
  "terminated_rays",
  "culled_packets",
  "staggered_blocks" };

using RBFCounts = std::array<std::int64_t, NumRBFCounters>;

struct RBFCounters
{
  std::array<std::atomic<std::int64_t>, NumRBFCounters> totals{};

  /// Adds a tile's counts.
  void add(const RBFCounts& c)
  {
    for (int k = 0; k < NumRBFCounters; ++k)
    {
      totals[k] += c[k];
    }
  }
};

/// The direct method (section 3.3): every sample gathers its particles by a BVH point query.
void renderDirect(const RBFFrameInputs& in, RBFCounters& counters);

/// The coherent method (section 4): packets, a BVH walk per pass of K samples, the sample
/// buffer integrated front to back.
void renderCoherent(const RBFFrameInputs& in, RBFCounters& counters);

} // namespace rbf
} // namespace raymappers

#endif
