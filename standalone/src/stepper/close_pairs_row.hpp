#pragma once
//! The pair build's inner loop: append (i, j) for every j of a contiguous run [j0, j1) of the
//! cell-sorted spheres that lies within the list cut-off of sphere i. Most of a rebuild is spent
//! here; with AVX-512 it tests 8 candidates per instruction and compacts the hits with one
//! compress, otherwise it is the branch-free scalar loop. Both compute |d|^2 as
//! (dx dx + dy dy) + dz dz from the same coordinates, so they keep the same pairs.
#include <algorithm>
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

#ifdef HS_CLOSE_PAIRS_AVX512
//! Eight lanes of Real: 256-bit floats or 512-bit doubles, so one mask covers both.
template <class Real>
struct Lanes8;
template <>
struct Lanes8<float> {
  static __m256 set(float a) { return _mm256_set1_ps(a); }
  static __m256 load(__mmask8 m, const float* p) { return _mm256_maskz_loadu_ps(m, p); }
  static __m256 add(__m256 a, __m256 b) { return _mm256_add_ps(a, b); }
  static __m256 sub(__m256 a, __m256 b) { return _mm256_sub_ps(a, b); }
  static __m256 mul(__m256 a, __m256 b) { return _mm256_mul_ps(a, b); }
  static __m256 fmadd(__m256 a, __m256 b, __m256 c) { return _mm256_fmadd_ps(a, b, c); }
  static __mmask8 less(__mmask8 m, __m256 a, __m256 b) { return _mm256_mask_cmp_ps_mask(m, a, b, _CMP_LT_OQ); }
};
template <>
struct Lanes8<double> {
  static __m512d set(double a) { return _mm512_set1_pd(a); }
  static __m512d load(__mmask8 m, const double* p) { return _mm512_maskz_loadu_pd(m, p); }
  static __m512d add(__m512d a, __m512d b) { return _mm512_add_pd(a, b); }
  static __m512d sub(__m512d a, __m512d b) { return _mm512_sub_pd(a, b); }
  static __m512d mul(__m512d a, __m512d b) { return _mm512_mul_pd(a, b); }
  static __m512d fmadd(__m512d a, __m512d b, __m512d c) { return _mm512_fmadd_pd(a, b, c); }
  static __mmask8 less(__mmask8 m, __m512d a, __m512d b) { return _mm512_mask_cmp_pd_mask(m, a, b, _CMP_LT_OQ); }
};

//! Eight candidates j .. j + 7 of a run [.., j1), loaded once (lanes past the run masked off),
//! and the pair words (0, j + k) they would make. Shared by the row and the block kernel.
template <class Real, bool Mono>
struct Chunk8 {
  using L = Lanes8<Real>;
  decltype(L::set(Real(0))) x, y, z, r;
  __mmask8 live;
  __m512i pair_j;  // x86 is little-endian: the 64-bit lane i | j << 32 is the uint32 pair (i, j)
  Chunk8(const RowSoA<Real>& s, std::uint32_t j, std::uint32_t j1)
      : x(), y(), z(), r(L::set(Real(0))), live(j1 - j >= 8 ? __mmask8(0xff) : __mmask8((1u << (j1 - j)) - 1)) {
    x = L::load(live, s.x + j), y = L::load(live, s.y + j), z = L::load(live, s.z + j);
    if constexpr (!Mono) r = L::load(live, s.r + j);
    pair_j = _mm512_maskz_slli_epi64(
        0xff, _mm512_add_epi64(_mm512_set1_epi64(j), _mm512_set_epi64(7, 6, 5, 4, 3, 2, 1, 0)), 32);
  }
  //! The lanes of `mask` within the cut-off of a sphere at (px, py, pz) of radius ri:
  //! |d|^2 = fma(dz, dz, fma(dy, dy, dx dx)) against cut2 (Mono) or ((ri + r_j) + skin)^2.
  __mmask8 hits(__mmask8 mask, Real px, Real py, Real pz, Real ri, Real skin, Real cut2) const {
    const auto dx = L::sub(L::set(px), x), dy = L::sub(L::set(py), y), dz = L::sub(L::set(pz), z);
    const auto d2 = L::fmadd(dz, dz, L::fmadd(dy, dy, L::mul(dx, dx)));
    auto c2 = L::set(cut2);
    if constexpr (!Mono) {
      const auto c = L::add(L::add(L::set(ri), r), L::set(skin));
      c2 = L::mul(c, c);
    }
    return L::less(mask, d2, c2);
  }
  //! Appends the pairs (i, j + k) of the lanes in `hit` at out[2 n ..]; returns the new count.
  //! Compressed in a register and stored as a whole vector (a compressing store to memory is
  //! slow on Intel cores); the entries past the hits are scratch, overwritten or cut off later.
  std::size_t append(std::uint32_t* out, std::size_t n, std::uint32_t i, __mmask8 hit) const {
    _mm512_storeu_si512(out + 2 * n,
                        _mm512_maskz_compress_epi64(hit, _mm512_or_si512(_mm512_set1_epi64(std::int64_t(i)), pair_j)));
    return n + std::size_t(__builtin_popcount(hit));
  }
};
#endif

//! Radii: the cut-off is (r_i + r_j) + skin, squared; Mono uses cut2 for every pair. out holds
//! pairs as two uint32 (i, j); n counts pairs. Returns the new count.
template <class Real, bool Mono>
inline std::size_t append_close_row(const RowSoA<Real>& s, std::uint32_t i, Real px, Real py, Real pz, Real ri,
                                    Real skin, Real cut2, std::uint32_t j0, std::uint32_t j1, std::uint32_t* out,
                                    std::size_t n) {
#ifdef HS_CLOSE_PAIRS_AVX512
  for (std::uint32_t j = j0; j < j1; j += 8) {
    const Chunk8<Real, Mono> chunk(s, j, j1);
    n = chunk.append(out, n, i, chunk.hits(chunk.live, px, py, pz, ri, skin, cut2));
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

//! append_close_row() for every sphere i of [i0, i1) against one run [j0, j1), taking only j > i
//! if `upper` (a run that starts inside i's own cell). The pair build's kernel: a cell's few
//! spheres share their forward runs, so each run's coordinates are loaded once (eight lanes at
//! a time with AVX-512) for all of them. Pairs come out run by run; the distance is computed
//! as in append_close_row, so the pairs are the same. If `degree` is given, degree[i] and
//! degree[j] go up by one for each pair (i, j) found: the list's row lengths, counted here where
//! the hit masks are at hand instead of in a pass over the pairs.
template <class Real, bool Mono>
inline std::size_t append_close_block(const RowSoA<Real>& s, std::uint32_t i0, std::uint32_t i1, std::uint32_t j0,
                                      std::uint32_t j1, bool upper, Real skin, Real cut2, std::uint32_t* out,
                                      std::size_t n, std::uint32_t* degree = nullptr) {
#ifdef HS_CLOSE_PAIRS_AVX512
  for (std::uint32_t j = j0; j < j1; j += 8) {
    const Chunk8<Real, Mono> chunk(s, j, j1);
    __m256i hits_j = _mm256_setzero_si256();  // pairs per j of this chunk, over all i
    for (std::uint32_t i = i0; i < i1; ++i) {
      __mmask8 m = chunk.live;
      if (upper && i >= j) m &= i - j >= 7 ? __mmask8(0) : __mmask8(~((2u << (i - j)) - 1));
      const __mmask8 hit = chunk.hits(m, s.x[i], s.y[i], s.z[i], Mono ? Real(0) : s.r[i], skin, cut2);
      n = chunk.append(out, n, i, hit);
      if (degree) {
        degree[i] += std::uint32_t(__builtin_popcount(hit));
        hits_j = _mm256_mask_add_epi32(hits_j, hit, hits_j, _mm256_set1_epi32(1));
      }
    }
    if (degree)  // after the i loop: an i of this chunk (own cell) has its own count in by now
      _mm256_mask_storeu_epi32(degree + j, chunk.live,
                               _mm256_add_epi32(_mm256_maskz_loadu_epi32(chunk.live, degree + j), hits_j));
  }
  return n;
#else
  for (std::uint32_t i = i0; i < i1; ++i) {
    const std::uint32_t from = upper ? std::max(j0, i + 1) : j0;
    if (from >= j1) continue;
    const std::size_t before = n;
    n = append_close_row<Real, Mono>(s, i, s.x[i], s.y[i], s.z[i], Mono ? Real(0) : s.r[i], skin, cut2, from, j1, out,
                                     n);
    if (degree)
      for (std::size_t k = before; k < n; ++k) ++degree[out[2 * k]], ++degree[out[2 * k + 1]];
  }
  return n;
#endif
}

}  // namespace hardsphere::detail
