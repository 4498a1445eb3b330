#include "slot_map.h"

using namespace LAMMPS_NS;

void SlotMap::make(hardsphere::StepperBase &stepper, const std::vector<int> &input_row,
                   const std::vector<Vec3d> &input_shift, const std::vector<Offset> &input_offset,
                   const double *box_length, int owned_rows) {
  auto &exch = hardsphere::state_exchange(stepper);
  const std::size_t n = exch.size();
  input_.resize(n), images_.resize(3 * n), row_.resize(n), dest_.resize(n);
  base_.resize(n), shift_.resize(n), offset_.resize(n);
  for (int d = 0; d < 3; d++) length_[std::size_t(d)] = box_length[d];
  exch.copy_input_index(input_.data());
  exch.copy_images(images_.data());
  slot_of_row_.assign(std::size_t(owned_rows), hardsphere::StateExchange::kNoRow);
  ghost_slots_.clear();
  for (std::size_t k = 0; k < n; k++) {
    const std::uint32_t in = input_[k];
    const int row = input_row[in];
    row_[k] = std::uint32_t(row);
    base_[k] = input_shift.empty() ? Vec3d{0, 0, 0} : input_shift[in];
    for (std::size_t d = 0; d < 3; d++)
      offset_[k][d] = images_[3 * k + d] + (input_offset.empty() ? 0 : input_offset[in][d]);
    set_shift(k);
    const bool ghost = row >= owned_rows;
    dest_[k] = ghost ? hardsphere::StateExchange::kNoRow : std::uint32_t(row);
    if (ghost)
      ghost_slots_.push_back(std::uint32_t(k));
    else
      slot_of_row_[std::size_t(row)] = std::uint32_t(k);
  }
  rebuilds_ = stepper.counters().rebuilds;
}

void SlotMap::move(std::size_t slot, int axis, int boxes) {
  offset_[slot][std::size_t(axis)] += boxes;
  set_shift(slot);
}

void SlotMap::set_shift(std::size_t k) {
  for (std::size_t d = 0; d < 3; d++) shift_[k][int(d)] = base_[k][int(d)] + double(offset_[k][d]) * length_[d];
}
