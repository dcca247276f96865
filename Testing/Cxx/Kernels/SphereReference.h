// The brute-force reference of the sphere kernel tests: every sphere against the ray, in
// double precision, independent of any accelerator.
#ifndef RayMappers_Test_SphereReference_h
#define RayMappers_Test_SphereReference_h

#include "Mappers/Common/RayCamera.h"
#include "Mappers/CGT/SphereSet.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace raymappers::test
{

/// The unit roundoff of float, 2^-24.
constexpr double FloatRoundoff = 1.0 / 16777216.0;

/// The largest |centre| + radius of the set (origin-relative): the scale of its float
/// coordinates.
inline double sceneRadius(const SphereSet& s)
{
  double m = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
  {
    m = std::max(m, length(Vec3d(s.centers[i])) + s.radii[i]);
  }
  return m;
}

/// How far from a sphere's silhouette (|d - r|, d the distance from its centre to the ray's
/// line) a float accelerator may decide a ray's hit or miss differently from exact
/// arithmetic on the same float data, for a ray starting at o in a set of scene radius S
/// (u = 2^-24):
///  - the ray-sphere test (f = o - c, b = f.d, p = f - b d, |p|^2 <= r^2): |f| and b are
///    rounded to 4u|f|, p to 6u|f| + u|p|, |p|^2 and r^2 to 3u and u, so the decision is
///    right once |d - r| > 6u |o - c| + 3u r <= 6u (|o| + S) + 3u r;
///  - frustum culling (a side plane from double, rounded to float, at the centre): the
///    plane distance is off by at most 8u (|o| + S), and a sphere the ray hits lies at most
///    d from the plane, so it can be culled only when r - 8u (|o| + S) < d;
///  - the grid's cell range (grid coordinates (x - lower) / h of magnitude |x| + S, about
///    ten roundings between a ray's U and V at a slice face and a centre's cell, times
///    1 + slope, the slope at most 2 for the packets here): at most 30u (|o| + S).
/// Embree's test has the same form (its BVH boxes touch a sphere only at its six extreme
/// points, where the same rounding of the box test applies). The sum, 44u (|o| + S) + 3u r,
/// is bounded by 48u (|o| + S + r): outside this band float and double must agree.
inline double grazingBand(const Ray& ray, double sceneRadius, double r)
{
  return 48 * FloatRoundoff * (length(Vec3d(ray.org)) + sceneRadius + r);
}

/// The exact closest hit of a ray (in double on the float data) and how close it comes to
/// grazing a sphere: margin is min |d - r| / r over the spheres, bands min |d - r| /
/// grazingBand over the spheres that could come before the hit (below 1: the float
/// decision may go either way for such a sphere; one behind the hit cannot change it).
struct ReferenceHit
{
  int id = -1; // closest sphere hit with t in [tnear, tfar], -1 for none
  double t = std::numeric_limits<double>::infinity();
  double margin = std::numeric_limits<double>::infinity();
  double bands = std::numeric_limits<double>::infinity();
  /// How far a float t of the hit sphere may lie from t (the grid's arithmetic: b to
  /// 4u|f|; the half chord w = sqrt(r^2 - d^2) from a w^2 off by E = 2r(6u|f| + ur) + 4ur^2,
  /// so w by at most |w'^2 - w^2| / (w' + w) <= min(sqrt(E), E / w); the sum -b - w to
  /// 2u|t|). Near grazing (w -> 0) the error grows to sqrt(E).
  double tTolerance = 0;
};

inline ReferenceHit exactHit(const SphereSet& s, const Ray& ray, double sceneRadius)
{
  const Vec3d o(ray.org), d(ray.dir);
  const double u = FloatRoundoff;
  const double bandBase = grazingBand(ray, sceneRadius, 0.0);
  ReferenceHit hit;
  std::vector<std::pair<double, double>> grazed; // (bands, nearest t) of spheres in the band
  for (std::size_t i = 0; i < s.size(); ++i)
  {
    const Vec3d c(s.centers[i]);
    const double r = s.radii[i];
    const Vec3d f = o - c;
    const double b = dot(f, d);
    const double dist = length(f - d * b);
    hit.margin = std::min(hit.margin, std::fabs(dist - r) / r);
    const double bands = std::fabs(dist - r) / (bandBase + 48 * u * r);
    if (bands < 1)
    {
      grazed.emplace_back(bands, -b - r);
    }
    if (dist > r)
    {
      continue;
    }
    const double root = std::sqrt(r * r - dist * dist);
    double t = -b - root;
    if (t < ray.tnear)
    {
      t = -b + root;
    }
    if (t >= ray.tnear && t <= ray.tfar && t < hit.t)
    {
      hit.t = t;
      hit.id = static_cast<int>(i);
      const double E = 2 * r * (6 * u * length(f) + u * r) + 4 * u * r * r;
      hit.tTolerance = 4 * u * length(f) + std::min(std::sqrt(E), E / root) + 2 * u * std::fabs(t);
    }
  }
  for (const auto& [bands, tNearest] : grazed)
  {
    if (tNearest <= hit.t)
    {
      hit.bands = std::min(hit.bands, bands);
    }
  }
  return hit;
}

/// Closest hit of the ray over all spheres with t in [tnear, tfar] (the far root when the
/// ray starts inside a sphere). Returns the sphere index or -1; margin is how close the ray
/// comes to grazing any sphere it passes, relative to that sphere's radius (where float and
/// double may disagree).
inline int bruteForce(const SphereSet& s, const Ray& ray, double& tHit, double& margin)
{
  const ReferenceHit hit = exactHit(s, ray, 0.0);
  tHit = hit.t;
  margin = hit.margin;
  return hit.id;
}

}

#endif
