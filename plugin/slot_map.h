#pragma once
//! Which LAMMPS row each slot of a stepper is, and the shift from the stepper's position to
//! LAMMPS's x (the stepper works in its own box and wraps on its own): slot k holds the sphere
//! made from input input(k), so its row is that input's row, and its shift that input's shift
//! plus a whole number of box lengths per axis (the input's own offset and the stepper's wraps
//! since). The slots change at every re-sort of the stepper (stale()); rows at or past the owned
//! ones are ghosts, which are never written.
#include <array>
#include <cstdint>
#include <vector>

#include "hardsphere/state_exchange.hpp"
#include "hardsphere/stepper.hpp"

namespace LAMMPS_NS {

class SlotMap {
 public:
  using Vec3d = hardsphere::Vec3d;
  using Offset = std::array<int, 3>;
  //! Maps the slots of `stepper`: input i is LAMMPS row input_row[i], shifted by input_shift[i]
  //! plus input_offset[i] box lengths (empty vectors: none); rows from `owned_rows` on are
  //! ghosts. `box_length`: LAMMPS's box length per axis.
  void make(hardsphere::StepperBase &stepper, const std::vector<int> &input_row, const std::vector<Vec3d> &input_shift,
            const std::vector<Offset> &input_offset, const double *box_length, int owned_rows);
  //! Whether the stepper has re-sorted its spheres since make().
  bool stale(const hardsphere::StepperBase &stepper) const { return stepper.counters().rebuilds != rebuilds_; }
  std::size_t size() const { return row_.size(); }
  const std::uint32_t *rows() const { return row_.data(); }
  //! Per slot its row if owned, else StateExchange::kNoRow: where scatter_state writes.
  const std::uint32_t *owned_rows() const { return dest_.data(); }
  //! Per slot: LAMMPS x - stepper position.
  const Vec3d *shifts() const { return shift_.data(); }
  std::uint32_t input(std::size_t slot) const { return input_[slot]; }
  //! Box lengths of `slot`'s shift along each axis.
  const Offset &offset(std::size_t slot) const { return offset_[slot]; }
  //! Moves `slot`'s shift by `boxes` box lengths along `axis` (LAMMPS re-imaged its atom).
  void move(std::size_t slot, int axis, int boxes);
  //! The slot of owned row `row`.
  std::uint32_t slot_of_row(int row) const { return slot_of_row_[std::size_t(row)]; }
  //! The slots that hold ghosts.
  const std::vector<std::uint32_t> &ghost_slots() const { return ghost_slots_; }

 private:
  void set_shift(std::size_t slot);
  std::vector<std::uint32_t> input_, row_, dest_, slot_of_row_, ghost_slots_;
  std::vector<std::int32_t> images_;
  std::vector<Vec3d> base_, shift_;
  std::vector<Offset> offset_;
  std::array<double, 3> length_{};
  std::int64_t rebuilds_ = -1;
};

}  // namespace LAMMPS_NS
