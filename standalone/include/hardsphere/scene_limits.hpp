#pragma once
//! The numbers a scene makes the engines carry. Every one must stay finite, and coordinates must
//! resolve the spheres; what cannot be simulated is refused with an InputError naming the value
//! and where it came from, instead of overflowing into NaN or wrapping spheres onto each other.
#include <array>
#include <string>
#include <vector>

#include "hardsphere/particles.hpp"

namespace hardsphere {

//! Coordinates (and box bounds) must be resolved to this fraction of the smallest diameter: a
//! double is spaced wider than that beyond ~4.5e7 smallest diameters from the origin.
constexpr double kCoordinateResolution = 1e-8;

//! Checks in double arithmetic, before any wrapping: finite box lengths, box bounds and
//! coordinates resolved to kCoordinateResolution, masses whose products neither overflow nor
//! underflow, speeds and the surface speeds |w| r of angular velocities whose squares and
//! kinetic energies (translational and rotational, with the largest inertia 2/3 m r^2) stay
//! finite (also summed).
//! `atom_lines` (optional): each atom's line in the file `source`, for "file:line" in messages.
void check_scene_numbers(const ParticleSystem& sys, const std::string& source,
                         const std::vector<long>* atom_lines = nullptr);

//! What an engine computing in a type with machine epsilon `eps` and largest value `largest`
//! (coordinates relative to the box corner) needs on top: speeds, masses and sizes within
//! its range, with `rotation` (rough spheres, whose angular velocities the engine computes
//! with) the surface speeds |w| r too, final overlaps from rounding below 1e-3 of the smallest
//! diameter, and, for a time step dt > 0, a step that moves a sphere at the rms speed (and under
//! an acceleration of magnitude `gravity`) by at least 100 roundings of a coordinate. `what`
//! names the engine and precision in messages, atoms are named with their file:line when the
//! system records it.
void check_engine_numbers(const ParticleSystem& sys, double eps, double largest, double dt, const std::string& what,
                          double gravity = 0, bool rotation = false);

//! Wall bounces per unit time the spheres' straight flights between opposite walls imply,
//! sum over spheres and wall axes of |v_d| / (L_d - 2 r): in a gap barely wider than a sphere
//! they are endless, and both engines count them into the work a run will take.
double wall_bounce_rate(const ParticleSystem& sys);

//! The same for a type T (float or double).
template <class T>
void check_engine_numbers(const ParticleSystem& sys, double dt, const std::string& what, double gravity = 0,
                          bool rotation = false);

}  // namespace hardsphere
