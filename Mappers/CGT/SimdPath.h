// Which SIMD instructions the innermost ray-sphere loop of the coherent grid uses
// (RaySphereLanes.h), chosen at run time from what the CPU supports.
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

/// The path `requested` resolves to on this CPU (an unsupported request falls back to the
/// widest supported path).
SimdPath resolveSimdPath(SimdPath requested);
const char* simdPathName(SimdPath path);

} // namespace raymappers

#endif
