// What the packet kernels' structure-of-arrays lanes share (CGT's ray-sphere loop,
// RaySphereLanes.h; RBF's coherent method, RBFCoherentMethod.cxx): a packet's rays stored
// one array per coordinate, so that one sphere, node or particle is tested against all of
// them in SIMD lanes (Gribble et al. 2007, section 4; Knoll et al. 2014, section 5.3).
// Arrays are 64-byte aligned and lane counts padded to a multiple of the widest SIMD width
// (AVX-512: 16 floats), so that no vector loop needs a remainder; what a padding lane holds
// is the kernel's choice (a ray that can never record a hit).
#ifndef RayMappers_SimdLanes_h
#define RayMappers_SimdLanes_h

namespace raymappers
{

/// The widest SIMD width in floats, the multiple lane counts are padded to.
constexpr int SimdLaneWidth = 16;

/// `count` lanes padded to a multiple of SimdLaneWidth.
constexpr int paddedLaneCount(int count)
{
  return (count + SimdLaneWidth - 1) / SimdLaneWidth * SimdLaneWidth;
}

/// The origins and unit directions of up to N rays, one array per coordinate.
template <int N>
struct RayLaneArrays
{
  static_assert(N % SimdLaneWidth == 0, "whole SIMD blocks");
  alignas(64) float ox[N];
  alignas(64) float oy[N];
  alignas(64) float oz[N];
  alignas(64) float dx[N];
  alignas(64) float dy[N];
  alignas(64) float dz[N];
};

} // namespace raymappers

#endif
