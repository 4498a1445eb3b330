#pragma once
//! The stepper's drift: every sphere moves by v dt, records its squared displacement from the
//! rebuild reference (for the list guard) and, optionally, its speed. Positions and velocities
//! are xyz triples (AoS). With AVX-512 a block of L spheres (16 floats or 8 doubles per
//! register) is three registers: the move is element-wise on them as they are, and the
//! per-sphere sums of squares take the components apart with two permutes each. The scalar
//! loop was a visible part of a dense step (no vectorised sqrt, three strided streams; see
//! docs/dev/performance.md).
//! Both paths compute |d|^2 as fma(dz, dz, fma(dx, dx, dy dy)) (what GCC makes of the scalar
//! expression), so they give the same numbers.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>

#if defined(__AVX512F__)
#include <immintrin.h>
#define HS_DRIFT_AVX512 1
#endif

namespace hardsphere::detail {

//! Max of squared displacements (starting from max_d2) and of squared speeds.
template <class Real>
struct DriftMaxima {
  Real d2, v2;
};

#ifdef HS_DRIFT_AVX512
template <class Real>
struct DriftLanes;
template <>
struct DriftLanes<float> {
  static constexpr int L = 16;
  using V = __m512;
  using I = __m512i;
  static V load(const float* p) { return _mm512_loadu_ps(p); }
  static void store(float* p, V a) { _mm512_storeu_ps(p, a); }
  static V set(float a) { return _mm512_set1_ps(a); }
  static V fmadd(V a, V b, V c) { return _mm512_fmadd_ps(a, b, c); }
  static V sub(V a, V b) { return _mm512_sub_ps(a, b); }
  static V mul(V a, V b) { return _mm512_mul_ps(a, b); }
  static V max(V a, V b) { return _mm512_maskz_max_ps(0xffff, a, b); }
  static V sqrt(V a) { return _mm512_maskz_sqrt_ps(0xffff, a); }
  static V perm2(V a, I idx, V b) { return _mm512_permutex2var_ps(a, idx, b); }
  static std::uint32_t at_least(V a, float b) { return _mm512_cmp_ps_mask(a, _mm512_set1_ps(b), _CMP_GE_OQ); }
  static I index(const int* k) { return _mm512_loadu_si512(k); }
};
template <>
struct DriftLanes<double> {
  static constexpr int L = 8;
  using V = __m512d;
  using I = __m512i;
  static V load(const double* p) { return _mm512_loadu_pd(p); }
  static void store(double* p, V a) { _mm512_storeu_pd(p, a); }
  static V set(double a) { return _mm512_set1_pd(a); }
  static V fmadd(V a, V b, V c) { return _mm512_fmadd_pd(a, b, c); }
  static V sub(V a, V b) { return _mm512_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm512_mul_pd(a, b); }
  static V max(V a, V b) { return _mm512_maskz_max_pd(0xff, a, b); }
  static V sqrt(V a) { return _mm512_maskz_sqrt_pd(0xff, a); }
  static V perm2(V a, I idx, V b) { return _mm512_permutex2var_pd(a, idx, b); }
  static std::uint32_t at_least(V a, double b) { return _mm512_cmp_pd_mask(a, _mm512_set1_pd(b), _CMP_GE_OQ); }
  static I index(const int* k) {  // 64-bit lanes
    return _mm512_maskz_cvtepi32_epi64(0xff, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(k)));
  }
};

//! Permute indices that take component c (0 = x) of the L spheres held in registers a, b, e
//! (3 L values, sphere k's component at 3 k + c): first from (a, b), then the rest from e.
template <int L>
struct ComponentIndex {
  int from_ab[3][L], from_e[3][L];
  constexpr ComponentIndex() : from_ab(), from_e() {
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < L; ++k) {
        const int at = 3 * k + c;
        from_ab[c][k] = at < 2 * L ? at : 0;
        from_e[c][k] = at < 2 * L ? k : L + (at - 2 * L);  // keep lane k, or take e's lane
      }
  }
};
#endif

//! Moves the n spheres and records d2max[i] = max(d2max[i], |p - p0|^2) and, if `speed`,
//! speed[i] = |v|; returns the maxima of |p - p0|^2 (with max_d2 as a floor) and of |v|^2.
//! The spheres whose record reaches flag_d2 are appended to flagged (room for n), in order.
template <class Real>
DriftMaxima<Real> drift_spheres(Real* __restrict p, const Real* __restrict v, const Real* __restrict p0,
                                Real* __restrict d2max, Real* __restrict speed, std::size_t n, Real dt, Real max_d2,
                                Real flag_d2, std::uint32_t* __restrict flagged, std::size_t& n_flagged) {
  Real m = max_d2, v2max = 0;
  n_flagged = 0;
  std::size_t i = 0;
#ifdef HS_DRIFT_AVX512
  using T = DriftLanes<Real>;
  constexpr int L = T::L;
  static constexpr ComponentIndex<L> idx{};
  typename T::I ab[3], e[3];
  for (int c = 0; c < 3; ++c) ab[c] = T::index(idx.from_ab[c]), e[c] = T::index(idx.from_e[c]);
  auto component = [&](typename T::V a, typename T::V b, typename T::V c3, int c) {
    return T::perm2(T::perm2(a, ab[c], b), e[c], c3);
  };
  auto sum_sq = [&](typename T::V a, typename T::V b, typename T::V c3) {
    const auto x = component(a, b, c3, 0), y = component(a, b, c3, 1), z = component(a, b, c3, 2);
    return T::fmadd(z, z, T::fmadd(x, x, T::mul(y, y)));
  };
  const auto vdt = T::set(dt);
  auto vm = T::set(m), vv = T::set(Real(0));
  for (; i + L <= n; i += L) {
    Real* pi = p + 3 * i;
    const Real* vi = v + 3 * i;
    const Real* p0i = p0 + 3 * i;
    const auto v0 = T::load(vi), v1 = T::load(vi + L), v2 = T::load(vi + 2 * L);
    const auto q0 = T::fmadd(v0, vdt, T::load(pi)), q1 = T::fmadd(v1, vdt, T::load(pi + L)),
               q2 = T::fmadd(v2, vdt, T::load(pi + 2 * L));
    T::store(pi, q0), T::store(pi + L, q1), T::store(pi + 2 * L, q2);
    const auto d2 = sum_sq(T::sub(q0, T::load(p0i)), T::sub(q1, T::load(p0i + L)), T::sub(q2, T::load(p0i + 2 * L)));
    const auto rec = T::max(d2, T::load(d2max + i));
    T::store(d2max + i, rec);
    for (std::uint32_t f = T::at_least(rec, flag_d2); f != 0; f &= f - 1)  // rare: movers
      flagged[n_flagged++] = std::uint32_t(i) + std::uint32_t(__builtin_ctz(f));
    vm = T::max(vm, d2);
    const auto w2 = sum_sq(v0, v1, v2);
    if (speed) T::store(speed + i, T::sqrt(w2));
    vv = T::max(vv, w2);
  }
  // (The masked forms above and this reduction avoid GCC 12's false "uninitialized" warnings
  // from the intrinsics that take an undefined pass-through register.)
  alignas(64) Real lanes_m[L], lanes_v[L];
  T::store(lanes_m, vm), T::store(lanes_v, vv);
  for (int k = 0; k < L; ++k) m = lanes_m[k] > m ? lanes_m[k] : m, v2max = lanes_v[k] > v2max ? lanes_v[k] : v2max;
#endif
  for (; i < n; ++i) {
    Real* pi = p + 3 * i;
    const Real* vi = v + 3 * i;
    const Real* p0i = p0 + 3 * i;
    pi[0] += vi[0] * dt;
    pi[1] += vi[1] * dt;
    pi[2] += vi[2] * dt;
    const Real dx = pi[0] - p0i[0], dy = pi[1] - p0i[1], dz = pi[2] - p0i[2];
    const Real d2 = dx * dx + dy * dy + dz * dz;
    d2max[i] = d2 > d2max[i] ? d2 : d2max[i];
    if (d2max[i] >= flag_d2) flagged[n_flagged++] = std::uint32_t(i);
    m = d2 > m ? d2 : m;
    const Real v2 = vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2];
    if (speed) speed[i] = std::sqrt(v2);
    v2max = v2 > v2max ? v2 : v2max;
  }
  return {m, v2max};
}

//! Adds dv to component `axis` of n velocities (xyz triples), compensated: residual (laid out like
//! v) keeps what rounding each sum lost, and the next sum adds it back (Knuth's TwoSum, exact for
//! any magnitudes). A plain v += dv rounds the same way every time while v stays in one binade (dv
//! is the same fraction of its ulp), which in float biased a gas's energy under gravity (+2.3e-5
//! in 6000 steps of 1000 spheres, every seed alike). Only the axes with gravity need it.
template <class Real>
void kick_compensated(Real* __restrict v, Real* __restrict residual, std::size_t n, int axis, Real dv) {
  for (std::size_t k = std::size_t(axis); k < 3 * n; k += 3) {
    const Real x = v[k], y = dv + residual[k];
    const Real s = x + y, y_in_s = s - x;
    residual[k] = (x - (s - y_in_s)) + (y - y_in_s);
    v[k] = s;
  }
}

}  // namespace hardsphere::detail
