// One sphere against every active ray of a packet: the innermost loop of the coherent grid
// traversal (Gribble et al. 2007, section 4: the packet's rays are tested together, in SIMD
// lanes). The rays live in structure-of-arrays form, padded to a multiple of 16 lanes so
// that the vector paths need no remainder loop: a padding lane has tNear = +inf and can
// never record a hit.
//
// The intersection, for ray o + t d (|d| = 1) and sphere (c, r), with f = o - c, b = f.d:
//   |f + t d|^2 = r^2  =>  t = -b -+ sqrt(disc),  disc = r^2 - |f - b d|^2
// (the form with |f - b d|^2, the squared distance from the centre to the ray's line, keeps
// its precision far from the sphere, unlike b^2 - |f|^2 + r^2). A ray starting inside the
// sphere (near root before tNear) takes the far root.
//
// Ordered (RayPacket::ordered): the hits in the total order of (t, index), so that a
// translucent ray's queries from each hit on (tNear = t, tieFrom = index + 1) meet coincident
// spheres too, one by one: a hit counts when t > tNear or (t == tNear and index >= tieFrom),
// and beats the best when t < tBest or (t == tBest and index < prim).
//
// Three paths with the same arithmetic: a portable loop (vectorized by the compiler if it
// can), AVX2 + FMA (8 lanes) and AVX-512 (16 lanes), chosen at run time from the CPU.
#ifndef RayMappers_RaySphereLanes_h
#define RayMappers_RaySphereLanes_h

#include "Mappers/Common/SimdLanes.h"
#include "Mappers/CGT/SimdPath.h"
#include "Mappers/CGT/SphereAccelerator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#if defined(__x86_64__) || defined(_M_X64)
#include <immintrin.h>
#define RAYMAPPERS_X86_SIMD 1
#endif

namespace raymappers
{

struct RayLanes : RayLaneArrays<MaxPacketRays>
{
  alignas(64) float tNear[MaxPacketRays];
  alignas(64) float tBest[MaxPacketRays];
  alignas(64) std::uint32_t prim[MaxPacketRays];
  alignas(64) std::uint32_t tieFrom[MaxPacketRays]; // read by the ordered tests only

  /// Lanes [count, padded(count)) become padding.
  static int padded(int count) { return paddedLaneCount(count); }
  void pad(int count)
  {
    for (int i = count; i < padded(count); ++i)
    {
      ox[i] = oy[i] = oz[i] = dx[i] = dy[i] = dz[i] = 0.f;
      tNear[i] = std::numeric_limits<float>::infinity();
      tBest[i] = 0.f;
      prim[i] = NoHit;
      tieFrom[i] = 0;
    }
  }
};

struct PortableLanes
{
  template<bool Ordered>
  static void
  intersect(RayLanes& L, int padded, float cx, float cy, float cz, float r2, std::uint32_t id)
  {
#pragma omp simd
    for (int i = 0; i < padded; ++i)
    {
      const float fx = L.ox[i] - cx, fy = L.oy[i] - cy, fz = L.oz[i] - cz;
      const float b = fx * L.dx[i] + fy * L.dy[i] + fz * L.dz[i];
      const float px = fx - L.dx[i] * b, py = fy - L.dy[i] * b, pz = fz - L.dz[i] * b;
      const float disc = r2 - (px * px + py * py + pz * pz);
      const float root = std::sqrt(std::max(disc, 0.f));
      const float near = -b - root;
      const float t = near < L.tNear[i] ? -b + root : near;
      const bool after = Ordered ? t > L.tNear[i] || (t == L.tNear[i] && id >= L.tieFrom[i])
                                 : t >= L.tNear[i];
      const bool before = Ordered ? t < L.tBest[i] || (t == L.tBest[i] && id < L.prim[i])
                                  : t < L.tBest[i];
      const bool hit = disc >= 0.f && after && before;
      L.tBest[i] = hit ? t : L.tBest[i];
      L.prim[i] = hit ? id : L.prim[i];
    }
  }
};

#ifdef RAYMAPPERS_X86_SIMD
struct Avx2Lanes
{
  // a > b on unsigned 32-bit lanes: the signed comparison with both sign bits flipped.
  __attribute__((target("avx2"))) static __m256 greaterUnsigned(__m256i a, __m256i b)
  {
    const __m256i sign = _mm256_set1_epi32(static_cast<int>(0x80000000u));
    return _mm256_castsi256_ps(
      _mm256_cmpgt_epi32(_mm256_xor_si256(a, sign), _mm256_xor_si256(b, sign)));
  }

  template<bool Ordered>
  __attribute__((target("avx2,fma"))) static void
  intersect(RayLanes& L, int padded, float cx, float cy, float cz, float r2, std::uint32_t id)
  {
    const __m256 vcx = _mm256_set1_ps(cx), vcy = _mm256_set1_ps(cy), vcz = _mm256_set1_ps(cz);
    const __m256 vr2 = _mm256_set1_ps(r2), zero = _mm256_setzero_ps();
    const __m256i vid = _mm256_set1_epi32(static_cast<int>(id));
    for (int i = 0; i < padded; i += 8)
    {
      const __m256 dx = _mm256_load_ps(L.dx + i), dy = _mm256_load_ps(L.dy + i),
                   dz = _mm256_load_ps(L.dz + i);
      const __m256 fx = _mm256_sub_ps(_mm256_load_ps(L.ox + i), vcx);
      const __m256 fy = _mm256_sub_ps(_mm256_load_ps(L.oy + i), vcy);
      const __m256 fz = _mm256_sub_ps(_mm256_load_ps(L.oz + i), vcz);
      const __m256 b = _mm256_fmadd_ps(fx, dx, _mm256_fmadd_ps(fy, dy, _mm256_mul_ps(fz, dz)));
      const __m256 px = _mm256_fnmadd_ps(dx, b, fx), py = _mm256_fnmadd_ps(dy, b, fy),
                   pz = _mm256_fnmadd_ps(dz, b, fz);
      const __m256 disc =
        _mm256_sub_ps(vr2, _mm256_fmadd_ps(px, px, _mm256_fmadd_ps(py, py, _mm256_mul_ps(pz, pz))));
      const __m256 root = _mm256_sqrt_ps(_mm256_max_ps(disc, zero));
      const __m256 nb = _mm256_sub_ps(zero, b);
      const __m256 nearT = _mm256_sub_ps(nb, root), farT = _mm256_add_ps(nb, root);
      const __m256 tNear = _mm256_load_ps(L.tNear + i), tBest = _mm256_load_ps(L.tBest + i);
      const __m256 t = _mm256_blendv_ps(nearT, farT, _mm256_cmp_ps(nearT, tNear, _CMP_LT_OQ));
      const __m256i prim = _mm256_load_si256(reinterpret_cast<const __m256i*>(L.prim + i));
      __m256 after = _mm256_cmp_ps(t, tNear, _CMP_GE_OQ);
      __m256 before = _mm256_cmp_ps(t, tBest, _CMP_LT_OQ);
      if constexpr (Ordered)
      {
        const __m256i from = _mm256_load_si256(reinterpret_cast<const __m256i*>(L.tieFrom + i));
        const __m256 tied = _mm256_cmp_ps(t, tNear, _CMP_EQ_OQ);
        after = _mm256_andnot_ps(_mm256_and_ps(tied, greaterUnsigned(from, vid)), after);
        before = _mm256_or_ps(before,
          _mm256_and_ps(_mm256_cmp_ps(t, tBest, _CMP_EQ_OQ), greaterUnsigned(prim, vid)));
      }
      const __m256 hit =
        _mm256_and_ps(_mm256_cmp_ps(disc, zero, _CMP_GE_OQ), _mm256_and_ps(after, before));
      if (_mm256_movemask_ps(hit) == 0)
      {
        continue;
      }
      _mm256_store_ps(L.tBest + i, _mm256_blendv_ps(tBest, t, hit));
      _mm256_store_si256(reinterpret_cast<__m256i*>(L.prim + i),
        _mm256_castps_si256(
          _mm256_blendv_ps(_mm256_castsi256_ps(prim), _mm256_castsi256_ps(vid), hit)));
    }
  }
};

// GCC 12 warns that the "undefined" pass-through vector inside _mm512_max_ps and
// _mm512_sqrt_ps may be used uninitialized: a false positive (the mask is all ones).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
struct Avx512Lanes
{
  template<bool Ordered>
  __attribute__((target("avx512f"))) static void
  intersect(RayLanes& L, int padded, float cx, float cy, float cz, float r2, std::uint32_t id)
  {
    const __m512 vcx = _mm512_set1_ps(cx), vcy = _mm512_set1_ps(cy), vcz = _mm512_set1_ps(cz);
    const __m512 vr2 = _mm512_set1_ps(r2), zero = _mm512_setzero_ps();
    const __m512i vid = _mm512_set1_epi32(static_cast<int>(id));
    for (int i = 0; i < padded; i += 16)
    {
      const __m512 dx = _mm512_load_ps(L.dx + i), dy = _mm512_load_ps(L.dy + i),
                   dz = _mm512_load_ps(L.dz + i);
      const __m512 fx = _mm512_sub_ps(_mm512_load_ps(L.ox + i), vcx);
      const __m512 fy = _mm512_sub_ps(_mm512_load_ps(L.oy + i), vcy);
      const __m512 fz = _mm512_sub_ps(_mm512_load_ps(L.oz + i), vcz);
      const __m512 b = _mm512_fmadd_ps(fx, dx, _mm512_fmadd_ps(fy, dy, _mm512_mul_ps(fz, dz)));
      const __m512 px = _mm512_fnmadd_ps(dx, b, fx), py = _mm512_fnmadd_ps(dy, b, fy),
                   pz = _mm512_fnmadd_ps(dz, b, fz);
      const __m512 disc =
        _mm512_sub_ps(vr2, _mm512_fmadd_ps(px, px, _mm512_fmadd_ps(py, py, _mm512_mul_ps(pz, pz))));
      const __mmask16 real = _mm512_cmp_ps_mask(disc, zero, _CMP_GE_OQ);
      if (real == 0)
      {
        continue;
      }
      const __m512 root = _mm512_sqrt_ps(_mm512_max_ps(disc, zero));
      const __m512 nb = _mm512_sub_ps(zero, b);
      const __m512 nearT = _mm512_sub_ps(nb, root), farT = _mm512_add_ps(nb, root);
      const __m512 tNear = _mm512_load_ps(L.tNear + i), tBest = _mm512_load_ps(L.tBest + i);
      const __m512 t =
        _mm512_mask_blend_ps(_mm512_cmp_ps_mask(nearT, tNear, _CMP_LT_OQ), nearT, farT);
      __mmask16 after = _mm512_cmp_ps_mask(t, tNear, _CMP_GE_OQ);
      __mmask16 before = _mm512_cmp_ps_mask(t, tBest, _CMP_LT_OQ);
      if constexpr (Ordered)
      {
        const __m512i from = _mm512_load_si512(L.tieFrom + i);
        const __m512i prim = _mm512_load_si512(L.prim + i);
        after &= ~(_mm512_cmp_ps_mask(t, tNear, _CMP_EQ_OQ) &
          _mm512_cmp_epu32_mask(vid, from, _MM_CMPINT_LT));
        before |= _mm512_cmp_ps_mask(t, tBest, _CMP_EQ_OQ) &
          _mm512_cmp_epu32_mask(vid, prim, _MM_CMPINT_LT);
      }
      const __mmask16 hit = real & after & before;
      _mm512_mask_store_ps(L.tBest + i, hit, t);
      _mm512_mask_store_epi32(L.prim + i, hit, vid);
    }
  }
};
#pragma GCC diagnostic pop
#endif

} // namespace raymappers

#endif
