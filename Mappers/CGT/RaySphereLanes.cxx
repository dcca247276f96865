#include "Mappers/CGT/RaySphereLanes.h" // RAYMAPPERS_X86_SIMD
#include "Mappers/CGT/SimdPath.h"

#include <cstdlib>
#include <cstring>

namespace raymappers
{

namespace
{
// RAYMAPPERS_SIMD (portable, avx2 or avx512) in the environment, Auto when unset or unknown.
SimdPath environmentSimdPath()
{
  const char* value = std::getenv("RAYMAPPERS_SIMD");
  for (const SimdPath path : { SimdPath::Portable, SimdPath::Avx2, SimdPath::Avx512 })
  {
    if (value && std::strcmp(value, simdPathName(path)) == 0)
    {
      return path;
    }
  }
  return SimdPath::Auto;
}
}

SimdPath resolveSimdPath(SimdPath requested)
{
#ifdef RAYMAPPERS_X86_SIMD
  // The levels the dispatched kernels are compiled for (SimdTarget.h); __builtin_cpu_supports
  // also checks that the operating system saves the wide registers.
  const bool avx512 = __builtin_cpu_supports("x86-64-v4");
  const bool avx2 = __builtin_cpu_supports("x86-64-v3");
#else
  const bool avx512 = false, avx2 = false;
#endif
  const SimdPath widest = avx512 ? SimdPath::Avx512 : (avx2 ? SimdPath::Avx2 : SimdPath::Portable);
  switch (requested == SimdPath::Auto ? environmentSimdPath() : requested)
  {
    case SimdPath::Portable:
      return SimdPath::Portable;
    case SimdPath::Avx2:
      return avx2 ? SimdPath::Avx2 : widest;
    case SimdPath::Avx512:
      return avx512 ? SimdPath::Avx512 : widest;
    default:
      return widest;
  }
}

const char* simdPathName(SimdPath path)
{
  switch (path)
  {
    case SimdPath::Portable:
      return "portable";
    case SimdPath::Avx2:
      return "avx2";
    case SimdPath::Avx512:
      return "avx512";
    default:
      return "auto";
  }
}

} // namespace raymappers
