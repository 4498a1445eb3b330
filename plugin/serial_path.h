#pragma once
//! fix hardsphere on one rank: the owned atoms are handed to the standalone stepper, which
//! resolves periodic images itself, so LAMMPS builds no neighbour list for the fix and every
//! result is the standalone stepper's by construction. LAMMPS keeps its own copy of x and v (for
//! output, other fixes, restarts), written back through the slot map only on steps where LAMMPS
//! or another fix reads them; velocities another fix changed are taken up before the next step.
//! Rough spheres' angular velocities (LAMMPS's omega) are read, written and taken up with them.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "hardsphere/particles.hpp"
#include "other_fixes.h"
#include "part_timer.h"
#include "pointers.h"
#include "slot_map.h"
#include "step_path.h"

namespace LAMMPS_NS {

class SerialPath : public StepPath, protected Pointers {
 public:
  SerialPath(LAMMPS *lmp, PartTimer &timer, const OtherFixes &others) : Pointers(lmp), timer_(timer), others_(others) {}
  //! noexcept as StepPath's: newer LAMMPS declares ~Pointers() noexcept(false).
  ~SerialPath() noexcept override = default;
  void configure(const hardsphere::StepperConfig &config, const hardsphere::Physics &physics) override {
    config_ = config;
    physics_ = physics;
  }
  void set_gravity(const std::array<double, 3> &g) override {
    physics_.gravity = g;
    if (stepper_) stepper_->set_gravity(g);
  }
  void set_shape_rotation(std::size_t k, double omega) override {
    physics_.shapes.at(k).omega = omega;
    if (stepper_) stepper_->set_shape_rotation(k, omega);
  }
  void neighbours_changed() override { lammps_moved_ = true; }
  void run_starts() override { make("fix hardsphere", kStartHint); }
  //! The group bits of fix freeze groups: their atoms are kinematic spheres.
  void set_kinematic_bits(int bits) { kinematic_bits_ = bits; }
  bool before_step(const StepStart &start) override;
  StepTotals step(double *virial_rows, double scale) override;
  double owned_mv2() const override { return hardsphere::state_exchange(*stepper_).mv2_sum(); }
  bool needs_reneighbor() const override { return false; }
  void run_ends() override {
    if (stepper_ && !state_written_) write();  // a run cut short (timer timeout)
  }

 private:
  //! A fresh stepper from LAMMPS's atoms; `source` names where an invalid state came from.
  void make(const std::string &source, const std::string &hint);
  void map_tags();
  //! The slot map, made again if the stepper re-sorted or LAMMPS re-ordered its atoms.
  void map_if_stale();
  void map();
  //! LAMMPS re-neighboured: it may have wrapped atoms (image flags) or sorted them.
  void follow_lammps();
  void write();
  //! What was just written, if other fixes may change it before the next step.
  void keep_written();
  bool must_write() const;

  PartTimer &timer_;
  const OtherFixes &others_;
  hardsphere::StepperConfig config_;
  hardsphere::Physics physics_;
  std::unique_ptr<hardsphere::StepperBase> stepper_;
  SlotMap slots_;
  std::vector<int> input_row_;                          //!< stepper input -> LAMMPS row (as of mapped_tags_)
  std::vector<SlotMap::Offset> input_offset_;           //!< stepper input -> box lengths LAMMPS x is ahead
  std::vector<tagint> input_tag_;                       //!< stepper input -> atom tag
  std::vector<int> tag_local_;                          //!< atom tag -> LAMMPS row, as of mapped_tags_
  std::vector<tagint> mapped_tags_;                     //!< LAMMPS's tags in row order when tag_local_ was made
  std::vector<std::array<int, 3>> tag_image0_;          //!< per tag: LAMMPS unwrapped = stepper unwrapped + this * L
  std::vector<imageint> mapped_image_;                  //!< LAMMPS's image flags the shifts account for
  std::vector<hardsphere::Vec3d> slot_pos_, slot_vel_;  //!< scratch: the stepper's state while mapping
  std::vector<double> v_written_;                       //!< velocities last written, while other fixes may change them
  std::vector<double> w_written_;                       //!< the same for angular velocities (rough spheres)
  bool slots_dirty_ = true;                             //!< the slot map needs map()
  bool lammps_moved_ = false;                           //!< LAMMPS re-neighboured since the last step
  bool state_written_ = true;                           //!< LAMMPS's x and v hold the stepper's current state
  int kinematic_bits_ = 0;
  std::string atoms_changed_by_;  //!< non-empty: a fix inserted or deleted atoms after the last step
};

}  // namespace LAMMPS_NS
