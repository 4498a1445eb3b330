#pragma once
//! Four xyz triples as one vector per coordinate, for the vector filters of the list scan and
//! of the neighbour sweeps (AVX-512VL only: each triple is one masked three-lane load, which
//! reads nothing past the triple). HS_XYZ4 tells whether these exist.
#include "common/always_inline.hpp"

#if defined(__AVX512VL__)
#include <immintrin.h>
#define HS_XYZ4 1

namespace hardsphere {

//! The triple at p (x, y, z, 0).
HS_ALWAYS_INLINE __m128 load_xyz(const float* p) { return _mm_maskz_loadu_ps(0x7, p); }

struct Xyz4 {
  __m128 x, y, z;
};

//! Rows (x_k, y_k, z_k, *) of k = 0..3 transposed into the x, y and z of all four.
HS_ALWAYS_INLINE Xyz4 transpose_xyz4(__m128 r0, __m128 r1, __m128 r2, __m128 r3) {
  const __m128 t0 = _mm_unpacklo_ps(r0, r1), t1 = _mm_unpackhi_ps(r0, r1);
  const __m128 t2 = _mm_unpacklo_ps(r2, r3), t3 = _mm_unpackhi_ps(r2, r3);
  return {_mm_movelh_ps(t0, t2), _mm_movehl_ps(t2, t0), _mm_movelh_ps(t1, t3)};
}

}  // namespace hardsphere
#endif
