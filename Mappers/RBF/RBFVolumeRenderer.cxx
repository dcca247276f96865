#include "Mappers/RBF/RBFVolumeRenderer.h"

#include "Mappers/RBF/RBFMethods.h"

#include <algorithm>
#include <cmath>

namespace raymappers
{

namespace rbf
{
namespace
{
// The fields' transfer functions with their opacities corrected for the step dt (StepTable).
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
}

// Shading with the analytic gradient (section 5.4): VTK's Lambert + Phong model (Lighting.h)
// in world space, two-sided, the normal down the gradient.
void Classifier::shadeColor(const float* grad,
  const Vec3f& o,
  const Vec3f& d,
  float t,
  RGBA& c) const
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
  const Vec3d s =
    shadeParts(params->lights, params->material, Vec3d(c.r, c.g, c.b), pw, n, -dw).total();
  c.r = static_cast<float>(std::clamp(s.x, 0.0, 1.0));
  c.g = static_cast<float>(std::clamp(s.y, 0.0, 1.0));
  c.b = static_cast<float>(std::clamp(s.z, 0.0, 1.0));
}

// Classification and front-to-back blending of one sample (section 3.2, Listing 1).
void Classifier::blend(const float* phi,
  const float* weight,
  const float* grad,
  const Vec3f& o,
  const Vec3f& d,
  float t,
  RayAccumulator& acc) const
{
  const std::vector<StepTable>& tf = *tables;
  for (int m = 0; m < numFields; ++m)
  {
    if (weight && !(weight[m] > 0.f))
    {
      continue; // no particle of the field reaches the sample
    }
    const float value = weight ? phi[m] / weight[m] : phi[m];
    if (std::isnan(value))
    {
      continue; // classified as transparent black
    }
    RGBA c = tf[std::min<std::size_t>(m, tf.size() - 1)].lookup(value);
    if (weight)
    {
      c.a = coveredOpacity(c.a, weight[m]);
    }
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

} // namespace rbf

void renderRBF(const RBFScene& scene,
  const View& view,
  const RBFRenderParameters& params,
  Frame& frame,
  RenderStatistics& stats)
{
  const RBFParticles& particles = scene.particles;
  const std::vector<TransferFunctionTable>& fields = scene.fields;
  // Every pixel's colour is written below (or cleared here); the depth stays 1.
  frame.reshape(view.width(), view.height());
  for (const char* name : rbf::RBFCounterNames)
  {
    stats.declareCounter(name);
  }
  const int numFields = std::max(1, particles.numFields);
  stats.setEffect("shading", params.shade);
  stats.setEffect("multi_field", numFields > 1);
  stats.setEffect("early_termination", params.terminationOpacity < 1.0);
  const double dt = params.sampleDistance;
  if (scene.bvh.empty() || fields.empty() || !(dt > 0) || !std::isfinite(dt))
  {
    std::fill(frame.rgba.begin(), frame.rgba.end(), 0.f);
    return;
  }
  const std::vector<rbf::StepTable> tables = rbf::correctForStep(fields, dt);
  const bool emptyIsClear = params.normalizeWeights ||
                            std::all_of(tables.begin(),
                              tables.end(),
                              [](const rbf::StepTable& t) { return t.lookup(0.f).a == 0.f; });
  stats.setEffect("empty_space_skipping", emptyIsClear);
  stats.setEffect("normalized_weights", params.normalizeWeights);
  const rbf::Classifier classifier{ &tables, &params, particles.origin, numFields, emptyIsClear };
  const rbf::RBFFrameInputs in{ particles,
    scene.bvh.nodes(),
    view.camera(),
    params,
    tables,
    classifier,
    view.opaqueDepth(),
    frame,
    static_cast<float>(dt),
    static_cast<float>(params.kappa),
    static_cast<float>(std::max(0.0, params.sigma)),
    static_cast<float>(std::clamp(params.terminationOpacity, 0.0, 1.0)),
    numFields,
    params.shade,
    params.normalizeWeights,
    emptyIsClear,
    params.region.bounded(),
    std::clamp(params.packetSide, 1, MaxRBFPacketSide),
    std::clamp(params.samplesPerPass, 1, MaxRBFSamplesPerPass) };
  rbf::RBFCounters counters;
  if (params.direct)
  {
    rbf::renderDirect(in, counters);
  }
  else
  {
    rbf::renderCoherent(in, counters);
  }
  for (int k = 0; k < rbf::NumRBFCounters; ++k)
  {
    stats.addCounter(rbf::RBFCounterNames[k], counters.totals[k]);
  }
}

} // namespace raymappers
