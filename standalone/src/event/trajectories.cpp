#include "event/trajectories.hpp"

#include <algorithm>
#include <cstdint>

namespace hardsphere::event {

Trajectories::Trajectories(const ParticleSystem& sys, const std::vector<Vec3d>& pos, std::vector<std::uint32_t> orig,
                           const Physics& physics)
    : orig_(std::move(orig)), g_(physics.gravity), has_g_(physics.has_gravity()) {
  const std::size_t n = orig_.size();
  body_.resize(n);
  mass_.resize(n);
  wraps_.assign(n, {0, 0, 0});
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = orig_[k];
    body_[k] = Body{pos[i].x, pos[i].y, pos[i].z, 0.0, sys.vel[i].x, sys.vel[i].y, sys.vel[i].z, sys.radius[i]};
    mass_[k] = sys.mass[i];
  }
}

void Trajectories::rebase(double now) {
  for (std::size_t i = 0; i < body_.size(); ++i) {
    sync(body_[i], now);
    body_[i].t = 0;
  }
}

void Trajectories::state_at(const Body& s, double dt, Vec3d& pos, Vec3d& vel) const {
  if (has_g_) {
    pos = {s.x + (s.vx + 0.5 * g_[0] * dt) * dt, s.y + (s.vy + 0.5 * g_[1] * dt) * dt,
           s.z + (s.vz + 0.5 * g_[2] * dt) * dt};
    vel = {s.vx + g_[0] * dt, s.vy + g_[1] * dt, s.vz + g_[2] * dt};
  } else {
    pos = {s.x + s.vx * dt, s.y + s.vy * dt, s.z + s.vz * dt};
    vel = {s.vx, s.vy, s.vz};
  }
}

void Trajectories::observe(double now, ParticleSystem& out) const {
  for (std::size_t k = 0; k < body_.size(); ++k) {
    const Body& s = body_[k];
    const std::size_t i = orig_[k];
    state_at(s, now - s.t, out.pos[i], out.vel[i]);
    for (std::size_t d = 0; d < 3; ++d)
      out.image[i][d] =
          std::int32_t(std::clamp(out.image[i][d] + wraps_[i][d], std::int64_t(INT32_MIN), std::int64_t(INT32_MAX)));
  }
}

SphereSample Trajectories::sample(std::size_t index, double now, const ParticleSystem& proto) const {
  // Renumbering moves spheres in the internal order; only then is the index searched for again.
  if (orig_[sampled_at_] != index)
    sampled_at_ = std::size_t(std::find(orig_.begin(), orig_.end(), std::uint32_t(index)) - orig_.begin());
  const Body& s = body_[sampled_at_];
  SphereSample out;
  state_at(s, now - s.t, out.unwrapped, out.velocity);
  for (std::size_t d = 0; d < 3; ++d)
    if (proto.box.periodic[d])
      out.unwrapped[int(d)] += double(proto.image[index][d] + wraps_[index][d]) * proto.box.length(int(d));
  return out;
}

}  // namespace hardsphere::event
