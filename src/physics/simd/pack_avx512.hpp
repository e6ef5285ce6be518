#pragma once
// Eight doubles in an AVX-512 register (AVX-512F only), the same operations as PackAvx2. Included only by
// sweep_avx512.cpp (compiled with -mavx512f); internal linkage, like pack_avx2.hpp.
#include <immintrin.h>

#include <cstdint>

namespace {

struct PackAvx512 {
  static constexpr int W = 8;
  using V = __m512d;
  using M = __mmask8;
  using I = __m256i;  // 8 int32 indices

  static V load(const double* p) { return _mm512_loadu_pd(p); }
  static void store(double* p, V v) { _mm512_storeu_pd(p, v); }
  static V set1(double a) { return _mm512_set1_pd(a); }
  static V zero() { return _mm512_setzero_pd(); }
  static V add(V a, V b) { return _mm512_add_pd(a, b); }
  static V sub(V a, V b) { return _mm512_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm512_mul_pd(a, b); }
  static V div(V a, V b) { return _mm512_div_pd(a, b); }
  static V fmadd(V a, V b, V c) { return _mm512_fmadd_pd(a, b, c); }
  static V fnmadd(V a, V b, V c) { return _mm512_fnmadd_pd(a, b, c); }  // c - a b
  static V min(V a, V b) { return _mm512_min_pd(a, b); }
  static M lt(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
  static M eq(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_EQ_OQ); }
  static M neq(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_NEQ_UQ); }
  static M mand(M a, M b) { return M(a & b); }
  static M mandnot(M a, M b) { return M(~a & b); }
  static V masked(M m, V a) { return _mm512_maskz_mov_pd(m, a); }
  static unsigned bits(M m) { return unsigned(m); }

  static I iload(const std::int32_t* p) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)); }
  static I iscale(I j, int s) {
    return s == 1 ? j : s == 2 ? _mm256_slli_epi32(j, 1) : _mm256_add_epi32(j, _mm256_slli_epi32(j, 1));
  }
  static V gather(const double* base, I j) {  // masked: GCC 12 warns about the unmasked form's undefined source
    return _mm512_mask_i32gather_pd(_mm512_setzero_pd(), __mmask8(0xFF), j, base, 8);
  }
  static I trunc(V a) { return _mm512_cvttpd_epi32(a); }
  static V to_real(I a) { return _mm512_cvtepi32_pd(a); }
  static double hsum(V a) {  // fixed pairing: (0+4, 1+5, 2+6, 3+7), then as PackAvx2
    const __m256d s4 = _mm256_add_pd(_mm512_castpd512_pd256(a), _mm512_extractf64x4_pd(a, 1));
    const __m128d s2 = _mm_add_pd(_mm256_castpd256_pd128(s4), _mm256_extractf128_pd(s4, 1));
    return _mm_cvtsd_f64(_mm_add_sd(s2, _mm_unpackhi_pd(s2, s2)));
  }

  // compress to a register and store it whole (compress straight to memory is microcoded on some cores)
  static void compress(unsigned m, V a, double* out) { _mm512_storeu_pd(out, _mm512_maskz_compress_pd(M(m), a)); }
  static void compress(unsigned m, I a, std::int32_t* out) {
    const __m512i r = _mm512_maskz_compress_epi32(__mmask16(m), _mm512_castsi256_si512(a));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm512_castsi512_si256(r));
  }
  static int count(unsigned m) { return __builtin_popcount(m); }
};

}  // namespace
