#include "Mappers/CGT/SphereRenderer.h"

#include "Mappers/CGT/SphereOcclusion.h"
#include "Mappers/Common/TileScheduler.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>

namespace raymappers
{

SphereRoots sphereRoots(const Vec3d& org, const Vec3d& dir, const Vec3d& center, double radius)
{
  const Vec3d f = org - center;
  const double b = dot(f, dir);
  const Vec3d l = f - dir * b;
  const double disc = radius * radius - dot(l, l);
  const double s = std::sqrt(std::max(disc, 0.0));
  return { disc, -b - s, -b + s };
}

double refineSphereHit(const Vec3d& org,
  const Vec3d& dir,
  const Vec3d& center,
  double radius,
  double tGuess)
{
  const SphereRoots roots = sphereRoots(org, dir, center, radius);
  if (roots.disc < 0)
  {
    return tGuess;
  }
  return std::fabs(roots.t0 - tGuess) <= std::fabs(roots.t1 - tGuess) ? roots.t0 : roots.t1;
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

AoBasis aoBasis(const Vec3d& n, std::uint32_t pixel)
{
  AoBasis basis;
  double shift1 = 0;
  pixelShift(pixel, basis.shift0, shift1);
  basis.cosShift1 = std::cos(2.0 * M_PI * shift1);
  basis.sinShift1 = std::sin(2.0 * M_PI * shift1);
  const Vec3d a = std::fabs(n.x) > 0.9 ? Vec3d(0, 1, 0) : Vec3d(1, 0, 0);
  basis.t = normalize(cross(a, n));
  basis.b = cross(n, basis.t);
  basis.n = n;
  return basis;
}

AoSample aoSample(int k, int count)
{
  std::uint32_t bits = static_cast<std::uint32_t>(k);
  bits = (bits << 16) | (bits >> 16);
  bits = ((bits & 0x55555555u) << 1) | ((bits & 0xAAAAAAAAu) >> 1);
  bits = ((bits & 0x33333333u) << 2) | ((bits & 0xCCCCCCCCu) >> 2);
  bits = ((bits & 0x0F0F0F0Fu) << 4) | ((bits & 0xF0F0F0F0u) >> 4);
  bits = ((bits & 0x00FF00FFu) << 8) | ((bits & 0xFF00FF00u) >> 8);
  const double phi = 2.0 * M_PI * (bits * (1.0 / 4294967296.0));
  return { (k + 0.5) / count, std::cos(phi), std::sin(phi) };
}

Vec3d aoDirectionIn(const AoBasis& basis, const AoSample& sample)
{
  double u = sample.u + basis.shift0;
  u -= std::floor(u);
  // The angle 2 pi (v + s1) by its sum; cosine-weighted: radius sqrt(u) on the unit disc
  // lifted to the hemisphere.
  const double c = sample.cosV * basis.cosShift1 - sample.sinV * basis.sinShift1;
  const double s = sample.sinV * basis.cosShift1 + sample.cosV * basis.sinShift1;
  const double r = std::sqrt(u);
  return normalize(basis.t * (r * c) + basis.b * (r * s) + basis.n * std::sqrt(1.0 - u));
}

Vec3d aoDirection(const Vec3d& n, int k, int count, std::uint32_t pixel)
{
  return aoDirectionIn(aoBasis(n, pixel), aoSample(k, count));
}

namespace
{
// What every tile of a frame reads: the spheres, the accelerator, the camera, the shading
// and the effects it asks for.
struct SphereFrame
{
  const SphereSet& spheres;
  const SphereAccelerator& accel;
  const RayCamera& camera;
  const SphereShading& shading;
  Frame& frame;
  int side;                     // primary packets of side x side rays
  bool lit;                     // lights or the area light shade the spheres
  int shadowSide;               // shadow rays per hit: shadowSide^2 (0: none)
  int aoSamples;                // ambient-occlusion directions per hit, N (0: none)
  int aoSide;                   // the ambient-occlusion packet's side
  int aoBegin, aoEnd;           // this frame's directions [k0, k1) of the N
  const AoSample* aoPattern;    // aoSample(k, N) for k in [0, N)
  std::uint16_t* aoUnoccluded;  // U per pixel (AoAccumulation), or null: one shot
  const SphereOcclusion& occlusion;
  std::vector<Light> areaLight; // the area light's centre as the direct light (shadows)
  bool translucent;             // front-to-back compositing (see the header)
  double opacity;               // every sphere's opacity factor
  const float* opaqueDepth;     // window depth per pixel where translucent rays stop, or null
  const RegionBox& region;      // the primary rays' box (SphereScene)

  double opacityOf(std::uint32_t id) const
  {
    return spheres.opacities.empty() ? opacity : opacity * spheres.opacities[id];
  }
};

// The counts of a tile, summed into the frame's counters.
struct SphereCounts
{
  std::int64_t rays = 0, packets = 0, hits = 0, aoRays = 0, shadowRays = 0;
  std::int64_t layers = 0, queries = 0, terminated = 0;
  TraversalCounters traversal;
};

// A primary hit: the exact point (refined in double), its normal facing the ray, the
// sphere's colour and the shaded colour.
struct SurfacePoint
{
  double t;
  Vec3d pRel; // origin-relative
  Vec3d n;
  double r;
  Vec3d base, color;
};

// Shading of a primary hit (VTK's Lambert + Phong model, Lighting.h): the
// hit refined in double, its normal, the colour of the sphere lit in world space (by the
// area light's centre when there are soft shadows).
SurfacePoint shadeHit(const SphereFrame& f, const Ray& ray, std::uint32_t id, float tHit)
{
  const SphereSet& spheres = f.spheres;
  const double* mw = f.shading.modelToWorld;
  SurfacePoint sp;
  const Vec3d o(ray.org), d(ray.dir), c(spheres.centers[id]);
  sp.r = spheres.radii[id];
  sp.t = refineSphereHit(o, d, c, sp.r, tHit);
  sp.pRel = o + d * sp.t;
  sp.n = (sp.pRel - c) * (1.0 / sp.r);
  if (dot(sp.n, d) > 0)
  {
    sp.n = -sp.n; // the near plane cuts the sphere: we see its inside
  }
  const std::uint32_t packed = spheres.colors[id];
  sp.base =
    Vec3d((packed & 0xFF) / 255.0, ((packed >> 8) & 0xFF) / 255.0, ((packed >> 16) & 0xFF) / 255.0);
  sp.color = sp.base;
  if (f.lit)
  {
    const Vec3d pm = sp.pRel + spheres.origin;
    const Vec3d pw = mul3(mw, 4, pm) + Vec3d(mw[3], mw[7], mw[11]);
    const Vec3d nw = normalize(mul3(f.shading.normalToWorld, 3, sp.n));
    const Vec3d vw = normalize(-mul3(mw, 4, d));
    const bool shadows = f.shadowSide > 0;
    sp.color =
      shadeParts(shadows ? f.areaLight : f.shading.lights, f.shading.material, sp.base, pw, nw, vw)
        .total();
  }
  return sp;
}

// The secondary packets of a tile: shadow rays and ambient-occlusion rays, which bound no
// pixel block's frustum.
struct SecondaryPackets
{
  RayPacket shadow, ao;

  explicit SecondaryPackets(const SphereFrame& f)
  {
    shadow.side = f.shadowSide <= 4 ? 4 : (f.shadowSide <= 8 ? 8 : MaxPacketSide);
    shadow.pixelBlock = false;
    ao.side = f.aoSide;
    ao.pixelBlock = false;
  }
};

// The secondary rays of a hit in one packet: rays rayOf(a, start) for a < count in its first
// lanes, the rest invalid, all leaving from just above the surface so that they cannot hit
// their own sphere; returns how many of them meet a sphere (the accelerator's any-hit query).
template<typename RayOf>
int countBlocked(const SphereFrame& f,
  const SurfacePoint& sp,
  int count,
  const RayOf& rayOf,
  RayPacket& packet,
  SphereCounts& counts)
{
  const Vec3d start = sp.pRel + sp.n * (1e-4 * sp.r);
  for (int a = 0; a < packet.side * packet.side; ++a)
  {
    packet.valid[a] = a < count;
    if (a < count)
    {
      packet.rays[a] = rayOf(a, start);
    }
  }
  bool blocked[MaxPacketRays];
  return f.accel.occluded(packet, blocked, counts.traversal);
}

// Soft shadows (section 4.3): a packet of shadow rays to the area light's stratified
// samples (shadowTarget); returns the share of them that reach the light.
double lightVisibility(const SphereFrame& f,
  const SurfacePoint& sp,
  std::uint32_t pixel,
  SecondaryPackets& secondary,
  SphereCounts& counts)
{
  const int count = f.shadowSide * f.shadowSide;
  const auto shadowRay = [&](int a, const Vec3d& start)
  {
    const Vec3d q = shadowTarget(f.shading, a % f.shadowSide, a / f.shadowSide, pixel);
    const Vec3d toLight = q - start;
    const double dist = length(toLight);
    return Ray{ Vec3f(start), Vec3f(toLight * (1.0 / dist)), 0.f, static_cast<float>(dist) };
  };
  const int blocked =
    countBlocked(f, sp, count, shadowRay, secondary.shadow, counts);
  counts.shadowRays += count;
  return 1.0 - static_cast<double>(blocked) / count;
}

// Ambient occlusion: this frame's directions k in [k0, k1) of the N (aoDirection) as one
// packet of rays from just above the surface, answered by occlusion queries (any sphere
// within the radius blocks). With U the unoccluded rays among [0, k1) (the pixel's
// accumulated count plus this frame's), returns 1 - (k1 - U) / k1: for k0 = 0, k1 = N the
// share 1 - occluded / N of a one-shot render, in the same arithmetic.
double unoccluded(const SphereFrame& f,
  const SurfacePoint& sp,
  std::uint32_t pixel,
  SecondaryPackets& secondary,
  SphereCounts& counts)
{
  const int k0 = f.aoBegin, k1 = f.aoEnd, count = k1 - k0;
  RayPacket& packet = secondary.ao;
  const Vec3f start(sp.pRel + sp.n * (1e-4 * sp.r));
  const auto radius = static_cast<float>(f.shading.aoRadius);
  const AoBasis basis = aoBasis(sp.n, pixel);
  for (int a = 0; a < packet.side * packet.side; ++a)
  {
    packet.valid[a] = a < count;
    if (a < count)
    {
      packet.rays[a] = Ray{ start, Vec3f(aoDirectionIn(basis, f.aoPattern[k0 + a])), 0.f, radius };
    }
  }
  bool blocked[MaxPacketRays];
  int free = count > 0 ? count - f.occlusion.occluded(packet, count, blocked, counts.traversal) : 0;
  counts.aoRays += count;
  if (f.aoUnoccluded)
  {
    free += k0 > 0 ? f.aoUnoccluded[pixel] : 0;
    f.aoUnoccluded[pixel] = static_cast<std::uint16_t>(free);
  }
  const int occluded = k1 - free;
  return 1.0 - static_cast<double>(occluded) / k1;
}

// The primary packet of the pixel block at (bx, by): the rays of its pixels inside the tile.
// Returns how many there are.
int makePrimaryPacket(
  const RayCamera& camera, int side, const Tile& tile, int bx, int by, RayPacket& packet)
{
  int rays = 0;
  for (int k = 0; k < side * side; ++k)
  {
    const int i = bx + k % side;
    const int j = by + k / side;
    packet.valid[k] = i < tile.x1 && j < tile.y1;
    if (packet.valid[k])
    {
      packet.rays[k] = camera.pixelRay(i, j);
      ++rays;
    }
  }
  return rays;
}

// The primary rays cut to [entry, exit) of the region box (SphereScene): the exit is left
// out (the float below it), so that two boxes sharing a face never both see a hit on it.
// A ray that misses the box gets an empty interval (tnear > tfar: not traceable, NoHit).
void clipToRegion(const RegionBox& region, const Vec3d& origin, RayPacket& packet)
{
  if (!region.bounded())
  {
    return;
  }
  for (int k = 0; k < packet.side * packet.side; ++k)
  {
    Ray& r = packet.rays[k];
    if (!packet.valid[k])
    {
      continue;
    }
    double t0 = r.tnear, t1 = r.tfar;
    if (!region.clip(Vec3d(r.org), Vec3d(r.dir), origin, t0, t1))
    {
      r.tnear = 1.f;
      r.tfar = 0.f;
      continue;
    }
    r.tnear = static_cast<float>(t0);
    if (t1 < r.tfar)
    {
      r.tfar = std::nextafter(static_cast<float>(t1), 0.f);
    }
  }
}

// A primary ray's hit: the ray, the sphere, the accelerator's distance and the pixel.
struct PrimaryHit
{
  const Ray& ray;
  std::uint32_t id;
  float t;
  std::size_t idx;
};

// A hit's colour: its shaded colour, darkened by its shadows (the visible share scales the
// direct, non-ambient light) and its occlusion; `sp` receives the hit.
Vec3d hitColor(const SphereFrame& f,
  const PrimaryHit& hit,
  SecondaryPackets& secondary,
  SphereCounts& counts,
  SurfacePoint& sp)
{
  sp = shadeHit(f, hit.ray, hit.id, hit.t);
  Vec3d color = sp.color;
  const auto pixel = static_cast<std::uint32_t>(hit.idx);
  if (f.shadowSide > 0)
  {
    const double visible = lightVisibility(f, sp, pixel, secondary, counts);
    const Vec3d ambient = sp.base * f.shading.material.ambient;
    color = ambient + (color - ambient) * visible;
  }
  if (f.aoSamples > 0)
  {
    color = color * unoccluded(f, sp, pixel, secondary, counts);
  }
  return { std::clamp(color.x, 0.0, 1.0), std::clamp(color.y, 0.0, 1.0),
    std::clamp(color.z, 0.0, 1.0) };
}

// Pixel idx: premultiplied colour and alpha, and the window depth at distance t on the ray.
void writePixel(const SphereFrame& f,
  const Ray& ray,
  std::size_t idx,
  const Vec3d& premultiplied,
  double alpha,
  double t)
{
  Frame& frame = f.frame;
  frame.rgba[4 * idx] = static_cast<float>(premultiplied.x);
  frame.rgba[4 * idx + 1] = static_cast<float>(premultiplied.y);
  frame.rgba[4 * idx + 2] = static_cast<float>(premultiplied.z);
  frame.rgba[4 * idx + 3] = static_cast<float>(alpha);
  const double depth = f.camera.depthMap(ray).depthOf(t);
  frame.depth[idx] = static_cast<float>(std::clamp(depth, 0.0, 1.0));
}

// An opaque hit's pixel.
void renderHit(const SphereFrame& f,
  const PrimaryHit& hit,
  SecondaryPackets& secondary,
  SphereCounts& counts)
{
  SurfacePoint sp;
  const Vec3d color = hitColor(f, hit, secondary, counts, sp);
  writePixel(f, hit.ray, hit.idx, color, 1.0, sp.t);
}

// The front-to-back composite of one translucent ray: premultiplied colour C and alpha A,
// the ray's start, the distance of its first layer and the sphere composited last.
struct RayComposite
{
  Vec3d color;
  double alpha = 0.0;
  float tStart = 0.f;
  double tFirst = -1.0;
  std::uint32_t last = NoHit;
};

// Whether the hit at tHit on sphere id is that sphere's first surface at or after the ray's
// start (see the header): the hit is its near root, or its far root while the near one lies
// before the start; never the sphere composited just before (the two float roots of a ray
// grazing it, which double precision may not tell apart).
bool firstSurface(const SphereFrame& f, const Ray& ray, const RayComposite& rc, std::uint32_t id, float tHit)
{
  const Vec3d o(ray.org), d(ray.dir), c(f.spheres.centers[id]);
  const double r = f.spheres.radii[id];
  const SphereRoots roots = sphereRoots(o, d, c, r);
  const bool farRoot = refineSphereHit(o, d, c, r, tHit) > 0.5 * (roots.t0 + roots.t1);
  return id != rc.last && (!farRoot || roots.t0 < rc.tStart);
}

// One surface met by a translucent ray: composited when it is its sphere's first (a_i > 0).
void addLayer(const SphereFrame& f,
  const PrimaryHit& hit,
  RayComposite& rc,
  SecondaryPackets& secondary,
  SphereCounts& counts)
{
  const double a = f.opacityOf(hit.id);
  if (!(a > 0.0) || !firstSurface(f, hit.ray, rc, hit.id, hit.t))
  {
    return;
  }
  SurfacePoint sp;
  const Vec3d color = hitColor(f, hit, secondary, counts, sp);
  const double w = (1.0 - rc.alpha) * a; // C += (1 - A) a_i c_i, A += (1 - A) a_i
  rc.color = rc.color + color * w;
  rc.alpha += w;
  rc.last = hit.id;
  rc.tFirst = rc.tFirst < 0.0 ? sp.t : rc.tFirst;
  ++counts.layers;
}

// A translucent ray ends at the opaque geometry drawn before: tfar at its window depth.
void stopAtOpaque(const SphereFrame& f, std::size_t idx, Ray& ray)
{
  const float depth = f.opaqueDepth ? f.opaqueDepth[idx] : 1.f;
  if (depth < 1.f)
  {
    const double t = f.camera.depthMap(ray).distanceOf(static_cast<double>(depth));
    ray.tfar = std::min(ray.tfar, static_cast<float>(t));
  }
}

// The translucent packet of the pixel block at (bx, by), made by makePrimaryPacket: traced
// again from every lane's last hit on, in (t, sphere index) order (an ordered packet: from
// t with indices above the last one's, so that coincident spheres, whose float hits tie,
// are each composited), until each lane has nothing left before its end or reached
// TranslucentTerminationAlpha; then every pixel gets its composite.
void renderTranslucentPacket(const SphereFrame& f,
  int bx,
  int by,
  RayPacket& packet,
  PacketHits& result,
  SecondaryPackets& secondary,
  SphereCounts& counts)
{
  const int n = f.side * f.side;
  RayComposite rc[MaxPacketRays];
  bool drawn[MaxPacketRays];
  std::size_t idx[MaxPacketRays];
  for (int k = 0; k < n; ++k)
  {
    drawn[k] = packet.valid[k];
    idx[k] = drawn[k] ? f.frame.index(bx + k % f.side, by + k / f.side) : 0;
    packet.tieFrom[k] = 0;
    if (drawn[k])
    {
      stopAtOpaque(f, idx[k], packet.rays[k]);
      rc[k].tStart = packet.rays[k].tnear; // the whole ray's start, before the region's cut
    }
  }
  clipToRegion(f.region, f.spheres.origin, packet);
  for (bool any = true; any; ++counts.queries)
  {
    f.accel.intersect(packet, result, counts.traversal);
    any = false;
    for (int k = 0; k < n; ++k)
    {
      if (!packet.valid[k] || result.prim[k] == NoHit)
      {
        packet.valid[k] = false;
        continue;
      }
      addLayer(f, { packet.rays[k], result.prim[k], result.t[k], idx[k] }, rc[k], secondary, counts);
      packet.rays[k].tnear = result.t[k];
      packet.tieFrom[k] = result.prim[k] + 1;
      packet.valid[k] = rc[k].alpha < TranslucentTerminationAlpha;
      counts.terminated += packet.valid[k] ? 0 : 1;
      any = any || packet.valid[k];
    }
  }
  for (int k = 0; k < n; ++k)
  {
    if (drawn[k] && rc[k].tFirst >= 0.0)
    {
      ++counts.hits;
      writePixel(f, packet.rays[k], idx[k], rc[k].color, rc[k].alpha, rc[k].tFirst);
    }
  }
}

// A tile: primary packets of side x side pixels, the closest hits from the accelerator
// (section 4), and every hit's pixel.
void renderTile(const SphereFrame& f, const Tile& tile, SphereCounts& counts)
{
  const int side = f.side;
  SecondaryPackets secondary(f);
  RayPacket packet;
  packet.side = side;
  packet.ordered = f.translucent;
  PacketHits result;
  for (int by = tile.y0; by < tile.y1; by += side)
  {
    for (int bx = tile.x0; bx < tile.x1; bx += side)
    {
      counts.rays += makePrimaryPacket(f.camera, side, tile, bx, by, packet);
      ++counts.packets;
      if (f.translucent)
      {
        renderTranslucentPacket(f, bx, by, packet, result, secondary, counts);
        continue;
      }
      clipToRegion(f.region, f.spheres.origin, packet);
      f.accel.intersect(packet, result, counts.traversal);
      for (int k = 0; k < side * side; ++k)
      {
        if (!packet.valid[k] || result.prim[k] == NoHit)
        {
          continue;
        }
        ++counts.hits;
        const std::size_t idx = f.frame.index(bx + k % side, by + k / side);
        renderHit(f, { packet.rays[k], result.prim[k], result.t[k], idx }, secondary, counts);
      }
    }
  }
}

// The frame's counters, summed over the tiles.
struct SphereCounters
{
  std::atomic<std::int64_t> rays{ 0 }, packets{ 0 }, hits{ 0 }, cells{ 0 }, culled{ 0 }, tests{ 0 },
    rangeCulled{ 0 }, aoRays{ 0 }, shadowRays{ 0 }, layers{ 0 }, queries{ 0 }, terminated{ 0 };

  void add(const SphereCounts& c)
  {
    rays += c.rays;
    packets += c.packets;
    hits += c.hits;
    cells += c.traversal.cells;
    culled += c.traversal.culled;
    tests += c.traversal.sphereTests;
    rangeCulled += c.traversal.rangeCulled;
    aoRays += c.aoRays;
    shadowRays += c.shadowRays;
    layers += c.layers;
    queries += c.queries;
    terminated += c.terminated;
  }
};
// The bits of everything an image of renderSpheres depends on besides the spheres' own data
// (covered by the sphere set's and accelerator's identity and size and the caller's
// sceneVersion): two frames with the same key draw the same pixels.
std::vector<std::uint64_t> imageKey(const SphereScene& scene,
  const View& view,
  const SphereRenderParameters& params)
{
  std::vector<double> v(view.modelToClip().begin(), view.modelToClip().end());
  const auto put = [&](const Vec3d& p) { v.insert(v.end(), { p.x, p.y, p.z }); };
  v.insert(v.end(), { double(view.width()), double(view.height()) });
  put(view.origin());
  const SphereShading& s = params.shading;
  for (const Light& l : s.lights)
  {
    put(l.color);
    put(l.direction);
    put(l.position);
    put(l.attenuation);
    v.insert(v.end(), { l.positional ? 1.0 : 0.0, l.coneAngleDeg });
  }
  const Material& m = s.material;
  v.insert(v.end(), { m.ambient, m.diffuse, m.specular, m.specularPower });
  put(m.specularColor);
  v.insert(v.end(), s.modelToWorld, s.modelToWorld + 16);
  v.insert(v.end(), s.normalToWorld, s.normalToWorld + 9);
  v.insert(v.end(),
    { double(s.lights.size()),
      double(s.aoSamples),
      s.aoRadius,
      double(s.shadowSide),
      s.lightIntensity,
      params.opacity });
  for (const Vec3d& p : { s.lightCenter, s.lightEdgeU, s.lightEdgeV, s.lightCenterWorld })
  {
    put(p);
  }
  const RangeFilter& filter = scene.accel.rangeFilter();
  v.push_back(filter.count);
  v.insert(v.end(), filter.lo, filter.lo + MaxRangeAttributes);
  v.insert(v.end(), filter.hi, filter.hi + MaxRangeAttributes);
  std::vector<std::uint64_t> key(v.size() + 4);
  std::memcpy(key.data(), v.data(), v.size() * sizeof(double)); // bits: NaN equals itself
  key[v.size()] = reinterpret_cast<std::uintptr_t>(&scene.spheres);
  key[v.size() + 1] = reinterpret_cast<std::uintptr_t>(&scene.accel);
  key[v.size() + 2] = scene.spheres.size();
  key[v.size() + 3] = params.sceneVersion;
  return key;
}

// This frame's ambient-occlusion directions [k0, k1) of the N per hit, and the per-pixel
// count they add to: all N and none without accumulation (no AoAccumulation, budget 0,
// translucent spheres, AO off); else the accumulation goes on from k0 = done when the image
// key is unchanged (restarts from 0 otherwise) with k1 = min(N, k0 + budget).
struct AoFrameRange
{
  int begin, end;
  std::uint16_t* unoccluded;
};
AoFrameRange startAoFrame(const SphereScene& scene,
  const View& view,
  const SphereRenderParameters& params,
  int aoSamples,
  bool translucent)
{
  AoAccumulation* acc = params.aoAccumulation;
  if (!acc || params.aoSamplesPerFrame <= 0 || aoSamples <= 0 || translucent)
  {
    if (acc)
    {
      acc->reset();
    }
    return { 0, aoSamples, nullptr };
  }
  std::vector<std::uint64_t> key = imageKey(scene, view, params);
  const std::size_t pixels = static_cast<std::size_t>(view.width()) * view.height();
  if (key != acc->key || acc->unoccluded.size() != pixels)
  {
    acc->key = std::move(key);
    acc->unoccluded.assign(pixels, 0);
    acc->done = 0;
  }
  const int k0 = std::clamp(acc->done, 0, aoSamples);
  const int k1 = k0 + std::min(params.aoSamplesPerFrame, aoSamples - k0);
  return { k0, k1, acc->unoccluded.data() };
}
}

void renderSpheres(const SphereScene& scene,
  const View& view,
  const SphereRenderParameters& params,
  Frame& frame,
  RenderStatistics& stats)
{
  const SphereAccelerator& accel = scene.accel;
  const SphereShading& shading = params.shading;
  const int width = view.width();
  const int height = view.height();
  frame.resize(width, height);
  const bool lit = !shading.lights.empty() || shading.shadowSide > 0;
  stats.setEffect("shading", lit);
  stats.setEffect("specular", lit && shading.material.specular > 0);
  stats.setEffect("range_culling", accel.rangeFilter().count > 0);
  const int aoSamples = std::clamp(shading.aoSamples, 0, MaxPacketRays);
  const bool ao = aoSamples > 0 && shading.aoRadius > 0;
  stats.setEffect("ambient_occlusion", ao);
  const SphereOcclusion occlusion(scene.spheres, accel);
  stats.setEffect("ao_local_queries", ao && occlusion.local());
  const int shadowSide = std::clamp(shading.shadowSide, 0, MaxPacketSide);
  stats.setEffect("soft_shadows", shadowSide > 0);
  const bool translucent = drawsTranslucent(scene.spheres, params);
  stats.setEffect("translucency", translucent);
  stats.setEffect("region_clip", scene.region.bounded());
  const char* const counterNames[] = { "rays",
    "packets",
    "hits",
    "cells",
    "culled",
    "sphere_tests",
    "range_culled",
    "ao_rays",
    "ao_samples_done",
    "ao_converged",
    "shadow_rays",
    "translucent_layers",
    "translucent_queries",
    "translucent_terminated" };
  for (const char* c : counterNames)
  {
    stats.declareCounter(c);
  }
  if (accel.empty() || width <= 0 || height <= 0 || !(params.opacity > 0.0))
  {
    if (params.aoAccumulation)
    {
      params.aoAccumulation->reset();
    }
    stats.setEffect("ao_progressive", false);
    stats.addCounter("ao_converged", 1);
    return;
  }
  const AoFrameRange aoRange = startAoFrame(scene, view, params, ao ? aoSamples : 0, translucent);
  stats.setEffect("ao_progressive", aoRange.unoccluded != nullptr);
  std::vector<AoSample> aoPattern(ao ? aoSamples : 0);
  for (int k = 0; k < static_cast<int>(aoPattern.size()); ++k)
  {
    aoPattern[k] = aoSample(k, aoSamples);
  }
  SphereFrame f{ scene.spheres,
    accel,
    view.camera(),
    shading,
    frame,
    std::clamp(params.packetSide, 1, MaxPacketSide),
    lit,
    shadowSide,
    ao ? aoSamples : 0,
    aoSamples <= 16 ? 4 : (aoSamples <= 64 ? 8 : MaxPacketSide),
    aoRange.begin,
    aoRange.end,
    aoPattern.data(),
    aoRange.unoccluded,
    occlusion,
    {},
    translucent,
    std::clamp(params.opacity, 0.0, 1.0),
    view.opaqueDepth(),
    scene.region };
  if (shadowSide > 0)
  {
    Light l;
    l.positional = true;
    l.position = shading.lightCenterWorld;
    l.color = Vec3d(1, 1, 1) * shading.lightIntensity;
    f.areaLight.push_back(l);
  }
  SphereCounters counters;
  {
    ScopedPhase phase(stats, "trace");
    forEachTile(width,
      height,
      params.tileSize,
      [&](const Tile& tile)
      {
        SphereCounts counts;
        renderTile(f, tile, counts);
        counters.add(counts);
      });
  }
  if (params.aoAccumulation && aoRange.unoccluded)
  {
    params.aoAccumulation->done = aoRange.end;
  }
  const std::int64_t counts[] = { counters.rays,
    counters.packets,
    counters.hits,
    counters.cells,
    counters.culled,
    counters.tests,
    counters.rangeCulled,
    counters.aoRays,
    aoRange.end,
    !ao || aoRange.end == aoSamples ? 1 : 0,
    counters.shadowRays,
    counters.layers,
    counters.queries,
    counters.terminated };
  for (std::size_t c = 0; c < std::size(counts); ++c)
  {
    stats.addCounter(counterNames[c], counts[c]);
  }
}

namespace
{
// A tile of a selection pass: the closest hit of each pixel's ray, as the sphere's input
// point + 1 and the hit's window depth (the exact root, as renderHit writes it).
void pickTile(const SphereScene& scene, const RayCamera& camera, int side, const Tile& tile,
  IdFrame& picks, SphereCounts& counts)
{
  RayPacket packet;
  packet.side = side;
  PacketHits result;
  for (int by = tile.y0; by < tile.y1; by += side)
  {
    for (int bx = tile.x0; bx < tile.x1; bx += side)
    {
      counts.rays += makePrimaryPacket(camera, side, tile, bx, by, packet);
      ++counts.packets;
      clipToRegion(scene.region, scene.spheres.origin, packet);
      scene.accel.intersect(packet, result, counts.traversal);
      for (int k = 0; k < side * side; ++k)
      {
        if (!packet.valid[k] || result.prim[k] == NoHit)
        {
          continue;
        }
        ++counts.hits;
        const std::uint32_t id = result.prim[k];
        const Ray& ray = packet.rays[k];
        const double t = refineSphereHit(Vec3d(ray.org), Vec3d(ray.dir),
          Vec3d(scene.spheres.centers[id]), scene.spheres.radii[id], result.t[k]);
        const std::size_t idx = static_cast<std::size_t>(by + k / side) * picks.width +
          static_cast<std::size_t>(bx + k % side);
        picks.ids[idx] = scene.spheres.sourceIds[id] + 1u;
        picks.depth[idx] =
          static_cast<float>(std::clamp(camera.depthMap(ray).depthOf(t), 0.0, 1.0));
      }
    }
  }
}
}

void pickSpheres(const SphereScene& scene,
  const View& view,
  int packetSide,
  int tileSize,
  IdFrame& picks,
  RenderStatistics& stats)
{
  picks.resize(view.width(), view.height());
  for (const char* c : { "rays", "packets", "hits" })
  {
    stats.declareCounter(c);
  }
  stats.setEffect("selection_ids", true);
  if (scene.accel.empty() || picks.width <= 0 || picks.height <= 0)
  {
    return;
  }
  const int side = std::clamp(packetSide, 1, MaxPacketSide);
  SphereCounters counters;
  {
    ScopedPhase phase(stats, "pick");
    forEachTile(picks.width, picks.height, tileSize,
      [&](const Tile& tile)
      {
        SphereCounts counts;
        pickTile(scene, view.camera(), side, tile, picks, counts);
        counters.add(counts);
      });
  }
  stats.addCounter("rays", counters.rays);
  stats.addCounter("packets", counters.packets);
  stats.addCounter("hits", counters.hits);
}

} // namespace raymappers
