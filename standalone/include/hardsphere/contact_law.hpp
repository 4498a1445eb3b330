#pragma once
//! The contact laws: what a pair or wall collision does to the spheres' velocities, evaluated by
//! both engines (the stepper at a rewound contact, the event engine at a synced one). A pair law
//! is one prologue (the TC model: restituted, or the elastic fallback) and an evaluator per physics
//! (smooth: collide() / collide_equal_mass(); rough: collide_rough()). A wall law is the normal
//! part (reflection or the resting contact under gravity, and the impulse) and, for rough spheres,
//! wall_tangential(), each wall with its own law (WallLaw: restitution, tangential restitution and
//! friction). A new law is one more evaluator here; the engines keep only what is theirs (moving spheres to and from
//! the contact, tallies, re-predictions).
#include <array>
#include <cmath>

#include "hardsphere/collision.hpp"
#include "hardsphere/vec3.hpp"

namespace hardsphere::kernel {

//! What a contact law did, in double as both engines sum it.
struct ContactOutcome {
  double virial = 0;             //!< a pair's r_ij . dp_i at contact (0: receding)
  double dissipated_normal = 0;  //!< kinetic energy taken, by channel (rough spheres only)
  double dissipated_tangential = 0;
  bool changed = false;  //!< the velocities changed: the engine records a collision
  bool sliding = false;  //!< Walton's limit capped the tangential impulse
};

//! A pair law's parameters: normal restitution e (1: elastic) and, for rough spheres, the
//! tangential law.
template <class T>
struct PairLaw {
  T restitution = T(1);
  Roughness<T> roughness;
};

//! The TC model's decision for one pair collision (Luding and McNamara 1998).
struct PairRule {
  bool restituted;  //!< e < 1 applies; otherwise the collision is elastic
  bool full;        //!< the whole law applies; false: the TC model made it elastic, and smooth too
};

//! The prologue every pair law shares: with e < 1 a collision is restituted unless either sphere
//! collided within the contact time before it (`collided_recently()`, asked only then).
template <class T, class Recent>
inline PairRule pair_rule(const PairLaw<T>& law, Recent&& collided_recently) {
  const bool restituted = law.restitution != T(1) && !collided_recently();
  return {restituted, restituted || law.restitution == T(1)};
}

namespace detail {
//! The smooth evaluator: the normal impulse alone, its virial in double.
template <class T>
inline double smooth_impulse(const PairLaw<T>& law, PairRule rule, Vec3<T> dr, Vec3<T>& v1, Vec3<T>& v2, T m1, T m2,
                             bool equal_mass) {
  // The elastic forms without e where the rule is elastic: one multiplication fewer per collision.
  if (rule.restituted)
    return equal_mass ? double(m1) * double(collide_equal_mass(dr, v1, v2, law.restitution))
                      : double(collide(dr, v1, v2, m1, m2, law.restitution));
  return equal_mass ? double(m1) * double(collide_equal_mass(dr, v1, v2)) : double(collide(dr, v1, v2, m1, m2));
}
//! Not deduced from (T is the law's): a smooth call passes a plain nullptr.
template <class T>
struct NoDeduce {
  using type = T;
};
template <class T>
inline bool same(Vec3<T> a, Vec3<T> b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}
}  // namespace detail

//! A pair collision at contact separation dr = r1 - r2 under `rule` (from pair_rule()): the smooth
//! law, or with Rough the rough one (angular velocities w1, w2, radii a1, a2) unless the rule is
//! TC-elastic. equal_mass (m1 = m2): collide_equal_mass(), which conserves momentum bit for bit.
//! `changed`: with Exact, whether the normal impulse changed a velocity at all (an approach below
//! the velocities' rounding would be predicted again at once, without end: the event engine
//! parts such pairs); otherwise whether the pair approached (virial != 0). Nothing changes when
//! it is false.
template <bool Rough, bool Exact, class T>
inline ContactOutcome collide_pair(const PairLaw<T>& law, PairRule rule, Vec3<T> dr, Vec3<T>& v1, Vec3<T>& v2,
                                   typename detail::NoDeduce<Vec3<T>*>::type w1,
                                   typename detail::NoDeduce<Vec3<T>*>::type w2, T m1, T m2, T a1, T a2,
                                   bool equal_mass) {
  ContactOutcome out;
  if constexpr (Exact) {
    Vec3<T> u1 = v1, u2 = v2;
    out.virial = detail::smooth_impulse(law, rule, dr, u1, u2, m1, m2, equal_mass);
    out.changed = !(detail::same(u1, v1) && detail::same(u2, v2));
    if (!out.changed || !(Rough && rule.full)) {
      v1 = u1, v2 = u2;
      return out;
    }
  }
  if constexpr (Rough) {
    if (rule.full) {  // the normal impulse again, as collide_rough() applies it (the same bits)
      const RoughOutcome<T> r =
          collide_rough(dr, v1, v2, *w1, *w2, m1, m2, a1, a2, law.restitution, law.roughness, equal_mass);
      out.virial = double(r.virial);
      out.dissipated_normal = double(r.dissipated_normal);
      out.dissipated_tangential = double(r.dissipated_tangential);
      out.sliding = r.sliding;
      if constexpr (!Exact) out.changed = out.virial != 0.0;
      return out;
    }
  }
  if constexpr (!Exact) {
    out.virial = detail::smooth_impulse(law, rule, dr, v1, v2, m1, m2, equal_mass);
    out.changed = out.virial != 0.0;
  }
  return out;
}

//! A wall contact is a resting contact when gravity (g along the wall's axis) pulls the sphere
//! into that wall (side -1: the lower wall, +1: the upper one) and it arrives at normal speed |v|
//! no faster than gravity builds over the resting time: its bounces would follow each other
//! without end (a sphere at rest on a floor bounces at once again).
template <class T>
inline bool resting_contact(T v, T g, int side, T resting_time) {
  return (side < 0 ? g < T(0) : g > T(0)) && std::abs(v) <= std::abs(g) * resting_time;
}

//! A wall's law (Physics::walls, one box face): normal restitution e_w and, for rough spheres,
//! the tangential law, the wall an infinite mass (its q is the spheres').
template <class T>
using WallLaw = PairLaw<T>;

//! The kernel's laws of the six box faces (kFaceNames order) from validated physics (P: Physics,
//! a layer the kernel does not include), as both engines take them.
template <class T, class P>
inline std::array<WallLaw<T>, 6> wall_laws(const P& p) {
  std::array<WallLaw<T>, 6> laws;
  for (int f = 0; f < 6; ++f)
    laws[std::size_t(f)] = {T(p.walls[std::size_t(f)].restitution),
                            {T(p.wall_tangential_restitution(f)), T(p.wall_friction(f)), T(p.inertia)}};
  return laws;
}

//! What a wall contact does: the ContactOutcome's energy and, along the normal, whether it rested
//! and the normal velocity it leaves with; `impulse` is the momentum per unit mass the wall took,
//! dv the sphere's tangential velocity change (rough spheres).
template <class T>
struct WallOutcome {
  bool rested = false;
  bool restituted = false;  //!< e_w < 1 applied (the engine moves it off the wall at `leave`)
  T leave = T(0);           //!< the normal velocity at leaving (resting: -g hop / 2)
  double impulse = 0;
  Vec3<T> dv{};
  ContactOutcome contact;  //!< dissipated_normal: restitution's loss, or a rest's net energy taken
};

//! What a contact with a wall of any shape does (collide_surface()): the WallOutcome along the
//! normal (`leave`: the normal part of the velocity relative to the wall after it) and the
//! sphere's whole velocity change `dv` (normal and tangential).
template <class T>
struct SurfaceOutcome {
  WallOutcome<T> wall;
  Vec3<T> dv{};
};

//! The wall law at a contact of unit normal n (from the wall to the sphere) with a wall whose
//! surface moves at u there (an infinite mass): the sphere (mass m, radius a, velocity v) either
//! rests (gravity g with a part g.n into the wall, and a normal approach (v - u).n no faster than
//! it builds over `resting_time`: it leaves at half the normal speed gravity builds over `hop`)
//! or bounces, leaving at -e_w (v - u).n (the TC rule as pairs have it, pair_rule() with
//! `collided_recently`: within the contact time of its last collision it is elastic and smooth).
//! A sphere neither resting nor approaching is left alone (contact.changed false) unless
//! `Always` (a box face, which the stepper only predicts for spheres moving into it). Rough (w its
//! angular velocity, updated): the tangential impulse of the wall's law (wall_tangential()) for
//! the normal impulse, a resting contact's too, on the velocity relative to the surface, so a
//! sphere on a turning drum is carried while friction holds it. For a box face (n a unit axis,
//! u = 0) every dot product with n adds exact zeros: the same numbers as the axis's component.
template <bool Rough, bool Always = false, class T, class Recent>
inline SurfaceOutcome<T> collide_surface(const WallLaw<T>& law, Vec3<T> n, Vec3<T> u, Vec3<T> v, Vec3<T> g,
                                         T resting_time, T hop, typename detail::NoDeduce<Vec3<T>*>::type w, T m, T a,
                                         Recent&& collided_recently) {
  SurfaceOutcome<T> s;
  WallOutcome<T>& out = s.wall;
  const Vec3<T> vr = v - u;
  const T vn = dot(vr, n), gn = dot(g, n);
  out.rested = gn < T(0) && std::abs(vn) <= std::abs(gn) * resting_time;
  if (!Always && !out.rested && !(vn < T(0))) return s;  // receding from the surface: nothing to do
  out.contact.changed = true;
  T jn;  // the normal impulse per unit mass, in T for the tangential law
  if (out.rested) {
    out.leave = -(T(0.5) * gn * hop);
    out.impulse = std::abs(double(vn)) + std::abs(double(out.leave));
    out.contact.dissipated_normal = 0.5 * double(m) * (double(vn) * double(vn) - double(out.leave) * double(out.leave));
    jn = std::abs(vn) + std::abs(out.leave);
  } else {
    const PairRule rule = pair_rule(law, collided_recently);
    out.restituted = rule.restituted;
    if (!rule.restituted) {
      out.leave = -vn;
      out.impulse = 2.0 * std::abs(double(vn));
      jn = T(2) * std::abs(vn);
    } else {
      out.leave = -law.restitution * vn;
      out.impulse = std::abs(double(vn)) + std::abs(double(out.leave));
      out.contact.dissipated_normal =
          0.5 * double(m) * (double(vn) * double(vn) - double(out.leave) * double(out.leave));
      jn = std::abs(vn) + std::abs(out.leave);
    }
    s.dv = (out.leave - vn) * n;
    if (!rule.full) return s;  // TC-elastic: smooth too
  }
  if (out.rested) s.dv = (out.leave - vn) * n;
  if constexpr (Rough) {
    T dissipated = T(0);
    out.dv = wall_tangential(n, vr, *w, m, a, jn, law.roughness, dissipated, out.contact.sliding);
    out.contact.dissipated_tangential = double(dissipated);
    s.dv += out.dv;
  }
  return s;
}

//! The wall law at a box face: a sphere of mass m, radius a touching the wall on `side` of axis
//! d at velocity v (its normal part v[d] towards the wall) under gravity g along d, the face's
//! normal +-e_d and the face at rest (collide_surface(), whose numbers these are). `leave` is
//! the velocity along d after it (resting: it leaves at half the speed gravity builds over
//! `hop`, so it is back on the wall after hop); the engine moves its own coordinates (e_w = 1:
//! the mirror, v[d] -> -v[d]); out.dv, rough spheres' tangential change.
template <bool Rough, class T, class Recent>
inline WallOutcome<T> collide_wall(const WallLaw<T>& law, int d, int side, Vec3<T> v, T g, T resting_time, T hop,
                                   typename detail::NoDeduce<Vec3<T>*>::type w, T m, T a, Recent&& collided_recently) {
  const T sign = side < 0 ? T(1) : T(-1);  // the normal into the box
  Vec3<T> n{}, gv{};
  n[d] = sign;
  gv[d] = g;
  SurfaceOutcome<T> s =
      collide_surface<Rough, true>(law, n, Vec3<T>{}, v, gv, resting_time, hop, w, m, a, collided_recently);
  s.wall.leave = sign * s.wall.leave;
  return s.wall;
}

//! What a free sphere's contact with a kinematic sphere does: the free sphere's velocity change
//! (the kinematic one has infinite mass and never changes), whether it rested, and the work the
//! kinematic sphere's surface did on it (m dv . s, s the surface velocity at the contact point:
//! zero for a frozen one), so a run's energy budget closes with it.
template <class T>
struct KinematicOutcome {
  bool rested = false;
  Vec3<T> dv{};
  double work = 0;
  ContactOutcome contact;  //!< changed: the pair approached; dissipation as a wall's
};

//! The pair law with one infinite mass: a free sphere (mass m, radius a, velocity v, angular
//! velocity *w for Rough) at contact separation dr = r - r_k from a kinematic sphere (radius a_k,
//! velocity u, angular velocity w_k) takes the whole impulse, as from a wall whose normal is the
//! centre line n = dr / |dr| and whose surface moves at s = u + w_k x (a_k n): the relative normal
//! velocity (v - u).n is reversed with restitution e (the TC rule of pair_rule()), rough spheres
//! take Walton's tangential impulse for the relative surface velocity (wall_tangential()). Under
//! gravity g a contact with g.n < 0 (gravity pulls it onto the kinematic sphere) arriving no faster
//! than |g.n| resting_time rests as on a wall (resting_contact()): it leaves at -g.n hop / 2 along
//! n, back at the tangent plane after hop. Receding pairs are left alone (contact.changed false).
template <bool Rough, class T, class Recent>
inline KinematicOutcome<T> collide_kinematic(const PairLaw<T>& law, Vec3<T> dr, Vec3<T> v, Vec3<T> u,
                                             typename detail::NoDeduce<Vec3<T>*>::type w, Vec3<T> w_k, T m, T a, T a_k,
                                             Vec3<T> g, T resting_time, T hop, Recent&& collided_recently) {
  KinematicOutcome<T> out;
  (void)a;  // the tangential law's only
  const Vec3<T> n = (T(1) / std::sqrt(dot(dr, dr))) * dr;
  const T vn = dot(v - u, n);
  if (!(vn < T(0))) return out;
  out.contact.changed = true;
  const T gn = dot(g, n);
  out.rested = resting_contact(vn, gn, -1, resting_time);
  T leave = -vn;
  bool full = true;
  if (out.rested) {
    leave = -(T(0.5) * gn * hop);
  } else {
    const PairRule rule = pair_rule(law, collided_recently);
    if (rule.restituted) leave = -law.restitution * vn;
    full = rule.full;
  }
  out.contact.dissipated_normal = 0.5 * double(m) * (double(vn) * double(vn) - double(leave) * double(leave));
  const T jn = leave - vn;
  out.dv = jn * n;
  const Vec3<T> surface = u + a_k * cross(w_k, n);
  if constexpr (Rough) {
    if (full) {
      T dissipated = T(0);
      out.dv += wall_tangential(n, v - surface, *w, m, a, jn, law.roughness, dissipated, out.contact.sliding);
      out.contact.dissipated_tangential = double(dissipated);
    }
  }
  out.contact.virial = double(m) * double(dot(dr, out.dv));
  out.work = double(m) * double(dot(out.dv, surface));
  return out;
}

//! A coordinate that touched the contact plane `plane` a time s before the end of the window
//! under acceleration g along it (0: straight flight) and left it at normal velocity u: its
//! coordinate and velocity at the end of the window.
template <class T>
inline void leave_wall(T& x, T& v, T g, T plane, T s, T u) {
  x = plane + (u + T(0.5) * g * s) * s;
  v = u + g * s;
}

}  // namespace hardsphere::kernel
