// The image comparison on synthetic pictures with known differences: the measures are
// exact, and the perturbations of the check of the check (10% fainter, a 2-pixel shift)
// change what they must.
#include "ImageComparison.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

using namespace raymappers::test;

namespace
{
// A W x H picture of background b with a s x s square of colour f at (x0, y0).
RGBImage square(int w,
  int h,
  int x0,
  int y0,
  int s,
  std::array<std::uint8_t, 3> f,
  std::array<std::uint8_t, 3> b)
{
  RGBImage im;
  im.width = w;
  im.height = h;
  im.rgb.resize(3 * static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y)
  {
    for (int x = 0; x < w; ++x)
    {
      const bool in = x >= x0 && x < x0 + s && y >= y0 && y < y0 + s;
      std::copy_n((in ? f : b).data(), 3, im.at(x, y));
    }
  }
  return im;
}
const std::array<std::uint8_t, 3> grey{ 20, 20, 30 };
const std::array<std::uint8_t, 3> white{ 220, 200, 180 };
}

TEST(ImageComparison, IdenticalPicturesAreEqual)
{
  const RGBImage a = square(64, 48, 10, 10, 20, white, grey);
  const ImageDifference d = compareImages(a, a, 0);
  EXPECT_TRUE(d.sameSize);
  EXPECT_EQ(d.rmse, 0.0);
  EXPECT_EQ(d.maxError, 0);
  EXPECT_EQ(d.differing, 0.0);
  EXPECT_TRUE(withinThresholds(d, ImageThresholds{ 0, 0, 0, 0 }));
}

TEST(ImageComparison, TenPercentFainterMeasuresExactly)
{
  const RGBImage a = square(64, 48, 10, 10, 20, white, grey);
  EXPECT_EQ(dominantColor(a), grey);
  const RGBImage f = movedToward(a, grey, 0.1);
  // The square's channels move by 0.1 (220-20, 200-20, 180-30) = 20, 18, 15 levels.
  EXPECT_EQ(f.at(15, 15)[0], 200);
  EXPECT_EQ(f.at(15, 15)[1], 182);
  EXPECT_EQ(f.at(15, 15)[2], 165);
  EXPECT_EQ(f.at(0, 0)[0], 20);
  const ImageDifference d = compareImages(a, f, 2);
  const double pixels = 64.0 * 48.0, inside = 400.0;
  EXPECT_NEAR(d.rmse, std::sqrt(inside * (400.0 + 324.0 + 225.0) / (3 * pixels)), 1e-12);
  EXPECT_EQ(d.maxError, 20);
  EXPECT_DOUBLE_EQ(d.differing, inside / pixels);
  // Differences of 15 to 20 levels pass a tolerance of 20, with no pixel counted.
  EXPECT_EQ(compareImages(a, f, 20).differing, 0.0);
}

TEST(ImageComparison, TwoPixelShiftChangesTheEdgeBands)
{
  const RGBImage a = square(64, 48, 10, 10, 20, white, grey);
  const RGBImage s = shifted(a, 2, 0);
  EXPECT_EQ(s.at(12, 15)[0], 220);
  EXPECT_EQ(s.at(11, 15)[0], 20);
  // Two columns of 20 pixels enter the square on one side and leave it on the other.
  const ImageDifference d = compareImages(a, s, 2);
  EXPECT_DOUBLE_EQ(d.differing, 80.0 / (64 * 48));
  EXPECT_EQ(d.maxError, 200);
  const RGBImage v = shifted(a, 0, -2);
  EXPECT_EQ(v.at(15, 27)[0], 220);
  EXPECT_EQ(v.at(15, 28)[0], 20);
  EXPECT_DOUBLE_EQ(compareImages(a, v, 2).differing, 80.0 / (64 * 48));
  // The band uncovered at the border repeats the edge.
  const RGBImage edge = shifted(square(8, 8, 0, 0, 2, white, grey), 3, 0);
  EXPECT_EQ(edge.at(0, 0)[0], 220);
  EXPECT_EQ(edge.at(4, 0)[0], 220);
  EXPECT_EQ(edge.at(5, 0)[0], 20);
}

TEST(ImageComparison, NoiseWithinTheToleranceIsNotCounted)
{
  const RGBImage a = square(64, 48, 10, 10, 20, white, grey);
  RGBImage n = a;
  for (std::size_t i = 0; i < n.rgb.size(); ++i)
  {
    n.rgb[i] = static_cast<std::uint8_t>(n.rgb[i] + (i % 3 == 0 ? 1 : (i % 3 == 1 ? -1 : 0)));
  }
  const ImageDifference d = compareImages(a, n, 1);
  EXPECT_EQ(d.differing, 0.0);
  EXPECT_EQ(d.maxError, 1);
  EXPECT_NEAR(d.rmse, std::sqrt(2.0 / 3.0), 1e-12);
  EXPECT_EQ(compareImages(a, n, 0).differing, 1.0);
}

TEST(ImageComparison, EveryThresholdCanFail)
{
  const RGBImage a = square(64, 48, 10, 10, 20, white, grey);
  const ImageDifference d = compareImages(a, movedToward(a, grey, 0.1), 2);
  const ImageThresholds loose{ 100, 1, 2, 255 };
  EXPECT_TRUE(withinThresholds(d, loose));
  ImageThresholds t = loose;
  t.rmse = d.rmse * 0.99;
  EXPECT_FALSE(withinThresholds(d, t));
  t = loose;
  t.differing = d.differing * 0.99;
  EXPECT_FALSE(withinThresholds(d, t));
  t = loose;
  t.maxError = d.maxError - 1;
  EXPECT_FALSE(withinThresholds(d, t));
  // Measured at another tolerance than the thresholds' own: no verdict of pass.
  t = loose;
  t.tolerance = 3;
  EXPECT_FALSE(withinThresholds(d, t));
  // Different sizes never pass.
  EXPECT_FALSE(
    withinThresholds(compareImages(a, square(64, 47, 10, 10, 20, white, grey), 2), loose));
}

TEST(ImageComparison, ThresholdTableIsReadAndCheckedForForm)
{
  const std::string path = ::testing::TempDir() + "/thresholds-test.txt";
  {
    std::ofstream out(path);
    out << "# name rmse differing tolerance max\nTestA 0.25 0.0005 2 64  # comment\n\nTestB 1 0.01 "
           "3 255\n";
  }
  const auto table = readThresholdTable(path);
  ASSERT_EQ(table.size(), 2u);
  EXPECT_EQ(table.at("TestA").rmse, 0.25);
  EXPECT_EQ(table.at("TestA").differing, 0.0005);
  EXPECT_EQ(table.at("TestA").tolerance, 2);
  EXPECT_EQ(table.at("TestA").maxError, 64);
  EXPECT_EQ(table.at("TestB").tolerance, 3);
  {
    std::ofstream out(path);
    out << "TestA 0.25 0.0005\n";
  }
  EXPECT_THROW(readThresholdTable(path), std::runtime_error);
  EXPECT_THROW(readThresholdTable(path + ".missing"), std::runtime_error);
  std::remove(path.c_str());
}
