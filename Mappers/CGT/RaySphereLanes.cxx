#include "Mappers/CGT/RaySphereLanes.h" // RAYMAPPERS_X86_SIMD
#include "Mappers/CGT/SimdPath.h"

namespace raymappers
{

SimdPath resolveSimdPath(SimdPath requested)
{
#ifdef RAYMAPPERS_X86_SIMD
  const bool avx512 = __builtin_cpu_supports("avx512f");
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  const bool avx512 = false, avx2 = false;
#endif
  const SimdPath widest = avx512 ? SimdPath::Avx512 : (avx2 ? SimdPath::Avx2 : SimdPath::Portable);
  switch (requested)
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
