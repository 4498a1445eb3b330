#pragma once
//! pair_style hardsphere: contact distances per type pair and the neighbour/ghost cutoff for
//! fix hardsphere, which does all the dynamics. Forces and potential energy are zero.
//!   pair_style hardsphere
//!   pair_coeff I J [diameter]   diameter: contact distance of types I and J (mixed with the
//!                               pair_modify mix rule when I != J is not given); without it,
//!                               the largest per-atom diameter 2*max(radius) is used.
//! User documentation: docs/pair_hardsphere.md.
#include <string>

#include "pair.h"

namespace LAMMPS_NS {

class PairHardSphere : public Pair {
 public:
  explicit PairHardSphere(class LAMMPS *);
  ~PairHardSphere() override;
  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_data(FILE *) override;
  void write_data_all(FILE *) override;
  double single(int, int, int, int, double, double, double, double &fforce) override {
    fforce = 0.0;
    return 0.0;
  }
  //! Contact distance (neighbour cutoff) of types i, j in use. Valid after init().
  double contact(int i, int j) const { return cut[i][j]; }

 protected:
  double **cut = nullptr;       //!< contact distance per type pair in use (set by init_one)
  double **diam = nullptr;      //!< per type pair as pair_coeff gave it; < 0 means the per-atom diameters
  double auto_diameter = -1.0;  //!< 2 max(radius) over all atoms, when a coefficient needs it
  void allocate();
  double auto_cut();
  double per_atom_diameter();
  //! The contact distance pair_coeff I J gives, with the per-atom diameters resolved.
  double resolved(int i, int j);
  //! Refuses a contact distance `c` of types i, j (from `given`) that does not fit the box as a
  //! sphere's diameter would not: LAMMPS sizes its ghost copies by it before any check of atoms.
  void check_fits_box(int i, int j, double c, const std::string &given);
};

//! The input command being executed is 'rerun': it reads snapshots and integrates nothing.
bool hardsphere_rerun_in_progress(class LAMMPS *lmp);

}  // namespace LAMMPS_NS
