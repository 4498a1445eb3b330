#pragma once
//! Spheres exactly at contact in a closed chain (touching each other and walls or periodic
//! images, e.g. two spheres between walls two diameters apart, a simple cubic lattice at contact)
//! with approaching velocities take infinitely many collisions at one instant: no impulse frees
//! them, and an engine would never advance. Both engines count the events that fall within a
//! rounding-level window of one instant and refuse the run when they pass a bound no unjammed
//! scene reaches.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "hardsphere/errors.hpp"

namespace hardsphere {

//! The jam refusal: an InputError the engines complete with advice of the face's own words
//! (collapse_advice) where they hand it to their caller.
struct JammedSpheres : InputError {
  using InputError::InputError;
};

class JamGuard {
 public:
  JamGuard() = default;
  //! `window`: events this close in time count as one instant; `n`: spheres in the scene.
  JamGuard(double window, std::size_t n) : window_(window), limit_(100 * std::int64_t(n) + 10000) {}

  //! Counts an event at time t: true when the instant has taken more events than the bound.
  bool jammed(double t) {
    if (!(t - start_ <= window_ && start_ - t <= window_)) {
      start_ = t, count_ = 0;
      return false;
    }
    return ++count_ > limit_;
  }

  //! The refusal, naming the last event's atoms (id_j < 0: a wall).
  [[noreturn]] void refuse(const std::string& engine, std::int64_t id_i, std::int64_t id_j) const {
    const std::string who =
        "atoms " + std::to_string(id_i) + (id_j < 0 ? " and a wall" : " and " + std::to_string(id_j));
    throw JammedSpheres(engine + ": jammed spheres: " + who + " (and others) took more than " + std::to_string(limit_) +
                        " collisions at one instant, a closed chain of exact contacts (with each other, walls or "
                        "periodic images) whose approaching velocities no impulse can free; give the spheres room "
                        "(gaps between them, a lower packing fraction) or velocities that do not press the chain");
  }
  //! The refusal when the events piling up are one sphere's neighbour-list rebuilds: it moves
  //! too fast for the clock to tell its events apart.
  [[noreturn]] void refuse_fast(const std::string& engine, std::int64_t id, double speed, double move,
                                double time) const {
    std::ostringstream m;
    m.precision(6);
    m << engine << ": atom " << id << " took more than " << limit_ << " events at one instant (time " << time
      << "): moving at speed " << speed << ", it rebuilds its neighbour list every " << move / speed
      << " (each time it has moved " << move << "), faster than the clock resolves events at that time; lower its "
      << "speed (rough collisions also turn rotation into speed)";
    throw JammedSpheres(m.str());
  }
  //! The bound of events at one instant.
  std::int64_t limit() const { return limit_; }

 private:
  static constexpr double kFar = 1e308;
  double window_ = 0;
  std::int64_t limit_ = 0, count_ = 0;
  double start_ = kFar;
};

}  // namespace hardsphere
