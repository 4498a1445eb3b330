#pragma once
//! What rough collisions can make of rotation, for the run-length estimates of both engines: a
//! collision turns rotational energy into translational, so a sphere's own kinetic energy is a
//! speed it can reach, sqrt(v^2 + q r^2 w^2) (I = q m r^2). A spin that no clock or step could
//! follow is refused up front, naming the sphere and its file:line, instead of showing up later
//! as a jam or an endless step.
#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>

#include "hardsphere/particles.hpp"
#include "hardsphere/physics.hpp"

namespace hardsphere {

struct RotationReach {
  double speed = 0;        //!< the largest reach over the spheres (0 for smooth spheres)
  double sum = 0;          //!< the sum of every sphere's reach (the sum of |v| for smooth ones)
  double from_spin = 0;    //!< how much of `sum` the spins add over the speeds
  std::size_t sphere = 0;  //!< the sphere whose spin adds most
  //! "file:LINE: atom ID (angular velocity wx wy wz)" of that sphere.
  std::string describe(const ParticleSystem& sys) const {
    std::ostringstream m;
    m.precision(6);
    const Vec3d w = sphere < sys.omega.size() ? sys.omega[sphere] : Vec3d{};
    std::string who = velocity_origin(sys, sphere, "", nullptr);
    if (who.rfind(": ", 0) == 0) who = who.substr(2);  // no source of its own: "atom ID"
    m << who << " (angular velocity " << w.x << " " << w.y << " " << w.z << ")";
    return m.str();
  }
};

inline RotationReach rotation_reach(const ParticleSystem& sys, const Physics& physics) {
  RotationReach out;
  double most = -1;
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const Vec3d v = sys.vel[i];
    const double speed = std::hypot(std::hypot(v.x, v.y), v.z);
    double reach = speed;
    if (physics.rough() && i < sys.omega.size()) {
      const Vec3d w = sys.omega[i];
      reach = std::hypot(speed, std::sqrt(physics.inertia) * sys.radius[i] * std::hypot(std::hypot(w.x, w.y), w.z));
    }
    out.sum += reach;
    out.from_spin += reach - speed;
    if (physics.rough()) out.speed = std::max(out.speed, reach);
    if (reach - speed > most) most = reach - speed, out.sphere = i;
  }
  return out;
}

}  // namespace hardsphere
