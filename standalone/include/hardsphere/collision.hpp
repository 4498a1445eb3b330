#pragma once
//! The physics kernel: contact times, elastic impulses and wall reflection as pure functions.
//! Used by the time stepper and the event engine (the LAMMPS fix runs the stepper). "No contact" is +inf,
//! so this must never be compiled with -ffast-math.
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "hardsphere/vec3.hpp"

namespace hardsphere::kernel {

template <class T>
constexpr T never() {
  return std::numeric_limits<T>::infinity();
}

namespace detail {
//! Single precision collides in double: the float forms of collide(), collide_equal_mass(),
//! collide_rough() and wall_tangential() widen their inputs, run the double kernel and round each
//! result once, whose energy error then has mean 0 (its sum is a random walk). Float's own
//! rounding leaned one way: a unit contact puts |dr|^2 within a few ulps of 1, where b / |dr|^2
//! came out high more often than low (+3.0e-9 of the pair's energy per collision, every collision
//! alike), and the rough factors q mu / (n2 + q) and 1 / (q m a) carry fixed errors (+2.1e-8).
template <class T>
constexpr bool kWidened = std::is_same_v<T, float>;
inline Vec3<double> widen(Vec3<float> a) { return {a.x, a.y, a.z}; }
inline Vec3<float> narrow(Vec3<double> a) { return {float(a.x), float(a.y), float(a.z)}; }

//! rewind_time() from the pair's a = dv^2, b = dr.dv, c = dr^2 - sigma^2.
template <class T>
inline T rewind_from(T a, T b, T c) {
  const T root = std::sqrt(std::max(T(0), b * b - a * c));
  if (b < T(0)) return -c / (root - b);
  if (a > T(0)) return (b + root) / a;
  return never<T>();
}
}  // namespace detail

//! Back time s of a pair's entry into contact for straight-line motion: the larger root of
//! |dr - dv s| = sigma, i.e. of a s^2 - 2 b s + c = 0 with a = dv^2, b = dr.dv, c = dr^2 - sigma^2.
//! dr = r1 - r2, dv = v1 - v2 now. Valid when the pair touches at all (b^2 - a c >= 0), e.g. it
//! overlaps now (c < 0). Stable forms: -c / (sqrt(disc) - b) for b < 0, (b + sqrt(disc)) / a
//! for b >= 0, each a ratio of same-signed terms. +inf when there is no relative motion.
template <class T>
inline T rewind_time(Vec3<T> dr, Vec3<T> dv, T sigma) {
  return detail::rewind_from(dot(dv, dv), dot(dr, dv), dot(dr, dr) - sigma * sigma);
}

//! Did a pair moving in straight lines over the last `window` of time touch while approaching?
//! True iff it overlapped at some back time s in [0, window] at which it was still approaching:
//! the approach lasts for back times s > b/a and the overlap for s in (s_exit, s_entry), so the
//! test is b < window a, entry s_entry > 0 and a real contact (disc > 0). If so, returns
//! rewind_time() (>= 0, from the same dot products), otherwise -1.
//! `overlap_only` restricts it to pairs that overlap now (the seed's a posteriori detection).
template <class T>
inline T touched_back_time(Vec3<T> dr, Vec3<T> dv, T sigma, T window, bool overlap_only) {
  const T c = dot(dr, dr) - sigma * sigma;
  const T b = dot(dr, dv);
  if (!(c < T(0)) && (overlap_only || !(b > T(0)))) return T(-1);
  const T a = dot(dv, dv);
  if (!(b < window * a && b * b - a * c > T(0))) return T(-1);
  return detail::rewind_from(a, b, c);
}

//! Back time s of the contact of a sphere falling under acceleration g with a kinematic one (which
//! no gravity acts on): the root of |dr - dv s + g s^2 / 2| = sigma (dr, dv: the pair now, the
//! falling sphere first) near `guess` (the straight-line root, touched_back_time()), by Newton's
//! method, which from there converges in a few steps (their relative motion is no longer straight:
//! the straight root is off by about g s^2 / 2). Where Newton's root is not an approaching one in
//! [0, window], the entry is bracketed instead: a pair that overlapped and approached at the
//! window's start collides there (as touched_back_time() clamps), one that entered within the
//! window at its entry (bisection), one that overlaps and approaches only now, now. -1: no contact.
template <class T>
inline T kinematic_back_time(Vec3<T> dr, Vec3<T> dv, Vec3<T> g, T sigma, T guess, T window) {
  auto sep = [&](T s) { return dr - s * dv + (T(0.5) * s * s) * g; };
  auto gap = [&](T s) {
    const Vec3<T> d = sep(s);
    return dot(d, d) - sigma * sigma;
  };
  auto approaching = [&](T s) { return dot(sep(s), dv - s * g) < T(0); };
  T s = std::min(std::max(guess, T(0)), window);
  for (int it = 0; it < 32; ++it) {
    const T fp = T(2) * dot(sep(s), s * g - dv);
    if (!(fp != T(0))) break;
    const T ds = gap(s) / fp;
    s -= ds;
    if (!(std::abs(ds) > T(4) * std::numeric_limits<T>::epsilon() * std::abs(s))) break;
  }
  if (s >= T(0) && s <= window && approaching(s)) return s;
  if (gap(window) < T(0)) {
    if (approaching(window)) return window;
  } else if (gap(T(0)) < T(0)) {
    T in = 0, out = window;  // overlapping now, apart at the window's start: the entry between
    for (int it = 0; it < 200 && out - in > T(4) * std::numeric_limits<T>::epsilon() * out; ++it) {
      const T mid = T(0.5) * (in + out);
      (gap(mid) < T(0) ? in : out) = mid;
    }
    if (approaching(in)) return in;
  }
  return gap(T(0)) < T(0) && approaching(T(0)) ? T(0) : T(-1);
}

//! Time t >= 0 until a pair touches, or +inf if it never does (receding, or missing).
//! Same stable form as rewind_time; an overlapping approaching pair collides now (t = 0).
template <class T>
inline T contact_time(Vec3<T> dr, Vec3<T> dv, T sigma) {
  const T b = dot(dr, dv);
  if (!(b < T(0))) return never<T>();
  const T c = dot(dr, dr) - sigma * sigma;
  if (c <= T(0)) return T(0);
  const T a = dot(dv, dv);
  const T disc = b * b - a * c;
  if (disc <= T(0)) return never<T>();
  return c / (std::sqrt(disc) - b);
}

//! Elastic (or restituted, e < 1) impulse J along the contact normal n = dr/|dr|:
//! v1 += (J/m1) n, v2 -= (J/m2) n. Returns J >= 0 for an approaching pair, 0 otherwise.
//! dr.dp1 = J |dr| is the pair's contribution to the collision virial.
template <class T>
inline T normal_impulse(Vec3<T> dr, Vec3<T> dv, T m1, T m2, T restitution = T(1)) {
  const T r2 = dot(dr, dr);
  const T b = dot(dr, dv);
  if (!(b < T(0)) || !(r2 > T(0))) return T(0);
  const T reduced_mass = m1 * m2 / (m1 + m2);
  // J n = -(1+e) mu (dv.n) n with n = dr/|dr|; return J/|dr| times |dr| folded into one division.
  return -(T(1) + restitution) * reduced_mass * b / std::sqrt(r2);
}

//! Applies a pair collision at contact separation dr: v1 += m2 s dr, v2 -= m1 s dr with
//! s = -(1+e) dr.dv / (|dr|^2 (m1+m2)). No square root: at contact distances near a power of two
//! (unit diameters) |dr|^2 sits a few ulps from it, where a rounded square root leans one way and
//! every collision would gain energy. Returns the virial term dr.dp1 = -(1+e) mu dr.dv (>= 0).
template <class T>
inline T collide(Vec3<T> dr, Vec3<T>& v1, Vec3<T>& v2, T m1, T m2, T restitution = T(1)) {
  if constexpr (detail::kWidened<T>) {  // see detail::kWidened
    Vec3<double> u1 = detail::widen(v1), u2 = detail::widen(v2);
    const double virial = collide(detail::widen(dr), u1, u2, double(m1), double(m2), double(restitution));
    v1 = detail::narrow(u1), v2 = detail::narrow(u2);
    return T(virial);
  }
  const T r2 = dot(dr, dr);
  const T b = dot(dr, v1 - v2);
  if (!(b < T(0)) || !(r2 > T(0))) return T(0);
  const T s = -(T(1) + restitution) * b / (r2 * (m1 + m2));
  v1 += (s * m2) * dr;
  v2 -= (s * m1) * dr;
  return -(T(1) + restitution) * (m1 * m2 / (m1 + m2)) * b;
}

//! Equal-mass special case: the velocity change is exactly antisymmetric, so momentum is
//! conserved bit for bit. Returns dr.dp1 / m.
template <class T>
inline T collide_equal_mass(Vec3<T> dr, Vec3<T>& v1, Vec3<T>& v2) {
  if constexpr (detail::kWidened<T>) {  // see detail::kWidened
    Vec3<double> u1 = detail::widen(v1), u2 = detail::widen(v2);
    const double virial = collide_equal_mass(detail::widen(dr), u1, u2);
    v1 = detail::narrow(u1), v2 = detail::narrow(u2);
    return T(virial);
  }
  const T r2 = dot(dr, dr);
  const T b = dot(dr, v1 - v2);
  if (!(b < T(0)) || !(r2 > T(0))) return T(0);
  const Vec3<T> dv_n = (b / r2) * dr;  // normal component of the relative velocity
  v1 -= dv_n;
  v2 += dv_n;
  return -b;  // = |dr| * |dv.n|: with unit mass, J |dr| where J = mu*2|dv.n| = |dv.n|
}

//! The same with normal restitution e (1: elastic): the normal relative velocity is reversed
//! and scaled by e. Returns dr.dp1 / m.
template <class T>
inline T collide_equal_mass(Vec3<T> dr, Vec3<T>& v1, Vec3<T>& v2, T restitution) {
  if constexpr (detail::kWidened<T>) {  // see detail::kWidened
    Vec3<double> u1 = detail::widen(v1), u2 = detail::widen(v2);
    const double virial = collide_equal_mass(detail::widen(dr), u1, u2, double(restitution));
    v1 = detail::narrow(u1), v2 = detail::narrow(u2);
    return T(virial);
  }
  const T r2 = dot(dr, dr);
  const T b = dot(dr, v1 - v2);
  if (!(b < T(0)) || !(r2 > T(0))) return T(0);
  const T half = T(0.5) * (T(1) + restitution);
  const Vec3<T> dv_n = (half * b / r2) * dr;
  v1 -= dv_n;
  v2 += dv_n;
  return -half * b;
}

//! Rough spheres' tangential law, in the kernel's type: beta (tangential restitution, > -1),
//! Walton's friction mu (infinity: constant beta) and q of I = q m r^2.
template <class T>
struct Roughness {
  T beta = T(-1);
  T mu = std::numeric_limits<T>::infinity();
  T q = T(0.4);
};

//! What a rough collision did: the virial r_ij . dp_i (0: receding, nothing changed) and the
//! kinetic energy it took, by channel (normal, tangential).
template <class T>
struct RoughOutcome {
  T virial = T(0);
  T dissipated_normal = T(0);
  T dissipated_tangential = T(0);
  bool sliding = false;  //!< Walton's limit capped the tangential impulse
};

namespace detail {
//! The tangential impulse on the body whose contact point moves at g_t relative to the other
//! (g_t perpendicular to n), for reduced mass mu_ij and normal impulse magnitude jn: the
//! constant-beta impulse -(1+beta) q mu_ij/(1+q) g_t, or Walton's sliding one -mu jn g_t/|g_t| if
//! that is smaller. Sets the energy it takes, -(J.g_t + |J|^2 (1+q)/(2 q mu_ij)) (no cross term
//! with the normal impulse: it turns no sphere), and whether it slid. n2 = |n|^2, 1 but for the
//! rounding of n: in place of 1 it makes beta = 1 exact for the n used, so that rounding (leaning
//! one way at contact distances near a power of two) biases no energy.
template <class T>
inline Vec3<T> tangential_impulse(Vec3<T> g_t, T reduced_mass, T jn, const Roughness<T>& k, T& dissipated,
                                  bool& sliding, T n2 = T(1)) {
  const T c = (T(1) + k.beta) * k.q * reduced_mass / (n2 + k.q);
  Vec3<T> j = (-c) * g_t;
  const T g2 = dot(g_t, g_t);
  const T limit = k.mu * jn;
  sliding = c * c * g2 > limit * limit;  // never with mu = inf (inf > inf is false)
  if (sliding) j = (-limit / std::sqrt(g2)) * g_t;
  dissipated = -(dot(j, g_t) + dot(j, j) * (n2 + k.q) / (T(2) * k.q * reduced_mass));
  return j;
}
}  // namespace detail

//! A rough pair collision at contact separation dr = r1 - r2 (radii a1, a2, angular velocities
//! w1, w2): the normal impulse exactly as collide() (equal_mass: collide_equal_mass()), whose
//! velocities it leaves bit for bit when beta = -1, then the tangential impulse J_t from the
//! contact points' relative velocity, g = v1 - v2 - (a1 w1 + a2 w2) x n:
//! v1 += J_t/m1, v2 -= J_t/m2, w_k -= a_k (n x J_t)/I_k. Conserves momentum and the angular
//! momentum about the contact point. Nothing changes for a receding pair (virial 0).
template <class T>
inline RoughOutcome<T> collide_rough(Vec3<T> dr, Vec3<T>& v1, Vec3<T>& v2, Vec3<T>& w1, Vec3<T>& w2, T m1, T m2, T a1,
                                     T a2, T restitution, const Roughness<T>& k, bool equal_mass = false) {
  if constexpr (detail::kWidened<T>) {  // see detail::kWidened
    Vec3<double> u1 = detail::widen(v1), u2 = detail::widen(v2), o1 = detail::widen(w1), o2 = detail::widen(w2);
    const RoughOutcome<double> r = collide_rough(detail::widen(dr), u1, u2, o1, o2, double(m1), double(m2), double(a1),
                                                 double(a2), double(restitution), {k.beta, k.mu, k.q}, equal_mass);
    v1 = detail::narrow(u1), v2 = detail::narrow(u2), w1 = detail::narrow(o1), w2 = detail::narrow(o2);
    return {T(r.virial), T(r.dissipated_normal), T(r.dissipated_tangential), r.sliding};
  }
  RoughOutcome<T> out;
  // The smooth kernel first and untouched (its result is the smooth one bit for bit); the normal
  // impulse leaves the tangential relative velocity as it was, so g_t is taken after it.
  out.virial = equal_mass ? m1 * collide_equal_mass(dr, v1, v2, restitution) : collide(dr, v1, v2, m1, m2, restitution);
  if (!(out.virial > T(0))) return out;
  const T len = std::sqrt(dot(dr, dr));
  const Vec3<T> n = (T(1) / len) * dr;
  const T n2 = dot(n, n);
  const Vec3<T> g = v1 - v2 - cross(a1 * w1 + a2 * w2, n);
  const Vec3<T> g_t = g - (dot(g, n) / n2) * n;
  const T reduced_mass = m1 * m2 / (m1 + m2);
  const T jn = out.virial / len;  // |J_n| = (1+e) mu_ij |g.n|
  const T gn = jn / ((T(1) + restitution) * reduced_mass);
  out.dissipated_normal = T(0.5) * (T(1) - restitution * restitution) * reduced_mass * gn * gn;
  const Vec3<T> j = detail::tangential_impulse(g_t, reduced_mass, jn, k, out.dissipated_tangential, out.sliding, n2);
  v1 += (T(1) / m1) * j;
  v2 -= (T(1) / m2) * j;
  const Vec3<T> nj = cross(n, j);
  w1 -= (T(1) / (k.q * m1 * a1)) * nj;  // a1 / I1 = 1 / (q m1 a1)
  w2 -= (T(1) / (k.q * m2 * a2)) * nj;
  return out;
}

//! The tangential part of a rough wall contact (the wall an infinite mass of zero radius at
//! rest; its normal reflection is the caller's): n the unit normal from the wall into the box,
//! v the sphere's velocity at contact (the normal part is ignored), jn_per_mass the normal
//! impulse per unit mass (2 |v.n| for an elastic wall). Updates w and returns the velocity
//! change, which is tangential; `dissipated` gets the energy taken.
template <class T>
inline Vec3<T> wall_tangential(Vec3<T> n, Vec3<T> v, Vec3<T>& w, T m, T a, T jn_per_mass, const Roughness<T>& k,
                               T& dissipated, bool& sliding) {
  if constexpr (detail::kWidened<T>) {  // see detail::kWidened
    Vec3<double> o = detail::widen(w);
    double d = 0;
    const Vec3<double> dv = wall_tangential(detail::widen(n), detail::widen(v), o, double(m), double(a),
                                            double(jn_per_mass), {k.beta, k.mu, k.q}, d, sliding);
    w = detail::narrow(o), dissipated = T(d);
    return detail::narrow(dv);
  }
  const Vec3<T> g = v - a * cross(w, n);
  const Vec3<T> g_t = g - dot(g, n) * n;
  T d = T(0);
  const Vec3<T> dv = detail::tangential_impulse(g_t, T(1), jn_per_mass, k, d, sliding);
  dissipated = m * d;
  w -= (T(1) / (k.q * a)) * cross(n, dv);
  return dv;
}

//! The TC model of inelastic collapse (Luding and McNamara 1998): a collision at time t is
//! elastic if either sphere collided within contact_time before it (last_i, last_j).
inline bool tc_elastic(double t, double last_i, double last_j, double contact_time) {
  return t - last_i < contact_time || t - last_j < contact_time;
}

//! Reflects a coordinate from the walls [lo, hi] of one axis for a sphere of radius r:
//! rewind to the wall contact, flip the velocity, re-advance, which is an exact mirror.
//! Returns the momentum given to the wall per unit mass (2|v|) or 0 if no contact.
template <class T>
inline T reflect_from_walls(T& x, T& v, T lo, T hi, T r) {
  if (x - r < lo && v < T(0)) {
    x = T(2) * (lo + r) - x;
    v = -v;
    return T(2) * v;
  }
  if (x + r > hi && v > T(0)) {
    x = T(2) * (hi - r) - x;
    v = -v;
    return -T(2) * v;
  }
  return T(0);
}

//! Under a uniform acceleration g along a wall axis, a coordinate at the end of a window is x
//! with velocity v; going back a time s it was at x - v s + g s^2 / 2. Returns the largest s in
//! [0, window] at which it was on the contact plane w moving towards the wall (side -1: a lower
//! wall, the coordinate decreasing; +1: an upper one), i.e. when it first reached the wall in
//! the window, or -1 if it did not.
template <class T>
inline T wall_back_time(T x, T v, T g, T w, int side, T window) {
  // f(s) = x - w - v s + g s^2 / 2 = 0; a side -1 wall was reached at s if f changed sign from
  // positive (inside, earlier) to negative there, i.e. v(s) = v - g s < 0.
  const T a = T(0.5) * g, b = -v, c = x - w;
  T roots[2];
  int n = 0;
  if (a == T(0)) {
    if (b != T(0)) roots[n++] = -c / b;
  } else {
    const T disc = b * b - T(4) * a * c;
    if (disc >= T(0)) {
      const T q = -T(0.5) * (b + std::copysign(std::sqrt(disc), b));  // cancellation-free pair
      if (q != T(0))
        roots[n++] = q / a, roots[n++] = c / q;
      else
        roots[n++] = T(0);
    }
  }
  T best = T(-1);
  for (int k = 0; k < n; ++k) {
    const T s = roots[k];
    if (!(s >= T(0) && s <= window)) continue;
    const T vs = v - g * s;  // velocity at that moment
    if ((side < 0 && vs < T(0)) || (side > 0 && vs > T(0))) best = std::max(best, s);
  }
  return best;
}

//! Reflects at the contact plane w a coordinate that reached it a time s before the end of the
//! window under acceleration g: the velocity at contact is reversed and the flight continues.
template <class T>
inline void reflect_in_flight(T& x, T& v, T g, T w, T s) {
  x = T(2) * w - x + g * s * s;
  v = -v + T(2) * g * s;
}

}  // namespace hardsphere::kernel
