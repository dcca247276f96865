#include "Mappers/Common/Lighting.h"

#include <algorithm>
#include <cmath>

namespace raymappers
{

ShadedParts shadeParts(const std::vector<Light>& lights,
  const Material& m,
  const Vec3d& surfaceColor,
  const Vec3d& p,
  const Vec3d& n,
  const Vec3d& toEye)
{
  ShadedParts result{ surfaceColor * m.ambient, Vec3d() };
  for (const Light& light : lights)
  {
    Vec3d l;
    double attenuation = 1.0;
    if (light.positional)
    {
      const Vec3d d = light.position - p;
      const double dist = length(d);
      if (!(dist > 0))
      {
        continue;
      }
      l = d * (1.0 / dist);
      const double cosToAxis = -dot(l, light.direction);
      if (light.coneAngleDeg < 90.0 && cosToAxis < std::cos(light.coneAngleDeg * M_PI / 180.0))
      {
        continue;
      }
      const Vec3d& a = light.attenuation;
      const double denom = a.x + a.y * dist + a.z * dist * dist;
      attenuation = denom > 0 ? 1.0 / denom : 1.0;
    }
    else
    {
      l = -light.direction;
    }
    const double nl = dot(n, l);
    if (nl <= 0)
    {
      continue;
    }
    const Vec3d c = light.color * attenuation;
    result.diffuse += c * surfaceColor * (m.diffuse * nl);
    if (m.specular > 0)
    {
      const Vec3d r = n * (2.0 * nl) - l;
      const double rv = std::max(0.0, dot(r, toEye));
      result.specular += c * m.specularColor * (m.specular * std::pow(rv, m.specularPower));
    }
  }
  return result;
}

} // namespace raymappers
