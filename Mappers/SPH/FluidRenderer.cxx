#include "FluidRenderer.h"

#include "SurfaceLinks.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace raymappers
{
namespace
{
constexpr double Infinity = std::numeric_limits<double>::infinity();

/// Rows of a row-major matrix (stride 4 for the affine 4x4, 3 for the 3x3) times v, plus the
/// translation column when `affine`.
Vec3d applyMatrix(const double* m, int stride, const Vec3d& v, bool affine)
{
  Vec3d out;
  for (int r = 0; r < 3; ++r)
  {
    const double* row = m + r * stride;
    out[r] = row[0] * v.x + row[1] * v.y + row[2] * v.z + (affine ? row[3] : 0.0);
  }
  return out;
}

struct Tally
{
  std::int64_t shaded = 0, translucent = 0, paths = 0, events = 0, tir = 0, columns = 0,
               aoSamples = 0;
};

/// Whether depth z lies in one of pixel p's stored spans.
bool insideAt(const FluidSpans& spans, std::size_t p, double z)
{
  for (int k = 0; k < spans.count[p]; ++k)
  {
    if (z >= spans.entry(p, k) && z <= spans.exit(p, k))
    {
      return true;
    }
  }
  return false;
}

/// Unpolarized Fresnel reflectance from a medium of index n1 into n2 at incidence cosine
/// cosI (Fresnel's equations); 1 beyond the critical angle. cosT receives the refracted
/// cosine.
double fresnel(double cosI, double n1, double n2, double& cosT)
{
  const double eta = n1 / n2;
  const double sin2T = eta * eta * std::max(0.0, 1.0 - cosI * cosI);
  if (sin2T >= 1.0)
  {
    cosT = 0.0;
    return 1.0;
  }
  cosT = std::sqrt(1.0 - sin2T);
  const double rs = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT);
  const double rp = (n1 * cosT - n2 * cosI) / (n1 * cosT + n2 * cosI);
  return 0.5 * (rs * rs + rp * rp);
}

/// Where a marched ray meets a surface: parameter t along it, the column and the depth slot
/// whose normal applies (-1: none stored; a column's side is met where it has no slot).
struct MarchHit
{
  bool hit = false;
  double t = 0;
  std::size_t pixel = 0;
  int slot = -1;
};

/// Which square tiles of TileSize pixels hold a span: a ray outside the fluid crosses an empty
/// tile in one step (it can meet no surface there).
struct EmptyTiles
{
  static constexpr int TileSize = 16;
  int tilesX = 0, tilesY = 0;
  std::vector<std::uint8_t> occupied;

  explicit EmptyTiles(const FluidSpans& spans)
    : tilesX((spans.width + TileSize - 1) / TileSize)
    , tilesY((spans.height + TileSize - 1) / TileSize)
    , occupied(static_cast<std::size_t>(tilesX) * tilesY, 0)
  {
    for (int j = 0; j < spans.height; ++j)
    {
      for (int i = 0; i < spans.width; ++i)
      {
        occupied[static_cast<std::size_t>(j / TileSize) * tilesX + i / TileSize] |=
          spans.count[spans.pixel(i, j)] > 0 ? 1 : 0;
      }
    }
  }
  bool empty(int i, int j) const
  {
    return !occupied[static_cast<std::size_t>(j / TileSize) * tilesX + i / TileSize];
  }
};

/// Listing 2: marches the ray o + t d (t >= 0, d unit, model coordinates; inside tells
/// whether it starts in the fluid) through the columns from pixel (i, j), pixel boundary to
/// pixel boundary along its projection. In each column it meets [za, zb] of depth: a change
/// of inside/outside at the column's side is a hit there; else the first stored depth in
/// (za, zb] along the ray is. Without a hit before the grid's depth range or the screen
/// ends, the ray escapes at the t where it leaves. Outside the fluid, empty tiles are crossed
/// in one step, from the side where the ray enters to the one where it leaves.
MarchHit march(const FluidSpans& spans,
  const EmptyTiles& tiles,
  const ViewRays& rays,
  const Vec3d& o,
  const Vec3d& d,
  bool inside,
  int i,
  int j,
  std::int64_t& columns)
{
  const std::array<double, 4> c0 = rays.clip(o), c1 = rays.clip(o + d);
  std::array<double, 4> cd;
  for (int k = 0; k < 4; ++k)
  {
    cd[k] = c1[k] - c0[k];
  }
  const double z0 = rays.zetaOf(o), zd = rays.zetaOf(o + d) - z0;
  const double zmin = spans.layers.depths.front(), zmax = spans.layers.depths.back();
  const double tMax = zd > 0 ? (zmax - z0) / zd : (zd < 0 ? (zmin - z0) / zd : Infinity);
  // Pixel x(t) = (x_c / w_c + 1) W / 2 moves monotonically; the sign of its derivative is that
  // of x_c' w_c - x_c w_c'.
  const auto sgn = [](double v) { return v > 0 ? 1 : (v < 0 ? -1 : 0); };
  const int sx = sgn(cd[0] * c0[3] - c0[0] * cd[3]), sy = sgn(cd[1] * c0[3] - c0[1] * cd[3]);
  const auto boundary = [&](int axis, int s, int cell, int size)
  {
    if (s == 0)
    {
      return Infinity;
    }
    const double ndc = 2.0 * (s > 0 ? cell + 1 : cell) / size - 1.0;
    const double den = cd[axis] - ndc * cd[3];
    const double t = den != 0 ? (ndc * c0[3] - c0[axis]) / den : Infinity;
    return t >= 0 ? t : Infinity;
  };
  const int W = spans.width, H = spans.height;
  double tIn = 0;
  MarchHit result;
  const int T = EmptyTiles::TileSize;
  int ti = -1, tj = -1; // the column whose sides tx, ty are
  double tx = Infinity, ty = Infinity;
  for (bool first = true; i >= 0 && i < W && j >= 0 && j < H && tIn < tMax; first = false)
  {
    if (!inside && tiles.empty(i, j))
    {
      // The last pixel of the tile along each axis in the ray's direction: the ray leaves
      // the tile through the nearer of their far sides.
      const int ei = sx > 0 ? std::min(W, (i / T + 1) * T) - 1 : (i / T) * T;
      const int ej = sy > 0 ? std::min(H, (j / T + 1) * T) - 1 : (j / T) * T;
      const double sideX = boundary(0, sx, ei, W), sideY = boundary(1, sy, ej, H);
      const double tOut = std::max(tIn, std::min({ sideX, sideY, tMax }));
      ++columns;
      if (sideX <= sideY)
      {
        // Leaves through the x side: the row it is in there (within the tile's rows).
        const double y = ((c0[1] + tOut * cd[1]) / (c0[3] + tOut * cd[3]) + 1.0) * 0.5 * H;
        j = std::clamp(static_cast<int>(std::floor(y)), (j / T) * T, std::min(H, (j / T + 1) * T) - 1);
        i = ei + sx;
      }
      else
      {
        const double x = ((c0[0] + tOut * cd[0]) / (c0[3] + tOut * cd[3]) + 1.0) * 0.5 * W;
        i = std::clamp(static_cast<int>(std::floor(x)), (i / T) * T, std::min(W, (i / T + 1) * T) - 1);
        j = ej + sy;
      }
      tIn = tOut;
      continue;
    }
    // The column's far sides, computed again only when the ray has moved along that axis.
    if (i != ti)
    {
      ti = i;
      tx = boundary(0, sx, i, W);
    }
    if (j != tj)
    {
      tj = j;
      ty = boundary(1, sy, j, H);
    }
    const double tOut = std::max(tIn, std::min({ tx, ty, tMax }));
    const double za = z0 + zd * tIn, zb = z0 + zd * tOut;
    const std::size_t p = spans.pixel(i, j);
    ++columns;
    const int slots = 2 * spans.count[p];
    if (!first && insideAt(spans, p, za) != inside)
    {
      // The column's side: the normal of its depth value nearest to za.
      result = { true, tIn, p, -1 };
      double best = Infinity;
      for (int s = 0; s < slots; ++s)
      {
        const double gap = std::abs(spans.depth[spans.slot(p, s)] - za);
        if (gap < best)
        {
          best = gap;
          result.slot = s;
        }
      }
      return result;
    }
    const double eps = 1e-6 * std::abs(za);
    if (zd > 0)
    {
      for (int s = 0; s < slots; ++s)
      {
        const double z = spans.depth[spans.slot(p, s)];
        if (z > za + eps && z <= zb)
        {
          return { true, (z - z0) / zd, p, s };
        }
      }
    }
    else if (zd < 0)
    {
      for (int s = slots - 1; s >= 0; --s)
      {
        const double z = spans.depth[spans.slot(p, s)];
        if (z < za - eps && z >= zb)
        {
          return { true, (z - z0) / zd, p, s };
        }
      }
    }
    if (tx <= ty)
    {
      i += sx;
    }
    else
    {
      j += sy;
    }
    tIn = tOut;
  }
  result.t = std::min(tIn, tMax);
  return result;
}

/// The front surface seen through a pixel: its depth, the pixel's ray direction B (|B| per
/// unit of depth), the point and its outward normal (model coordinates).
struct FrontSurface
{
  double z;
  Vec3d B, P, N;
};

/// Calls fn(i, j, p, front, tally) for every pixel with fluid, rows in parallel.
template<typename Fn>
void forEachFrontSurface(const FluidSpans& spans,
  const ViewRays& rays,
  tbb::combinable<Tally>& tallies,
  Fn fn)
{
  tbb::parallel_for(tbb::blocked_range<int>(0, spans.height, 1),
    [&](const tbb::blocked_range<int>& r)
    {
      Tally& t = tallies.local();
      for (int j = r.begin(); j != r.end(); ++j)
      {
        for (int i = 0; i < spans.width; ++i)
        {
          const std::size_t p = spans.pixel(i, j);
          if (spans.count[p] == 0)
          {
            continue;
          }
          const double z = spans.entry(p, 0);
          const FrontSurface front{ z,
            rays.direction(i + 0.5, j + 0.5),
            rays.pointAt(i + 0.5, j + 0.5, z),
            Vec3d(decodeNormal(spans.normals[spans.slot(p, 0)])) };
          fn(i, j, p, front, t);
        }
      }
    });
}

/// Ambient occlusion of pixel p's front surface (the file comment's K spiral samples).
double ambientOcclusion(const FluidSpans& spans,
  const ViewRays& rays,
  const Vec3d& P,
  const Vec3d& n,
  double radius,
  int samples,
  double offset)
{
  const Vec3d helper = std::abs(n.x) < 0.9 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
  const Vec3d tu = normalize(cross(n, helper)), tv = cross(n, tu);
  int occluded = 0;
  for (int k = 0; k < samples; ++k)
  {
    // Cosine-weighted spiral directions, radii spread by the golden ratio.
    const double u = (k + 0.5) / samples;
    const double cosT = std::sqrt(1.0 - u), sinT = std::sqrt(u);
    const double phi = 2.399963229728653 * k;
    const double r = radius * (0.2 + 0.8 * std::fmod(0.5 + 0.6180339887498949 * k, 1.0));
    const Vec3d dir = tu * (std::cos(phi) * sinT) + tv * (std::sin(phi) * sinT) + n * cosT;
    const Vec3d q = P + n * offset + dir * r;
    const std::array<double, 4> c = rays.clip(q);
    if (!(c[3] > 0))
    {
      continue;
    }
    const double px = (c[0] / c[3] + 1.0) * 0.5 * spans.width;
    const double py = (c[1] / c[3] + 1.0) * 0.5 * spans.height;
    if (!(px >= 0 && px < spans.width && py >= 0 && py < spans.height))
    {
      continue;
    }
    occluded +=
      insideAt(spans, spans.pixel(static_cast<int>(px), static_cast<int>(py)), rays.zetaOf(q));
  }
  return 1.0 - static_cast<double>(occluded) / samples;
}
}

void renderFluidSpans(const FluidSpans& spans,
  const ViewRays& rays,
  const Vec3d& origin,
  const FluidRenderParameters& params,
  Frame& frame,
  RenderStatistics& stats)
{
  const bool refraction =
    params.translucency && params.refractiveIndex != 1.0 && params.bounces > 0;
  const bool ao = params.ambientOcclusion && params.aoSamples > 0 && params.aoRadius > 0;
  stats.setEffect("translucency", params.translucency);
  stats.setEffect("refraction", refraction);
  stats.setEffect("ambient_occlusion", ao);
  for (const char* name : { "shaded_pixels",
         "translucent_pixels",
         "refraction_paths",
         "surface_events",
         "tir_events",
         "march_columns",
         "ao_samples" })
  {
    stats.declareCounter(name);
  }
  const int W = spans.width, H = spans.height;
  frame.resize(W, H);
  if (spans.normals.size() != spans.depth.size())
  {
    return;
  }
  const std::size_t n = static_cast<std::size_t>(W) * H;
  tbb::combinable<Tally> tallies;

  // Ambient occlusion of the front surfaces.
  std::vector<float> occlusion;
  if (ao)
  {
    ScopedPhase phase(stats, "ao");
    occlusion.assign(n, 1.f);
    forEachFrontSurface(spans,
      rays,
      tallies,
      [&](int, int, std::size_t p, const FrontSurface& f, Tally& t)
      {
        // Off the surface by two layers, past the voxelization's conservative bulge.
        const double layer = std::floor(spans.layers.coordinate(f.z));
        const double offset =
          2.0 * (spans.layers.depth(layer + 1) - spans.layers.depth(layer)) * length(f.B);
        occlusion[p] = static_cast<float>(
          ambientOcclusion(spans, rays, f.P, f.N, params.aoRadius, params.aoSamples, offset));
        t.aoSamples += params.aoSamples;
      });
  }

  ScopedPhase phase(stats, refraction ? "refract" : "render");
  const Vec3d kappa = params.absorptionColor * params.density;
  const double eta = params.refractiveIndex;
  const int bounces = std::max(0, params.bounces);
  const EmptyTiles tiles = refraction ? EmptyTiles(spans) : EmptyTiles(FluidSpans());
  const auto toWorld = [&](const Vec3d& pModel)
  { return applyMatrix(params.modelToWorld, 4, pModel + origin, true); };
  const auto litColour = [&](const Vec3d& pModel, const Vec3d& nModel, const Vec3d& dModel)
  {
    const Vec3d nWorld = normalize(applyMatrix(params.normalToWorld, 3, nModel, false));
    const Vec3d dWorld = normalize(applyMatrix(params.modelToWorld, 4, dModel, false));
    return shade(params.lights, params.material, params.color, toWorld(pModel), nWorld, -dWorld);
  };
  const auto attenuation = [&](double s)
  { return Vec3d(std::exp(-kappa.x * s), std::exp(-kappa.y * s), std::exp(-kappa.z * s)); };
  forEachFrontSurface(spans,
    rays,
    tallies,
    [&](int i, int j, std::size_t p, const FrontSurface& f, Tally& t)
    {
      const Vec3d& B = f.B;
      const Vec3d& P = f.P;
      const Vec3d& N = f.N;
      const Vec3d d = normalize(B);
      const Vec3d L = litColour(P, N, d) * (ao ? double(occlusion[p]) : 1.0);
      ++t.shaded;
      Vec3d rgb = L, through(0, 0, 0);
      if (params.translucency && !refraction)
      {
        through = attenuation(spans.thickness(p) * length(B));
        rgb = L * (Vec3d(1, 1, 1) - through);
        ++t.translucent;
      }
      else if (refraction)
      {
        ++t.paths;
        rgb = Vec3d();
        Vec3d w(1, 1, 1), o = P, dir = d, normal = N;
        bool inside = false;
        int ci = i, cj = j;
        for (int event = 0;; ++event)
        {
          // A surface event at o with outward normal `normal`.
          ++t.events;
          const Vec3d facing = dot(normal, dir) < 0 ? normal : -normal;
          const double cosI = std::clamp(-dot(facing, dir), 0.0, 1.0);
          double cosT = 0;
          const double R = inside ? fresnel(cosI, eta, 1.0, cosT) : fresnel(cosI, 1.0, eta, cosT);
          if (R >= 1.0)
          {
            dir = normalize(dir + facing * (2.0 * cosI));
            ++t.tir;
          }
          else
          {
            rgb += w * L * R;
            w = w * (1.0 - R);
            const double ratio = inside ? eta : 1.0 / eta;
            dir = normalize(dir * ratio + facing * (ratio * cosI - cosT));
            inside = !inside;
          }
          if (event + 1 >= bounces)
          {
            break;
          }
          const MarchHit hit = march(spans, tiles, rays, o, dir, inside, ci, cj, t.columns);
          const double s = std::max(0.0, hit.t);
          if (inside)
          {
            const Vec3d a = attenuation(s);
            rgb += w * L * (Vec3d(1, 1, 1) - a);
            w = w * a;
          }
          if (!hit.hit)
          {
            inside = false; // left the grid: on to the background
            break;
          }
          o = o + dir * s;
          ci = static_cast<int>(hit.pixel % W);
          cj = static_cast<int>(hit.pixel / W);
          normal = hit.slot >= 0
                     ? Vec3d(decodeNormal(spans.normals[spans.slot(hit.pixel, hit.slot)]))
                     : -dir;
        }
        if (inside)
        {
          rgb += w * L; // out of bounces inside the fluid: absorbed
        }
        else
        {
          through = w;
        }
      }
      float* out = &frame.rgba[4 * frame.index(i, j)];
      out[0] = static_cast<float>(rgb.x);
      out[1] = static_cast<float>(rgb.y);
      out[2] = static_cast<float>(rgb.z);
      out[3] = static_cast<float>(1.0 - (through.x + through.y + through.z) / 3.0);
      const std::array<double, 4> c = rays.clip(P);
      frame.depth[frame.index(i, j)] =
        static_cast<float>(std::clamp(0.5 * (c[2] / c[3] + 1.0), 0.0, 1.0));
    });
  const Tally total = tallies.combine(
    [](Tally a, const Tally& b)
    {
      a.shaded += b.shaded;
      a.translucent += b.translucent;
      a.paths += b.paths;
      a.events += b.events;
      a.tir += b.tir;
      a.columns += b.columns;
      a.aoSamples += b.aoSamples;
      return a;
    });
  stats.addCounter("shaded_pixels", total.shaded);
  stats.addCounter("translucent_pixels", total.translucent);
  stats.addCounter("refraction_paths", total.paths);
  stats.addCounter("surface_events", total.events);
  stats.addCounter("tir_events", total.tir);
  stats.addCounter("march_columns", total.columns);
  stats.addCounter("ao_samples", total.aoSamples);
}

bool renderFluid(const FluidParticles& particles,
  const ViewRays& rays,
  const FluidRenderParameters& params,
  FluidSpans& spans,
  Frame& frame,
  RenderStatistics& stats)
{
  stats.addCounter("particles_skipped",
    static_cast<std::int64_t>(particles.skippedNonFinite + particles.skippedBadRadius));
  if (!voxelizeFluid(particles, rays, params.voxelizer, spans, stats))
  {
    frame.resize(rays.width(), rays.height());
    return false;
  }
  connectSurfaces(spans, stats);
  SurfaceNeighbourhoods neighbourhoods;
  findNeighbourhoods(spans, neighbourhoods, stats);
  smoothSurfaces(
    spans, neighbourhoods, rays, params.smoothingRadius, params.smoothingIterations, stats);
  computeNormals(spans, neighbourhoods, rays, stats);
  renderFluidSpans(spans, rays, particles.origin, params, frame, stats);
  return true;
}

} // namespace raymappers
