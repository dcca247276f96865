// Run-time dispatch of the hot kernels over SIMD instruction sets. A dispatched file (RBF's
// direct and coherent methods, SPH's volume ray casting: Mappers/RayMappersKernels.cmake) is
// compiled once per instruction set, with RAYMAPPERS_SIMD_TARGET = 0 (the build's own flags:
// any x86-64, or this machine's with RAYMAPPERS_NATIVE), 2 (AVX2 + FMA) or 3 (AVX-512), the
// values of SimdPath. Its code sits between RAYMAPPERS_SIMD_BEGIN and RAYMAPPERS_SIMD_END,
// which for AVX2 and AVX-512 open a namespace of its own (simd_avx2, simd_avx512) under that
// instruction set's target pragma; compiled with the build's own flags, the code stays where
// it is, and each entry point's first statement, RAYMAPPERS_SIMD_FORWARD, hands the call to
// the variant resolveSimdPath picks (declared by RAYMAPPERS_SIMD_VARIANTS).
//
// Why a pragma after the includes and not -mavx512f on the command line: an inline function
// or template of a shared header (Vec3, std::vector, TBB) compiled with AVX-512 in one object
// and without in another would be merged by the linker into one copy, which could then run
// AVX-512 instructions on a CPU without them. Under the pragma only what the file defines in
// its own namespace gets the instruction set (header code inlined there too); every
// out-of-line copy of header code keeps the build's flags.
//
// The kernels are compiled with -ffp-contract=off, so a*b+c is never fused into an FMA where
// the instruction set has one: every variant does the same float operations in the same
// order and draws the same bytes.
#ifndef RayMappers_SimdTarget_h
#define RayMappers_SimdTarget_h

#include "Mappers/CGT/SimdPath.h"

#ifndef RAYMAPPERS_SIMD_TARGET
#define RAYMAPPERS_SIMD_TARGET 0
#endif

// The instruction sets: x86-64-v3 (AVX2, FMA, BMI1/2, F16C, LZCNT, MOVBE) and x86-64-v4 (v3 +
// AVX-512 F/BW/CD/DQ/VL), the levels resolveSimdPath checks. (The feature list is spelled
// out: a target("arch=...") would keep the build's inline helpers from being inlined.)
#if RAYMAPPERS_SIMD_TARGET == 0
#define RAYMAPPERS_SIMD_BEGIN
#define RAYMAPPERS_SIMD_END
#elif RAYMAPPERS_SIMD_TARGET == 2
#define RAYMAPPERS_SIMD_BEGIN                                                                   \
  _Pragma("GCC push_options") _Pragma("GCC target(\"avx2,fma,bmi,bmi2,f16c,lzcnt,movbe,popcnt\")") \
    namespace simd_avx2                                                                         \
  {
#define RAYMAPPERS_SIMD_END                                                                     \
  }                                                                                             \
  _Pragma("GCC pop_options")
#elif RAYMAPPERS_SIMD_TARGET == 3
#define RAYMAPPERS_SIMD_BEGIN                                                                   \
  _Pragma("GCC push_options") _Pragma(                                                          \
    "GCC target(\"avx2,fma,bmi,bmi2,f16c,lzcnt,movbe,popcnt,avx512f,avx512bw,avx512cd,avx512dq,avx512vl\")") \
    namespace simd_avx512                                                                       \
  {
#define RAYMAPPERS_SIMD_END                                                                     \
  }                                                                                             \
  _Pragma("GCC pop_options")
#else
#error "RAYMAPPERS_SIMD_TARGET must be 0, 2 or 3 (SimdPath)"
#endif

// RAYMAPPERS_SIMD_DISPATCH (set by CMake when the AVX2 and AVX-512 objects are linked in):
// the compilation with the build's own flags hands each call of an entry point to the wider
// variant the CPU has, if any.
#if RAYMAPPERS_SIMD_DISPATCH && RAYMAPPERS_SIMD_TARGET == 0
/// Declares the AVX2 and AVX-512 variants of `fn`, a function of the enclosing namespace
/// declared before (not overloaded).
#define RAYMAPPERS_SIMD_VARIANTS(fn)                                                            \
  namespace simd_avx2                                                                           \
  {                                                                                             \
  decltype(fn) fn;                                                                              \
  }                                                                                             \
  namespace simd_avx512                                                                         \
  {                                                                                             \
  decltype(fn) fn;                                                                              \
  }
/// The first statement of entry point `fn`: returns the wider variant's result for the
/// arguments when resolveSimdPath picks AVX2 or AVX-512; else the portable body follows.
#define RAYMAPPERS_SIMD_FORWARD(fn, ...)                                                        \
  if (const auto wider = ::raymappers::widerSimdVariant(&simd_avx2::fn, &simd_avx512::fn))       \
  return wider(__VA_ARGS__)
#else
#define RAYMAPPERS_SIMD_VARIANTS(fn)
#define RAYMAPPERS_SIMD_FORWARD(fn, ...) static_cast<void>(0)
#endif

namespace raymappers
{

/// The variant for the path resolveSimdPath(SimdPath::Auto) picks (read per call, so a test
/// may change RAYMAPPERS_SIMD between frames), or null for the portable one.
template<typename Fn>
Fn widerSimdVariant(Fn avx2, Fn avx512)
{
  switch (resolveSimdPath(SimdPath::Auto))
  {
    case SimdPath::Avx512:
      return avx512;
    case SimdPath::Avx2:
      return avx2;
    default:
      return nullptr;
  }
}

} // namespace raymappers

#endif
