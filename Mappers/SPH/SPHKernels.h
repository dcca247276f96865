// The SPH smoothing kernels (Limper 2012, section 2.3.1) and their exact derivatives, written
// in terms of the support radius H (W = 0 for r >= H) and q = r/H, normalized in 3D
// (the integral of W over space is 1):
//   poly6 (equation 2.5, the thesis's kernel; H is its "h"):
//       W = 315/(64 pi H^3) (1 - q^2)^3
//   cubic spline (Monaghan's M4; with smoothing length h, H = 2h):
//       W = 8/(pi H^3) (1 - 6q^2 + 6q^3)   for q <= 1/2,   16/(pi H^3) (1 - q)^3 beyond
//   Wendland C2 (Wendland 1995, 3D; with smoothing length h, H = 2h):
//       W = 21/(2 pi H^3) (1 - q)^4 (1 + 4q)
// dW/dr = (1/H) dW/dq, and the gradient with respect to the evaluation point x of a
// particle at x_i is grad W = W'(r) (x - x_i)/r (equation 3.20); all three kernels have
// W'(0) = 0, so the gradient is continuous at the centre.
//
// The kernels are evaluated from r^2 where they can (poly6 never needs a square root).
#ifndef RayMappers_SPHKernels_h
#define RayMappers_SPHKernels_h

#include <cmath>

namespace raymappers
{

enum class SPHKernel
{
  Poly6 = 0,
  CubicSpline = 1,
  WendlandC2 = 2
};

/// The support radius of a kernel in units of the usual smoothing length h of SPH codes:
/// poly6's h is its support (as in the thesis); the cubic spline and Wendland C2 reach 2h.
inline double kernelSupportPerSmoothingLength(SPHKernel k)
{
  return k == SPHKernel::Poly6 ? 1.0 : 2.0;
}

/// The dimensionless constant c of W = c / H^3 * shape(q).
inline double kernelNormalization(SPHKernel k)
{
  constexpr double pi = 3.14159265358979323846;
  return k == SPHKernel::Poly6 ? 315.0 / (64.0 * pi)
                               : (k == SPHKernel::CubicSpline ? 8.0 / pi : 21.0 / (2.0 * pi));
}

/// shape(q) from q^2 < 1 (callers test the support first).
template<SPHKernel K>
inline float kernelShape(float q2)
{
  if constexpr (K == SPHKernel::Poly6)
  {
    const float a = 1.f - q2;
    return a * a * a;
  }
  else if constexpr (K == SPHKernel::CubicSpline)
  {
    const float q = std::sqrt(q2);
    const float a = 1.f - q;
    return q <= 0.5f ? 1.f - 6.f * q2 + 6.f * q2 * q : 2.f * a * a * a;
  }
  else
  {
    const float q = std::sqrt(q2);
    const float a = 1.f - q;
    const float a2 = a * a;
    return a2 * a2 * (1.f + 4.f * q);
  }
}

/// shape'(q) / q from q^2 < 1: finite at q = 0 for all three kernels, so that
/// grad W = c / H^5 * (shape'(q)/q) * (x - x_i).
///   poly6: d/dq (1 - q^2)^3 = -6q (1 - q^2)^2;  cubic: -12q + 18q^2 inside q <= 1/2,
///   -6 (1 - q)^2 beyond;  Wendland C2: d/dq (1 - q)^4 (1 + 4q) = -20 q (1 - q)^3.
template<SPHKernel K>
inline float kernelShapeDerivativeOverQ(float q2)
{
  if constexpr (K == SPHKernel::Poly6)
  {
    const float a = 1.f - q2;
    return -6.f * a * a;
  }
  else if constexpr (K == SPHKernel::CubicSpline)
  {
    const float q = std::sqrt(q2);
    const float a = 1.f - q;
    return q <= 0.5f ? -12.f + 18.f * q : (q > 0.f ? -6.f * a * a / q : 0.f);
  }
  else
  {
    const float q = std::sqrt(q2);
    const float a = 1.f - q;
    return -20.f * a * a * a;
  }
}

/// W(r) for support H, in double (for tests and references), any kernel.
inline double kernelValue(SPHKernel k, double r, double H)
{
  const double q = r / H;
  if (!(q < 1.0))
  {
    return 0.0;
  }
  const double q2 = q * q;
  double s;
  switch (k)
  {
    case SPHKernel::Poly6:
      s = (1 - q2) * (1 - q2) * (1 - q2);
      break;
    case SPHKernel::CubicSpline:
      s = q <= 0.5 ? 1 - 6 * q2 + 6 * q2 * q : 2 * (1 - q) * (1 - q) * (1 - q);
      break;
    default:
      s = (1 - q) * (1 - q) * (1 - q) * (1 - q) * (1 + 4 * q);
  }
  return kernelNormalization(k) / (H * H * H) * s;
}

} // namespace raymappers

#endif
