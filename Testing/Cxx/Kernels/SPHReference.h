// A brute-force SPH volume ray caster for the tests: every pixel's ray takes the same
// sample depths as the renderer (the grid's depth steps, with the same jitter pattern),
// and at every sample sums, in double, all particles whose support the pixel's ray meets
// (no grid, no slabs, no spans); the gradient of A comes from central differences of A,
// not from the kernels' derivatives.
// Classification follows the renderer's specification (SPHVolumeRenderer.h). Taking the
// renderer's sample depths, jitter and kernels, it checks the acceleration (grid, slabs,
// spans), not the sampling: Testing/References' SPH reference (its own kernels and uniform
// converged sampling) checks the picture end to end (Rendering.TestSPHVolumeMapperReference).
#ifndef RayMappers_Test_SPHReference_h
#define RayMappers_Test_SPHReference_h

#include "Mappers/SPH/SPHVolumeRenderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace raymappers::test
{

struct ReferenceField
{
  double A = 0, B = 0;
};

/// A and B at x summed over the particles `near` (the others' supports miss x).
inline ReferenceField sumParticles(const SPHParticles& P,
  SPHKernel kernel,
  const Vec3d& x,
  const std::vector<std::size_t>& near)
{
  ReferenceField f;
  for (const std::size_t i : near)
  {
    const double w = kernelValue(kernel, length(x - Vec3d(P.centers[i])), P.support[i]);
    f.A += double(P.qv[i]) * w;
    f.B += double(P.v[i]) * w;
  }
  return f;
}

/// The particles whose support comes within `margin` of the line a + z b.
inline std::vector<std::size_t> particlesNearLine(const SPHParticles& P,
  const Vec3d& a,
  const Vec3d& b,
  double margin)
{
  std::vector<std::size_t> near;
  const Vec3d u = normalize(b);
  for (std::size_t i = 0; i < P.size(); ++i)
  {
    const Vec3d f = Vec3d(P.centers[i]) - a;
    const double d = length(f - u * dot(f, u));
    if (d < P.support[i] + margin)
    {
      near.push_back(i);
    }
  }
  return near;
}

/// Premultiplied RGBA per pixel (row 0 at the bottom).
inline std::vector<double> renderReference(const SPHParticles& P,
  const ViewRays& rays,
  const DepthSteps& steps,
  const SPHRenderParameters& params,
  const TransferFunctionTable& tf,
  const float* opaqueDepth)
{
  const int W = rays.width(), H = rays.height();
  std::vector<double> out(4 * static_cast<std::size_t>(W) * H, 0.0);
  // Extinction at the table's nodes, interpolated linearly (as specified).
  const int n = std::max(2, tf.size());
  const double lo = tf.rangeMin(), hi = tf.rangeMax();
  std::vector<std::array<double, 4>> nodes(n);
  for (int k = 0; k < n; ++k)
  {
    const auto c = tf.lookup(lo + (hi > lo ? k * (hi - lo) / (n - 1) : 0.0));
    const double a = std::clamp(double(c[3]), 0.0, 1.0 - 1e-7);
    nodes[k] = { c[0], c[1], c[2], -std::log1p(-a) / tf.unitDistance() };
  }
  auto classify = [&](double v)
  {
    const double x = std::clamp(hi > lo ? (v - lo) * (n - 1) / (hi - lo) : 0.0, 0.0, n - 1.0);
    const int k = std::min(static_cast<int>(x), n - 2);
    const double f = x - k;
    std::array<double, 4> e;
    for (int c = 0; c < 4; ++c)
    {
      e[c] = nodes[k][c] + f * (nodes[k + 1][c] - nodes[k][c]);
    }
    return e;
  };
  const bool normalized = params.normalization == SPHNormalization::Normalized;
  const double wMax = params.referenceWeightSum;
  const double contourTau =
    -std::log1p(-std::min(params.contourOpacity, 1.0 - 1e-7)) / tf.unitDistance();
  for (int py = 0; py < H; ++py)
  {
    for (int px = 0; px < W; ++px)
    {
      const double cx = px + 0.5, cy = py + 0.5;
      double zStop = std::numeric_limits<double>::infinity();
      if (opaqueDepth && opaqueDepth[static_cast<std::size_t>(py) * W + px] < 1.f)
      {
        zStop = rays.zetaOfWindowDepth(cx, cy, opaqueDepth[static_cast<std::size_t>(py) * W + px]);
      }
      const double j = params.jitter ? sphJitterOffset(px, py) : 0.5;
      const double dirLength = length(rays.direction(cx, cy));
      // (The gradient's central differences reach 1e-4 H_max off the ray.)
      const double hstep = 1e-4 * P.maxSupport;
      const std::vector<std::size_t> near =
        particlesNearLine(P, rays.start(cx, cy), rays.direction(cx, cy), 2 * hstep);
      double r = 0, g = 0, b = 0, a = 0;
      for (int k = 0; k < steps.samples() && a < params.terminationOpacity; ++k)
      {
        const double zk = steps.zeta(k), zk1 = steps.zeta(k + 1);
        const double z = zk + j * (zk1 - zk);
        if (z >= zStop)
        {
          break;
        }
        const Vec3d x = rays.pointAt(cx, cy, z);
        const ReferenceField f = sumParticles(P, params.kernel, x, near);
        bool hasValue;
        double value;
        if (normalized)
        {
          hasValue = f.B > 0;
          value = hasValue ? std::clamp(f.A / f.B, double(P.minQ), double(P.maxQ)) : 0.0;
        }
        else
        {
          hasValue = f.A != 0;
          value = params.normalization == SPHNormalization::PseudoNormalized ? f.A / wMax : f.A;
        }
        const bool contour = params.contour && f.B > 0;
        if (!hasValue && !contour)
        {
          continue;
        }
        const double len = (std::min(zk1, zStop) - zk) * dirLength;
        double cr = 0, cg = 0, cb = 0, alpha = 0;
        if (hasValue)
        {
          const auto e = classify(value);
          alpha = -std::expm1(-e[3] * len);
          cr = e[0];
          cg = e[1];
          cb = e[2];
          if (params.shade && alpha > 0)
          {
            Vec3d grad;
            for (int c = 0; c < 3; ++c)
            {
              Vec3d dx;
              dx[c] = hstep;
              grad[c] = (sumParticles(P, params.kernel, x + dx, near).A -
                          sumParticles(P, params.kernel, x - dx, near).A) /
                        (2 * hstep);
            }
            if (length(grad) > 0)
            {
              // Identity model transform in the tests: world = origin + x.
              Vec3d nrm = normalize(grad) * -1.0;
              const Vec3d dir = normalize(rays.direction(cx, cy));
              if (dot(nrm, dir) > 0)
              {
                nrm = -nrm;
              }
              const Vec3d s = shadeParts(
                params.lights, params.material, Vec3d(cr, cg, cb), x + P.origin, nrm, -dir)
                                .total();
              cr = std::clamp(s.x, 0.0, 1.0);
              cg = std::clamp(s.y, 0.0, 1.0);
              cb = std::clamp(s.z, 0.0, 1.0);
            }
          }
        }
        double pr = alpha * cr, pg = alpha * cg, pb = alpha * cb;
        if (contour)
        {
          const double I = std::clamp(1.0 - f.B / wMax, 0.0, 1.0);
          const double ac = -std::expm1(-contourTau * I * len);
          pr += ac * params.contourColor[0];
          pg += ac * params.contourColor[1];
          pb += ac * params.contourColor[2];
          alpha = std::min(1.0, alpha + ac);
        }
        const double t = 1 - a;
        r += t * pr;
        g += t * pg;
        b += t * pb;
        a += t * alpha;
      }
      double* o = &out[4 * (static_cast<std::size_t>(py) * W + px)];
      o[0] = r;
      o[1] = g;
      o[2] = b;
      o[3] = a;
    }
  }
  return out;
}

}

#endif
