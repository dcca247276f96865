// The typical particle spacing (ParticleSpacing.h) against a brute-force reference written
// here: every point's nearest distinct neighbour among all points, O(N^2), and their median.
// The kernel medians over a sample only, so on irregular sets the two agree statistically;
// on a lattice every distance is the lattice step and they agree exactly.
#include "Mappers/Common/ParticleSpacing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace
{
using raymappers::Vec3d;

double spacingOf(const std::vector<Vec3d>& points, std::size_t sampleSize = 1024)
{
  return raymappers::typicalParticleSpacing(
    points.size(), [&](std::size_t i) { return points[i]; }, sampleSize);
}

/// The reference: median over all points of the distance to the nearest point at a
/// different position.
double bruteForceMedian(const std::vector<Vec3d>& points)
{
  std::vector<double> nearest;
  for (const Vec3d& p : points)
  {
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3d& q : points)
    {
      const double dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
      const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
      if (d > 0.0 && d < best)
      {
        best = d;
      }
    }
    nearest.push_back(best);
  }
  std::sort(nearest.begin(), nearest.end());
  return nearest[nearest.size() / 2];
}

std::vector<Vec3d> lattice(int n, double step, double scale = 1.0)
{
  std::vector<Vec3d> points;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        points.emplace_back(scale * (3.0 + i * step), scale * (-1.0 + j * step), scale * k * step);
  return points;
}

/// A Plummer sphere: density ~ (1 + r^2/a^2)^(-5/2), a dense core and sparse outskirts.
std::vector<Vec3d> plummer(std::size_t n, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(1e-6, 1.0 - 1e-6), v(-1.0, 1.0);
  std::vector<Vec3d> points;
  const double pi = std::acos(-1.0);
  while (points.size() < n)
  {
    const double r = 1.0 / std::sqrt(std::pow(u(rng), -2.0 / 3.0) - 1.0);
    const double c = v(rng), phi = 2.0 * pi * u(rng), s = std::sqrt(1.0 - c * c);
    points.emplace_back(r * s * std::cos(phi), r * s * std::sin(phi), r * c);
  }
  return points;
}
}

TEST(ParticleSpacing, LatticeIsItsStepAtEveryScale)
{
  for (double scale : { 1e-3, 1.0, 1e3 })
  {
    const std::vector<Vec3d> points = lattice(16, 0.1, scale);
    EXPECT_NEAR(spacingOf(points), 0.1 * scale, 1e-9 * scale) << "scale " << scale;
  }
}

TEST(ParticleSpacing, UniformRandomMatchesTheBruteForceMedian)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 2.0);
  std::vector<Vec3d> points;
  for (int i = 0; i < 4000; ++i)
    points.emplace_back(u(rng), u(rng), 0.5 * u(rng));
  const double reference = bruteForceMedian(points);
  EXPECT_NEAR(spacingOf(points), reference, 0.05 * reference);
}

TEST(ParticleSpacing, ClusteredSetMatchesTheBruteForceMedian)
{
  // With every point sampled the kernel's median is the reference's exactly; with a quarter
  // of them, within the median's sampling error.
  for (unsigned seed : { 3u, 4u, 5u })
  {
    const std::vector<Vec3d> points = plummer(4000, seed);
    const double reference = bruteForceMedian(points);
    EXPECT_DOUBLE_EQ(spacingOf(points, points.size()), reference) << "seed " << seed;
    EXPECT_NEAR(spacingOf(points), reference, 0.12 * reference) << "seed " << seed;
  }
}

TEST(ParticleSpacing, PlaneOfPointsAndLargeSetUseTheWholeSet)
{
  // 2D data (z = 0) and more points than the sample: 300 x 300 unit lattice.
  std::vector<Vec3d> points;
  for (int j = 0; j < 300; ++j)
    for (int i = 0; i < 300; ++i)
      points.emplace_back(i * 0.25, j * 0.25, 0.0);
  EXPECT_NEAR(spacingOf(points), 0.25, 1e-12);
}

TEST(ParticleSpacing, CoincidentPointsAreNotNeighbours)
{
  std::vector<Vec3d> points = lattice(10, 0.5);
  const std::vector<Vec3d> copy = points;
  points.insert(points.end(), copy.begin(), copy.end());
  EXPECT_NEAR(spacingOf(points), 0.5, 1e-12);
}

TEST(ParticleSpacing, NonFinitePointsAndAFarOutlierChangeNothing)
{
  std::vector<Vec3d> points = lattice(12, 0.2);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < points.size(); i += 7)
    points.insert(points.begin() + static_cast<std::ptrdiff_t>(i), Vec3d(nan, 0.0, inf));
  points.emplace_back(1e30, -1e30, 1e30);
  EXPECT_NEAR(spacingOf(points), 0.2, 1e-12);
}

TEST(ParticleSpacing, FewerThanTwoDistinctPointsGiveZero)
{
  EXPECT_EQ(spacingOf({}), 0.0);
  EXPECT_EQ(spacingOf({ Vec3d(1, 2, 3) }), 0.0);
  EXPECT_EQ(spacingOf(std::vector<Vec3d>(50, Vec3d(1, 2, 3))), 0.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(spacingOf(std::vector<Vec3d>(5, Vec3d(nan, nan, nan))), 0.0);
}

TEST(ParticleSpacing, TightClusterWithSparseHaloIsTheClustersSpacing)
{
  // 90% of the points in a cluster 1e-6 the size of the domain: the median is the cluster's.
  std::vector<Vec3d> points = lattice(20, 1e-8);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 800; ++i)
    points.emplace_back(u(rng), u(rng), u(rng));
  EXPECT_NEAR(spacingOf(points), 1e-8, 1e-14);
}

TEST(ParticleSpacing, SampledPointsWithFarNeighboursWidenTheSearch)
{
  // 65,536 points; the 1,024 of the sample form a lattice of step 1 and all others a lattice
  // of step 0.1 far away: the first guess from density scaling is a quarter of the answer,
  // so only the widened passes find it.
  std::vector<Vec3d> points, sample;
  for (std::size_t k = 0; k < 1024; ++k)
  {
    sample.emplace_back(double(k % 8), double(k / 8 % 8), double(k / 64));
    points.push_back(sample.back());
  }
  for (std::size_t k = 0; points.size() < 65536; ++k)
  {
    points.emplace_back(1000.0 + 0.1 * double(k % 48), 0.1 * double(k / 48 % 48), 0.1 * double(k / 2304));
  }
  const std::vector<double> d = raymappers::sampleNeighbourDistances(
    points.size(), [&](std::size_t i) { return points[i]; }, sample);
  ASSERT_EQ(d.size(), sample.size());
  EXPECT_NEAR(raymappers::medianSpacing(d), 1.0, 1e-12);
}

// Two spatial halves of a set, each sampling its share (512 of the 1024) and gathering the
// distances, give the whole set's median spacing within the sampling's noise and the few
// sample points whose neighbour lies across the cut. (The representations' use of it on
// several ranks is checked by Python.TestDistributedRendering.spheres.2ranks at the
// automatic radius.)
TEST(ParticleSpacing, PiecesGatherTheSpacingOfTheWholeSet)
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3d> points(60000);
  for (Vec3d& p : points)
  {
    p = Vec3d(u(rng), u(rng), u(rng));
  }
  std::vector<Vec3d> left, right;
  for (const Vec3d& p : points)
  {
    (p.x < 0.5 ? left : right).push_back(p);
  }
  std::vector<double> gathered;
  for (const std::vector<Vec3d>* piece : { &left, &right })
  {
    const std::size_t share = 1024 * piece->size() / points.size();
    const std::vector<double> d = raymappers::spacingSampleDistances(
      piece->size(), [&](std::size_t i) { return (*piece)[i]; }, share);
    EXPECT_EQ(d.size(), share);
    gathered.insert(gathered.end(), d.begin(), d.end());
  }
  const double serial = spacingOf(points);
  EXPECT_NEAR(raymappers::medianSpacing(gathered), serial, 0.02 * serial);
}
