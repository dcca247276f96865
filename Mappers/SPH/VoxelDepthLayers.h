// The depth layers of the voxelizer's perspective grid (Zirr 2015, section 4.2).
//
// A surface coplanar to the viewer and a neighbouring one bent towards it by one cell
// differ in angle by alpha with tan(alpha) = c_d / c_w (cell depth over cell width). In a
// perspective grid the cell width grows with depth, c_w = sigma d with sigma the pixel size
// at depth 1 (2 tan(theta_y / 2) / R_y, ViewRays::pixelSize), so keeping alpha constant
// gives cells of depth c_d = K d with K = sigma tan(alpha), and layer i starts at
//   d_i = (1 + K)^i d_0,      i(d) = floor(log(d / d_0) / log(1 + K)).
// A parallel view has cells of constant width sigma, so its layers are uniform:
// d_i = d_0 + i sigma tan(alpha).
// The layers cover [d_0, d_L] (the part of the view frustum the particles occupy); when the
// angle resolution asks for more than `maxLayers` layers, K (or the uniform step) grows so
// that maxLayers layers cover the range, and the angle actually reached is coarser.
#ifndef RayMappers_VoxelDepthLayers_h
#define RayMappers_VoxelDepthLayers_h

#include <algorithm>
#include <cmath>
#include <vector>

namespace raymappers
{

struct VoxelDepthLayers
{
  bool logarithmic = true;
  double d0 = 1.0;            // depth of the first layer's front
  double step = 0.0;          // log(1 + K) (logarithmic) or the layer depth (uniform)
  int count = 0;              // layers L
  std::vector<double> depths; // d_0 .. d_L: layer i spans [depths[i], depths[i + 1])

  /// Layers over [zFront, zBack] for the angle resolution alpha (degrees) and pixel size
  /// sigma, at most maxLayers of them.
  void assign(bool perspective,
    double zFront,
    double zBack,
    double sigma,
    double alphaDeg,
    int maxLayers)
  {
    logarithmic = perspective;
    d0 = zFront;
    const double t = std::tan(std::clamp(alphaDeg, 1e-3, 89.0) * 3.14159265358979323846 / 180.0);
    const double extent = logarithmic ? std::log(zBack / zFront) : zBack - zFront;
    step = logarithmic ? std::log1p(sigma * t) : sigma * t;
    const double needed = std::ceil(extent / step - 1e-9);
    count = static_cast<int>(std::clamp(needed, 1.0, static_cast<double>(std::max(1, maxLayers))));
    if (needed > count)
    {
      step = extent / count;
    }
    depths.resize(static_cast<std::size_t>(count) + 1);
    for (int i = 0; i <= count; ++i)
    {
      depths[i] = depth(i);
    }
    depths[count] = std::max(depths[count], zBack);
  }
  double depth(double i) const { return logarithmic ? d0 * std::exp(i * step) : d0 + i * step; }
  /// The (fractional) layer coordinate of depth z: layer floor(coordinate(z)) holds z.
  double coordinate(double z) const
  {
    return logarithmic ? (z > 0 ? std::log(z / d0) / step : -1e30) : (z - d0) / step;
  }
  /// The layer holding z (clamped to [0, L - 1]) from the layer coordinate `u` of a depth
  /// near z (e.g. a Taylor polynomial of coordinate about a nearby depth), corrected against
  /// the depth table so the answer is exact for the table.
  int layerOf(double z, double u) const
  {
    int l = static_cast<int>(std::clamp(std::floor(u), 0.0, count - 1.0));
    while (l > 0 && depths[l] > z)
    {
      --l;
    }
    while (l + 1 < count && depths[l + 1] <= z)
    {
      ++l;
    }
    return l;
  }
  /// The angle resolution reached (degrees) for pixel size sigma.
  double angleDeg(double sigma) const
  {
    const double cd = logarithmic ? std::expm1(step) : step;
    return std::atan(cd / sigma) * 180.0 / 3.14159265358979323846;
  }
};

} // namespace raymappers

#endif
