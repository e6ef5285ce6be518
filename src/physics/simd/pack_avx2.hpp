#pragma once
// Four doubles in an AVX2 register, with the handful of operations the vectorised pair sweep needs
// (physics/simd/sweep_kernel.hpp). Included only by sweep_avx2.cpp, which is compiled with -mavx2 -mfma;
// everything here has internal linkage so no AVX2 instruction can leak into the portable code.
#include <immintrin.h>

#include <cstdint>

namespace {

struct PackAvx2 {
  static constexpr int W = 4;  // lanes
  using V = __m256d;           // W doubles
  using M = __m256d;           // lane mask: all bits set or clear
  using I = __m128i;           // W int32 indices

  static V load(const double* p) { return _mm256_loadu_pd(p); }
  static void store(double* p, V v) { _mm256_storeu_pd(p, v); }
  static V set1(double a) { return _mm256_set1_pd(a); }
  static V zero() { return _mm256_setzero_pd(); }
  static V add(V a, V b) { return _mm256_add_pd(a, b); }
  static V sub(V a, V b) { return _mm256_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm256_mul_pd(a, b); }
  static V div(V a, V b) { return _mm256_div_pd(a, b); }
  static V fmadd(V a, V b, V c) { return _mm256_fmadd_pd(a, b, c); }  // a b + c
  static V fnmadd(V a, V b, V c) { return _mm256_fnmadd_pd(a, b, c); }  // c - a b
  static V min(V a, V b) { return _mm256_min_pd(a, b); }
  static M lt(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
  static M eq(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
  static M neq(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_NEQ_UQ); }
  static M mand(M a, M b) { return _mm256_and_pd(a, b); }
  static M mandnot(M a, M b) { return _mm256_andnot_pd(a, b); }  // (not a) and b
  static V masked(M m, V a) { return _mm256_and_pd(m, a); }       // m ? a : 0
  static unsigned bits(M m) { return unsigned(_mm256_movemask_pd(m)); }

  static I iload(const std::int32_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }
  static I iscale(I j, int s) { return s == 1 ? j : s == 2 ? _mm_slli_epi32(j, 1) : _mm_add_epi32(j, _mm_slli_epi32(j, 1)); }
  static V gather(const double* base, I j) {  // the masked form: GCC 12 warns about the unmasked one's undefined source
    return _mm256_mask_i32gather_pd(_mm256_setzero_pd(), base, j, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)), 8);
  }
  static I trunc(V a) { return _mm256_cvttpd_epi32(a); }
  static V to_real(I a) { return _mm256_cvtepi32_pd(a); }
  static double hsum(V a) {
    const __m128d lo = _mm256_castpd256_pd128(a), hi = _mm256_extractf128_pd(a, 1);
    const __m128d s = _mm_add_pd(lo, hi);  // (l0 + l2, l1 + l3)
    return _mm_cvtsd_f64(_mm_add_sd(s, _mm_unpackhi_pd(s, s)));
  }

  // Stores the lanes selected by `m` contiguously at `out` (a whole register is written: out needs
  // W - 1 slots of slack); the caller advances by count(m). AVX2 has no compress instruction: a
  // 16-entry table of 32-bit word permutations does it (one vpermps per array).
  struct Tables {
    alignas(32) std::int32_t d[16][8];  // for doubles: word pairs (2l, 2l + 1) of the selected lanes l
    alignas(32) std::int32_t i[16][8];  // for int32 lanes: word l of the selected lanes l
    constexpr Tables() : d{}, i{} {
      for (int m = 0; m < 16; ++m) {
        int n = 0;
        for (int l = 0; l < 4; ++l)
          if (m >> l & 1) {
            d[m][2 * n] = 2 * l;
            d[m][2 * n + 1] = 2 * l + 1;
            i[m][n] = l;
            ++n;
          }
        for (int k = n; k < 4; ++k) {  // unused lanes: anything in range
          d[m][2 * k] = 2 * k;
          d[m][2 * k + 1] = 2 * k + 1;
          i[m][k] = k;
        }
        for (int k = 4; k < 8; ++k) i[m][k] = k;
      }
    }
  };
  static const Tables& tables() {
    static constexpr Tables t{};
    return t;
  }
  static void compress(unsigned m, V a, double* out) {
    const __m256i p = _mm256_load_si256(reinterpret_cast<const __m256i*>(tables().d[m]));
    _mm256_storeu_pd(out, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(a), p)));
  }
  static void compress(unsigned m, I a, std::int32_t* out) {
    const __m256i p = _mm256_load_si256(reinterpret_cast<const __m256i*>(tables().i[m]));
    const __m256i r = _mm256_permutevar8x32_epi32(_mm256_castsi128_si256(a), p);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm256_castsi256_si128(r));
  }
  static int count(unsigned m) { return __builtin_popcount(m); }
};

}  // namespace
