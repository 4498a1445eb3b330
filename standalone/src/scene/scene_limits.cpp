#include "hardsphere/scene_limits.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "hardsphere/errors.hpp"

namespace hardsphere {

namespace {

const char* const kAxis = "xyz";

//! Distance from |x| to the next double: the resolution of a coordinate there.
double spacing(double x) {
  const double a = std::abs(x);
  return std::nextafter(a, std::numeric_limits<double>::infinity()) - a;
}

//! A magnitude below which every double is resolved to tol (spacing() <= tol): a power of two
//! whose spacing is at most tol, so per-coordinate spacing() is needed only at or above it.
double resolved_below(double tol) { return tol > 0 ? std::ldexp(1.0, std::ilogb(tol) + 52) : 0.0; }

//! |v| without overflow in the squares.
double speed(Vec3d v) { return std::hypot(std::hypot(v.x, v.y), v.z); }

//! The speed |w| r of a sphere's surface (what a rough collision turns into translation).
double surface_speed(const ParticleSystem& sys, std::size_t i) {
  return i < sys.omega.size() ? speed(sys.omega[i]) * sys.radius[i] : 0.0;
}

//! "atom ID", or "file:LINE: atom ID" when the system records where it was read (the Velocities
//! line for a velocity or angular velocity).
std::string atom_name(const ParticleSystem& sys, std::size_t i, bool velocity = false) {
  if (sys.source_line.size() != sys.size() || sys.source.empty()) return "atom " + std::to_string(sys.id[i]);
  return velocity ? velocity_origin(sys, i, sys.source, nullptr) : atom_origin(sys, i, sys.source, nullptr);
}

double smallest_diameter(const ParticleSystem& sys) {
  double d = std::numeric_limits<double>::infinity();
  for (const double r : sys.radius) d = std::min(d, 2 * r);
  return d;
}

[[noreturn]] void refuse(const std::string& source, const std::ostringstream& what) {
  throw InputError(source + ": " + what.str());
}

std::ostringstream message() {
  std::ostringstream m;
  m.precision(6);
  return m;
}

void check_box_extent(const ParticleSystem& sys, const std::string& source) {
  for (int d = 0; d < 3; ++d) {
    const double lo = sys.box.lo[d], hi = sys.box.hi[d], len = hi - lo;
    if (!std::isfinite(lo) || !std::isfinite(hi) || !std::isfinite(len) || !(len > 0)) {
      auto m = message();
      m << "box " << kAxis[d] << " extent [" << lo << ", " << hi << "] must be finite with a finite positive length";
      refuse(source, m);
    }
  }
}

void check_finite_atoms(const ParticleSystem& sys, const std::string& source, const std::vector<long>* atom_lines) {
  if (sys.radius.size() != sys.size() || sys.mass.size() != sys.size() || sys.vel.size() != sys.size() ||
      sys.id.size() != sys.size())
    throw InputError(source + ": inconsistent particle arrays");
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const Vec3d p = sys.pos[i], v = sys.vel[i], w = i < sys.omega.size() ? sys.omega[i] : Vec3d{};
    if (!(std::isfinite(sys.radius[i]) && sys.radius[i] > 0) || !(std::isfinite(sys.mass[i]) && sys.mass[i] > 0) ||
        !(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) ||
        !(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) ||
        !(std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z))) {
      throw InputError(atom_origin(sys, i, source, atom_lines) +
                       ": radius, mass, position, velocity and angular velocity must be finite (radius and mass "
                       "positive)");
    }
  }
}

//! The box's bounds must be resolved to a fraction of the smallest diameter dmin (tol).
void check_box_resolution(const ParticleSystem& sys, const std::string& source, double dmin, double tol) {
  for (int d = 0; d < 3; ++d)
    for (const double bound : {sys.box.lo[d], sys.box.hi[d]})
      if (spacing(bound) > tol) {
        auto m = message();
        m << "box bound " << kAxis[d] << " = " << bound << " is too far from the origin for spheres of diameter "
          << dmin << ": doubles there are " << spacing(bound) << " apart, more than " << kCoordinateResolution
          << " of a diameter; shift the box towards the origin";
        refuse(source, m);
      }
}

//! Each atom's position resolved, mass, speed, surface speed and the running kinetic energy
//! within the ranges the arithmetic keeps finite.
void check_atom_ranges(const ParticleSystem& sys, const std::string& source, const std::vector<long>* atom_lines,
                       double dmin, double tol) {
  // Masses: reduced masses m1 m2 / (m1 + m2) must neither overflow nor underflow.
  const double mass_lo = 1e-150, mass_hi = 1e150, speed_hi = 1e150;
  const double resolved = resolved_below(tol);
  double sum_mv2 = 0;
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const double m_i = sys.mass[i];
    auto atom = [&](bool velocity = false) {
      auto m = message();
      m << (velocity ? velocity_origin(sys, i, source, atom_lines) : atom_origin(sys, i, source, atom_lines)) << ": ";
      return m;
    };
    const Vec3d p = sys.pos[i];
    const bool near_origin = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) < resolved;
    for (int d = 0; d < 3 && !near_origin; ++d)
      if (spacing(sys.pos[i][d]) > tol) {
        auto m = atom();
        m << kAxis[d] << " = " << sys.pos[i][d] << " cannot be resolved: doubles there are " << spacing(sys.pos[i][d])
          << " apart, more than " << kCoordinateResolution << " of the smallest diameter " << dmin
          << " (wrapping it into a periodic box would move it by that much)";
        throw InputError(m.str());
      }
    if (m_i < mass_lo || m_i > mass_hi) {
      auto m = atom();
      m << "mass " << m_i << " is outside [" << mass_lo << ", " << mass_hi
        << "], where the collision arithmetic (products of masses) stays finite and nonzero";
      throw InputError(m.str());
    }
    const Vec3d v = sys.vel[i];
    const double v2 = dot(v, v);
    if (!(v2 <= speed_hi * speed_hi)) {
      auto m = atom(true);
      m << "speed " << speed(v) << " (velocity " << v.x << " " << v.y << " " << v.z << ") is above " << speed_hi
        << ": its square would overflow";
      throw InputError(m.str());
    }
    // Rough spheres turn the surface's speed into translation and back: it is a speed like v.
    const double surface = surface_speed(sys, i);
    if (!(surface <= speed_hi)) {
      const Vec3d w = sys.omega[i];
      auto m = atom(true);
      m << "angular velocity " << w.x << " " << w.y << " " << w.z << " turns the surface at |w| r = " << surface
        << ", above " << speed_hi << ": its square would overflow";
      throw InputError(m.str());
    }
    // m v^2 + I w^2 with the largest moment of inertia, 2/3 m r^2 (a thin shell).
    sum_mv2 += m_i * v2 + 2.0 / 3.0 * m_i * surface * surface;
    if (!(sum_mv2 <= 1e300)) {
      auto m = atom(true);
      m << "the kinetic energy (sum of m v^2 + I w^2 up to this atom: " << sum_mv2 << ") overflows double precision";
      throw InputError(m.str());
    }
  }
}

}  // namespace

void check_scene_numbers(const ParticleSystem& sys, const std::string& source, const std::vector<long>* atom_lines) {
  check_box_extent(sys, source);
  if (sys.size() == 0) return;
  check_finite_atoms(sys, source, atom_lines);
  const double dmin = smallest_diameter(sys), tol = kCoordinateResolution * dmin;
  check_box_resolution(sys, source, dmin, tol);
  check_atom_ranges(sys, source, atom_lines, dmin, tol);
}

void check_engine_numbers(const ParticleSystem& sys, double eps, double largest, double dt, const std::string& what,
                          double gravity, bool rotation) {
  if (sys.size() == 0) return;
  // Squares and products of speeds, masses and lengths must stay inside the type's range.
  const double big = std::cbrt(largest) / 1e3, small = 1 / big;
  double len = 0, v2sum = 0, m_sum = 0;
  for (int d = 0; d < 3; ++d) len = std::max(len, sys.box.length(d));
  const double dmin = smallest_diameter(sys);
  auto fail = [&](auto&&... parts) {
    auto m = message();
    (m << ... << parts);
    throw InputError(what + ": " + m.str());
  };
  if (len > big) fail("box length ", len, " is above ", big, ", the largest this precision carries");
  if (dmin < small) fail("diameter ", dmin, " is below ", small, ", the smallest this precision carries");
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const double v2 = dot(sys.vel[i], sys.vel[i]);
    // The square decides away from the bound (big^2 is finite); hypot only near it.
    if (!(v2 <= 0.99 * big * big) && !(speed(sys.vel[i]) <= big))
      fail(atom_name(sys, i, true), ": speed ", speed(sys.vel[i]), " is above ", big,
           ", the largest this precision carries");
    if (sys.mass[i] > big || sys.mass[i] < small)
      fail(atom_name(sys, i), ": mass ", sys.mass[i], " is outside [", small, ", ", big,
           "], the range this precision carries");
    if (rotation && !(surface_speed(sys, i) <= big))
      fail(atom_name(sys, i, true), ": angular velocity ", sys.omega[i].x, " ", sys.omega[i].y, " ", sys.omega[i].z,
           " turns the surface at |w| r = ", surface_speed(sys, i), ", above ", big,
           ", the largest speed this precision carries (rough collisions turn it into translation)");
    v2sum += sys.mass[i] * v2;
    m_sum += sys.mass[i];
  }
  // Rounding of coordinates relative to the box corner shows up as overlaps of ~16 eps L.
  if (16 * eps * len > 1e-3 * dmin)
    fail("a box ", len, " long resolves spheres of diameter ", dmin, " to only ", 16 * eps * len / dmin,
         " of a diameter in this precision (at most 1e-3); use double precision");
  if (dt > 0 && v2sum > 0) {
    const double v_rms = std::sqrt(v2sum / m_sum), moved = v_rms * dt + 0.5 * gravity * dt * dt;
    if (moved < 100 * eps * len)
      fail("time step dt = ", dt, " moves a sphere at the rms speed ", v_rms, gravity > 0 ? " under gravity" : "",
           " by ", moved, ", less than 100 roundings (", 100 * eps * len, ") of a coordinate in a box ", len,
           " long: positions would not resolve the motion; use a longer dt", eps > 1e-10 ? " or double precision" : "");
  }
}

double wall_bounce_rate(const ParticleSystem& sys) {
  double rate = 0;
  for (int d = 0; d < 3; ++d) {
    if (sys.box.periodic[d]) continue;
    for (std::size_t i = 0; i < sys.size(); ++i)
      rate += std::abs(sys.vel[i][d]) / std::max(sys.box.length(d) - 2 * sys.radius[i], 0.0);
  }
  return rate;
}

template <class T>
void check_engine_numbers(const ParticleSystem& sys, double dt, const std::string& what, double gravity,
                          bool rotation) {
  check_engine_numbers(sys, double(std::numeric_limits<T>::epsilon()), double(std::numeric_limits<T>::max()), dt, what,
                       gravity, rotation);
}
template void check_engine_numbers<float>(const ParticleSystem&, double, const std::string&, double, bool);
template void check_engine_numbers<double>(const ParticleSystem&, double, const std::string&, double, bool);

}  // namespace hardsphere
