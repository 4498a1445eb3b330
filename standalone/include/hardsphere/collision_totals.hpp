#pragma once
//! What the collisions of a run or a step add up to, kept by every layer that totals them: the run
//! summary (RunTotals), the LAMMPS fix's steps (StepTotals) and its owned + ghost path's
//! ownership-weighted tally. Engines count in their own counters; collision_totals() takes the
//! totals from them in one place.
#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

namespace hardsphere {

//! Count: whole numbers (std::int64_t), or double where collisions are weighted by ownership.
template <class Count>
struct BasicCollisionTotals {
  Count collisions = 0, wall_collisions = 0;
  Count resting_contacts = 0;                                         //!< wall contacts too slow to bounce
  double pair_virial = 0;                                             //!< sum over collisions of r_ij . dp_i
  std::array<double, 6> pair_virial_tensor{0, 0, 0, 0, 0, 0};         //!< r_ij (x) dp_i: xx yy zz xy xz yz
  std::array<double, 3> wall_impulse{0, 0, 0};                        //!< momentum given to the walls of each axis
  double dissipated_normal = 0, dissipated_tangential = 0;            //!< rough spheres: energy taken by channel
  double wall_dissipated_normal = 0, wall_dissipated_tangential = 0;  //!< what the walls took, any spheres
  Count kinematic_collisions = 0;  //!< free spheres' bounces off kinematic ones (their dissipation: the walls')
  double kinematic_work = 0;       //!< the work kinematic spheres did on free ones

  BasicCollisionTotals& operator+=(const BasicCollisionTotals& o) {
    collisions += o.collisions, wall_collisions += o.wall_collisions, resting_contacts += o.resting_contacts;
    pair_virial += o.pair_virial;
    for (std::size_t k = 0; k < 6; k++) pair_virial_tensor[k] += o.pair_virial_tensor[k];
    for (std::size_t k = 0; k < 3; k++) wall_impulse[k] += o.wall_impulse[k];
    dissipated_normal += o.dissipated_normal, dissipated_tangential += o.dissipated_tangential;
    wall_dissipated_normal += o.wall_dissipated_normal, wall_dissipated_tangential += o.wall_dissipated_tangential;
    kinematic_collisions += o.kinematic_collisions, kinematic_work += o.kinematic_work;
    return *this;
  }
  //! What was added since `o` (counters read at two times).
  friend BasicCollisionTotals operator-(BasicCollisionTotals a, const BasicCollisionTotals& o) {
    a.collisions -= o.collisions, a.wall_collisions -= o.wall_collisions, a.resting_contacts -= o.resting_contacts;
    a.pair_virial -= o.pair_virial;
    for (std::size_t k = 0; k < 6; k++) a.pair_virial_tensor[k] -= o.pair_virial_tensor[k];
    for (std::size_t k = 0; k < 3; k++) a.wall_impulse[k] -= o.wall_impulse[k];
    a.dissipated_normal -= o.dissipated_normal, a.dissipated_tangential -= o.dissipated_tangential;
    a.wall_dissipated_normal -= o.wall_dissipated_normal;
    a.wall_dissipated_tangential -= o.wall_dissipated_tangential;
    a.kinematic_collisions -= o.kinematic_collisions, a.kinematic_work -= o.kinematic_work;
    return a;
  }
};

using CollisionTotals = BasicCollisionTotals<std::int64_t>;
using WeightedCollisionTotals = BasicCollisionTotals<double>;

namespace detail {
template <class C, class = void>
struct HasVirialTensor : std::false_type {};
template <class C>
struct HasVirialTensor<C, std::void_t<decltype(std::declval<const C&>().pair_virial_tensor)>> : std::true_type {};
}  // namespace detail

//! The totals an engine's counters (StepCounters, EventCounters) hold; the event engine keeps no
//! virial tensor (zero here).
template <class Count = std::int64_t, class Counters>
BasicCollisionTotals<Count> collision_totals(const Counters& c) {
  BasicCollisionTotals<Count> t;
  t.collisions = Count(c.collisions), t.wall_collisions = Count(c.wall_collisions);
  t.resting_contacts = Count(c.resting_contacts);
  t.pair_virial = c.pair_virial;
  if constexpr (detail::HasVirialTensor<Counters>::value) t.pair_virial_tensor = c.pair_virial_tensor;
  t.wall_impulse = c.wall_impulse;
  t.dissipated_normal = c.dissipated_normal, t.dissipated_tangential = c.dissipated_tangential;
  t.wall_dissipated_normal = c.wall_dissipated_normal, t.wall_dissipated_tangential = c.wall_dissipated_tangential;
  t.kinematic_collisions = Count(c.kinematic_collisions), t.kinematic_work = c.kinematic_work;
  return t;
}

}  // namespace hardsphere
