// exp(x) in float for the RBF kernels, written so that a `#pragma omp simd` loop can
// vectorize it (std::exp is a libm call the compiler cannot put in SIMD lanes).
//
// Range reduction (Cody-Waite): x = n ln2 + r with n = round(x / ln2), |r| <= ln2 / 2
// (rounded with the 1.5 * 2^23 trick: std::floor would not vectorize without
// -fno-trapping-math); ln2 is split as C1 + C2 (C1 = 0.693359375 has few mantissa bits)
// and r = (x - n C1) - n C2. Then
//   exp(r) ~= 1 + r + r^2 P(r),  P of degree 5,
// with the minimax coefficients of Cephes' expf (S. L. Moshier, Cephes Math Library,
// expf.c), and exp(x) = 2^n exp(r), 2^n built directly in the float's exponent bits.
// x is clamped to [-87, 88] first, so 2^n stays a normal float: below -87 the result is
// about 1.6e-38 instead of smaller (or 0), above 88 it is about 1.65e38 instead of
// infinity. Relative error within [-87, 88]: below 1e-7 (measured over every float there;
// the kernel test checks 1e-6 against std::exp). Relies on IEEE float arithmetic without
// reassociation (no -ffast-math), as the rest of the kernels do. x must not be NaN.
#ifndef RayMappers_FastExp_h
#define RayMappers_FastExp_h

#include <cstdint>
#include <cstring>

namespace raymappers
{

inline float fastExp(float x)
{
  x = x < -87.f ? -87.f : x; // (two selects: a nested one can keep a loop from vectorizing)
  x = x > 88.f ? 88.f : x;
  // n = round(x / ln2): adding 1.5 * 2^23 leaves no fraction bits, so the sum is rounded to
  // an integer (to nearest); subtracting it back is exact.
  const float n = (x * 1.44269504088896341f + 12582912.f) - 12582912.f;
  const float r = (x - n * 0.693359375f) - n * -2.12194440e-4f;
  float p = 1.9875691500e-4f;
  p = p * r + 1.3981999507e-3f;
  p = p * r + 8.3334519073e-3f;
  p = p * r + 4.1665795894e-2f;
  p = p * r + 1.6666665459e-1f;
  p = p * r + 5.0000001201e-1f;
  const float e = p * (r * r) + r + 1.f;
  // 2^n: n + 127 in the exponent field (n in [-126, 127] after the clamp).
  const std::int32_t bits = (static_cast<std::int32_t>(n) + 127) << 23;
  float scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return e * scale;
}

} // namespace raymappers

#endif
