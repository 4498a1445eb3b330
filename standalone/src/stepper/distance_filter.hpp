#pragma once
//! The stepper's SIMD distance filters, together: the per-step list scan's (distance2_filter,
//! filter_pairs) and the contact resolver's neighbour sweeps (filter_partners).
//!
//! |a - b|^2 for the per-step list scan's distance filter. With AVX-512VL each position is one
//! masked three-lane load and the squares are summed with two shuffles: fewer instructions and
//! cycles per pair than six scalar loads (see docs/dev/performance.md). The lanes are summed in
//! another order than dot(), so the result may differ from it in the last bits:
//! kDistanceFilterSlack widens the filter, and the caller decides each pair that passes with
//! the exact expression.
#include <cstddef>
#include <cstdint>

#include "common/always_inline.hpp"
#include "common/neighbour_entry.hpp"
#include "common/xyz4.hpp"
#include "hardsphere/vec3.hpp"

#ifdef HS_XYZ4
#define HS_DISTANCE_FILTER_SIMD 1
#endif

namespace hardsphere::detail {

#ifdef HS_DISTANCE_FILTER_SIMD
//! Relative widening of a squared limit (the sum's rounding is ~1e-7 of it in float).
template <class Real>
constexpr Real kDistanceFilterSlack = Real(1) + Real(1e-4);
#else
template <class Real>
constexpr Real kDistanceFilterSlack = Real(1);  // the scalar path is dot() itself
#endif

template <class Real>
HS_ALWAYS_INLINE Real distance2_filter(const Vec3<Real>& a, const Vec3<Real>& b) {
#ifdef HS_DISTANCE_FILTER_SIMD
  if constexpr (sizeof(Real) == sizeof(float)) {
    const __m128 d = _mm_sub_ps(load_xyz(&a.x), load_xyz(&b.x));
    const __m128 d2 = _mm_mul_ps(d, d);
    return _mm_cvtss_f32(_mm_add_ss(_mm_add_ss(d2, _mm_movehdup_ps(d2)), _mm_movehl_ps(d2, d2)));
  } else {
    const __m256d d = _mm256_sub_pd(_mm256_maskz_loadu_pd(0x7, &a.x), _mm256_maskz_loadu_pd(0x7, &b.x));
    const __m256d d2 = _mm256_mul_pd(d, d);
    const __m128d xy = _mm256_castpd256_pd128(d2), z = _mm256_extractf128_pd(d2, 1);
    return _mm_cvtsd_f64(_mm_add_sd(_mm_add_sd(xy, _mm_unpackhi_pd(xy, xy)), z));
  }
#else
  const Vec3<Real> d = a - b;
  return dot(d, d);
#endif
}

//! The filter over a run of pairs that share one limit (equal radii): appends to `hits` the
//! index k of every pair (pairs[2k], pairs[2k + 1]) with distance2_filter() < lim2 (lim2 already
//! widened by the caller) and returns their number; `hits` needs room for len + 4. In float with
//! AVX-512VL four pairs at a time: their differences transposed into x, y and z vectors and one
//! compress of the passing indices (fewer instructions per pair than one pair at a time; see
//! docs/dev/performance.md).
template <class Real>
HS_ALWAYS_INLINE std::uint32_t filter_pairs(const Vec3<Real>* __restrict pos, const std::uint32_t* __restrict pairs,
                                            std::uint32_t len, Real lim2, std::uint32_t* __restrict hits) {
  std::uint32_t n = 0, k = 0;
#ifdef HS_DISTANCE_FILTER_SIMD
  if constexpr (sizeof(Real) == sizeof(float)) {
    const float* base = &pos[0].x;
    const __m128 lim = _mm_set1_ps(lim2);
    const __m128i iota = _mm_setr_epi32(0, 1, 2, 3);
    auto diff = [&](std::uint32_t m) {
      return _mm_sub_ps(load_xyz(base + 3 * std::size_t(pairs[2 * m])),
                        load_xyz(base + 3 * std::size_t(pairs[2 * m + 1])));
    };
    for (; k + 4 <= len; k += 4) {
      const Xyz4 d = transpose_xyz4(diff(k), diff(k + 1), diff(k + 2), diff(k + 3));
      const __m128 d2 = _mm_fmadd_ps(d.z, d.z, _mm_fmadd_ps(d.x, d.x, _mm_mul_ps(d.y, d.y)));
      const __mmask8 pass = _mm_cmp_ps_mask(d2, lim, _CMP_LT_OQ);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(hits + n),
                       _mm_maskz_compress_epi32(pass, _mm_add_epi32(_mm_set1_epi32(int(k)), iota)));
      n += std::uint32_t(__builtin_popcount(pass));
    }
  }
#endif
  for (; k < len; ++k) {
    hits[n] = k;
    n += distance2_filter(pos[pairs[2 * k]], pos[pairs[2 * k + 1]]) < lim2;
  }
  return n;
}

#ifdef HS_DISTANCE_FILTER_SIMD
//! The contact resolver's neighbour-sweep filter (ContactResolver::sweep_neighbours) for equal
//! radii in float with per-sphere speeds, over list entries [k, plain) of the sphere at `ps`
//! (entries without an image): appends to hits[m...] each entry whose partner q has
//! |dr|^2 < (near + speed[q] w)^2 and q != skip, returns the new m. Four partners at a time: one
//! masked three-lane load per position, a 4x4 transpose, vector arithmetic and one compress of
//! the passing entries. |dr|^2 may round differently from dot(), far inside the bound's slack.
HS_ALWAYS_INLINE std::uint32_t filter_partners(const Vec3<float>& ps, float near, float w, std::uint32_t skip,
                                               const std::uint32_t* __restrict adj, const Vec3<float>* __restrict pos,
                                               const float* speed, std::uint32_t k, std::uint32_t plain,
                                               std::uint32_t* __restrict hits, std::uint32_t m) {
  const __m128 px = _mm_set1_ps(ps.x), py = _mm_set1_ps(ps.y), pz = _mm_set1_ps(ps.z);
  const __m128 near4 = _mm_set1_ps(near), w4 = _mm_set1_ps(w);
  const __m128i skip4 = _mm_set1_epi32(int(skip)), iota = _mm_setr_epi32(0, 1, 2, 3);
  const float* pbase = &pos[0].x;
  for (; k < plain; k += 4) {
    const __mmask8 live = plain - k >= 4 ? __mmask8(0xf) : __mmask8((1u << (plain - k)) - 1);
    const __m128i q = _mm_srli_epi32(_mm_maskz_loadu_epi32(live, adj + k), int(kAdjImageBits));
    alignas(16) std::uint32_t qs[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(qs), q);  // dead lanes: sphere 0, masked below
    const Xyz4 r = transpose_xyz4(load_xyz(pbase + 3 * std::size_t(qs[0])), load_xyz(pbase + 3 * std::size_t(qs[1])),
                                  load_xyz(pbase + 3 * std::size_t(qs[2])), load_xyz(pbase + 3 * std::size_t(qs[3])));
    const __m128 dx = _mm_sub_ps(px, r.x), dy = _mm_sub_ps(py, r.y), dz = _mm_sub_ps(pz, r.z);
    const __m128 d2 = _mm_fmadd_ps(dz, dz, _mm_fmadd_ps(dx, dx, _mm_mul_ps(dy, dy)));
    const __m128 sq = _mm_setr_ps(speed[qs[0]], speed[qs[1]], speed[qs[2]], speed[qs[3]]);
    const __m128 far = _mm_fmadd_ps(sq, w4, near4);
    const __mmask8 pass =
        _mm_mask_cmp_ps_mask(live, d2, _mm_mul_ps(far, far), _CMP_LT_OQ) & _mm_mask_cmpneq_epi32_mask(live, q, skip4);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(hits + m),
                     _mm_maskz_compress_epi32(pass, _mm_add_epi32(_mm_set1_epi32(int(k)), iota)));
    m += std::uint32_t(__builtin_popcount(pass));
  }
  return m;
}
#endif

}  // namespace hardsphere::detail
