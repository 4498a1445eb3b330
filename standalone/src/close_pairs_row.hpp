#pragma once
//! The pair build's inner loop: append (i, j) for every j of a contiguous run [j0, j1) of the
//! cell-sorted spheres that lies within the list cut-off of sphere i. Most of a rebuild is spent
//! here; with AVX-512 it tests 8 candidates per instruction and compacts the hits with one
//! compress, otherwise it is the branch-free scalar loop. Both compute |d|^2 as
//! (dx dx + dy dy) + dz dz from the same coordinates, so they keep the same pairs.
#include <cstddef>
#include <cstdint>

#if defined(__AVX512F__) && defined(__AVX512VL__)
#include <immintrin.h>
#define HS_CLOSE_PAIRS_AVX512 1
#endif

namespace hardsphere::detail {

//! Structure-of-arrays view of the cell-sorted spheres (radii null when all are equal).
template <class Real>
struct RowSoA {
  const Real *x, *y, *z, *r;
};

//! Spare entries the output must have beyond the hits: the vector path stores whole vectors.
constexpr std::size_t kRowSlack = 8;

//! Radii: the cut-off is (r_i + r_j) + skin, squared; Mono uses cut2 for every pair. out holds
//! pairs as two uint32 (i, j); n counts pairs. Returns the new count.
template <class Real, bool Mono>
inline std::size_t append_close_row(const RowSoA<Real>& s, std::uint32_t i, Real px, Real py, Real pz,
                                    Real ri, Real skin, Real cut2, std::uint32_t j0, std::uint32_t j1,
                                    std::uint32_t* out, std::size_t n) {
#ifdef HS_CLOSE_PAIRS_AVX512
  const __m512i iota = _mm512_set_epi64(7, 6, 5, 4, 3, 2, 1, 0);
  const __m512i ii = _mm512_set1_epi64(std::int64_t(i));
  for (std::uint32_t j = j0; j < j1; j += 8) {
    const __mmask8 live = j1 - j >= 8 ? __mmask8(0xff) : __mmask8((1u << (j1 - j)) - 1);
    __mmask8 hit;
    if constexpr (sizeof(Real) == 4) {
      const __m256 dx = _mm256_sub_ps(_mm256_set1_ps(px), _mm256_maskz_loadu_ps(live, s.x + j));
      const __m256 dy = _mm256_sub_ps(_mm256_set1_ps(py), _mm256_maskz_loadu_ps(live, s.y + j));
      const __m256 dz = _mm256_sub_ps(_mm256_set1_ps(pz), _mm256_maskz_loadu_ps(live, s.z + j));
      const __m256 d2 = _mm256_fmadd_ps(dz, dz, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dx, dx)));
      __m256 c2 = _mm256_set1_ps(cut2);
      if constexpr (!Mono) {
        const __m256 c = _mm256_add_ps(_mm256_add_ps(_mm256_set1_ps(ri), _mm256_maskz_loadu_ps(live, s.r + j)),
                                       _mm256_set1_ps(skin));
        c2 = _mm256_mul_ps(c, c);
      }
      hit = _mm256_mask_cmp_ps_mask(live, d2, c2, _CMP_LT_OQ);
    } else {
      const __m512d dx = _mm512_sub_pd(_mm512_set1_pd(px), _mm512_maskz_loadu_pd(live, s.x + j));
      const __m512d dy = _mm512_sub_pd(_mm512_set1_pd(py), _mm512_maskz_loadu_pd(live, s.y + j));
      const __m512d dz = _mm512_sub_pd(_mm512_set1_pd(pz), _mm512_maskz_loadu_pd(live, s.z + j));
      const __m512d d2 = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dy, dy, _mm512_mul_pd(dx, dx)));
      __m512d c2 = _mm512_set1_pd(cut2);
      if constexpr (!Mono) {
        const __m512d c = _mm512_add_pd(_mm512_add_pd(_mm512_set1_pd(ri), _mm512_maskz_loadu_pd(live, s.r + j)),
                                        _mm512_set1_pd(skin));
        c2 = _mm512_mul_pd(c, c);
      }
      hit = _mm512_mask_cmp_pd_mask(live, d2, c2, _CMP_LT_OQ);
    }
    // x86 is little-endian: the 64-bit lane i | j << 32 is the uint32 pair (i, j) in memory.
    const __m512i pairs = _mm512_or_si512(ii, _mm512_maskz_slli_epi64(0xff, _mm512_add_epi64(_mm512_set1_epi64(j), iota), 32));
    // Compress in a register and store the whole vector (a compressing store to memory is slow
    // on Intel cores); the entries past the hits are scratch, overwritten or cut off later.
    _mm512_storeu_si512(out + 2 * n, _mm512_maskz_compress_epi64(hit, pairs));
    n += std::size_t(__builtin_popcount(hit));
  }
  return n;
#else
  for (std::uint32_t j = j0; j < j1; ++j) {
    const Real dx = px - s.x[j], dy = py - s.y[j], dz = pz - s.z[j];
    const Real d2 = (dx * dx + dy * dy) + dz * dz;
    Real c2 = cut2;
    if constexpr (!Mono) {
      const Real c = (ri + s.r[j]) + skin;
      c2 = c * c;
    }
    out[2 * n] = i, out[2 * n + 1] = j;
    n += d2 < c2;
  }
  return n;
#endif
}

}  // namespace hardsphere::detail
