#include "ReferenceRenderers.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <functional>
#include <limits>

namespace raymappers::reference
{

namespace
{
constexpr double pi = 3.14159265358979323846;

// Runs f(i, j) for every pixel, rows in parallel.
void forEachPixel(const ReferenceCamera& camera, const std::function<void(int, int)>& f)
{
  tbb::parallel_for(0,
    camera.height(),
    [&](int j)
    {
      for (int i = 0; i < camera.width(); ++i)
      {
        f(i, j);
      }
    });
}

// The ray parameters where the ray meets the sphere (c, r): t = -b -+ sqrt(b^2 - |f|^2 + r^2)
// with f = o - c, b = f.d; false when it misses.
bool sphereRoots(const PixelRay& ray, Point c, double r, double& t0, double& t1)
{
  const Point f = ray.origin - c;
  const double b = dot(f, ray.direction);
  const double disc = b * b - (dot(f, f) - r * r);
  if (disc < 0)
  {
    return false;
  }
  const double s = std::sqrt(disc);
  t0 = -b - s;
  t1 = -b + s;
  return true;
}

// The first hit in [0, length] (the far root when the ray starts inside) over the spheres
// `candidates` lists, in their order: the sphere's index and t, or -1.
int firstHit(const PixelRay& ray,
  const std::vector<ReferenceSphere>& spheres,
  const std::vector<int>& candidates,
  double& tHit)
{
  int best = -1;
  tHit = std::numeric_limits<double>::infinity();
  for (const int k : candidates)
  {
    double t0, t1;
    if (!sphereRoots(ray, spheres[k].center, spheres[k].radius, t0, t1))
    {
      continue;
    }
    const double t = t0 >= 0 ? t0 : t1;
    if (t >= 0 && t <= ray.length && t < tHit)
    {
      tHit = t;
      best = k;
    }
  }
  return best;
}

constexpr int TileSide = 16;

// For each tile of TileSide x TileSide pixels, in index order, the spheres whose screen
// rectangle meets it. The rectangle bounds the projections of the corners of the sphere's
// bounding box (a convex set in front of the eye projects inside the hull of its corners'
// projections), one pixel wider on each side; a sphere with a corner behind the eye plane
// covers every tile. Every pixel whose ray can hit a sphere is in a tile listing it, so a
// search over the tile's list finds what a search over all spheres finds.
std::vector<std::vector<int>> tileCandidates(const ReferenceCamera& camera,
  const std::vector<ReferenceSphere>& spheres)
{
  const int tx = (camera.width() + TileSide - 1) / TileSide;
  const int ty = (camera.height() + TileSide - 1) / TileSide;
  std::vector<std::vector<int>> tiles(static_cast<std::size_t>(tx) * ty);
  for (std::size_t k = 0; k < spheres.size(); ++k)
  {
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    bool behind = false;
    for (int corner = 0; corner < 8; ++corner)
    {
      const double r = spheres[k].radius;
      const Point p =
        spheres[k].center + Point{ corner & 1 ? r : -r, corner & 2 ? r : -r, corner & 4 ? r : -r };
      double x, y;
      behind = behind || !camera.project(p, x, y);
      x0 = std::min(x0, x);
      x1 = std::max(x1, x);
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
    }
    const auto tileOf = [](double pixel, int count)
    { return std::clamp(static_cast<int>(std::floor(pixel / TileSide)), 0, count - 1); };
    const int i0 = behind ? 0 : tileOf(x0 - 1, tx), i1 = behind ? tx - 1 : tileOf(x1 + 1, tx);
    const int j0 = behind ? 0 : tileOf(y0 - 1, ty), j1 = behind ? ty - 1 : tileOf(y1 + 1, ty);
    if (!behind && (x1 < -1 || x0 > camera.width() || y1 < -1 || y0 > camera.height()))
    {
      continue;
    }
    for (int j = j0; j <= j1; ++j)
    {
      for (int i = i0; i <= i1; ++i)
      {
        tiles[static_cast<std::size_t>(j) * tx + i].push_back(static_cast<int>(k));
      }
    }
  }
  return tiles;
}

const std::vector<int>& candidatesAt(const std::vector<std::vector<int>>& tiles,
  const ReferenceCamera& camera,
  int i,
  int j)
{
  const int tx = (camera.width() + TileSide - 1) / TileSide;
  return tiles[static_cast<std::size_t>(j / TileSide) * tx + i / TileSide];
}

// A particle's stretch of a ray: the interval where its support (centre c, reach R) holds the
// ray, and its index.
struct Stretch
{
  double tIn, tOut;
  std::size_t index;
};

// The stretches of every particle whose support the ray crosses inside [0, length], by tIn.
template<typename Reach>
std::vector<Stretch> stretchesAlong(const PixelRay& ray,
  std::size_t count,
  const std::function<Point(std::size_t)>& center,
  Reach reach)
{
  std::vector<Stretch> out;
  for (std::size_t k = 0; k < count; ++k)
  {
    double t0, t1;
    if (sphereRoots(ray, center(k), reach(k), t0, t1) && t1 >= 0 && t0 <= ray.length)
    {
      out.push_back({ std::max(t0, 0.0), std::min(t1, ray.length), k });
    }
  }
  std::sort(
    out.begin(), out.end(), [](const Stretch& a, const Stretch& b) { return a.tIn < b.tIn; });
  return out;
}

// The emission-absorption integral along the ray over the stretches. The stretches' ends cut
// the ray into pieces on which the same particles hold the points (the field is smooth
// there, and may jump only at the cuts: the normalized SPH field at the edge of the
// supports); each piece takes n = ceil(length / ds) samples at the midpoints of n equal
// segments. At each sample `classify(t, particles)` gives the colour and extinction there
// (false: nothing there), and the sample adds T (1 - exp(-tau h)) c for its segment h.
// Premultiplied RGBA.
std::array<double, 4> integrate(const std::vector<Stretch>& stretches,
  double ds,
  const std::function<bool(double, const std::vector<std::size_t>&, std::array<double, 4>&)>&
    classify)
{
  // The cuts in order, each entering (+) or leaving (-) one stretch; the particles of a
  // piece are those entered and not yet left.
  struct Cut
  {
    double t;
    bool enters;
    std::size_t stretch;
  };
  std::vector<Cut> cuts;
  for (std::size_t k = 0; k < stretches.size(); ++k)
  {
    cuts.push_back({ stretches[k].tIn, true, k });
    cuts.push_back({ stretches[k].tOut, false, k });
  }
  // At equal t a stretch enters before any leaves (a tangent stretch enters and leaves).
  std::sort(cuts.begin(),
    cuts.end(),
    [](const Cut& a, const Cut& b) { return a.t < b.t || (a.t == b.t && a.enters && !b.enters); });
  std::array<double, 4> out{ 0, 0, 0, 0 };
  double transmittance = 1;
  // particles[k] is the particle of stretch active[k]; slot[s] where stretch s sits.
  std::vector<std::size_t> particles, active, slot(stretches.size());
  for (std::size_t c = 0; c + 1 < cuts.size(); ++c)
  {
    const std::size_t s = cuts[c].stretch;
    if (cuts[c].enters)
    {
      slot[s] = active.size();
      active.push_back(s);
      particles.push_back(stretches[s].index);
    }
    else
    {
      // The last one moves into the leaving one's place.
      const std::size_t at = slot[s];
      active[at] = active.back();
      particles[at] = particles.back();
      slot[active[at]] = at;
      active.pop_back();
      particles.pop_back();
    }
    const double a = cuts[c].t, b = cuts[c + 1].t;
    if (!(b > a) || particles.empty())
    {
      continue;
    }
    const long n = std::max(1L, static_cast<long>(std::ceil((b - a) / ds)));
    const double h = (b - a) / n;
    for (long k = 0; k < n; ++k)
    {
      std::array<double, 4> cTau;
      if (!classify(a + (k + 0.5) * h, particles, cTau))
      {
        continue;
      }
      const double alpha = -std::expm1(-cTau[3] * h);
      for (int i = 0; i < 3; ++i)
      {
        out[i] += transmittance * alpha * cTau[i];
      }
      transmittance *= 1 - alpha;
    }
  }
  out[3] = 1 - transmittance;
  return out;
}

// Colour and extinction of the transfer function at value v.
std::array<double, 4> emissionAt(const ReferenceTransferFunction& tf, double v)
{
  std::array<double, 4> c = tf.at(v);
  c[3] = tf.extinction(c[3]);
  return c;
}
}

ReferenceImage renderSpheres(const ReferenceCamera& camera,
  const std::vector<ReferenceSphere>& spheres,
  const std::vector<ReferenceLight>& lights,
  const ReferenceMaterial& material)
{
  ReferenceImage image(camera.width(), camera.height());
  const auto tiles = tileCandidates(camera, spheres);
  forEachPixel(camera,
    [&](int i, int j)
    {
      const PixelRay ray = camera.ray(i, j);
      double t;
      const int k = firstHit(ray, spheres, candidatesAt(tiles, camera, i, j), t);
      if (k < 0)
      {
        return;
      }
      const Point p = ray.origin + ray.direction * t;
      const Point n = unit(p - spheres[k].center);
      const Point c = phong(lights, material, spheres[k].color, n, ray.direction * -1.0);
      image.at(i, j) = { c.x, c.y, c.z, 1.0 };
      image.depth[static_cast<std::size_t>(j) * image.width + i] = camera.windowDepth(p);
    });
  return image;
}

namespace
{
// A layer of a translucent ray: its distance, straight colour and opacity.
struct Layer
{
  double t;
  Point color;
  double opacity;
};

// The layers of a ray, unsorted: every sphere at its first surface, every plane it crosses.
std::vector<Layer> layersAlong(const PixelRay& ray,
  const std::vector<ReferenceSphere>& spheres,
  const std::vector<ReferenceLight>& lights,
  const ReferenceMaterial& material,
  const std::vector<ReferencePlane>& planes)
{
  std::vector<Layer> layers;
  for (const ReferenceSphere& s : spheres)
  {
    double t0, t1;
    if (!sphereRoots(ray, s.center, s.radius, t0, t1))
    {
      continue;
    }
    const double t = t0 >= 0 ? t0 : t1;
    if (t >= 0 && t <= ray.length)
    {
      Point n = unit(ray.origin + ray.direction * t - s.center);
      n = dot(n, ray.direction) > 0 ? n * -1.0 : n;
      layers.push_back({ t, phong(lights, material, s.color, n, ray.direction * -1.0), s.opacity });
    }
  }
  for (const ReferencePlane& p : planes)
  {
    const double t = (p.offset - dot(p.normal, ray.origin)) / dot(p.normal, ray.direction);
    if (t >= 0 && t <= ray.length)
    {
      layers.push_back({ t, p.color, p.opacity });
    }
  }
  return layers;
}
}

ReferenceImage renderTranslucentSpheres(const ReferenceCamera& camera,
  const std::vector<ReferenceSphere>& spheres,
  const std::vector<ReferenceLight>& lights,
  const ReferenceMaterial& material,
  const std::vector<ReferencePlane>& planes)
{
  ReferenceImage image(camera.width(), camera.height());
  forEachPixel(camera,
    [&](int i, int j)
    {
      const PixelRay ray = camera.ray(i, j);
      std::vector<Layer> layers = layersAlong(ray, spheres, lights, material, planes);
      if (layers.empty())
      {
        return;
      }
      std::sort(layers.begin(), layers.end(), [](const Layer& a, const Layer& b) { return a.t < b.t; });
      std::array<double, 4> c{ 0, 0, 0, 0 };
      for (const Layer& l : layers)
      {
        const double w = (1.0 - c[3]) * l.opacity;
        c = { c[0] + w * l.color.x, c[1] + w * l.color.y, c[2] + w * l.color.z, c[3] + w };
      }
      image.at(i, j) = c;
      image.depth[static_cast<std::size_t>(j) * image.width + i] =
        camera.windowDepth(ray.origin + ray.direction * layers.front().t);
    });
  return image;
}

ReferenceImage renderUnionSurface(const ReferenceCamera& camera,
  const std::vector<ReferenceSphere>& spheres)
{
  ReferenceImage image(camera.width(), camera.height());
  const auto tiles = tileCandidates(camera, spheres);
  forEachPixel(camera,
    [&](int i, int j)
    {
      const PixelRay ray = camera.ray(i, j);
      double t;
      if (firstHit(ray, spheres, candidatesAt(tiles, camera, i, j), t) >= 0)
      {
        image.at(i, j) = { 1, 1, 1, 1 };
        image.depth[static_cast<std::size_t>(j) * image.width + i] =
          camera.windowDepth(ray.origin + ray.direction * t);
      }
    });
  return image;
}

ReferenceImage renderRBF(const ReferenceCamera& camera,
  const std::vector<ReferenceGaussian>& gaussians,
  const RBFReference& params,
  const ReferenceTransferFunction& tf)
{
  ReferenceImage image(camera.width(), camera.height());
  const auto center = [&](std::size_t k) { return gaussians[k].center; };
  const auto reach = [&](std::size_t k) { return params.cutoff * gaussians[k].radius; };
  forEachPixel(camera,
    [&](int i, int j)
    {
      const PixelRay ray = camera.ray(i, j);
      const auto stretches = stretchesAlong(ray, gaussians.size(), center, reach);
      image.at(i, j) = integrate(stretches,
        params.step,
        [&](double t, const std::vector<std::size_t>& near, std::array<double, 4>& cTau)
        {
          const Point x = ray.origin + ray.direction * t;
          double phi = 0, w = 0;
          for (std::size_t k : near)
          {
            const Point d = x - gaussians[k].center;
            const double r = gaussians[k].radius;
            const double g = std::exp(-dot(d, d) / (2 * r * r));
            phi += gaussians[k].weight * g;
            w += g;
          }
          if (!params.average)
          {
            cTau = emissionAt(tf, params.kappa * phi);
            return true;
          }
          if (!(w > 0))
          {
            return false;
          }
          cTau = emissionAt(tf, phi / w);
          cTau[3] *= std::min(1.0, params.kappa * w);
          return true;
        });
    });
  return image;
}

double kernelWeight(ReferenceKernel kernel, double r, double H)
{
  const double q = r / H;
  if (q >= 1)
  {
    return 0;
  }
  const double H3 = H * H * H, a = 1 - q;
  switch (kernel)
  {
    case ReferenceKernel::Poly6:
    {
      const double b = 1 - q * q;
      return 315.0 / (64.0 * pi * H3) * b * b * b;
    }
    case ReferenceKernel::CubicSpline:
      return q <= 0.5 ? 8.0 / (pi * H3) * (1 - 6 * q * q + 6 * q * q * q)
                      : 16.0 / (pi * H3) * a * a * a;
    case ReferenceKernel::WendlandC2:
      return 21.0 / (2.0 * pi * H3) * a * a * a * a * (1 + 4 * q);
  }
  return 0;
}

ReferenceImage renderSPH(const ReferenceCamera& camera,
  const std::vector<ReferenceSPHParticle>& particles,
  const SPHReference& params,
  const ReferenceTransferFunction& tf)
{
  ReferenceImage image(camera.width(), camera.height());
  const auto center = [&](std::size_t k) { return particles[k].center; };
  const auto reach = [&](std::size_t k) { return particles[k].support; };
  forEachPixel(camera,
    [&](int i, int j)
    {
      const PixelRay ray = camera.ray(i, j);
      const auto stretches = stretchesAlong(ray, particles.size(), center, reach);
      image.at(i, j) = integrate(stretches,
        params.step,
        [&](double t, const std::vector<std::size_t>& near, std::array<double, 4>& cTau)
        {
          const Point x = ray.origin + ray.direction * t;
          double A = 0, B = 0;
          for (std::size_t k : near)
          {
            const ReferenceSPHParticle& p = particles[k];
            const double w = p.volume * kernelWeight(params.kernel, norm(x - p.center), p.support);
            A += p.quantity * w;
            B += w;
          }
          if (!(B > 0))
          {
            return false;
          }
          cTau = emissionAt(tf, params.normalized ? A / B : A);
          return true;
        });
    });
  return image;
}

}
