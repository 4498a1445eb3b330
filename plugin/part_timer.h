#pragma once
//! fix hardsphere ... timing yes: wall time per part of the fix's step, summed over a run and
//! printed at its end as min / avg / max over ranks (like LAMMPS's own breakdown), so a user sees
//! where an MPI run's time goes.
#include <array>
#include <chrono>

#include "pointers.h"

namespace LAMMPS_NS {

class PartTimer {
 public:
  enum Part { Steps, Remake, Follow, Write, Moves, Ghosts, Check, Rerun, kParts };

  void enable(bool on) { on_ = on; }
  bool enabled() const { return on_; }
  void reset() { total_.fill(0.0); }
  //! Marks the start of a step's first part.
  void start() {
    if (on_) last_ = Clock::now();
  }
  //! Charges the time since the last mark (or start()) to `part`.
  void charge(Part part) {
    if (!on_) return;
    const auto now = Clock::now();
    total_[part] += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }
  //! The table, on rank 0 (collective: every rank must call it).
  void report(class LAMMPS *lmp, MPI_Comm world, long steps) const;

 private:
  using Clock = std::chrono::steady_clock;
  bool on_ = false;
  Clock::time_point last_{};
  std::array<double, kParts> total_{};
};

}  // namespace LAMMPS_NS
