#pragma once
//! Measurements on a particle state: energy, momentum, temperature, pressure, speed statistics.
#include <array>
#include <cstdint>
#include <vector>

#include "hardsphere/particles.hpp"

namespace hardsphere {

double kinetic_energy(const ParticleSystem& sys);  //!< sum m v^2 / 2
Vec3d total_momentum(const ParticleSystem& sys);   //!< sum m v
double temperature(const ParticleSystem& sys);     //!< sum m v^2 / 3N (k_B = 1)
//! Rotational kinetic energy sum q m r^2 |w|^2 / 2 (I = q m r^2; 0 without omegas).
double rotational_kinetic_energy(const ParticleSystem& sys, double inertia);
//! sum m |v - v_cm|^2 / 3N: the translational temperature in the centre-of-mass frame.
double translational_temperature(const ParticleSystem& sys);
//! sum I |w|^2 / 3N with I = q m r^2.
double rotational_temperature(const ParticleSystem& sys, double inertia);
//! Total angular momentum about the origin, sum m r x v + I w (positions as stored).
Vec3d angular_momentum(const ParticleSystem& sys, double inertia);
//! Potential energy in a uniform acceleration g: -sum m g.(x - lo), zero at the lower box corner,
//! x unwrapped (pos + image L) along periodic axes.
double potential_energy(const ParticleSystem& sys, const std::array<double, 3>& g);

//! Z = PV/(NkT) from the collision virial: 1 + sum(r_ij . dp_i) / (3 N T t).
double compressibility_factor(double pair_virial, double sim_time, std::size_t n, double temperature);

struct Histogram {
  double lo = 0, hi = 0;
  std::vector<std::int64_t> counts;
  double width() const { return counts.empty() ? 0.0 : (hi - lo) / double(counts.size()); }
};
//! Histogram of |v| over [0, vmax) in `bins` bins (speeds >= vmax land in the last bin).
Histogram speed_histogram(const ParticleSystem& sys, int bins, double vmax);

//! Maxwell-Boltzmann cumulative distribution of u = |v| sqrt(m/T) (a chi distribution, 3 dof).
double maxwell_cdf(double u);
//! Kolmogorov-Smirnov distance between the scaled speeds u_i = |v_i| sqrt(m_i/T) and maxwell_cdf.
double maxwell_ks_distance(const ParticleSystem& sys, double temperature);
//! Asymptotic Kolmogorov distribution tail Q(lambda) = P(sqrt(n) D > lambda).
double kolmogorov_pvalue(double d, std::size_t n);

}  // namespace hardsphere
