#pragma once
//! What the contact resolver adds up over the contacts it resolves (the stepper's StepCounters
//! take it from here).
#include <array>
#include <cstdint>

namespace hardsphere {

//! Totals of resolved contacts.
struct ContactTally {
  std::int64_t collisions = 0;
  std::int64_t unresolved_steps = 0;  //!< steps that hit the event limit with contacts left
  std::int64_t resting_contacts = 0;  //!< wall contacts too slow to bounce (see bounce())
  std::int64_t wall_collisions = 0;
  std::array<double, 3> wall_impulse{0, 0, 0};  //!< sum of |m dv| of wall bounces, per axis
  double virial = 0;                            //!< sum over collisions of r_ij . dp_i at contact
  //! The same sum as a tensor, r_ij (x) dp_i: xx, yy, zz, xy, xz, yz (LAMMPS's virial order).
  std::array<double, 6> virial_tensor{0, 0, 0, 0, 0, 0};
  //! Kinetic energy the collisions took, by channel (rough spheres only).
  double dissipated_normal = 0, dissipated_tangential = 0;
  //! What the walls took (restitution and resting contacts; friction), any spheres.
  double wall_dissipated_normal = 0, wall_dissipated_tangential = 0;
  //! Contacts with kinematic spheres that bounced (resting ones count in resting_contacts; their
  //! dissipation is the walls'), and the work the kinematic spheres did (kernel::KinematicOutcome).
  std::int64_t kinematic_collisions = 0;
  double kinematic_work = 0;
  double wall_work = 0;  //!< the work moving walls did on the spheres
};

}  // namespace hardsphere
