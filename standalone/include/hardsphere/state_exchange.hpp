#pragma once
//! For adapters that keep their own copy of the spheres (the LAMMPS fix) and for engines that
//! share spheres with others (one stepper per MPI rank over its owned and ghost spheres): the
//! stepper's spheres in its internal order, and collision totals weighted by ownership.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>

#include "hardsphere/stepper.hpp"
#include "hardsphere/vec3.hpp"

namespace hardsphere {

//! Totals weighted by ownership (see StateExchange::set_owned): a collision counts
//! (owned_i + owned_j) / 2, a wall bounce owned_i, so engines that share spheres add up to
//! the totals of one engine over all of them.
struct OwnedCounters {
  double collisions = 0;
  double wall_collisions = 0;
  double pair_virial = 0;                                      //!< sum of weight * r_ij . dp_i
  std::array<double, 6> pair_virial_tensor{0, 0, 0, 0, 0, 0};  //!< xx yy zz xy xz yz
};

class StateExchange {
 public:
  virtual ~StateExchange() = default;
  //! The spheres in the engine's internal order ("slots"), which changes only when
  //! counters().rebuilds does.
  virtual std::size_t size() const = 0;
  virtual void copy_ids(std::int64_t* out) const = 0;
  //! Each slot's index in the ParticleSystem the engine was made from.
  virtual void copy_input_index(std::uint32_t* out) const = 0;
  //! Per slot and axis (3 per slot), how many box lengths the engine has taken off the
  //! position by wrapping since construction: position + image * L is continuous in time.
  virtual void copy_images(std::int32_t* out) const = 0;
  virtual void copy_state(Vec3d* pos, Vec3d* vel) const = 0;
  //! A row index that scatter_state skips.
  static constexpr std::uint32_t kNoRow = 0xffffffffu;
  //! Writes the state straight into an adapter's flat arrays (3 doubles per sphere): slot k
  //! goes to row dest[k] (none if kNoRow), its position shifted by shift[k]. One pass, no
  //! intermediate copy.
  virtual void scatter_state(const std::uint32_t* dest, const Vec3d* shift, double* x, double* v) const = 0;
  //! Sum over all spheres of m v^2 (twice the kinetic energy), e.g. for a temperature that
  //! gravity or inelastic collisions change inside the steps.
  virtual double mv2_sum() const = 0;
  //! The velocities of the given slots.
  virtual void copy_velocities(const std::uint32_t* slots, std::size_t count, Vec3d* out) const = 0;
  //! Replaces every velocity (slot order), e.g. after a thermostat changed them.
  virtual void set_velocities(const Vec3d* vel) = 0;
  //! The same from an adapter's flat array: slot k takes row src[k] of v.
  virtual void gather_velocities(const std::uint32_t* src, const double* v) = 0;
  //! Overwrites the position (the engine's frame, as copy_state gives it) and velocity of the
  //! given slots, e.g. copies of spheres another engine owns; the next step treats a moved
  //! position like any displacement. Positions must not overlap other spheres.
  virtual void set_spheres(const std::uint32_t* slots, std::size_t count, const Vec3d* pos, const Vec3d* vel) = 0;
  //! Per-sphere collision virial (for a per-atom stress): while on, every collision adds half
  //! of its r_ij (x) dp_i (xx yy zz xy xz yz, as counters().pair_virial_tensor) to each of its two
  //! spheres, so the spheres' sums add up to the engine's.
  virtual void set_sphere_virial(bool on) = 0;
  //! Adds each slot's sums since the last take, times `scale`, to row dest[k] of `out` (6
  //! doubles per row; kNoRow skipped) and clears them.
  virtual void take_sphere_virial(const std::uint32_t* dest, double scale, double* out) = 0;
  //! Marks which spheres (input order, 1 = owned) this engine owns; owned_counters() then
  //! accumulate from the next step on. Without it nothing is accumulated there.
  virtual void set_owned(const std::uint8_t* owned) = 0;
  virtual const OwnedCounters& owned_counters() const = 0;
  //! Per given slot: 1 if the sphere is not owned and collided with an owned one in the last
  //! run().
  virtual void copy_met_owned(const std::uint32_t* slots, std::size_t count, std::uint8_t* out) const = 0;
  //! For engines that step side by side and wait for each other after every step (one per MPI
  //! rank): they rebuild their pair lists on the same steps, so none waits while another
  //! rebuilds. In every step, after its first drift, the engine calls agree(due), due telling
  //! whether its own list must be rebuilt, and rebuilds if its list is due or the answer is true
  //! (a "no" never skips a rebuild). Each step calls it exactly once. Empty (the default): each
  //! engine decides alone.
  virtual void set_rebuild_agreement(std::function<bool(bool)> agree) = 0;
};

//! The exchange interface of a stepper made by make_stepper.
StateExchange& state_exchange(StepperBase& stepper);

}  // namespace hardsphere
