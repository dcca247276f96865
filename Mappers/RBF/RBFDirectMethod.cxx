// The direct method of RBF volume rendering (Knoll et al. 2014, section 3.3, the
// reference): every sample of every ray gathers the particles whose support holds it, one
// BVH point query per sample, then is classified and blended front to back.
#include "Mappers/RBF/RBFMethods.h"

#include "Mappers/Common/TileScheduler.h"
#include "Mappers/Common/SimdTarget.h"

namespace raymappers
{
namespace rbf
{

RAYMAPPERS_SIMD_VARIANTS(renderDirect)

RAYMAPPERS_SIMD_BEGIN

namespace
{
// The fields, their weight sums (normalized weights only) and the gradient at one sample.
struct FieldSample
{
  float phi[MaxRBFFields] = { 0, 0, 0, 0 };
  float weight[MaxRBFFields] = { 0, 0, 0, 0 };
  float grad[3] = { 0, 0, 0 };
};

// Gathering (section 3.3): the field at x, Phi_m(x) = sum of kappa k_i exp(-d^2 / 2r_i^2)
// over the particles of field m whose support sigma r_i holds x (equations 1 and 2), found
// by a point query of the BVH with its nodes grown by sigma r_max; with gradients also
// grad Phi = sum of -phi_i (x - x_i) / r_i^2 (equation 4). With normalized weights also
// W_m(x) = sum of kappa exp(-d^2 / 2r_i^2), and the gradient is that of sum_m W_m.
void gatherField(const RBFFrameInputs& in,
  const Vec3f& x,
  std::vector<std::uint32_t>& stack,
  FieldSample& field,
  RBFCounts& counts)
{
  const RBFParticles& particles = in.particles;
  const std::vector<BVHNode>& nodes = in.nodes;
  const float sigma = in.sigma, kappa = in.kappa;
  const bool grads = in.grads, normalize = in.normalize;
  stack.assign(1, 0u);
  while (!stack.empty())
  {
    const BVHNode& node = nodes[stack.back()];
    stack.pop_back();
    ++counts[NodeVisits];
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
      ++counts[Deposits];
      const float w = kappa * std::exp(-d2 / (2.f * r * r));
      const float v = w * particles.values[p];
      field.phi[particles.fields[p]] += v;
      if (normalize)
      {
        field.weight[particles.fields[p]] += w;
      }
      if (grads)
      {
        const float s = -(normalize ? w : v) / (r * r);
        field.grad[0] += s * e.x;
        field.grad[1] += s * e.y;
        field.grad[2] += s * e.z;
      }
    }
  }
}

// One pixel's ray: its samples t = k dt front to back, each gathered and blended
// (section 3.2, Listing 1), until the opacity reaches the termination threshold.
RayAccumulator castRay(const RBFFrameInputs& in,
  int i,
  int j,
  std::vector<std::uint32_t>& stack,
  RBFCounts& counts)
{
  const Ray ray = in.camera.pixelRay(i, j);
  const SampleRange range = in.sampleRange(i, j, ray);
  const float dt = in.dt;
  RayAccumulator acc;
  for (std::int64_t k = range.k0; k <= range.k1; ++k)
  {
    const float t = static_cast<float>(k) * dt;
    const Vec3f x = ray.org + ray.dir * t;
    FieldSample field;
    gatherField(in, x, stack, field, counts);
    // (With normalized weights a particle adds W > 0 even where its height is 0.)
    const float* reached = in.normalize ? field.weight : field.phi;
    if (in.emptyIsClear && reached[0] == 0.f && reached[1] == 0.f && reached[2] == 0.f &&
        reached[3] == 0.f)
    {
      continue; // no particle reaches this sample
    }
    ++counts[Samples];
    in.classifier.blend(field.phi,
      in.normalize ? field.weight : nullptr,
      in.grads ? field.grad : nullptr,
      ray.org,
      ray.dir,
      t,
      acc);
    if (acc.a >= in.threshold)
    {
      ++counts[TerminatedRays];
      break;
    }
  }
  return acc;
}
}

void renderDirect(const RBFFrameInputs& in, RBFCounters& counters)
{
  RAYMAPPERS_SIMD_FORWARD(renderDirect, in, counters);
  forEachTile(in.camera.width(),
    in.camera.height(),
    in.params.tileSize,
    [&](const Tile& tile)
    {
      RBFCounts counts{};
      std::vector<std::uint32_t> stack;
      stack.reserve(128);
      for (int j = tile.y0; j < tile.y1; ++j)
      {
        for (int i = tile.x0; i < tile.x1; ++i)
        {
          ++counts[Rays];
          in.store(i, j, castRay(in, i, j, stack, counts));
        }
      }
      counters.add(counts);
    });
}

RAYMAPPERS_SIMD_END

} // namespace rbf
} // namespace raymappers
