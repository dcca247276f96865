// The frame check of vtkRayMapperStatistics::ValidateFrames (FrameValidation.h): every kind
// of bad value planted in a valid frame is counted exactly once, and a valid frame (empty
// pixels, opaque and translucent premultiplied colours, depths at 0 and 1) counts nothing.
#include "Mappers/Common/FrameValidation.h"

#include <gtest/gtest.h>

#include <limits>

using raymappers::Frame;
using raymappers::validateFrame;

namespace
{
// 4 x 3 pixels: empty ones, an opaque one at the near plane, a translucent premultiplied
// one (colour <= alpha) and one whose colour equals its alpha.
Frame ValidFrame()
{
  Frame f;
  f.resize(4, 3);
  const float opaque[4] = { 0.2f, 0.9f, 1.0f, 1.0f };
  const float translucent[4] = { 0.1f, 0.0f, 0.25f, 0.25f };
  for (int k = 0; k < 4; ++k)
  {
    f.rgba[4 * 1 + k] = opaque[k];
    f.rgba[4 * 2 + k] = translucent[k];
    f.rgba[4 * 3 + k] = 0.5f;
  }
  f.depth[1] = 0.f;
  f.depth[2] = 0.73f;
  return f;
}
}

TEST(FrameValidation, ValidFrameCountsNothing)
{
  const auto v = validateFrame(ValidFrame());
  EXPECT_EQ(v.nonFinite, 0);
  EXPECT_EQ(v.outOfRange, 0);
}

TEST(FrameValidation, NonFiniteValuesOfColourAlphaAndDepth)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  Frame f = ValidFrame();
  f.rgba[4 * 5 + 0] = nan;  // a colour channel
  f.rgba[4 * 6 + 3] = inf;  // an alpha
  f.rgba[4 * 7 + 2] = -inf; // another channel
  f.depth[8] = nan;
  const auto v = validateFrame(f);
  EXPECT_EQ(v.nonFinite, 4);
  EXPECT_EQ(v.outOfRange, 0);
}

TEST(FrameValidation, OutOfRangeValues)
{
  Frame f = ValidFrame();
  f.rgba[4 * 5 + 3] = 1.5f;  // alpha above 1 (its colours stay below it)
  f.rgba[4 * 6 + 3] = -0.1f; // alpha below 0 (its colours, 0, are above it)
  f.rgba[4 * 7 + 3] = 0.5f;
  f.rgba[4 * 7 + 1] = 0.6f; // a colour above its alpha
  f.rgba[4 * 8 + 0] = -0.01f; // a negative colour
  f.depth[9] = 1.01f;
  f.depth[10] = -0.5f;
  const auto v = validateFrame(f);
  EXPECT_EQ(v.nonFinite, 0);
  // Pixel 6: its alpha and its three colours of 0 (above the alpha -0.1).
  EXPECT_EQ(v.outOfRange, 1 + 4 + 1 + 1 + 2);
}

TEST(FrameValidation, RoundingBelowTheToleranceIsNotOutOfRange)
{
  Frame f = ValidFrame();
  f.rgba[4 * 3 + 0] = 0.5f + 0.5f * raymappers::FrameColorTolerance;
  f.rgba[4 * 3 + 1] = -0.5f * raymappers::FrameColorTolerance;
  EXPECT_EQ(validateFrame(f).outOfRange, 0);
  f.rgba[4 * 3 + 0] = 0.5f + 2.f * raymappers::FrameColorTolerance;
  EXPECT_EQ(validateFrame(f).outOfRange, 1);
}

TEST(FrameValidation, LargeFrameSumsAllTiles)
{
  // More pixels than one TBB grain: every planted NaN is counted once.
  Frame f;
  f.resize(1000, 100);
  for (std::size_t p = 0; p < 100000; p += 997)
  {
    f.depth[p] = std::numeric_limits<float>::quiet_NaN();
  }
  EXPECT_EQ(validateFrame(f).nonFinite, 101);
}
