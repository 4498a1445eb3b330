// Dense initial states (the soft-sphere quench and its compression stages): exact packing
// fraction, no overlap, walls, determinism, an amorphous structure, bounded refusals, and both
// engines running from them with the conservation laws intact.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/init.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/particles.hpp"
#include "hardsphere/stepper.hpp"
#include "init/dense_packing.hpp"
#include "scenes.hpp"

using namespace hardsphere;

namespace {

ParticleSystem dense(std::int64_t n, double phi, std::uint64_t seed, std::array<bool, 3> periodic = {true, true, true},
                     InitMethod method = InitMethod::Auto) {
  return test::gas(n, phi, seed, std::nullopt, periodic, method);
}

// Smallest gap between two spheres or a sphere and a wall, in diameters.
double smallest_gap(const ParticleSystem& s) {
  ParticleSystem grown = s;
  double lo = 0, hi = 0.01;  // bisect on the radius increase that first makes an overlap
  for (int k = 0; k < 40; ++k) {
    const double mid = 0.5 * (lo + hi);
    for (auto& r : grown.radius) r = 0.5 * (1 + mid);
    bool overlap = max_overlap(grown) > 0;
    for (std::size_t i = 0; i < s.size() && !overlap; ++i)
      for (int d = 0; d < 3; ++d)
        if (!s.box.periodic[d])
          overlap =
              overlap || s.pos[i][d] - s.box.lo[d] < grown.radius[i] || s.box.hi[d] - s.pos[i][d] < grown.radius[i];
    (overlap ? hi : lo) = mid;
  }
  return lo;
}

// Steinhardt bond order with neighbours closer than 1.4 diameters (unit diameters).
struct BondOrder {
  double q6_global = 0;     // 0.575 for FCC, ~0 for an amorphous packing
  double crystal_like = 0;  // fraction with >= 7 neighbours of aligned q6 (dot > 0.7)
};

using Q6 = std::array<std::complex<double>, 7>;  // m = 0..6; m < 0 follow by symmetry

void add_y6(Vec3d b, Q6& q) {
  const double ct = b.z / norm(b), st = std::sqrt(std::max(0.0, 1 - ct * ct)), ph = std::atan2(b.y, b.x);
  for (int m = 0; m <= 6; ++m) {
    double pmm = 1;  // associated Legendre P_6^m(ct) by the standard recurrence
    for (int i = 1; i <= m; ++i) pmm *= -(2.0 * i - 1) * st;
    double p = pmm;
    if (m < 6) {
      double a = pmm, b1 = ct * (2 * m + 1) * pmm;
      for (int l = m + 2; l <= 6; ++l) {
        const double c = (ct * (2 * l - 1) * b1 - (l + m - 1) * a) / (l - m);
        a = b1;
        b1 = c;
      }
      p = b1;
    }
    double f = 1;  // (6 - m)! / (6 + m)!
    for (int k = 6 - m + 1; k <= 6 + m; ++k) f /= k;
    q[m] += std::sqrt(13 / (4 * M_PI) * f) * p * std::polar(1.0, m * ph);
  }
}

double dot_q6(const Q6& a, const Q6& b) {
  double s = std::real(a[0] * std::conj(b[0]));
  for (int m = 1; m <= 6; ++m) s += 2 * std::real(a[m] * std::conj(b[m]));
  return s;
}

BondOrder bond_order(const ParticleSystem& s) {
  const std::size_t n = s.size();
  std::vector<Q6> q(n);
  std::vector<std::vector<std::size_t>> nb(n);
  Q6 total{};
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      Vec3d dr = s.pos[j] - s.pos[i];
      for (int d = 0; d < 3; ++d)
        if (s.box.periodic[d]) dr[d] -= s.box.length(d) * std::nearbyint(dr[d] / s.box.length(d));
      if (norm(dr) >= 1.4) continue;
      nb[i].push_back(j);
      nb[j].push_back(i);
      add_y6(dr, q[i]);
      add_y6(dr, q[j]);  // Y_6m(-b) = Y_6m(b)
      add_y6(dr, total);
      add_y6(dr, total);
    }
  BondOrder out;
  std::size_t bonds = 0;
  for (auto& l : nb) bonds += l.size();
  out.q6_global = std::sqrt(4 * M_PI / 13 * dot_q6(total, total)) / double(bonds);
  std::size_t crystal = 0;
  for (std::size_t i = 0; i < n; ++i) {
    int aligned = 0;
    for (std::size_t j : nb[i])
      if (dot_q6(q[i], q[j]) > 0.7 * std::sqrt(dot_q6(q[i], q[i]) * dot_q6(q[j], q[j]))) ++aligned;
    crystal += aligned >= 7;
  }
  out.crystal_like = double(crystal) / double(n);
  return out;
}

ParticleSystem fcc(int cells, double phi) {
  ParticleSystem s;
  const double a = std::cbrt(4 * M_PI / 6 / phi);
  s.box = Box::from_lengths({cells * a, cells * a, cells * a}, {true, true, true});
  static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  std::int64_t id = 1;
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j)
      for (int k = 0; k < cells; ++k)
        for (const auto& b : basis) s.push_back(id++, 1, 0.5, 1, {(i + b[0]) * a, (j + b[1]) * a, (k + b[2]) * a}, {});
  return s;
}

std::string refusal(const Box& box, std::int64_t n, const DensePackingConfig& cfg) {
  Rng rng(5);
  try {
    dense_packing(box, n, 0.5, rng, cfg);
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST(DenseInit, ExactPackingFractionNoOverlapAndGaps) {
  for (const double phi : {0.58, 0.62, 0.64}) {
    const auto s = dense(1000, phi, 3);
    EXPECT_NEAR(s.packing_fraction(), phi, 1e-12);
    EXPECT_EQ(max_overlap(s), 0.0);
    // The quench leaves every pair at least eps/2 = 0.001 diameters apart.
    EXPECT_GE(smallest_gap(s), 0.001 * (1 - 1e-6)) << "phi " << phi;
    EXPECT_NEAR(temperature(s), 1.0, 1e-12);
    EXPECT_LT(norm(total_momentum(s)), 1e-10);
  }
}

TEST(DenseInit, WallsOnSomeOrAllAxes) {
  // Walls lower the reach (the spheres cannot fill the layer by a wall as densely): with walls
  // on every axis N = 800 reaches ~0.58.
  struct Case {
    std::array<bool, 3> periodic;
    double phi;
  };
  for (const auto& c : {Case{{true, true, false}, 0.58}, Case{{true, true, false}, 0.62},
                        Case{{false, false, false}, 0.56}, Case{{false, false, false}, 0.58}}) {
    {
      const double phi = c.phi;
      const auto s = dense(800, phi, 1, c.periodic, InitMethod::Dense);
      EXPECT_NEAR(s.packing_fraction(), phi, 1e-12);
      EXPECT_EQ(max_overlap(s), 0.0);
      EXPECT_GE(smallest_gap(s), 0.001 * (1 - 1e-6));  // walls: eps/2 radii from the sphere surface
    }
  }
}

TEST(DenseInit, DeterministicPerSeed) {
  const auto a = dense(500, 0.63, 7), b = dense(500, 0.63, 7), c = dense(500, 0.63, 8);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.pos[i].x, b.pos[i].x);
    EXPECT_EQ(a.pos[i].y, b.pos[i].y);
    EXPECT_EQ(a.pos[i].z, b.pos[i].z);
    EXPECT_EQ(a.vel[i].x, b.vel[i].x);
  }
  EXPECT_NE(a.pos[0].x, c.pos[0].x);
}

TEST(DenseInit, AmorphousNotCrystalline) {
  // The order parameter itself: a perfect FCC crystal is all crystal-like with Q6 = 0.575.
  const auto crystal = bond_order(fcc(5, 0.60));
  EXPECT_NEAR(crystal.q6_global, 0.5745, 1e-3);
  EXPECT_EQ(crystal.crystal_like, 1.0);
  // Straight quench (0.60) and compression stages (0.635): no crystal nuclei to speak of. Over
  // seeds 11-18 Q6 had mean 0.034 and 0.046, sd 0.006 and 0.010, the crystal-like fraction mean
  // 0.003 and 0.014, sd 0.003 and 0.009 (phi 0.60, 0.635): the bounds are |mean| + 4 sd or more.
  for (const double phi : {0.60, 0.635}) {
    const auto order = bond_order(dense(1000, phi, 2));
    EXPECT_LT(order.q6_global, 0.1) << "phi " << phi;
    EXPECT_LT(order.crystal_like, 0.06) << "phi " << phi;
  }
}

TEST(DenseInit, SmallSystemsAndTinyBoxes) {
  // n = 1, 2, 3 in boxes of two diameters; no dynamics fits such boxes, the quench alone works.
  for (const std::int64_t n : {1, 2, 3}) {
    InitSpec spec;
    spec.n = n;
    spec.method = InitMethod::Dense;
    spec.box = Box::from_lengths({2, 2, 2}, {true, true, false});
    const auto s = make_initial_state(spec);
    EXPECT_EQ(s.size(), std::size_t(n));
    EXPECT_EQ(max_overlap(s), 0.0);
  }
}

TEST(DenseInit, RefusesWhatItCannotReachInBoundedTime) {
  // Past the reach (skipping make_initial_state's up-front limit): the stages stop once their
  // step has halved to min_step, and the message names the target and the densest reached.
  const double l = std::cbrt(300 * M_PI / 6.0 / 0.67);
  const Box box = Box::from_lengths({l, l, l}, {true, true, true});
  std::string m = refusal(box, 300, {});
  EXPECT_NE(m.find("packing fraction 0.67"), std::string::npos) << m;
  EXPECT_NE(m.find("densest packing reached was 0.6"), std::string::npos) << m;
  // A starved quench: the first quench fails at every retry.
  DensePackingConfig starved;
  starved.quench.max_iterations = 3;
  m = refusal(Box::from_lengths({8, 8, 8}, {true, true, true}), 500, starved);
  EXPECT_NE(m.find("first quench"), std::string::npos) << m;
}

namespace {

struct RunResult {
  double rate = 0, z = 0;  // collisions per sphere and time; compressibility factor
};

void expect_conserved(const ParticleSystem& s0, const ParticleSystem& s1, double energy_tol, double momentum_tol,
                      const std::string& what) {
  const double e0 = kinetic_energy(s0), e1 = kinetic_energy(s1);
  EXPECT_LT(std::abs(e1 - e0) / e0, energy_tol) << what;
  EXPECT_LT(norm(total_momentum(s1) - total_momentum(s0)), momentum_tol) << what;
}

}  // namespace

TEST(DenseEngines, BothEnginesRunFromDenseStates) {
  // N = 800 at 0.60 (straight quench) and 0.62 (at the edge of the straight quench), t = 0.5:
  // ~50 collisions per sphere. The stepper (sweep detection, dt ~0.1 mean free times) and the
  // event engine start from the same state; their trajectories decorrelate, so collision rate
  // and Z agree only statistically (4% covers the spread of such short runs; over 10 seeds on the
  // portable build both ratios were 1 to 1e-10: in 0.5 time units the runs had not decorrelated).
  for (const double phi : {0.60, 0.62}) {
    const auto s = dense(800, phi, 11);
    const double t = temperature(s), duration = 0.5;
    EventEngine ev(s);
    ev.advance(duration);
    const auto out_ev = ev.state();
    const auto& ce = ev.counters();
    const std::string what = "phi " + std::to_string(phi);
    expect_conserved(s, out_ev, 1e-12, 1e-10, what + " event");
    EXPECT_LT(max_overlap(out_ev), 1e-10) << what;
    EXPECT_GT(ce.collisions, 20 * 800) << what;

    StepperConfig cfg;
    cfg.dt = 0.001;
    cfg.detect = Detect::Sweep;
    auto st = make_stepper(s, {}, cfg);
    st->run(500);
    const auto out_st = st->state();
    const auto& cs = st->counters();
    expect_conserved(s, out_st, 1e-12, 1e-10, what + " stepper");
    EXPECT_EQ(max_overlap(out_st), 0.0) << what;
    EXPECT_EQ(cs.unresolved_steps, 0) << what;

    const double rate_ev = 2.0 * double(ce.collisions) / (800 * duration);
    const double rate_st = 2.0 * double(cs.collisions) / (800 * cs.sim_time);
    const double z_ev = compressibility_factor(ce.pair_virial, duration, 800, t);
    const double z_st = compressibility_factor(cs.pair_virial, cs.sim_time, 800, t);
    EXPECT_NEAR(rate_st / rate_ev, 1.0, 0.04) << what << " stepper " << rate_st << " event " << rate_ev;
    EXPECT_NEAR(z_st / z_ev, 1.0, 0.04) << what << " stepper " << z_st << " event " << z_ev;

    auto fl = make_stepper(s, {}, StepperConfig{}, Precision::Float);
    fl->run(50);  // dt 0.01: ~50 collisions per sphere as well
    const auto out_fl = fl->state();
    expect_conserved(s, out_fl, 1e-4, 1e-3, what + " float");
    EXPECT_LT(max_overlap(out_fl), 1e-5) << what;
  }
}
