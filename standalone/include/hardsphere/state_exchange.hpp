#pragma once
//! For adapters that keep their own copy of the spheres (the LAMMPS fix) and for engines that
//! share spheres with others (one stepper per MPI rank over its owned and ghost spheres): the
//! stepper's spheres in its internal order, and every collision as it is resolved.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>

#include "hardsphere/stepper.hpp"
#include "hardsphere/vec3.hpp"

namespace hardsphere {

//! Told of every collision and wall bounce an engine resolves, by slot (StateExchange's order),
//! e.g. by an adapter whose engines share spheres and weight their totals by ownership.
class CollisionObserver {
 public:
  virtual ~CollisionObserver() = default;
  //! The spheres in slots i and j collided: `tensor` is r_ij (x) dp_i (xx yy zz xy xz yz, as
  //! StepCounters::pair_virial_tensor), `virial` r_ij . dp_i.
  virtual void collision(std::uint32_t i, std::uint32_t j, const double* tensor, double virial) = 0;
  //! The sphere in slot i bounced off a wall.
  virtual void bounce(std::uint32_t i) = 0;
  //! The engine re-sorted its spheres: slot k now holds the sphere that was in slot old[k].
  virtual void reordered(const std::uint32_t* old, std::size_t n) = 0;
};

//! The per-sphere fields that cross the engine/adapter boundary through StateExchange's copy,
//! set, scatter and gather, as LAMMPS's AtomVecSphere lists its communicated fields: a new
//! per-sphere quantity is one more line here and in the engine's field list.
enum class SphereField {
  Position,  //!< the caller's coordinates; periodic axes are wrapped at the engine's rebuilds
  Velocity,
  //! Angular velocity (rough spheres, Physics::rough()); a smooth engine carries the spins it
  //! was given unchanged (no smooth collision changes them) and counts no rotational energy.
  Omega,
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
  //! A row index that scatter and scatter_state skip.
  static constexpr std::uint32_t kNoRow = 0xffffffffu;
  //! One per-sphere field in and out by slot, 3 doubles per sphere (see SphereField). `slots`
  //! nullptr: slots 0 to count - 1.
  virtual void copy(SphereField field, const std::uint32_t* slots, std::size_t count, Vec3d* out) const = 0;
  //! Overwrites the given slots' values, e.g. copies of spheres another engine owns; the next
  //! step treats a moved position like any displacement (positions must not overlap other
  //! spheres), and new velocities raise the engine's speed bound.
  virtual void set(SphereField field, const std::uint32_t* slots, std::size_t count, const Vec3d* in) = 0;
  //! Straight into an adapter's flat array (3 doubles per row): slot k to row dest[k] (kNoRow:
  //! none).
  virtual void scatter(SphereField field, const std::uint32_t* dest, double* out) const = 0;
  //! Every slot from an adapter's flat array: slot k takes row src[k], e.g. velocities after a
  //! thermostat changed them.
  virtual void gather(SphereField field, const std::uint32_t* src, const double* in) = 0;
  //! Positions and velocities into an adapter's flat arrays in one pass, no intermediate copy:
  //! slot k to row dest[k] (none if kNoRow), its position shifted by shift[k].
  virtual void scatter_state(const std::uint32_t* dest, const Vec3d* shift, double* x, double* v) const = 0;
  //! Sum over all spheres of m v^2 (twice the kinetic energy), e.g. for a temperature that
  //! gravity or inelastic collisions change inside the steps.
  virtual double mv2_sum() const = 0;
  //! Sum over all spheres of I w^2 (twice the rotational kinetic energy; 0 when smooth).
  virtual double iw2_sum() const = 0;
  //! Per-sphere collision virial (for a per-atom stress): while on, every collision adds half
  //! of its r_ij (x) dp_i (xx yy zz xy xz yz, as counters().pair_virial_tensor) to each of its two
  //! spheres, so the spheres' sums add up to the engine's.
  virtual void set_sphere_virial(bool on) = 0;
  //! Adds each slot's sums since the last take, times `scale`, to row dest[k] of `out` (6
  //! doubles per row; kNoRow skipped) and clears them.
  virtual void take_sphere_virial(const std::uint32_t* dest, double scale, double* out) = 0;
  //! From the next step on, `observer` (not owned; nullptr: none) is told of every collision and
  //! bounce; it must outlive the engine or be removed first.
  virtual void set_collision_observer(CollisionObserver* observer) = 0;
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
