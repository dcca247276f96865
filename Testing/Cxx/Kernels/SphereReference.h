// The brute-force reference of the sphere kernel tests: every sphere against the ray, in
// double precision, independent of any accelerator.
#ifndef RayMappers_Test_SphereReference_h
#define RayMappers_Test_SphereReference_h

#include "RayCamera.h"
#include "SphereSet.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace raymappers::test
{

/// Closest hit of the ray over all spheres with t in [tnear, tfar] (the far root when the
/// ray starts inside a sphere). Returns the sphere index or -1; margin is how close the ray
/// comes to grazing any sphere it passes, relative to that sphere's radius (where float and
/// double may disagree).
inline int bruteForce(const SphereSet& s, const Ray& ray, double& tHit, double& margin)
{
  const Vec3d o(ray.org), d(ray.dir);
  int best = -1;
  tHit = std::numeric_limits<double>::infinity();
  margin = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.size(); ++i)
  {
    const Vec3d c(s.centers[i]);
    const double r = s.radii[i];
    const Vec3d f = o - c;
    const double b = dot(f, d);
    const double dist = length(f - d * b);
    margin = std::min(margin, std::fabs(dist - r) / r);
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
    if (t >= ray.tnear && t <= ray.tfar && t < tHit)
    {
      tHit = t;
      best = static_cast<int>(i);
    }
  }
  return best;
}

}

#endif
