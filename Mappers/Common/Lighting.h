// Lights and the Lambert + Phong shading model of VTK's OpenGL mappers, in world space.
//
// For a surface point with unit normal n, unit direction to the eye v and, per light, unit
// direction to the light l and light colour c (diffuse colour times intensity):
//   colour = Ka * C + sum_lights [ Kd * max(0, n.l) * c * C
//                                 + Ks * max(0, r.v)^p * c * S ]   (only where n.l > 0)
// with r = 2 (n.l) n - l the reflected light direction, C the surface colour, S the
// specular colour, Ka/Kd/Ks/p the property's ambient, diffuse, specular, specular power.
// Positional lights attenuate by 1/(a0 + a1 d + a2 d^2) and are cut off outside their cone.
#ifndef RayMappers_Lighting_h
#define RayMappers_Lighting_h

#include "Mappers/Common/Vec3.h"

#include <vector>

namespace raymappers
{

struct Light
{
  Vec3d color{ 1, 1, 1 };      // diffuse colour times intensity
  Vec3d direction{ 0, 0, -1 }; // unit vector the light travels along (directional lights)
  bool positional = false;
  Vec3d position;            // positional lights
  double coneAngleDeg = 180; // >= 90: no cone
  Vec3d attenuation{ 1, 0, 0 };
};

struct Material
{
  double ambient = 0.0;
  double diffuse = 1.0;
  double specular = 0.0;
  double specularPower = 1.0;
  Vec3d specularColor{ 1, 1, 1 };
};

/// The two terms of the model above: `diffuse` (the ambient and diffuse terms, which carry the
/// surface colour C) and `specular` (the specular terms, which carry S).
struct ShadedParts
{
  Vec3d diffuse, specular;
  /// The shaded colour: their sum.
  Vec3d total() const { return diffuse + specular; }
};

/// The terms of the shaded colour (not clamped) of a surface point p (world) with unit normal
/// n and unit direction toEye (minus the ray direction, which serves perspective and parallel
/// views).
ShadedParts shadeParts(const std::vector<Light>& lights,
  const Material& m,
  const Vec3d& surfaceColor,
  const Vec3d& p,
  const Vec3d& n,
  const Vec3d& toEye);

} // namespace raymappers

#endif
