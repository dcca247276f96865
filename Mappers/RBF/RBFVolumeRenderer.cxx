#include "RBFVolumeRenderer.h"

#include "TileScheduler.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace raymappers
{

namespace
{
// The transfer function of each field with its opacities corrected for the step dt
// (1 - (1 - alpha)^(dt / unit distance)), sampled as the original table.
std::vector<TransferFunctionTable> correctForStep(const std::vector<TransferFunctionTable>& fields,
  double dt)
{
  std::vector<TransferFunctionTable> out;
  for (const TransferFunctionTable& tf : fields)
  {
    const int n = tf.size();
    std::vector<float> rgba(4 * static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k)
    {
      const double v =
        n > 1 ? tf.rangeMin() + (tf.rangeMax() - tf.rangeMin()) * k / (n - 1) : tf.rangeMin();
      const auto c = tf.lookup(v);
      rgba[4 * k] = c[0];
      rgba[4 * k + 1] = c[1];
      rgba[4 * k + 2] = c[2];
      rgba[4 * k + 3] =
        static_cast<float>(TransferFunctionTable::correctOpacity(c[3], dt, tf.unitDistance()));
    }
    out.emplace_back();
    out.back().assign(std::move(rgba), tf.rangeMin(), tf.rangeMax(), tf.unitDistance());
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
  const std::vector<TransferFunctionTable>* tables;
  const RBFRenderParameters* params;
  Vec3d origin;
  int numFields;
  bool emptyIsClear; // every field's opacity at 0 is 0: samples no particle reaches are skipped

  /// Blends the sample at t of ray (o, d) with field values phi[] and field-sum gradient
  /// grad (used only when shading) into acc, sequentially per field (section 5.5).
  void blend(const float* phi,
    const float* grad,
    const Vec3f& o,
    const Vec3f& d,
    float t,
    RayAccumulator& acc) const
  {
    const std::vector<TransferFunctionTable>& tf = *tables;
    for (int m = 0; m < numFields; ++m)
    {
      const TransferFunctionTable& table = tf[std::min<std::size_t>(m, tf.size() - 1)];
      const auto c = table.lookup(phi[m]);
      const float alpha = c[3];
      if (!(alpha > 0.f))
      {
        continue;
      }
      float cr = c[0], cg = c[1], cb = c[2];
      if (params->shade && grad)
      {
        const Vec3d gm(grad[0], grad[1], grad[2]);
        const double len = length(gm);
        if (len > 0 && std::isfinite(len))
        {
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
          const Vec3d s = shade(params->lights, params->material, Vec3d(cr, cg, cb), pw, n, -dw);
          cr = static_cast<float>(std::clamp(s.x, 0.0, 1.0));
          cg = static_cast<float>(std::clamp(s.y, 0.0, 1.0));
          cb = static_cast<float>(std::clamp(s.z, 0.0, 1.0));
        }
      }
      const float w = (1.f - acc.a) * alpha;
      acc.r += w * cr;
      acc.g += w * cg;
      acc.b += w * cb;
      acc.a += w;
    }
  }
};

// Whether the ray o + t d (inv = 1/d per axis) meets the box grown by `grow` for some t in
// [t0, t1]. A zero direction component gives an infinite inverse; the NaN of 0 * inf then
// drops out of the min/max, which keeps the test conservative.
inline bool slabsHit(const Vec3f& o,
  const Vec3f& inv,
  const float lo[3],
  const float hi[3],
  float grow,
  float t0,
  float t1)
{
  for (int a = 0; a < 3; ++a)
  {
    float ta = (lo[a] - grow - o[a]) * inv[a], tb = (hi[a] + grow - o[a]) * inv[a];
    if (ta > tb)
    {
      std::swap(ta, tb);
    }
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
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
  frame.resize(width, height);
  stats.declareCounter("rays");
  stats.declareCounter("packets");
  stats.declareCounter("passes");
  stats.declareCounter("samples");
  stats.declareCounter("node_visits");
  stats.declareCounter("deposits");
  stats.declareCounter("terminated_rays");
  const int numFields = std::max(1, particles.numFields);
  stats.setEffect("shading", params.shade);
  stats.setEffect("multi_field", numFields > 1);
  stats.setEffect("early_termination", params.terminationOpacity < 1.0);
  const double dtD = params.sampleDistance;
  if (bvh.empty() || fields.empty() || !(dtD > 0) || !std::isfinite(dtD))
  {
    return;
  }
  const float dt = static_cast<float>(dtD);
  const float kappa = static_cast<float>(params.kappa);
  const float sigma = static_cast<float>(std::max(0.0, params.sigma));
  const float threshold = static_cast<float>(std::clamp(params.terminationOpacity, 0.0, 1.0));
  const bool grads = params.shade;
  const std::vector<TransferFunctionTable> tables = correctForStep(fields, dtD);
  const bool emptyIsClear = std::all_of(tables.begin(),
    tables.end(),
    [](const TransferFunctionTable& t) { return t.lookup(0.0)[3] == 0.f; });
  stats.setEffect("empty_space_skipping", emptyIsClear);
  const Classifier classifier{ &tables, &params, particles.origin, numFields, emptyIsClear };
  const std::vector<BVHNode>& nodes = bvh.nodes();
  const BVHNode& root = nodes[0];
  const int side = std::clamp(params.packetSide, 1, MaxRBFPacketSide);
  const int K = std::clamp(params.samplesPerPass, 1, MaxRBFSamplesPerPass);

  std::atomic<std::int64_t> rays{ 0 }, packets{ 0 }, passes{ 0 }, samples{ 0 }, visits{ 0 },
    deposits{ 0 }, terminated{ 0 };

  // A ray of the grid: its samples lie in the root's grown box, before opaque geometry.
  auto setUp = [&](int i, int j, Ray& ray, SampleRange& range)
  {
    ray = camera.pixelRay(i, j);
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
    if (clipToBox(ray.org, ray.dir, root.lo, root.hi, sigma * root.rMax, t0, t1))
    {
      range.k0 = static_cast<std::int64_t>(std::ceil(t0 / dt));
      range.k1 = static_cast<std::int64_t>(std::floor(t1 / dt));
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
            Ray ray;
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
        constexpr int MaxRays = MaxRBFPacketSide * MaxRBFPacketSide;
        std::int64_t tileRays = 0, tilePackets = 0, tilePasses = 0, tileSamples = 0, tileVisits = 0,
                     tileDeposits = 0, tileTerminated = 0;
        // The packet's sample buffer: K samples per ray, numFields values each (and the
        // gradient of their sum when shading), reused for every pass.
        std::vector<float> phiBuf(static_cast<std::size_t>(MaxRays) * K * MaxRBFFields);
        std::vector<float> gradBuf(grads ? static_cast<std::size_t>(MaxRays) * K * 3 : 0);
        std::vector<std::uint32_t> stack;
        stack.reserve(128);
        Ray ray[MaxRays];
        Vec3f invDir[MaxRays];
        SampleRange range[MaxRays];
        RayAccumulator acc[MaxRays];
        bool active[MaxRays];
        int pi[MaxRays], pj[MaxRays];
        for (int by = tile.y0; by < tile.y1; by += side)
        {
          for (int bx = tile.x0; bx < tile.x1; bx += side)
          {
            int n = 0;
            std::int64_t kFirst = std::numeric_limits<std::int64_t>::max(),
                         kLast = std::numeric_limits<std::int64_t>::min();
            for (int q = 0; q < side * side; ++q)
            {
              const int i = bx + q % side, j = by + q / side;
              if (i >= tile.x1 || j >= tile.y1)
              {
                continue;
              }
              pi[n] = i;
              pj[n] = j;
              setUp(i, j, ray[n], range[n]);
              acc[n] = RayAccumulator();
              active[n] = range[n].k0 <= range[n].k1;
              if (active[n])
              {
                kFirst = std::min(kFirst, range[n].k0);
                kLast = std::max(kLast, range[n].k1);
              }
              ++n;
            }
            tileRays += n;
            ++tilePackets;
            for (int r = 0; r < n; ++r)
            {
              invDir[r] = Vec3f(1.f / ray[r].dir.x, 1.f / ray[r].dir.y, 1.f / ray[r].dir.z);
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
              // This pass's samples of each ray [passFirst, passLast] (empty for rays not
              // in it) and their t interval.
              std::int64_t passFirst[MaxRays], passLast[MaxRays];
              // The samples of the pass some particle reached, per ray.
              std::int64_t touchedFirst[MaxRays], touchedLast[MaxRays];
              float segT0[MaxRays], segT1[MaxRays];
              for (int r = 0; r < n; ++r)
              {
                const bool in = active[r] && range[r].k0 <= s1;
                passFirst[r] = in ? std::max(s0, range[r].k0) : 1;
                passLast[r] = in ? std::min(s1, range[r].k1) : 0;
                touchedFirst[r] = std::numeric_limits<std::int64_t>::max();
                touchedLast[r] = std::numeric_limits<std::int64_t>::min();
                segT0[r] = in ? static_cast<float>(passFirst[r]) * dt : 1.f;
                segT1[r] = in ? static_cast<float>(passLast[r]) * dt : 0.f;
              }
              // Coherent BVH traversal: a node is entered when any ray's pass interval
              // meets its box grown by sigma r_max.
              stack.assign(1, 0u);
              while (!stack.empty())
              {
                const BVHNode& node = nodes[stack.back()];
                stack.pop_back();
                ++tileVisits;
                const float grow = sigma * node.rMax;
                bool any = false;
                for (int r = 0; r < n && !any; ++r)
                {
                  any = segT0[r] <= segT1[r] &&
                        slabsHit(ray[r].org, invDir[r], node.lo, node.hi, grow, segT0[r], segT1[r]);
                }
                if (!any)
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
                  const float inv2r2 = 0.5f / (rad * rad);
                  const float amp = kappa * particles.values[p];
                  const int field = particles.fields[p];
                  const float gamma = std::exp(-dt * dt * 2.f * inv2r2);
                  for (int r = 0; r < n; ++r)
                  {
                    if (passFirst[r] > passLast[r])
                    {
                      continue;
                    }
                    const Vec3f f = ray[r].org - c;
                    const Vec3f& d = ray[r].dir;
                    const float b = dot(f, d);
                    const Vec3f l = f - d * b;
                    const float h2 = dot(l, l);
                    if (h2 > R * R)
                    {
                      continue;
                    }
                    // The samples inside the support, t = k dt in [-b - w, -b + w], kept
                    // in index space (clamped to the pass and to the ray's own samples).
                    const float w = std::sqrt(R * R - h2);
                    const std::int64_t ka =
                      std::max(passFirst[r], static_cast<std::int64_t>(std::ceil((-b - w) / dt)));
                    const std::int64_t kb =
                      std::min(passLast[r], static_cast<std::int64_t>(std::floor((-b + w) / dt)));
                    if (ka > kb)
                    {
                      continue;
                    }
                    ++tileDeposits;
                    touchedFirst[r] = std::min(touchedFirst[r], ka);
                    touchedLast[r] = std::max(touchedLast[r], kb);
                    const float u0 = static_cast<float>(ka) * dt + b;
                    float g = amp * std::exp(-(u0 * u0 + h2) * inv2r2);
                    float rho = std::exp(-(2.f * u0 * dt + dt * dt) * inv2r2);
                    float* phi =
                      &phiBuf[(static_cast<std::size_t>(r) * K + (ka - s0)) * MaxRBFFields + field];
                    const int count = static_cast<int>(kb - ka + 1);
                    if (!grads)
                    {
                      for (int k = 0; k < count; ++k)
                      {
                        phi[k * MaxRBFFields] += g;
                        g *= rho;
                        rho *= gamma;
                      }
                    }
                    else
                    {
                      float* gr = &gradBuf[(static_cast<std::size_t>(r) * K + (ka - s0)) * 3];
                      const float s = -2.f * inv2r2; // -1 / r^2
                      for (int k = 0; k < count; ++k)
                      {
                        const float t = static_cast<float>(ka + k) * dt;
                        phi[k * MaxRBFFields] += g;
                        gr[3 * k] += s * g * (f.x + t * d.x);
                        gr[3 * k + 1] += s * g * (f.y + t * d.y);
                        gr[3 * k + 2] += s * g * (f.z + t * d.z);
                        g *= rho;
                        rho *= gamma;
                      }
                    }
                  }
                }
              }
              // Integrate the buffer front to back (section 4.1, step 5).
              int stillActive = 0;
              for (int r = 0; r < n; ++r)
              {
                // With a clear empty field only the reached samples can add anything.
                const std::int64_t first = emptyIsClear ? touchedFirst[r] : passFirst[r];
                const std::int64_t last = emptyIsClear ? touchedLast[r] : passLast[r];
                for (std::int64_t k = first; k <= last; ++k)
                {
                  const std::size_t slot = static_cast<std::size_t>(r) * K + (k - s0);
                  ++tileSamples;
                  classifier.blend(&phiBuf[slot * MaxRBFFields],
                    grads ? &gradBuf[slot * 3] : nullptr,
                    ray[r].org,
                    ray[r].dir,
                    static_cast<float>(k) * dt,
                    acc[r]);
                  if (acc[r].a >= threshold)
                  {
                    active[r] = false;
                    ++tileTerminated;
                    break;
                  }
                }
                stillActive += active[r];
                // Leave the buffer zero for the next pass: only the reached samples changed.
                if (touchedFirst[r] <= touchedLast[r])
                {
                  const std::size_t a = static_cast<std::size_t>(r) * K + (touchedFirst[r] - s0);
                  const std::size_t b = static_cast<std::size_t>(r) * K + (touchedLast[r] - s0) + 1;
                  std::fill(
                    phiBuf.begin() + a * MaxRBFFields, phiBuf.begin() + b * MaxRBFFields, 0.f);
                  if (grads)
                  {
                    std::fill(gradBuf.begin() + a * 3, gradBuf.begin() + b * 3, 0.f);
                  }
                }
              }
              if (stillActive == 0)
              {
                break; // every ray of the packet is opaque or past its samples
              }
            }
            for (int r = 0; r < n; ++r)
            {
              store(pi[r], pj[r], acc[r]);
            }
          }
        }
        rays += tileRays;
        packets += tilePackets;
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
}

} // namespace raymappers
