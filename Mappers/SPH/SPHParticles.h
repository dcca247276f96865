// The particles of an SPH field (Limper 2012, equation 2.4): particle i at x_i carries the
// quantity Q_i, the volume V_i (= m_i / rho_i) and the support radius H_i of its kernel;
//   A(x) = sum_i Q_i V_i W(|x - x_i|, H_i)    (the unnormalized field, equation 3.15)
//   B(x) = sum_i V_i W(|x - x_i|, H_i)        (the sum of weights)
//   Q(x) = A(x) / B(x)                        (the normalized field, equation 3.14).
// Centres are stored relative to an origin (float precision near the data). Invalid input
// (non-finite centre, quantity or volume; support not finite or not positive; volume
// negative) is dropped while building and counted.
#ifndef RayMappers_SPHParticles_h
#define RayMappers_SPHParticles_h

#include "Mappers/Common/ParticleInput.h"
#include "Mappers/Common/Vec3.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace raymappers
{

struct SPHParticles
{
  Vec3d origin;
  std::vector<Vec3f> centers; // relative to origin
  std::vector<float> support; // H_i > 0
  std::vector<float> qv;      // Q_i V_i
  std::vector<float> v;       // V_i >= 0
  float maxSupport = 0.f;
  float minQ = 0.f, maxQ = 0.f;  // range of the quantity (the normalized field stays in it)
  double medianVolume = 0.0;     // for the reference weight sum (equation 3.16)
  double medianSupport = 0.0;
  float minSupport = 0.f;
  std::size_t skippedNonFinite = 0; // NaN/Inf centre, or Q, V or QV not finite as float
  std::size_t skippedBadSupport = 0; // support NaN/Inf, zero, negative or above MaxLength
  std::size_t skippedBadVolume = 0;  // negative volume

  std::size_t size() const { return centers.size(); }
};

/// Builds `out` from n input points in parallel: point(i) -> Vec3d, support(i) -> double
/// (H_i), quantity(i) -> double (Q_i), volume(i) -> double (V_i); called from several
/// threads.
template<typename PointFn, typename SupportFn, typename QuantityFn, typename VolumeFn>
void buildSPHParticles(std::size_t n,
  const Vec3d& origin,
  PointFn point,
  SupportFn support,
  QuantityFn quantity,
  VolumeFn volume,
  SPHParticles& out)
{
  out.origin = origin;
  out.centers.resize(n);
  out.support.resize(n);
  out.qv.resize(n);
  out.v.resize(n);
  std::vector<float> q(n);
  std::vector<unsigned char> negativeVolume(n, 0);
  const ParticleTally tally = tallyParticles(n,
    [&](std::size_t i, ParticleTally& t)
    {
      const Vec3d p = point(i);
      const double Q = quantity(i);
      const double V = volume(i);
      float H = t.admit(
        p, finiteAsFloat(Q) && finiteAsFloat(V) && finiteAsFloat(Q * V), isFinite(p) ? support(i) : 0.0);
      if (H > 0.f && V < 0.0)
      {
        negativeVolume[i] = 1;
        H = 0.f;
      }
      out.centers[i] = H > 0.f ? Vec3f(p - origin) : Vec3f();
      out.support[i] = H;
      out.qv[i] = H > 0.f ? static_cast<float>(Q * V) : 0.f;
      out.v[i] = H > 0.f ? static_cast<float>(V) : 0.f;
      q[i] = H > 0.f ? static_cast<float>(Q) : 0.f;
    });
  out.skippedNonFinite = tally.nonFinite;
  out.skippedBadSupport = tally.badRadius;
  out.skippedBadVolume = 0;
  for (const unsigned char b : negativeVolume)
  {
    out.skippedBadVolume += b;
  }
  out.maxSupport = tally.maxRadius;
  // (Entry i is read before any write reaches it: writes go to kept <= i.)
  compactStable(
    n,
    [&](std::size_t i) { return out.support[i] > 0.f; },
    out.centers,
    out.support,
    out.qv,
    out.v,
    q);
  if (q.empty())
  {
    out.minQ = out.maxQ = 0.f;
    out.medianVolume = out.medianSupport = 0.0;
    out.minSupport = 0.f;
    return;
  }
  const auto [lo, hi] = std::minmax_element(q.begin(), q.end());
  out.minQ = *lo;
  out.maxQ = *hi;
  std::vector<float> tmp(out.v);
  std::nth_element(tmp.begin(), tmp.begin() + tmp.size() / 2, tmp.end());
  out.medianVolume = tmp[tmp.size() / 2];
  tmp = out.support;
  out.minSupport = *std::min_element(tmp.begin(), tmp.end());
  std::nth_element(tmp.begin(), tmp.begin() + tmp.size() / 2, tmp.end());
  out.medianSupport = tmp[tmp.size() / 2];
}

} // namespace raymappers

#endif
