// Which SIMD instructions the hot kernels use, chosen at run time from what the CPU supports:
// the innermost ray-sphere loop of the coherent grid (RaySphereLanes.h) and the kernels
// compiled once per instruction set (SimdTarget.h). The environment variable RAYMAPPERS_SIMD
// (portable, avx2 or avx512) overrides the choice of Auto, e.g. for a test of the portable
// path on a CPU with AVX-512.
#ifndef RayMappers_SimdPath_h
#define RayMappers_SimdPath_h

namespace raymappers
{

enum class SimdPath
{
  Auto = 0,     // the widest the CPU has
  Portable = 1, // plain C++
  Avx2 = 2,     // 8 lanes, FMA
  Avx512 = 3    // 16 lanes
};

/// The path `requested` resolves to on this CPU: Auto is RAYMAPPERS_SIMD if set, else the
/// widest; an unsupported request falls back to the widest supported path.
SimdPath resolveSimdPath(SimdPath requested);
const char* simdPathName(SimdPath path);

} // namespace raymappers

#endif
