#pragma once
//! The contact resolver's members for kinematic spheres (ParticleSystem::kinematic), defined
//! after the class (contact_resolver.hpp includes this at its end): their detection under gravity
//! and their collisions with free spheres (kernel::collide_kinematic()).
#include "stepper/contact_resolver.hpp"

namespace hardsphere {

//! consider() for a free and a kinematic sphere under gravity: their relative motion is a
//! parabola, whose contact (kernel::kinematic_back_time()) orders the pair among the step's
//! contacts; the straight-line root `straight` (-1: none) is where it starts from.
template <class Real, bool Mono>
void ContactResolver<Real, Mono>::consider_kinematic(std::uint32_t i, std::uint32_t j, std::uint8_t image,
                                                     Vec3<Real> dr, Real sigma, Real straight) {
  if (a_.kinematic[i] & a_.kinematic[j]) return;
  const auto& gravity = walls_.gravity();
  const Real sign = a_.kinematic[j] ? Real(1) : Real(-1);  // dr's relative acceleration: g of the free one
  const Vec3<Real> g{sign * gravity[0], sign * gravity[1], sign * gravity[2]};
  if (!(straight >= Real(0)) && !(dot(dr, dr) < sigma * sigma)) return;
  const Real w = std::min(change_[i].back, change_[j].back);
  const Real back = kernel::kinematic_back_time(dr, a_.vel[i] - a_.vel[j], g, sigma, std::max(straight, Real(0)), w);
  if (back >= Real(0)) candidates_.push_back({i, j, image, back, change_[i].count, change_[j].count});
}

//! A free sphere's contact with a kinematic one (kernel::collide_kinematic()), `c.back` before
//! the end of the step (under gravity the parabola's, from consider_kinematic()); two kinematic
//! spheres never collide. Only the free sphere changes; it is re-predicted as after a bounce.
template <class Real, bool Mono>
template <bool Rough, class Hooks>
bool ContactResolver<Real, Mono>::collide_kinematic(const Candidate& c, Hooks& hooks, ContactTally& tally) {
  const std::uint32_t f = free_of(c.i, c.j);
  if (f == kWall) return false;
  const std::uint32_t k = f == c.i ? c.j : c.i;
  const Vec3<Real> shift = f == c.i ? a_.image_shift[c.image] : -a_.image_shift[c.image];
  const Vec3<Real> dr = a_.pos[f] - a_.pos[k] - shift, dv = a_.vel[f] - a_.vel[k];
  const auto& gravity = walls_.gravity();
  const Vec3<Real> g{gravity[0], gravity[1], gravity[2]};
  const Real back = c.back;  // under gravity the parabola's (consider_kinematic())
  const Vec3<Real> contact = dr - back * dv + (Real(0.5) * back * back) * g;
  Vec3<Real> wf{}, wk{};
  if constexpr (Rough) wf = a_.omega[f], wk = a_.omega[k];
  const auto out = kernel::collide_kinematic<Rough>(law_, contact, a_.vel[f] - back * g, a_.vel[k], &wf, wk, mass(f),
                                                    radius(f), radius(k), g, walls_.resting_time(dt_), back,
                                                    [&] { return collided_recently(f, f, back); });
  if (!out.contact.changed) return false;
  if (law_.restitution != Real(1) && !out.rested) last_collision_[id_index(f)] = step_end_ - double(back);
  if constexpr (Rough) {
    a_.omega[f] = wf;
    tally.dissipated_normal += out.contact.dissipated_normal;
    tally.dissipated_tangential += out.contact.dissipated_tangential;
  }
  a_.vel[f] += out.dv;
  a_.pos[f] += back * out.dv;
  const Real speed = norm(a_.vel[f]);
  speed_bound_ = std::max(speed_bound_, speed);
  if (a_.speed) a_.speed[f] = speed;
  tally.wall_dissipated_normal += out.contact.dissipated_normal;
  tally.wall_dissipated_tangential += out.contact.dissipated_tangential;
  tally.kinematic_work += out.work;
  ++(out.rested ? tally.resting_contacts : tally.kinematic_collisions);
  mark_changed(f, back);
  hooks.after_collision(f, back);
  if (g.x != Real(0) || g.y != Real(0) || g.z != Real(0)) {
    // Gravity may bring it back onto the same sphere within the step, which the straight-line
    // sweep (it skips the partner) cannot see: a pair overlapping at the step's end is queued again.
    const Vec3<Real> end = a_.pos[f] - a_.pos[k] - shift;
    if (dot(end, end) < sigma(f, k) * sigma(f, k)) {
      const Real again = kernel::kinematic_back_time(end, a_.vel[f] - a_.vel[k], g, sigma(f, k), Real(0), back);
      if (again >= Real(0) && again < back)
        candidates_.push_back({c.i, c.j, c.image, again, change_[c.i].count, change_[c.j].count});
    }
  }
  return true;
}

}  // namespace hardsphere
