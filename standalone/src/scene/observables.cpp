#include "hardsphere/observables.hpp"

#include <algorithm>
#include <cmath>

namespace hardsphere {

double kinetic_energy(const ParticleSystem& sys) {
  double e = 0;
  for (std::size_t i = 0; i < sys.size(); ++i) e += 0.5 * sys.mass[i] * dot(sys.vel[i], sys.vel[i]);
  return e;
}

Vec3d total_momentum(const ParticleSystem& sys) {
  Vec3d p{};
  for (std::size_t i = 0; i < sys.size(); ++i) p += sys.mass[i] * sys.vel[i];
  return p;
}

double potential_energy(const ParticleSystem& sys, const std::array<double, 3>& g) {
  // Along a periodic axis the height is the unwrapped coordinate (a chute's spheres keep falling).
  double u = 0;
  for (std::size_t i = 0; i < sys.size(); ++i)
    for (int d = 0; d < 3; ++d) {
      const std::size_t a = std::size_t(d);
      double x = sys.pos[i][d] - sys.box.lo[a];
      if (sys.box.periodic[a] && g[a] != 0 && i < sys.image.size()) x += double(sys.image[i][a]) * sys.box.length(d);
      u -= sys.mass[i] * g[a] * x;
    }
  return u;
}

double temperature(const ParticleSystem& sys) {
  return sys.size() ? 2.0 * kinetic_energy(sys) / (3.0 * double(sys.size())) : 0.0;
}

double rotational_kinetic_energy(const ParticleSystem& sys, double q) {
  if (sys.omega.size() < sys.size()) return 0.0;
  double e = 0;
  for (std::size_t i = 0; i < sys.size(); ++i)
    e += 0.5 * q * sys.mass[i] * sys.radius[i] * sys.radius[i] * dot(sys.omega[i], sys.omega[i]);
  return e;
}

double translational_temperature(const ParticleSystem& sys) {
  if (!sys.size()) return 0.0;
  double m = 0;
  for (const double mi : sys.mass) m += mi;
  const Vec3d v_cm = (1.0 / m) * total_momentum(sys);
  double sum = 0;
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const Vec3d u = sys.vel[i] - v_cm;
    sum += sys.mass[i] * dot(u, u);
  }
  return sum / (3.0 * double(sys.size()));
}

double rotational_temperature(const ParticleSystem& sys, double q) {
  return sys.size() ? 2.0 * rotational_kinetic_energy(sys, q) / (3.0 * double(sys.size())) : 0.0;
}

Vec3d angular_momentum(const ParticleSystem& sys, double q) {
  Vec3d l{};
  const bool spin = sys.omega.size() >= sys.size();
  for (std::size_t i = 0; i < sys.size(); ++i) {
    l += sys.mass[i] * cross(sys.pos[i], sys.vel[i]);
    if (spin) l += (q * sys.mass[i] * sys.radius[i] * sys.radius[i]) * sys.omega[i];
  }
  return l;
}

double compressibility_factor(double pair_virial, double sim_time, std::size_t n, double t) {
  if (!(sim_time > 0) || n == 0 || !(t > 0)) return 1.0;
  return 1.0 + pair_virial / (3.0 * double(n) * t * sim_time);
}

Histogram speed_histogram(const ParticleSystem& sys, int bins, double vmax) {
  Histogram h;
  h.lo = 0;
  h.hi = vmax;
  h.counts.assign(std::size_t(std::max(1, bins)), 0);
  for (const auto& v : sys.vel) {
    const auto b = std::size_t(norm(v) / vmax * double(h.counts.size()));
    ++h.counts[std::min(b, h.counts.size() - 1)];
  }
  return h;
}

double maxwell_cdf(double u) {
  return std::erf(u / std::sqrt(2.0)) - std::sqrt(2.0 / M_PI) * u * std::exp(-0.5 * u * u);
}

double maxwell_ks_distance(const ParticleSystem& sys, double t) {
  std::vector<double> u(sys.size());
  for (std::size_t i = 0; i < sys.size(); ++i) u[i] = norm(sys.vel[i]) * std::sqrt(sys.mass[i] / t);
  std::sort(u.begin(), u.end());
  double d = 0;
  const double n = double(u.size());
  for (std::size_t i = 0; i < u.size(); ++i) {
    const double f = maxwell_cdf(u[i]);
    d = std::max({d, f - double(i) / n, double(i + 1) / n - f});
  }
  return d;
}

double kolmogorov_pvalue(double d, std::size_t n) {
  // Stephens' finite-n correction of the asymptotic Kolmogorov series.
  const double sn = std::sqrt(double(n));
  const double lambda = (sn + 0.12 + 0.11 / sn) * d;
  if (lambda < 0.2) return 1.0;
  double q = 0;
  for (int k = 1; k <= 100; ++k) q += 2 * ((k % 2) ? 1 : -1) * std::exp(-2.0 * k * k * lambda * lambda);
  return std::clamp(q, 0.0, 1.0);
}

}  // namespace hardsphere
