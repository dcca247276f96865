// Transfer-function tables against closed-form values.
#include "Mappers/Common/TransferFunctionTable.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using raymappers::TransferFunctionTable;

namespace
{
// A ramp: sample k (of n over [lo, hi]) has rgba = (x, 1 - x, 0.5, x^2) at x = k/(n-1).
TransferFunctionTable ramp(int n, double lo, double hi)
{
  std::vector<float> rgba;
  for (int k = 0; k < n; ++k)
  {
    const float x = static_cast<float>(k) / (n - 1);
    rgba.insert(rgba.end(), { x, 1 - x, 0.5f, x * x });
  }
  TransferFunctionTable t;
  t.assign(rgba, lo, hi, 2.0);
  return t;
}
}

TEST(TransferFunctionTable, SamplesAreExactAndLinearInBetween)
{
  const TransferFunctionTable t = ramp(11, -5, 15);
  for (int k = 0; k < 11; ++k)
  {
    const double v = -5 + 2.0 * k;
    const auto c = t.lookup(v);
    EXPECT_NEAR(c[0], k / 10.0, 1e-6);
    EXPECT_NEAR(c[3], (k / 10.0) * (k / 10.0), 1e-6);
  }
  // Halfway between samples 3 and 4: the mean of their values.
  const auto c = t.lookup(-5 + 7.0);
  EXPECT_NEAR(c[0], 0.35, 1e-6);
  EXPECT_NEAR(c[3], 0.5 * (0.09 + 0.16), 1e-6);
}

TEST(TransferFunctionTable, ClampsOutsideTheRangeAndNeverReturnsNaN)
{
  const TransferFunctionTable t = ramp(5, 0, 1);
  EXPECT_FLOAT_EQ(t.lookup(-100)[0], 0.f);
  EXPECT_FLOAT_EQ(t.lookup(100)[0], 1.f);
  const auto n = t.lookup(std::numeric_limits<double>::quiet_NaN());
  for (float x : n)
  {
    EXPECT_EQ(x, 0.f);
  }
  EXPECT_FLOAT_EQ(t.lookup(std::numeric_limits<double>::infinity())[3], 1.f);
}

TEST(TransferFunctionTable, ConstantTables)
{
  TransferFunctionTable one;
  one.assign({ 0.2f, 0.4f, 0.6f, 0.8f }, 3, 3);
  EXPECT_FLOAT_EQ(one.lookup(-1)[1], 0.4f);
  EXPECT_FLOAT_EQ(one.lookup(7)[3], 0.8f);
  TransferFunctionTable degenerate = ramp(4, 2, 2); // lo == hi
  EXPECT_FLOAT_EQ(degenerate.lookup(2)[0], 0.f);
  TransferFunctionTable empty;
  EXPECT_EQ(empty.lookup(0)[3], 0.f);
}

TEST(TransferFunctionTable, OpacityCorrectionMatchesBeerLambert)
{
  // alpha over the unit distance u; a step dt has 1 - (1 - alpha)^(dt/u).
  EXPECT_NEAR(TransferFunctionTable::correctOpacity(0.3, 2.0, 2.0), 0.3, 1e-15);
  EXPECT_NEAR(TransferFunctionTable::correctOpacity(0.3, 4.0, 2.0), 1 - 0.7 * 0.7, 1e-15);
  EXPECT_NEAR(TransferFunctionTable::correctOpacity(0.3, 1.0, 2.0), 1 - std::sqrt(0.7), 1e-15);
  EXPECT_EQ(TransferFunctionTable::correctOpacity(1.0, 0.01, 1.0), 1.0);
  EXPECT_EQ(TransferFunctionTable::correctOpacity(0.0, 5.0, 1.0), 0.0);
  // Tiny opacities keep their relative precision: alpha dt/u to first order.
  EXPECT_NEAR(TransferFunctionTable::correctOpacity(1e-12, 0.5, 1.0), 0.5e-12, 1e-24);
  // Two half steps compose to one full step.
  const double half = TransferFunctionTable::correctOpacity(0.6, 0.5, 1.0);
  EXPECT_NEAR(1 - (1 - half) * (1 - half), 0.6, 1e-14);
}
