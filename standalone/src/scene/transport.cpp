#include "hardsphere/transport.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

#include "hardsphere/errors.hpp"

namespace hardsphere {

void TransportTally::start(const ParticleSystem& sys) {
  *this = TransportTally{};
  double dk[6] = {0, 0, 0, 0, 0, 0}, dj[3] = {0, 0, 0};
  for (std::size_t i = 0; i < sys.size(); ++i) change(sys.mass[i], Vec3d{}, sys.vel[i], dk, dj, true);
  for (std::size_t k = 0; k < 6; ++k) kinetic_[k] = dk[k];
  for (std::size_t k = 0; k < 3; ++k) current_[k] = dj[k];
}

namespace {

[[noreturn]] void refuse_transport(const std::string& option, const std::string& why) {
  throw InputError(option + " needs an elastic one-species fluid in an all-periodic box without gravity: " + why);
}

}  // namespace

void check_transport(const std::array<bool, 3>& periodic, const Physics& physics, const std::string& option) {
  auto refuse = [&](const std::string& why) { refuse_transport(option, why); };
  for (int d = 0; d < 3; ++d)
    if (!periodic[std::size_t(d)]) refuse(std::string("the ") + "xyz"[d] + " axis has walls (boundary w)");
  if (!physics.shapes.empty()) refuse("the scene has " + std::to_string(physics.shapes.size()) + " shaped walls");
  for (int d = 0; d < 3; ++d)
    if (physics.gravity[std::size_t(d)] != 0) {
      std::ostringstream m;
      m << "gravity " << physics.gravity[0] << "," << physics.gravity[1] << "," << physics.gravity[2];
      refuse(m.str());
    }
  if (physics.restitution != 1.0) {
    std::ostringstream m;
    m << "restitution " << physics.restitution << " (inelastic spheres have no equilibrium)";
    refuse(m.str());
  }
  if (physics.rough()) {
    std::ostringstream m;
    m << "tangential restitution " << physics.tangential_restitution << " (rough spheres carry heat in rotation)";
    refuse(m.str());
  }
}

void check_transport(const ParticleSystem& sys, const Physics& physics, const std::string& option) {
  auto refuse = [&](const std::string& why) { refuse_transport(option, why); };
  check_transport(sys.box.periodic, physics, option);
  if (sys.kinematic_count() > 0) refuse(std::to_string(sys.kinematic_count()) + " kinematic spheres");
  if (sys.size() < 2) refuse(std::to_string(sys.size()) + " spheres");
  for (std::size_t i = 1; i < sys.size(); ++i)
    if (sys.radius[i] != sys.radius[0] || sys.mass[i] != sys.mass[0]) {
      std::ostringstream m;
      m << "atom " << sys.id[i] << " has radius " << sys.radius[i] << " and mass " << sys.mass[i] << ", atom "
        << sys.id[0] << " radius " << sys.radius[0] << " and mass " << sys.mass[0] << " (mixtures are not handled)";
      refuse(m.str());
    }
  const double l = sys.box.length(0);
  if (sys.box.length(1) != l || sys.box.length(2) != l) {
    std::ostringstream m;
    m << "the box is " << l << " x " << sys.box.length(1) << " x " << sys.box.length(2)
      << " (the 1/L correction of D is a cube's)";
    refuse(m.str());
  }
}

double yeh_hummer(double d_box, double eta, double length) {
  constexpr double kXi = 2.837297, kPi = 3.14159265358979323846;
  return d_box + kXi / (6 * kPi * eta * length);
}

TransportEstimator::TransportEstimator(const ParticleSystem& sys, double interval, int lags, int blocks)
    : n_(sys.size()),
      volume_(sys.box.volume()),
      sigma_(n_ ? 2 * sys.radius[0] : 1.0),
      mass_(n_ ? sys.mass[0] : 1.0),
      length_(sys.box.length(0)),
      interval_(interval),
      lags_(lags),
      blocks_wanted_(blocks) {
  Vec3d p{};
  double m = 0, mv2 = 0;
  for (std::size_t i = 0; i < n_; ++i) p += sys.mass[i] * sys.vel[i], m += sys.mass[i];
  for (std::size_t i = 0; i < n_; ++i) {
    const Vec3d v = sys.vel[i] - (1 / m) * p;
    mv2 += sys.mass[i] * dot(v, v);
  }
  temperature_ = n_ > 1 ? mv2 / (3.0 * double(n_ - 1)) : 0.0;  // the centre of mass's 3 degrees taken off
  total_mass_ = m;
  v_cm_ = (1 / m) * p;
  for (std::size_t i = 0; i < n_; ++i) energy_ += 0.5 * sys.mass[i] * dot(sys.vel[i], sys.vel[i]);
  ring_m_.resize(std::size_t(lags) + 1);
  ring_x_.resize(std::size_t(lags) + 1);
  end_block();
}

void TransportEstimator::end_block() {
  if (!blocks_.empty() && blocks_.back().count.empty()) return;  // nothing sampled since the last one
  Block b;
  b.count.assign(std::size_t(lags_) + 1, 0.0);
  b.msd.assign(std::size_t(lags_) + 1, 0.0);
  b.s2.assign(std::size_t(lags_) + 1, {});
  blocks_.push_back(std::move(b));
  filled_ = 0;
  head_ = 0;
}

void TransportEstimator::sample(const TransportMoments& m, const ParticleSystem& state) {
  // The channels whose increments give eta (each the same autocorrelation in an isotropic fluid:
  // a 45 degree rotation turns P_xy into (P_yy - P_xx) / 2) and lambda.
  // In the centre-of-mass frame (velocities v - V): the kinetic tensor loses M V (x) V, the energy
  // current becomes J - E V - K V + M V^2 V and the collisional heat r_ij (dE_i - V . dp_i); in
  // the integrals, with G the whole stress moment, H - E V t - G V + M V^2 V t.
  const Vec3d& v = v_cm_;
  const double t = m.time, mv2 = total_mass_ * dot(v, v);
  const auto& g = m.stress;
  const double gv[3] = {g[0] * v.x + g[3] * v.y + g[4] * v.z, g[3] * v.x + g[1] * v.y + g[5] * v.z,
                        g[4] * v.x + g[5] * v.y + g[2] * v.z};
  double s[6] = {v.x * v.x, v.y * v.y, v.z * v.z, v.x * v.y, v.x * v.z, v.y * v.z};
  for (std::size_t k = 0; k < 6; ++k) s[k] = g[k] - total_mass_ * s[k] * t;
  double h[3];
  for (std::size_t k = 0; k < 3; ++k) h[k] = m.heat[k] - (energy_ - mv2) * v[int(k)] * t - gv[k];
  auto& q = ring_m_[head_];
  q = {s[3], s[4], s[5], 0.5 * (s[0] - s[1]), 0.5 * (s[1] - s[2]), 0.5 * (s[2] - s[0]), h[0], h[1], h[2]};
  auto& x = ring_x_[head_];
  x.resize(3 * n_);
  Vec3d c{};
  for (std::size_t i = 0; i < n_; ++i) {
    Vec3d u = state.pos[i];
    if (i < state.image.size())
      for (int d = 0; d < 3; ++d) u[d] += double(state.image[i][d]) * state.box.length(d);
    x[3 * i] = u.x, x[3 * i + 1] = u.y, x[3 * i + 2] = u.z;
    c += u;
  }
  c = (1.0 / double(n_)) * c;  // equal masses: the centre of mass is the mean position
  for (std::size_t i = 0; i < n_; ++i) x[3 * i] -= c.x, x[3 * i + 1] -= c.y, x[3 * i + 2] -= c.z;
  filled_ = std::min(filled_ + 1, ring_m_.size());
  add_lags();
  head_ = (head_ + 1) % ring_m_.size();
}

void TransportEstimator::add_lags() {
  Block& b = blocks_.back();
  const std::size_t size = ring_m_.size();
  const auto& q1 = ring_m_[head_];
  const auto& x1 = ring_x_[head_];
  for (std::size_t lag = 1; lag < filled_; ++lag) {
    const std::size_t o = (head_ + size - lag) % size;
    const auto& q0 = ring_m_[o];
    const auto& x0 = ring_x_[o];
    double s = 0;
    for (std::size_t k = 0; k < x1.size(); ++k) s += (x1[k] - x0[k]) * (x1[k] - x0[k]);
    b.msd[lag] += s / double(n_);
    for (std::size_t c = 0; c < 9; ++c) {
      const double d = q1[c] - q0[c];
      b.s2[lag][c] += d * d;
    }
    b.count[lag] += 1;
  }
}

namespace {

//! Least-squares slope of y over x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0, my = 0;
  for (std::size_t k = 0; k < x.size(); ++k) mx += x[k], my += y[k];
  mx /= double(x.size()), my /= double(x.size());
  double sxy = 0, sxx = 0;
  for (std::size_t k = 0; k < x.size(); ++k) sxy += (x[k] - mx) * (y[k] - my), sxx += (x[k] - mx) * (x[k] - mx);
  return sxx > 0 ? sxy / sxx : 0.0;
}

std::pair<double, double> mean_error(const std::vector<double>& v) {
  double m = 0, s = 0;
  for (double x : v) m += x;
  m /= double(v.size());
  for (double x : v) s += (x - m) * (x - m);
  const double n = double(v.size());
  return {m, v.size() > 1 ? std::sqrt(s / (n - 1) / n) : 0.0};
}

}  // namespace

TransportResult TransportEstimator::result() const {
  TransportResult r;
  r.window = interval_ * lags_;
  r.sample_interval = interval_;
  r.lags = lags_;
  r.temperature = temperature_;
  std::vector<double> d, eta, lambda;
  const double kt = temperature_;
  // Reduced units: lengths in sigma, times in sigma sqrt(m / kT).
  const double v0 = std::sqrt(kt / mass_);
  for (const Block& b : blocks_) {
    if (b.count[std::size_t(lags_)] < 1) continue;  // a block too short for the window
    std::vector<double> t, msd, ys, yh;
    for (int lag = (lags_ + 1) / 2; lag <= lags_; ++lag) {
      const std::size_t l = std::size_t(lag);
      const double c = b.count[l];
      double vs = 0, vh = 0;
      for (std::size_t k = 0; k < 9; ++k) {
        (k < 6 ? vs : vh) += b.s2[l][k] / c;
      }
      t.push_back(lag * interval_);
      msd.push_back(b.msd[l] / c);
      ys.push_back(vs / 6);
      yh.push_back(vh / 3);
    }
    d.push_back(slope(t, msd) / 6 / (sigma_ * v0));
    eta.push_back(slope(t, ys) / (2 * volume_ * kt) * sigma_ * sigma_ / std::sqrt(mass_ * kt));
    lambda.push_back(slope(t, yh) / (2 * volume_ * kt * kt) * sigma_ * sigma_ / v0);
  }
  r.blocks = int(d.size());
  if (d.empty()) return r;
  std::tie(r.diffusion_raw, r.diffusion_raw_error) = mean_error(d);
  std::tie(r.shear_viscosity, r.shear_viscosity_error) = mean_error(eta);
  std::tie(r.thermal_conductivity, r.thermal_conductivity_error) = mean_error(lambda);
  const double l = length_ / sigma_;
  r.diffusion = yeh_hummer(r.diffusion_raw, r.shear_viscosity, l);
  // The correction's share of the error, through eta's.
  const double dc = (r.diffusion - r.diffusion_raw) * r.shear_viscosity_error / r.shear_viscosity;
  r.diffusion_error = std::hypot(r.diffusion_raw_error, dc);
  return r;
}

}  // namespace hardsphere
