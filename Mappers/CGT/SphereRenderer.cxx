#include "SphereRenderer.h"

#include "TileScheduler.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace raymappers
{

double refineSphereHit(const Vec3d& org,
  const Vec3d& dir,
  const Vec3d& center,
  double radius,
  double tGuess)
{
  // |f + t d|^2 = r^2 with f = o - c and |d| = 1. With b = f.d and the perpendicular part
  // l = f - b d, the roots are t = -b -+ sqrt(r^2 - |l|^2); this form avoids the
  // cancellation of |f|^2 - r^2 when the sphere is far from the ray origin.
  const Vec3d f = org - center;
  const double b = dot(f, dir);
  const Vec3d l = f - dir * b;
  const double disc = radius * radius - dot(l, l);
  if (disc < 0)
  {
    return tGuess;
  }
  const double s = std::sqrt(disc);
  const double t0 = -b - s;
  const double t1 = -b + s;
  return std::fabs(t0 - tGuess) <= std::fabs(t1 - tGuess) ? t0 : t1;
}

namespace
{
inline Vec3d mul3(const double* m, int stride, const Vec3d& v)
{
  return { m[0] * v.x + m[1] * v.y + m[2] * v.z,
    m[stride] * v.x + m[stride + 1] * v.y + m[stride + 2] * v.z,
    m[2 * stride] * v.x + m[2 * stride + 1] * v.y + m[2 * stride + 2] * v.z };
}
}

namespace
{
// Per-pixel Cranley-Patterson shift in [0, 1)^2 from an integer hash of the pixel index.
void pixelShift(std::uint32_t pixel, double& shift0, double& shift1)
{
  std::uint32_t h = pixel * 0x9E3779B1u;
  h ^= h >> 16;
  h *= 0x85EBCA6Bu;
  h ^= h >> 13;
  shift0 = (h & 0xFFFF) / 65536.0;
  shift1 = (h >> 16) / 65536.0;
}
}

Vec3d shadowTarget(const SphereShading& shading, int a, int b, std::uint32_t pixel)
{
  const int side = std::max(1, shading.shadowSide);
  double s0 = 0.5, s1 = 0.5;
  if (side > 1)
  {
    pixelShift(pixel, s0, s1);
  }
  const double u = (a + s0) / side, v = (b + s1) / side;
  return shading.lightCenter + shading.lightEdgeU * (u - 0.5) + shading.lightEdgeV * (v - 0.5);
}

Vec3d aoDirection(const Vec3d& n, int k, int count, std::uint32_t pixel)
{
  double shift0, shift1;
  pixelShift(pixel, shift0, shift1);
  std::uint32_t bits = static_cast<std::uint32_t>(k);
  bits = (bits << 16) | (bits >> 16);
  bits = ((bits & 0x55555555u) << 1) | ((bits & 0xAAAAAAAAu) >> 1);
  bits = ((bits & 0x33333333u) << 2) | ((bits & 0xCCCCCCCCu) >> 2);
  bits = ((bits & 0x0F0F0F0Fu) << 4) | ((bits & 0xF0F0F0F0u) >> 4);
  bits = ((bits & 0x00FF00FFu) << 8) | ((bits & 0xFF00FF00u) >> 8);
  double u = (k + 0.5) / count + shift0;
  double v = bits * (1.0 / 4294967296.0) + shift1;
  u -= std::floor(u);
  v -= std::floor(v);
  // Cosine-weighted: radius sqrt(u) on the unit disc lifted to the hemisphere.
  const double r = std::sqrt(u), phi = 2.0 * M_PI * v;
  const Vec3d a = std::fabs(n.x) > 0.9 ? Vec3d(0, 1, 0) : Vec3d(1, 0, 0);
  const Vec3d t = normalize(cross(a, n));
  const Vec3d b = cross(n, t);
  return normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * std::sqrt(1.0 - u));
}

void renderSpheres(const SphereSet& spheres,
  const SphereAccelerator& accel,
  int packetSide,
  const RayCamera& camera,
  const SphereShading& shading,
  int tileSize,
  Frame& frame,
  RenderStatistics& stats)
{
  const int width = camera.width();
  const int height = camera.height();
  frame.resize(width, height);
  const bool lit = !shading.lights.empty() || shading.shadowSide > 0;
  stats.setEffect("shading", lit);
  stats.setEffect("specular", lit && shading.material.specular > 0);
  stats.setEffect("range_culling", accel.rangeFilter().count > 0);
  const int aoSamples = std::clamp(shading.aoSamples, 0, MaxPacketRays);
  const bool ao = aoSamples > 0 && shading.aoRadius > 0;
  stats.setEffect("ambient_occlusion", ao);
  const int aoSide = aoSamples <= 16 ? 4 : (aoSamples <= 64 ? 8 : MaxPacketSide);
  const int shadowSide = std::clamp(shading.shadowSide, 0, MaxPacketSide);
  const bool shadows = shadowSide > 0;
  stats.setEffect("soft_shadows", shadows);
  std::vector<Light> areaLight;
  if (shadows)
  {
    Light l;
    l.positional = true;
    l.position = shading.lightCenterWorld;
    l.color = Vec3d(1, 1, 1) * shading.lightIntensity;
    areaLight.push_back(l);
  }
  for (const char* c : { "rays",
         "packets",
         "hits",
         "cells",
         "culled",
         "sphere_tests",
         "range_culled",
         "ao_rays",
         "shadow_rays" })
  {
    stats.declareCounter(c);
  }
  if (accel.empty() || width <= 0 || height <= 0)
  {
    return;
  }
  const int side = std::clamp(packetSide, 1, MaxPacketSide);

  const double* mw = shading.modelToWorld;
  std::atomic<std::int64_t> rays{ 0 }, packets{ 0 }, hits{ 0 }, cells{ 0 }, culled{ 0 }, tests{ 0 },
    rangeCulled{ 0 }, aoRays{ 0 }, shadowRays{ 0 };
  {
    ScopedPhase phase(stats, "trace");
    forEachTile(width,
      height,
      tileSize,
      [&](const Tile& tile)
      {
        std::int64_t tileRays = 0, tilePackets = 0, tileHits = 0, tileAoRays = 0,
                     tileShadowRays = 0;
        RayPacket shadowPacket;
        shadowPacket.side = shadowSide <= 4 ? 4 : (shadowSide <= 8 ? 8 : MaxPacketSide);
        shadowPacket.pixelBlock = false;
        PacketHits shadowHits;
        RayPacket aoPacket;
        aoPacket.side = aoSide;
        aoPacket.pixelBlock = false;
        PacketHits aoHits;
        TraversalCounters counters;
        RayPacket packet;
        packet.side = side;
        PacketHits result;
        for (int by = tile.y0; by < tile.y1; by += side)
        {
          for (int bx = tile.x0; bx < tile.x1; bx += side)
          {
            for (int k = 0; k < side * side; ++k)
            {
              const int i = bx + k % side;
              const int j = by + k / side;
              packet.valid[k] = i < tile.x1 && j < tile.y1;
              if (packet.valid[k])
              {
                packet.rays[k] = camera.pixelRay(i, j);
                ++tileRays;
              }
            }
            ++tilePackets;
            accel.intersect(packet, result, counters);
            for (int k = 0; k < side * side; ++k)
            {
              if (!packet.valid[k] || result.prim[k] == NoHit)
              {
                continue;
              }
              ++tileHits;
              const std::uint32_t id = result.prim[k];
              const Ray& ray = packet.rays[k];
              const Vec3d o(ray.org), d(ray.dir), c(spheres.centers[id]);
              const double r = spheres.radii[id];
              const double t = refineSphereHit(o, d, c, r, result.t[k]);
              const Vec3d pRel = o + d * t;
              Vec3d n = (pRel - c) * (1.0 / r);
              if (dot(n, d) > 0)
              {
                n = -n; // the near plane cuts the sphere: we see its inside
              }
              const std::uint32_t packed = spheres.colors[id];
              const Vec3d base((packed & 0xFF) / 255.0,
                ((packed >> 8) & 0xFF) / 255.0,
                ((packed >> 16) & 0xFF) / 255.0);
              Vec3d color = base;
              if (lit)
              {
                const Vec3d pm = pRel + spheres.origin;
                const Vec3d pw = mul3(mw, 4, pm) + Vec3d(mw[3], mw[7], mw[11]);
                const Vec3d nw = normalize(mul3(shading.normalToWorld, 3, n));
                const Vec3d vw = normalize(-mul3(mw, 4, d));
                color =
                  shade(shadows ? areaLight : shading.lights, shading.material, base, pw, nw, vw);
              }
              const std::size_t idx = frame.index(bx + k % side, by + k / side);
              if (shadows)
              {
                // Shadow rays from just above the surface to the light's samples; the
                // visible share scales the direct (non-ambient) light.
                const Vec3d start = pRel + n * (1e-4 * r);
                const int count = shadowSide * shadowSide;
                for (int a = 0; a < shadowPacket.side * shadowPacket.side; ++a)
                {
                  shadowPacket.valid[a] = a < count;
                  if (a < count)
                  {
                    const Vec3d q = shadowTarget(
                      shading, a % shadowSide, a / shadowSide, static_cast<std::uint32_t>(idx));
                    const Vec3d toLight = q - start;
                    const double dist = length(toLight);
                    Ray& sr = shadowPacket.rays[a];
                    sr.org = Vec3f(start);
                    sr.dir = Vec3f(toLight * (1.0 / dist));
                    sr.tnear = 0.f;
                    sr.tfar = static_cast<float>(dist);
                  }
                }
                accel.intersect(shadowPacket, shadowHits, counters);
                int blocked = 0;
                for (int a = 0; a < count; ++a)
                {
                  blocked += shadowHits.prim[a] != NoHit ? 1 : 0;
                }
                tileShadowRays += count;
                const double visible = 1.0 - static_cast<double>(blocked) / count;
                const Vec3d ambient = base * shading.material.ambient;
                color = ambient + (color - ambient) * visible;
              }
              if (ao)
              {
                // Ambient occlusion: the fraction of hemisphere rays that escape within
                // the radius scales the shaded colour. The rays leave slightly above the
                // surface so they cannot hit their own sphere.
                const Vec3d start = pRel + n * (1e-4 * r);
                for (int a = 0; a < aoSide * aoSide; ++a)
                {
                  aoPacket.valid[a] = a < aoSamples;
                  if (a < aoSamples)
                  {
                    Ray& aoRay = aoPacket.rays[a];
                    aoRay.org = Vec3f(start);
                    aoRay.dir =
                      Vec3f(aoDirection(n, a, aoSamples, static_cast<std::uint32_t>(idx)));
                    aoRay.tnear = 0.f;
                    aoRay.tfar = static_cast<float>(shading.aoRadius);
                  }
                }
                accel.intersect(aoPacket, aoHits, counters);
                int occluded = 0;
                for (int a = 0; a < aoSamples; ++a)
                {
                  occluded += aoHits.prim[a] != NoHit ? 1 : 0;
                }
                tileAoRays += aoSamples;
                color = color * (1.0 - static_cast<double>(occluded) / aoSamples);
              }
              frame.rgba[4 * idx] = static_cast<float>(std::clamp(color.x, 0.0, 1.0));
              frame.rgba[4 * idx + 1] = static_cast<float>(std::clamp(color.y, 0.0, 1.0));
              frame.rgba[4 * idx + 2] = static_cast<float>(std::clamp(color.z, 0.0, 1.0));
              frame.rgba[4 * idx + 3] = 1.f;
              const double depth = camera.depthMap(ray).depthOf(t);
              frame.depth[idx] = static_cast<float>(std::clamp(depth, 0.0, 1.0));
            }
          }
        }
        rays += tileRays;
        packets += tilePackets;
        hits += tileHits;
        cells += counters.cells;
        culled += counters.culled;
        tests += counters.sphereTests;
        rangeCulled += counters.rangeCulled;
        aoRays += tileAoRays;
        shadowRays += tileShadowRays;
      });
  }
  stats.addCounter("rays", rays.load());
  stats.addCounter("packets", packets.load());
  stats.addCounter("hits", hits.load());
  stats.addCounter("cells", cells.load());
  stats.addCounter("culled", culled.load());
  stats.addCounter("sphere_tests", tests.load());
  stats.addCounter("range_culled", rangeCulled.load());
  stats.addCounter("ao_rays", aoRays.load());
  stats.addCounter("shadow_rays", shadowRays.load());
}

} // namespace raymappers
