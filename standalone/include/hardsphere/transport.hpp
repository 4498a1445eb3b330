#pragma once
//! Equilibrium transport of elastic hard spheres: the exact time integrals of the stress tensor
//! and of the heat flux (TransportTally, fed by either engine at each collision), and the
//! Einstein/Helfand estimators of self-diffusion, shear viscosity and thermal conductivity
//! (TransportEstimator, fed with samples by the run layer). Formulas: docs/transport.md.
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "hardsphere/particles.hpp"
#include "hardsphere/physics.hpp"

namespace hardsphere {

//! Time integrals of V P_ab (xx yy zz xy xz yz) and of V J_q (x y z) from the tally's start:
//! kinetic parts integrated exactly between velocity changes, collisional parts summed at contact.
struct TransportMoments {
  double time = 0;
  std::array<double, 6> stress{0, 0, 0, 0, 0, 0};
  std::array<double, 3> heat{0, 0, 0};
};

//! The exact accumulator. The kinetic tensor K = sum m v (x) v and the energy current
//! J = sum (m v^2 / 2) v are constant between collisions, so their integrals advance by K h and
//! J h; a collision `back` before the tally's clock changed them that long ago, so the integrals
//! take the change times `back` (the stepper's rewind; 0 for the event engine).
class TransportTally {
 public:
  //! K and J of `sys`, integrals and clock zero.
  void start(const ParticleSystem& sys);
  void advance(double h) {
    for (std::size_t k = 0; k < 6; ++k) m_.stress[k] += kinetic_[k] * h;
    for (std::size_t k = 0; k < 3; ++k) m_.heat[k] += current_[k] * h;
    m_.time += h;
  }
  //! The event engine's clock: advances to time t.
  void advance_to(double t) { advance(t - m_.time); }
  //! A pair collision `back` before the clock: r = x_i - x_j at contact, velocities before and after.
  void collision(double back, const double r[3], double mi, const Vec3d& vi0, const Vec3d& vi1, double mj,
                 const Vec3d& vj0, const Vec3d& vj1) {
    const Vec3d dp{mi * (vi1.x - vi0.x), mi * (vi1.y - vi0.y), mi * (vi1.z - vi0.z)};
    // Collisional parts: r_ij (x) dp_i, and r_ij times the energy sphere i gained (elastic: j lost it).
    const double de = 0.5 * mi * (dot(vi1, vi1) - dot(vi0, vi0));
    const double rc[6] = {r[0] * dp.x, r[1] * dp.y, r[2] * dp.z, r[0] * dp.y, r[0] * dp.z, r[1] * dp.z};
    double dk[6], dj[3];
    change(mi, vi0, vi1, dk, dj, false);
    change(mj, vj0, vj1, dk, dj, true);
    for (std::size_t k = 0; k < 6; ++k) {
      kinetic_[k] += dk[k];
      m_.stress[k] += rc[k] + dk[k] * back;
    }
    for (std::size_t k = 0; k < 3; ++k) {
      current_[k] += dj[k];
      m_.heat[k] += r[k] * de + dj[k] * back;
    }
  }
  const TransportMoments& moments() const { return m_; }
  const std::array<double, 6>& kinetic() const { return kinetic_; }  //!< K now
  const std::array<double, 3>& current() const { return current_; }  //!< J now

 private:
  //! Adds (or starts with, add = false) the change of m v (x) v and of (m v^2 / 2) v.
  static void change(double m, const Vec3d& v0, const Vec3d& v1, double* dk, double* dj, bool add) {
    const double k1[6] = {v1.x * v1.x, v1.y * v1.y, v1.z * v1.z, v1.x * v1.y, v1.x * v1.z, v1.y * v1.z};
    const double k0[6] = {v0.x * v0.x, v0.y * v0.y, v0.z * v0.z, v0.x * v0.y, v0.x * v0.z, v0.y * v0.z};
    const double e1 = 0.5 * m * dot(v1, v1), e0 = 0.5 * m * dot(v0, v0);
    const double j[3] = {e1 * v1.x - e0 * v0.x, e1 * v1.y - e0 * v0.y, e1 * v1.z - e0 * v0.z};
    for (std::size_t k = 0; k < 6; ++k) dk[k] = (add ? dk[k] : 0.0) + m * (k1[k] - k0[k]);
    for (std::size_t k = 0; k < 3; ++k) dj[k] = (add ? dj[k] : 0.0) + j[k];
  }
  TransportMoments m_;
  std::array<double, 6> kinetic_{0, 0, 0, 0, 0, 0};
  std::array<double, 3> current_{0, 0, 0};
};

//! Refuses (InputError) a scene whose transport coefficients these estimators do not define:
//! walls, gravity, inelastic or rough collisions, kinematic spheres, unequal radii or masses.
//! `option` names the request (--transport, transport=True).
void check_transport(const ParticleSystem& sys, const Physics& physics, const std::string& option);
//! The part that needs no state: the boundaries and the physics.
void check_transport(const std::array<bool, 3>& periodic, const Physics& physics, const std::string& option);

//! Results in reduced units (sphere diameter, mass and the run's temperature kT = 1); each error is
//! the standard error of the mean of independent blocks.
struct TransportResult {
  double diffusion = 0, diffusion_error = 0;          //!< D with the 1/L correction (Yeh-Hummer)
  double diffusion_raw = 0, diffusion_raw_error = 0;  //!< D of the periodic box
  double shear_viscosity = 0, shear_viscosity_error = 0;
  double thermal_conductivity = 0, thermal_conductivity_error = 0;
  double window = 0, sample_interval = 0;  //!< the longest correlation time and the sampling (simulated time)
  int blocks = 0, lags = 0;
  double temperature = 0;  //!< kT the reduced units take
};

//! Einstein/Helfand estimators. The measured run is cut into `blocks` equal blocks; in each, the
//! mean squared increments of the moments and of the unwrapped positions (centre of mass taken
//! off) over every origin and lag 1..lags samples are fitted by a line over the lags lags/2..lags;
//! coefficient = slope / (2 V kT) (eta), / (2 V kT^2) (lambda), / 6 (D). Increments never span two
//! blocks, so the blocks are independent when a block is much longer than the window.
class TransportEstimator {
 public:
  //! `sys` is the state at the start of the measured run; the samples come every `interval`.
  TransportEstimator(const ParticleSystem& sys, double interval, int lags, int blocks);
  //! Closes the current block (the next sample starts a new one).
  void end_block();
  //! A sample: the tally's moments and the unwrapped positions in id order.
  void sample(const TransportMoments& m, const ParticleSystem& state);
  TransportResult result() const;

 private:
  //! Per lag: origins, summed squared displacements and per channel (6 shear, 3 heat) the summed
  //! squared increments. (Not their variance: the mean over a block's origins would take a share
  //! growing with the lag, biasing the slope low by twice the lag over the block length.)
  struct Block {
    std::vector<double> count, msd;
    std::vector<std::array<double, 9>> s2;
  };
  void add_lags();
  std::size_t n_ = 0;
  double volume_ = 0, temperature_ = 0, sigma_ = 0, mass_ = 0, length_ = 0, interval_ = 0;
  // The centre of mass's velocity, total mass and kinetic energy (constant): the moments are taken
  // in the centre-of-mass frame.
  Vec3d v_cm_{};
  double total_mass_ = 0, energy_ = 0;
  int lags_ = 0, blocks_wanted_ = 0;
  std::vector<Block> blocks_;
  // The last lags + 1 samples of the current block: moments (6 + 3) and unwrapped positions.
  std::vector<std::array<double, 9>> ring_m_;
  std::vector<std::vector<double>> ring_x_;
  std::size_t filled_ = 0, head_ = 0;
};

//! Yeh and Hummer's finite-box correction of D in a periodic cube of side L (reduced units):
//! D = D_box + xi / (6 pi eta L), xi = 2.837297.
double yeh_hummer(double d_box, double eta, double length);

}  // namespace hardsphere
