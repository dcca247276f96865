#include "Mappers/SPH/FluidRenderer.h"

#include "Mappers/SPH/SurfaceLinks.h"
#include "Mappers/SPH/Tallies.h"
#include "Mappers/Common/SimdTarget.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>

namespace raymappers
{

RAYMAPPERS_SIMD_VARIANTS(renderFluidSpans)
RAYMAPPERS_SIMD_VARIANTS(renderFluid)

RAYMAPPERS_SIMD_BEGIN
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
               tileSkips = 0, aoSamples = 0, colorSamples = 0;
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

/// Empty-space skipping for the march: the screen in square tiles of TileSize pixels, the
/// layers' range in DepthBins bins of equal layer count. Per tile and bin, whether every column
/// of the tile is inside a span throughout the bin (no stored depth in the bin), or outside
/// every span throughout it. A ray whose depths over a tile stay in bins that are clear for
/// its state (inside or outside the fluid) meets no surface there (no stored depth, and no
/// change of inside/outside at a column's side): it crosses the tile in one step.
struct MarchTiles
{
  int TileSize;
  static constexpr int Words = 16; // 64-bit words of bins per tile and state
  static constexpr int DepthBins = 64 * Words;
  using Bins = std::array<std::uint64_t, Words>;
  const VoxelDepthLayers& layers;
  int tilesX = 0, tilesY = 0;
  double keyFront = 0, binsPerKey = 0;
  std::vector<Bins> clearInside, clearOutside; // per tile, bit b: bin b is clear
  std::vector<std::uint8_t> anyInside, anyOutside; // per tile: some bin is clear

  MarchTiles(const FluidSpans& spans, int tileSize)
    : TileSize(tileSize)
    , layers(spans.layers)
    , tilesX((spans.width + TileSize - 1) / TileSize)
    , tilesY((spans.height + TileSize - 1) / TileSize)
    , clearInside(static_cast<std::size_t>(tilesX) * tilesY)
    , clearOutside(static_cast<std::size_t>(tilesX) * tilesY)
    , anyInside(static_cast<std::size_t>(tilesX) * tilesY)
    , anyOutside(static_cast<std::size_t>(tilesX) * tilesY)
  {
    if (!layers.depths.empty())
    {
      keyFront = key(layers.depths.front());
      const double keyRange = key(layers.depths.back()) - keyFront;
      binsPerKey = keyRange > 0 ? DepthBins / keyRange : 0.0;
    }
    tbb::parallel_for(tbb::blocked_range<int>(0, tilesY, 1),
      [&](const tbb::blocked_range<int>& r)
      {
        for (int ty = r.begin(); ty != r.end(); ++ty)
        {
          for (int tx = 0; tx < tilesX; ++tx)
          {
            classifyTile(spans, tx, ty);
          }
        }
      });
  }
  /// The bin holding depth z (depths beyond the layers' range in the end bins): uniform in
  /// the bit pattern of z as a double, which for positive depths grows monotonically with z,
  /// piecewise linearly in log2 z (perspective: like the layers), or uniform in z (parallel).
  /// Any monotonic binning keeps the skip exact: a depth between za and zb has its bin between
  /// theirs, and one in a bin strictly between two depths' bins lies between them.
  int bin(double z) const
  {
    const double u = (key(z) - keyFront) * binsPerKey;
    return static_cast<int>(std::clamp(u, 0.0, DepthBins - 1.0));
  }
  double key(double z) const
  {
    if (!layers.logarithmic)
    {
      return z;
    }
    std::int64_t bits;
    std::memcpy(&bits, &z, sizeof bits);
    return static_cast<double>(std::max<std::int64_t>(bits, 0));
  }
  /// Bins lo..hi within word w (bins 64 w .. 64 w + 63) as a mask.
  static std::uint64_t wordMask(int lo, int hi, int w)
  {
    const int a = std::max(lo - 64 * w, 0), b = std::min(hi - 64 * w, 63);
    const std::uint64_t upTo = b == 63 ? ~std::uint64_t(0) : (std::uint64_t(1) << (b + 1)) - 1;
    return upTo & (~std::uint64_t(0) << a);
  }
  /// Sets bins lo..hi of m.
  static void mark(Bins& m, int lo, int hi)
  {
    for (int w = lo >> 6; w <= hi >> 6; ++w)
    {
      m[w] |= wordMask(lo, hi, w);
    }
  }
  /// A column's spans [e_k, x_k]: the bins strictly between bin(e_k) and bin(x_k) are inside,
  /// those holding a stored depth neither inside nor outside, the rest outside. A tile's bin is
  /// clear for a state when it is so in every column.
  void classifyTile(const FluidSpans& spans, int tx, int ty)
  {
    Bins in, out;
    in.fill(~std::uint64_t(0));
    out.fill(~std::uint64_t(0));
    const int i1 = std::min(spans.width, (tx + 1) * TileSize);
    const int j1 = std::min(spans.height, (ty + 1) * TileSize);
    for (int j = ty * TileSize; j < j1; ++j)
    {
      for (int i = tx * TileSize; i < i1; ++i)
      {
        const std::size_t p = spans.pixel(i, j);
        Bins columnIn{}, surfaces{};
        for (int k = 0; k < spans.count[p]; ++k)
        {
          const int be = bin(spans.entry(p, k)), bx = bin(spans.exit(p, k));
          mark(surfaces, be, be);
          mark(surfaces, bx, bx);
          if (bx > be + 1)
          {
            mark(columnIn, be + 1, bx - 1);
          }
        }
        for (int w = 0; w < Words; ++w)
        {
          in[w] &= columnIn[w];
          out[w] &= ~(columnIn[w] | surfaces[w]);
        }
      }
    }
    const std::size_t t = static_cast<std::size_t>(ty) * tilesX + tx;
    clearInside[t] = in;
    clearOutside[t] = out;
    std::uint64_t anyIn = 0, anyOut = 0;
    for (int w = 0; w < Words; ++w)
    {
      anyIn |= in[w];
      anyOut |= out[w];
    }
    anyInside[t] = anyIn != 0;
    anyOutside[t] = anyOut != 0;
  }
  const Bins& clearBins(int i, int j, bool inside) const
  {
    const std::size_t t = static_cast<std::size_t>(j / TileSize) * tilesX + i / TileSize;
    return inside ? clearInside[t] : clearOutside[t];
  }
  /// Whether pixel (i, j)'s tile has a bin clear for the state.
  bool anyClear(int i, int j, bool inside) const
  {
    const std::size_t t = static_cast<std::size_t>(j / TileSize) * tilesX + i / TileSize;
    return (inside ? anyInside : anyOutside)[t] != 0;
  }
  /// Whether the ray, inside or not, meets no surface in pixel (i, j)'s tile while its depth
  /// goes from za to zb: every bin between theirs is clear (only their words are read).
  bool clear(int i, int j, bool inside, double za, double zb) const
  {
    const int lo = bin(std::min(za, zb)), hi = bin(std::max(za, zb));
    const Bins& c = clearBins(i, j, inside);
    for (int w = lo >> 6; w <= hi >> 6; ++w)
    {
      const std::uint64_t need = wordMask(lo, hi, w);
      if ((c[w] & need) != need)
      {
        return false;
      }
    }
    return true;
  }
};

/// The march's tile levels, coarse to fine.
constexpr int MarchTileSizes[] = { 64, 8 };
constexpr int MarchLevels = sizeof(MarchTileSizes) / sizeof(MarchTileSizes[0]);

/// The marched ray o + t d in the terms of the march: its clip coordinates c0 + t cd, its depth
/// z0 + t zd, the t where it leaves the grid's depth range, and the signs sx, sy of the motion
/// of its pixel x(t) = (x_c / w_c + 1) W / 2 (monotonic; the sign of its derivative is that of
/// x_c' w_c - x_c w_c').
struct MarchLine
{
  std::array<double, 4> c0, cd;
  double z0, zd, tMax;
  int sx, sy;

  MarchLine(const FluidSpans& spans, const ViewRays& rays, const Vec3d& o, const Vec3d& d)
  {
    c0 = rays.clip(o);
    const std::array<double, 4> c1 = rays.clip(o + d);
    for (int k = 0; k < 4; ++k)
    {
      cd[k] = c1[k] - c0[k];
    }
    z0 = rays.zetaOf(o);
    zd = rays.zetaOf(o + d) - z0;
    const double zmin = spans.layers.depths.front(), zmax = spans.layers.depths.back();
    tMax = zd > 0 ? (zmax - z0) / zd : (zd < 0 ? (zmin - z0) / zd : Infinity);
    const auto sgn = [](double v) { return v > 0 ? 1 : (v < 0 ? -1 : 0); };
    sx = sgn(cd[0] * c0[3] - c0[0] * cd[3]);
    sy = sgn(cd[1] * c0[3] - c0[1] * cd[3]);
  }
  /// The t >= 0 where the ray crosses the far side (in its direction s along `axis`) of pixel
  /// `cell` of `size`; infinity when it does not move along the axis.
  double boundary(int axis, int s, int cell, int size) const
  {
    if (s == 0)
    {
      return Infinity;
    }
    const double ndc = 2.0 * (s > 0 ? cell + 1 : cell) / size - 1.0;
    const double den = cd[axis] - ndc * cd[3];
    const double t = den != 0 ? (ndc * c0[3] - c0[axis]) / den : Infinity;
    return t >= 0 ? t : Infinity;
  }
  /// The pixel coordinate along `axis` (image size `size`) at t.
  double pixelAt(int axis, double t, int size) const
  {
    return ((c0[axis] + t * cd[axis]) / (c0[3] + t * cd[3]) + 1.0) * 0.5 * size;
  }
};

/// Crosses the tile of pixel (i, j) in one step from tIn: the ray leaves the tile through the
/// nearer of the far sides of the tile's last pixel along each axis; (i, j) becomes the pixel
/// beyond, the one the march column by column reaches (it moves along x where a column's x
/// side comes first or ties, else along y): leaving through the x side at t, the first row
/// from the entry row whose far y side is at t or beyond; through the y side, the first column
/// whose far x side is beyond t. Returns the t where it leaves.
double crossTile(const MarchLine& line, int W, int H, int T, double tIn, int& i, int& j)
{
  const int ei = line.sx > 0 ? std::min(W, (i / T + 1) * T) - 1 : (i / T) * T;
  const int ej = line.sy > 0 ? std::min(H, (j / T + 1) * T) - 1 : (j / T) * T;
  const double sideX = line.boundary(0, line.sx, ei, W), sideY = line.boundary(1, line.sy, ej, H);
  const double tOut = std::max(tIn, std::min({ sideX, sideY, line.tMax }));
  // The first cell from the entry whose far side the ray has not crossed at t (for columns,
  // with ties: the march moves along x on a tie): from the cell the exit point projects to,
  // corrected against the sides.
  const auto exitCell = [&](int axis, int s, int size, int entry, int last, double t, bool ties)
  {
    if (s == 0)
    {
      return entry;
    }
    const double x = line.pixelAt(axis, t, size);
    const int lo = std::min(entry, last), hi = std::max(entry, last);
    int c = std::isfinite(x) ? static_cast<int>(std::clamp(std::floor(x), double(lo), double(hi))) : entry;
    const auto crossed = [&](int cell)
    {
      const double side = line.boundary(axis, s, cell, size);
      return ties ? side <= t : side < t;
    };
    while (c != last && crossed(c))
    {
      c += s;
    }
    while (c != entry && !crossed(c - s))
    {
      c -= s;
    }
    return c;
  };
  if (sideX <= sideY)
  {
    j = exitCell(1, line.sy, H, j, ej, sideX, false);
    i = ei + line.sx;
  }
  else
  {
    i = exitCell(0, line.sx, W, i, ei, sideY, true);
    j = ej + line.sy;
  }
  return tOut;
}

/// A hit at the side of column p where the ray enters it at depth za (inside/outside changed
/// there): its normal is that of the column's depth value nearest to za.
MarchHit sideHit(const FluidSpans& spans, std::size_t p, double tIn, double za)
{
  MarchHit result{ true, tIn, p, -1 };
  double best = Infinity;
  for (int s = 0; s < 2 * spans.count[p]; ++s)
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

/// The first stored depth of column p along the ray between the depths za (excluded, with a
/// relative margin) and zb where it enters and leaves the column; no hit when there is none.
MarchHit storedDepthHit(const FluidSpans& spans,
  const MarchLine& line,
  std::size_t p,
  double za,
  double zb)
{
  const int slots = 2 * spans.count[p];
  const double eps = 1e-6 * std::abs(za);
  if (line.zd > 0)
  {
    for (int s = 0; s < slots; ++s)
    {
      const double z = spans.depth[spans.slot(p, s)];
      if (z > za + eps && z <= zb)
      {
        return { true, (z - line.z0) / line.zd, p, s };
      }
    }
  }
  else if (line.zd < 0)
  {
    for (int s = slots - 1; s >= 0; --s)
    {
      const double z = spans.depth[spans.slot(p, s)];
      if (z < za - eps && z >= zb)
      {
        return { true, (z - line.z0) / line.zd, p, s };
      }
    }
  }
  return {};
}

/// Moves (i, j) to the column the start point of `line` projects to, a point on the side
/// between two columns (a hit at a column's side) into the one it moves into: every far side
/// the ray crosses must lie ahead of it (MarchLine::boundary never returns a side behind it:
/// the march would stay in that column).
void startColumn(const MarchLine& line, int W, int H, int& i, int& j)
{
  const auto startCell = [&](int axis, int s, int size, int& cell)
  {
    const double x = line.pixelAt(axis, 0.0, size);
    if (!std::isfinite(x))
    {
      return;
    }
    cell = static_cast<int>(
      std::clamp(s < 0 ? std::ceil(x) - 1.0 : std::floor(x), -1.0, double(size)));
    if (s != 0 && cell >= 0 && cell < size && line.boundary(axis, s, cell, size) == Infinity)
    {
      cell += s; // its far side rounds to just behind the start: already crossed
    }
  };
  startCell(0, line.sx, W, i);
  startCell(1, line.sy, H, j);
}

/// The march's empty-space skipping: at each column, the coarsest tile level whose tile around
/// it is clear for the ray's state over the ray's depths until it leaves the tile is crossed
/// in one step (each tile tried once per level: the one last found not clear is remembered).
struct TileSkipper
{
  const MarchTiles* tiles; // MarchLevels levels, or null: no skipping
  std::array<int, MarchLevels> triedX, triedY;

  explicit TileSkipper(const MarchTiles* t)
    : tiles(t)
  {
    triedX.fill(-1);
    triedY.fill(-1);
  }
  /// Whether the ray at column (i, j) from tIn crossed a tile: then tIn and (i, j) are where
  /// it left it.
  bool skip(const MarchLine& line, int W, int H, bool inside, double& tIn, int& i, int& j)
  {
    for (int level = 0; tiles && level < MarchLevels; ++level)
    {
      const MarchTiles& m = tiles[level];
      const int T = m.TileSize;
      if ((i / T == triedX[level] && j / T == triedY[level]) || !m.anyClear(i, j, inside))
      {
        continue;
      }
      int ni = i, nj = j;
      const double tLeave = crossTile(line, W, H, T, tIn, ni, nj);
      if (m.clear(i, j, inside, line.z0 + line.zd * tIn, line.z0 + line.zd * tLeave))
      {
        tIn = tLeave;
        i = ni;
        j = nj;
        return true;
      }
      triedX[level] = i / T;
      triedY[level] = j / T;
    }
    return false;
  }
};

/// Listing 2: marches the ray o + t d (t >= 0, d unit, model coordinates; inside tells
/// whether it starts in the fluid) through the columns from the one its start projects to
/// (startColumn; (i, j) the column it was found in), pixel boundary to pixel boundary along
/// its projection. In each column it meets [za, zb] of depth: a change
/// of inside/outside at the column's side is a hit there; else the first stored depth in
/// (za, zb] along the ray is. Without a hit before the grid's depth range or the screen
/// ends, the ray escapes at the t where it leaves. With `tiles`, a tile whose bins over the
/// ray's depths there are clear for its state is crossed in one step, from where the ray
/// enters it to where it leaves (TileSkipper).
MarchHit march(const FluidSpans& spans,
  const MarchTiles* tiles,
  const ViewRays& rays,
  const Vec3d& o,
  const Vec3d& d,
  bool inside,
  int i,
  int j,
  Tally& t)
{
  const MarchLine line(spans, rays, o, d);
  const int W = spans.width, H = spans.height;
  startColumn(line, W, H, i, j);
  double tIn = 0;
  int ti = -1, tj = -1; // the column whose sides tx, ty are
  double tx = Infinity, ty = Infinity;
  TileSkipper skipper(tiles);
  for (bool first = true; i >= 0 && i < W && j >= 0 && j < H && tIn < line.tMax; first = false)
  {
    if (skipper.skip(line, W, H, inside, tIn, i, j))
    {
      ++t.columns;
      ++t.tileSkips;
      continue;
    }
    // The column's far sides, computed again only when the ray has moved along that axis.
    if (i != ti)
    {
      ti = i;
      tx = line.boundary(0, line.sx, i, W);
    }
    if (j != tj)
    {
      tj = j;
      ty = line.boundary(1, line.sy, j, H);
    }
    const double tOut = std::max(tIn, std::min({ tx, ty, line.tMax }));
    const double za = line.z0 + line.zd * tIn, zb = line.z0 + line.zd * tOut;
    const std::size_t p = spans.pixel(i, j);
    ++t.columns;
    if (!first && insideAt(spans, p, za) != inside)
    {
      return sideHit(spans, p, tIn, za);
    }
    const MarchHit hit = storedDepthHit(spans, line, p, za, zb);
    if (hit.hit)
    {
      return hit;
    }
    if (tx <= ty)
    {
      i += line.sx;
    }
    else
    {
      j += line.sy;
    }
    tIn = tOut;
  }
  MarchHit escaped;
  escaped.t = std::min(tIn, line.tMax);
  return escaped;
}

/// The front surface seen through a pixel: its depth, the pixel's ray direction B (|B| per
/// unit of depth), the point and its outward normal (model coordinates).
struct FrontSurface
{
  double z;
  Vec3d B, P, N;
};

/// Calls fn(i, j, p, front, tally) for every pixel with fluid, square blocks of BlockSize
/// pixels in parallel (neighbouring paths march through the same columns: a block's columns
/// stay in the cache).
template<typename Fn>
void forEachFrontSurface(const FluidSpans& spans,
  const ViewRays& rays,
  tbb::combinable<Tally>& tallies,
  Fn fn)
{
  constexpr int BlockSize = 32;
  const int blocksX = (spans.width + BlockSize - 1) / BlockSize;
  const int blocksY = (spans.height + BlockSize - 1) / BlockSize;
  tbb::parallel_for(tbb::blocked_range<int>(0, blocksX * blocksY, 1),
    [&](const tbb::blocked_range<int>& r)
    {
      Tally& t = tallies.local();
      for (int b = r.begin(); b != r.end(); ++b)
      {
        const int i0 = (b % blocksX) * BlockSize, j0 = (b / blocksX) * BlockSize;
        for (int j = j0; j < std::min(spans.height, j0 + BlockSize); ++j)
        {
          for (int i = i0; i < std::min(spans.width, i0 + BlockSize); ++i)
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

/// The ambient occlusion of every front surface (section 3.6; 1 where there is no fluid).
std::vector<float> frontSurfaceOcclusion(const FluidSpans& spans,
  const ViewRays& rays,
  const FluidRenderParameters& params,
  tbb::combinable<Tally>& tallies)
{
  std::vector<float> occlusion(static_cast<std::size_t>(spans.width) * spans.height, 1.f);
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
  return occlusion;
}

/// The fluid's look (the file comment of FluidRenderer.h): the lit parts D and S of a surface
/// point (Lighting.h, world space) with its surface colour C, the transmittance
/// exp(-kappa_c s) of a path of length s through the medium and the albedo omega_c.
struct FluidLook
{
  const FluidRenderParameters& params;
  Vec3d origin;
  Vec3d kappa;
  Vec3d omega;

  FluidLook(const FluidRenderParameters& p, const Vec3d& o)
    : params(p)
    , origin(o)
    , kappa(p.absorptionColor * p.density)
  {
    // omega_c = min_k kappa_k / kappa_c: the grey scattering over channel c's extinction.
    const double sigma = std::min({ kappa.x, kappa.y, kappa.z });
    for (int c = 0; c < 3; ++c)
    {
      omega[c] = kappa[c] > 0 ? sigma / kappa[c] : 1.0;
    }
  }
  /// Point p, outward normal n and view direction d in model coordinates (p origin-relative).
  ShadedParts lit(const Vec3d& pModel, const Vec3d& nModel, const Vec3d& dModel, Tally& t) const
  {
    const Vec3d nWorld = normalize(applyMatrix(params.normalToWorld, 3, nModel, false));
    const Vec3d dWorld = normalize(applyMatrix(params.modelToWorld, 4, dModel, false));
    const Vec3d pWorld = applyMatrix(params.modelToWorld, 4, pModel + origin, true);
    const Vec3d C =
      params.colors
        ? fluidColorAt(*params.colorParticles, *params.colors, pModel, params.color, t.colorSamples)
        : params.color;
    return shadeParts(params.lights, params.material, C, pWorld, nWorld, -dWorld);
  }
  Vec3d attenuation(double s) const
  {
    return Vec3d(std::exp(-kappa.x * s), std::exp(-kappa.y * s), std::exp(-kappa.z * s));
  }
};

/// What a pixel shows: premultiplied colour and the transmittance `through` to the background.
struct PixelLight
{
  Vec3d rgb, through;
};

/// Traces pixel (i, j)'s refraction path (section 3.5, the file comment) from its front
/// surface f (seen along the unit direction d, diffuse lit colour D) through at most `bounces`
/// surface events. At each event at o with outward normal `normal`, the Fresnel reflectance R
/// of the interface takes w R D to the pixel and the path refracts with weight w (1 - R)
/// (under total internal reflection, R = 1, it reflects, keeping w); between events it marches
/// to the next surface, scattering and absorbing inside the medium: w_c omega_c (1 -
/// exp(-kappa_c s)) D_c to the pixel, w_c exp(-kappa_c s) left. A path still inside after its
/// bounces is absorbed (w omega D to the pixel), one that left reaches the background with its
/// weight. Inlined into the pixel loop: with
/// -march=native the compiler fuses multiplies and adds (FMA) differently in a call, and the
/// chaotic paths (total internal reflection) then change a few pixels.
[[gnu::always_inline]] inline PixelLight refract(const FluidSpans& spans,
  const MarchTiles* tiles,
  const ViewRays& rays,
  const FluidLook& look,
  const FrontSurface& f,
  const Vec3d& d,
  const Vec3d& D,
  int i,
  int j,
  Tally& t)
{
  ++t.paths;
  const double eta = look.params.refractiveIndex;
  const int bounces = std::max(0, look.params.bounces);
  Vec3d rgb, w(1, 1, 1), o = f.P, dir = d, normal = f.N;
  bool inside = false;
  int ci = i, cj = j; // the column the path is in
  for (int event = 0;; ++event)
  {
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
      rgb += w * D * R;
      w = w * (1.0 - R);
      const double ratio = inside ? eta : 1.0 / eta;
      dir = normalize(dir * ratio + facing * (ratio * cosI - cosT));
      inside = !inside;
    }
    if (event + 1 >= bounces)
    {
      break;
    }
    const MarchHit hit = march(spans, tiles, rays, o, dir, inside, ci, cj, t);
    const double s = std::max(0.0, hit.t);
    if (inside)
    {
      const Vec3d a = look.attenuation(s);
      rgb += w * look.omega * D * (Vec3d(1, 1, 1) - a);
      w = w * a;
    }
    if (!hit.hit)
    {
      inside = false; // left the grid: on to the background
      break;
    }
    o = o + dir * s;
    ci = static_cast<int>(hit.pixel % spans.width);
    cj = static_cast<int>(hit.pixel / spans.width);
    normal =
      hit.slot >= 0 ? Vec3d(decodeNormal(spans.normals[spans.slot(hit.pixel, hit.slot)])) : -dir;
  }
  if (inside)
  {
    rgb += w * look.omega * D; // out of bounces inside the fluid: absorbed
    return { rgb, Vec3d(0, 0, 0) };
  }
  return { rgb, w };
}

/// Writes a pixel: its premultiplied colour, alpha = 1 - mean_c T_c, and the window depth of
/// its front surface point P.
void writePixel(Frame& frame,
  const ViewRays& rays,
  int i,
  int j,
  const PixelLight& light,
  const Vec3d& P)
{
  float* out = &frame.rgba[4 * frame.index(i, j)];
  out[0] = static_cast<float>(light.rgb.x);
  out[1] = static_cast<float>(light.rgb.y);
  out[2] = static_cast<float>(light.rgb.z);
  out[3] = static_cast<float>(1.0 - (light.through.x + light.through.y + light.through.z) / 3.0);
  const std::array<double, 4> c = rays.clip(P);
  frame.depth[frame.index(i, j)] =
    static_cast<float>(std::clamp(0.5 * (c[2] / c[3] + 1.0), 0.0, 1.0));
}

/// The tallies by their counters' names in the statistics.
constexpr TallyField<Tally> Tallies[] = { { "shaded_pixels", &Tally::shaded },
  { "translucent_pixels", &Tally::translucent },
  { "refraction_paths", &Tally::paths },
  { "surface_events", &Tally::events },
  { "tir_events", &Tally::tir },
  { "march_columns", &Tally::columns },
  { "march_tile_skips", &Tally::tileSkips },
  { "ao_samples", &Tally::aoSamples },
  { "color_samples", &Tally::colorSamples } };
}

void renderFluidSpans(const FluidSpans& spans,
  const ViewRays& rays,
  const Vec3d& origin,
  const FluidRenderParameters& params,
  Frame& frame,
  RenderStatistics& stats)
{
  RAYMAPPERS_SIMD_FORWARD(renderFluidSpans, spans, rays, origin, params, frame, stats);
  const bool refraction =
    params.translucency && params.refractiveIndex != 1.0 && params.bounces > 0;
  const bool ao = params.ambientOcclusion && params.aoSamples > 0 && params.aoRadius > 0;
  stats.setEffect("translucency", params.translucency);
  stats.setEffect("refraction", refraction);
  stats.setEffect("ambient_occlusion", ao);
  stats.setEffect("particle_colors", params.colors != nullptr);
  for (const TallyField<Tally>& f : Tallies)
  {
    stats.declareCounter(f.name);
  }
  frame.resize(spans.width, spans.height);
  if (spans.normals.size() != spans.depth.size())
  {
    return;
  }
  tbb::combinable<Tally> tallies;
  std::vector<float> occlusion;
  if (ao)
  {
    ScopedPhase phase(stats, "ao");
    occlusion = frontSurfaceOcclusion(spans, rays, params, tallies);
  }

  ScopedPhase phase(stats, refraction ? "refract" : "render");
  const FluidLook look(params, origin);
  std::vector<MarchTiles> tiles;
  if (refraction && params.marchTileSkipping)
  {
    for (const int size : MarchTileSizes)
    {
      tiles.emplace_back(spans, size);
    }
  }
  forEachFrontSurface(spans,
    rays,
    tallies,
    [&](int i, int j, std::size_t p, const FrontSurface& f, Tally& t)
    {
      const Vec3d d = normalize(f.B);
      const ShadedParts L = look.lit(f.P, f.N, d, t);
      const double A = ao ? double(occlusion[p]) : 1.0;
      const Vec3d D = L.diffuse * A, S = L.specular * A;
      ++t.shaded;
      PixelLight light{ D + S, Vec3d(0, 0, 0) };
      if (params.translucency && !refraction)
      {
        // Beer-Lambert over the whole thickness; the medium scatters omega D (1 - T) back.
        light.through = look.attenuation(spans.thickness(p) * length(f.B));
        light.rgb = S + look.omega * D * (Vec3d(1, 1, 1) - light.through);
        ++t.translucent;
      }
      else if (refraction)
      {
        light = refract(spans, tiles.empty() ? nullptr : tiles.data(), rays, look, f, d, D, i, j, t);
        light.rgb += S;
      }
      writePixel(frame, rays, i, j, light, f.P);
    });
  addTallies(
    Tallies, [&](auto add) { tallies.combine_each(add); }, stats);
}

bool renderFluid(const FluidScene& scene,
  const View& view,
  const FluidRenderParameters& params,
  Frame& frame,
  RenderStatistics& stats)
{
  RAYMAPPERS_SIMD_FORWARD(renderFluid, scene, view, params, frame, stats);
  const FluidParticles& particles = scene.particles;
  FluidSpans& spans = scene.spans;
  const ViewRays& rays = view.depthRays();
  stats.addCounter("particles_skipped",
    static_cast<std::int64_t>(particles.skippedNonFinite + particles.skippedBadRadius));
  // Opaque geometry drawn before ends the fluid: its window depths as depths along the rays.
  VoxelizerParameters voxelizer = params.voxelizer;
  const std::vector<float> stop =
    view.opaqueDepth() ? stopDepthsFromWindowDepth(rays, view.opaqueDepth()) : std::vector<float>();
  if (view.opaqueDepth())
  {
    voxelizer.stopDepth = stop.data();
  }
  if (!voxelizeFluid(particles, rays, voxelizer, spans, stats))
  {
    frame.resize(rays.width(), rays.height());
    return false;
  }
  connectSurfaces(spans, stats);
  SurfaceNeighbourhoods ownNeighbourhoods;
  SurfaceNeighbourhoods& neighbourhoods =
    scene.neighbourhoods ? *scene.neighbourhoods : ownNeighbourhoods;
  findNeighbourhoods(spans, neighbourhoods, stats);
  smoothSurfaces(
    spans, neighbourhoods, rays, params.smoothingRadius, params.smoothingIterations, stats);
  computeNormals(spans, neighbourhoods, rays, stats);
  stats.addCounter("spans_bytes", static_cast<std::int64_t>(spans.bytes()));
  // (In parentheses: this variant's own, not also the entry point found by argument lookup.)
  (renderFluidSpans)(spans, rays, particles.origin, params, frame, stats);
  return true;
}

RAYMAPPERS_SIMD_END

} // namespace raymappers
