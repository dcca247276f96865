#include "Mappers/Common/TransferFunctionTable.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace raymappers
{

void TransferFunctionTable::assign(std::vector<float> rgba,
  double lo,
  double hi,
  double unitDistance)
{
  Samples = std::move(rgba);
  Samples.resize(Samples.size() / 4 * 4);
  Lo = lo;
  Hi = hi;
  UnitDistance = unitDistance > 0 && std::isfinite(unitDistance) ? unitDistance : 1.0;
  const int n = size();
  Scale = (n > 1 && hi > lo) ? (n - 1) / (hi - lo) : 0.0;
}

std::array<float, 4> TransferFunctionTable::lookup(double v) const
{
  const int n = size();
  if (n == 0 || std::isnan(v))
  {
    return { 0.f, 0.f, 0.f, 0.f };
  }
  const double x = std::clamp((v - Lo) * Scale, 0.0, static_cast<double>(n - 1));
  const int k = std::min(static_cast<int>(x), n - 2 < 0 ? 0 : n - 2);
  const float f = n > 1 ? static_cast<float>(x - k) : 0.f;
  const float* a = &Samples[4 * k];
  const float* b = n > 1 ? a + 4 : a;
  return { a[0] + f * (b[0] - a[0]),
    a[1] + f * (b[1] - a[1]),
    a[2] + f * (b[2] - a[2]),
    a[3] + f * (b[3] - a[3]) };
}

double TransferFunctionTable::correctOpacity(double alpha, double dt, double unitDistance)
{
  alpha = std::clamp(alpha, 0.0, 1.0);
  if (alpha >= 1.0)
  {
    return 1.0;
  }
  // 1 - (1 - alpha)^(dt/u), written with log1p/expm1 so small opacities keep precision.
  return -std::expm1(dt / unitDistance * std::log1p(-alpha));
}

} // namespace raymappers
