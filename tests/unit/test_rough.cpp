// Rough spheres: the kernel's two-body results (smooth limit, energy of perfectly rough spheres,
// analytic head-on and grazing cases, Walton's sticking and sliding sides, momentum and angular
// momentum about the contact point, wall contacts), the same results from both engines, and
// gases that conserve energy, momentum and angular momentum over many collisions.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hardsphere/collision.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/init.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/rng.hpp"
#include "hardsphere/state_exchange.hpp"
#include "hardsphere/stepper.hpp"
#include "scenes.hpp"

using namespace hardsphere;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

kernel::Roughness<double> law(double beta, double mu = kInf, double q = 0.4) { return {beta, mu, q}; }

Vec3d random_vec(Rng& rng, double scale) {
  return {scale * (2 * rng.uniform() - 1), scale * (2 * rng.uniform() - 1), scale * (2 * rng.uniform() - 1)};
}

//! A random approaching pair at contact: unequal radii and masses unless `equal`.
struct Pair {
  Vec3d dr, v1, v2, w1, w2;
  double m1, m2, a1, a2;
};
Pair random_pair(Rng& rng, bool equal) {
  Pair p;
  p.a1 = equal ? 0.5 : 0.3 + 0.4 * rng.uniform();
  p.a2 = equal ? 0.5 : 0.3 + 0.4 * rng.uniform();
  p.m1 = equal ? 1.0 : 0.5 + rng.uniform();
  p.m2 = equal ? 1.0 : 0.5 + rng.uniform();
  do {
    Vec3d d = random_vec(rng, 1);
    p.dr = ((p.a1 + p.a2) / norm(d)) * d;
    p.v1 = random_vec(rng, 1), p.v2 = random_vec(rng, 1);
  } while (!(dot(p.dr, p.v1 - p.v2) < 0));
  p.w1 = random_vec(rng, 2), p.w2 = random_vec(rng, 2);
  return p;
}

double energy(const Pair& p, double q) {
  return 0.5 * (p.m1 * dot(p.v1, p.v1) + p.m2 * dot(p.v2, p.v2) + q * p.m1 * p.a1 * p.a1 * dot(p.w1, p.w1) +
                q * p.m2 * p.a2 * p.a2 * dot(p.w2, p.w2));
}

//! Angular momentum of the pair about a point c, with r1 - r2 = dr and the contact at c.
Vec3d angular_momentum_about_contact(const Pair& p, double q) {
  const Vec3d n = (1 / norm(p.dr)) * p.dr;
  const Vec3d r1 = p.a1 * n, r2 = -p.a2 * n;  // positions relative to the contact point
  return p.m1 * cross(r1, p.v1) + p.m2 * cross(r2, p.v2) + (q * p.m1 * p.a1 * p.a1) * p.w1 +
         (q * p.m2 * p.a2 * p.a2) * p.w2;
}

// Out of line, as the engines call the kernels: inlined next to each other, the compiler could
// share their products and fuse multiply-adds differently in the two (the last bit would differ).
__attribute__((noinline)) kernel::RoughOutcome<double> collide(Pair& p, double e, const kernel::Roughness<double>& k,
                                                               bool equal = false) {
  return kernel::collide_rough(p.dr, p.v1, p.v2, p.w1, p.w2, p.m1, p.m2, p.a1, p.a2, e, k, equal);
}
__attribute__((noinline)) double collide_smooth(const Pair& p, Vec3d& u1, Vec3d& u2, double e, bool equal) {
  return equal ? p.m1 * kernel::collide_equal_mass(p.dr, u1, u2, e) : kernel::collide(p.dr, u1, u2, p.m1, p.m2, e);
}

void expect_vec_near(Vec3d a, Vec3d b, double tol, const char* what) {
  EXPECT_NEAR(a.x, b.x, tol) << what;
  EXPECT_NEAR(a.y, b.y, tol) << what;
  EXPECT_NEAR(a.z, b.z, tol) << what;
}

}  // namespace

TEST(RoughKernel, SmoothLimitIsTheSmoothKernelBitForBit) {
  Rng rng(1);
  for (int trial = 0; trial < 200; ++trial) {
    for (const bool equal : {true, false}) {
      for (const double e : {1.0, 0.8}) {
        const Pair p0 = random_pair(rng, equal);
        for (const bool swapped : {false, true}) {  // both argument orders
          Pair p = p0;
          if (swapped) std::swap(p.v1, p.v2), std::swap(p.w1, p.w2), std::swap(p.m1, p.m2), std::swap(p.a1, p.a2);
          if (swapped) p.dr = -p.dr;
          Vec3d u1 = p.v1, u2 = p.v2;
          const double virial = collide_smooth(p, u1, u2, e, equal);
          const Vec3d w1 = p.w1, w2 = p.w2;
          const auto out = collide(p, e, law(-1), equal);
          EXPECT_EQ(out.virial, virial);
          EXPECT_EQ(out.dissipated_tangential, 0.0);
          for (int d = 0; d < 3; ++d) {
            EXPECT_EQ(p.v1[d], u1[d]);
            EXPECT_EQ(p.v2[d], u2[d]);
            EXPECT_EQ(p.w1[d], w1[d]);
            EXPECT_EQ(p.w2[d], w2[d]);
          }
        }
      }
    }
  }
}

TEST(RoughKernel, PerfectlyRoughElasticCollisionsKeepTheEnergyAndBothMomenta) {
  Rng rng(2);
  for (int trial = 0; trial < 1000; ++trial) {
    for (const double q : {0.4, 2.0 / 3.0, 0.1}) {
      Pair p = random_pair(rng, trial % 2 == 0);
      const double e0 = energy(p, q);
      const Vec3d mom0 = p.m1 * p.v1 + p.m2 * p.v2, l0 = angular_momentum_about_contact(p, q);
      const auto out = collide(p, 1.0, law(1.0, kInf, q));
      EXPECT_GT(out.virial, 0);
      EXPECT_NEAR(energy(p, q) / e0, 1.0, 1e-14);
      EXPECT_NEAR(out.dissipated_normal, 0.0, 1e-15);
      EXPECT_NEAR(out.dissipated_tangential, 0.0, 1e-14 * e0);
      expect_vec_near(p.m1 * p.v1 + p.m2 * p.v2, mom0, 1e-14, "momentum");
      expect_vec_near(angular_momentum_about_contact(p, q), l0, 1e-13, "angular momentum about the contact");
    }
  }
}

TEST(RoughKernel, InelasticRoughCollisionsTakeTheEnergyTheirChannelsReport) {
  // Any e, beta, mu: the energy lost equals the sum of the two channels; momentum and the angular
  // momentum about the contact point are kept; the tangential relative velocity of the contact
  // points is -beta times its value when sticking.
  Rng rng(3);
  for (int trial = 0; trial < 1000; ++trial) {
    const double e = 0.5 + 0.5 * rng.uniform(), beta = 2 * rng.uniform() - 1, mu = trial % 2 ? kInf : rng.uniform();
    Pair p = random_pair(rng, false);
    const double e0 = energy(p, 0.4);
    const Vec3d mom0 = p.m1 * p.v1 + p.m2 * p.v2, l0 = angular_momentum_about_contact(p, 0.4);
    const auto out = collide(p, e, law(beta, mu));
    EXPECT_NEAR(e0 - energy(p, 0.4), out.dissipated_normal + out.dissipated_tangential, 1e-13 * e0);
    EXPECT_GE(out.dissipated_tangential, -1e-14 * e0);
    expect_vec_near(p.m1 * p.v1 + p.m2 * p.v2, mom0, 1e-14, "momentum");
    expect_vec_near(angular_momentum_about_contact(p, 0.4), l0, 1e-13, "angular momentum about the contact");
  }
}

TEST(RoughKernel, HeadOnCollisionOfASpinningSphereMatchesTheAnalyticResult) {
  // Unit masses, radii 1/2, q = 0.4 (I = 0.1): sphere 1 at +x moving -x at speed 1 and spinning
  // at 2 about z, sphere 2 at rest. g = (-1, -1, 0), so J_n = (1+e)/2 x and J_t = (1+beta)/7 y:
  // v1 = (-1 + (1+e)/2, (1+beta)/7, 0), v2 = -J, w1z = 2 - 5 (1+beta)/7, w2z = -5 (1+beta)/7.
  for (const double e : {1.0, 0.9})
    for (const double beta : {-0.5, 0.0, 0.5, 1.0})
      for (const bool swapped : {false, true}) {
        Pair p{{1, 0, 0}, {-1, 0, 0}, {0, 0, 0}, {0, 0, 2}, {0, 0, 0}, 1, 1, 0.5, 0.5};
        if (swapped) std::swap(p.v1, p.v2), std::swap(p.w1, p.w2), p.dr = -p.dr;
        collide(p, e, law(beta), true);
        Vec3d moving = swapped ? p.v2 : p.v1, rest = swapped ? p.v1 : p.v2;
        Vec3d spun = swapped ? p.w2 : p.w1, still = swapped ? p.w1 : p.w2;
        const double jt = (1 + beta) / 7;
        expect_vec_near(moving, {-1 + (1 + e) / 2, jt, 0}, 1e-15, "v of the spinning sphere");
        expect_vec_near(rest, {-(1 + e) / 2, -jt, 0}, 1e-15, "v of the sphere at rest");
        expect_vec_near(spun, {0, 0, 2 - 5 * jt}, 1e-14, "w of the spinning sphere");
        expect_vec_near(still, {0, 0, -5 * jt}, 1e-14, "w of the sphere at rest");
      }
}

TEST(RoughKernel, GrazingCollisionSticksOrSlidesByWaltonsRule) {
  // Sphere 1 at +x, approaching at 0.01 along x and moving at 1 along y; no spin. g_t = (0, 1, 0),
  // |J_n| = (1+e) mu_ij 0.01 with mu_ij = 1/2. The constant-beta impulse (1+beta) q mu_ij / (1+q) =
  // (1+beta)/7 is taken when it is at most mu |J_n| (sticking), otherwise mu |J_n| (sliding).
  const double e = 0.9, beta = 0.4;
  const double jn = (1 + e) * 0.5 * 0.01, stick = (1 + beta) / 7;
  for (const double mu : {kInf, 100.0, 10.0, 0.5, 0.0}) {
    for (const bool swapped : {false, true}) {
      Pair p{{1, 0, 0}, {-0.01, 1, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, 1, 1, 0.5, 0.5};
      if (swapped) std::swap(p.v1, p.v2), p.dr = -p.dr;
      const auto out = collide(p, e, law(beta, mu), false);
      const Vec3d v1 = swapped ? p.v2 : p.v1;
      const double jt = 1.0 - v1.y;  // tangential impulse magnitude on sphere 1 (unit mass)
      EXPECT_NEAR(out.virial, jn, 1e-16);
      const bool slides = stick > mu * jn;
      EXPECT_EQ(out.sliding, slides) << "mu " << mu;
      EXPECT_NEAR(jt, slides ? mu * jn : stick, 1e-15) << "mu " << mu;
      EXPECT_NEAR(v1.x, -0.01 + jn, 1e-16);
      // Sticking: the contact points' tangential relative velocity is -beta times its value.
      const Vec3d w1 = swapped ? p.w2 : p.w1, w2 = swapped ? p.w1 : p.w2;
      const Vec3d v2 = swapped ? p.v1 : p.v2;
      const Vec3d g = v1 - v2 - cross(0.5 * w1 + 0.5 * w2, Vec3d{1, 0, 0});
      if (!slides) {
        EXPECT_NEAR(g.y, -beta, 1e-14);
      }
    }
  }
}

TEST(RoughKernel, WallContactSticksOrSlides) {
  // Unit sphere (radius 1/2, I = 0.1) on a floor (n = +z) at v = (1, 0, -1): g_t = (1, 0, 0), the
  // normal impulse per mass 2, the constant-beta change -(1+beta) q/(1+q) = -(1+beta)/3.5 along x,
  // capped at 2 mu when sliding; the spin changes by -(n x dv) / (q a).
  const double beta = 0.5, stick = (1 + beta) / 3.5;
  for (const double mu : {kInf, 1.0, 0.1}) {
    Vec3d w{0, 0, 0};
    double dissipated = 0;
    bool sliding = false;
    const Vec3d dv =
        kernel::wall_tangential(Vec3d{0, 0, 1}, Vec3d{1, 0, -1}, w, 1.0, 0.5, 2.0, law(beta, mu), dissipated, sliding);
    const bool slides = stick > 2 * mu;
    EXPECT_EQ(sliding, slides);
    const double jt = slides ? 2 * mu : stick;
    expect_vec_near(dv, {-jt, 0, 0}, 1e-15, "dv");
    expect_vec_near(w, {0, jt / 0.2, 0}, 1e-14, "w");  // -(z x -jt x) / (0.4 * 0.5): topspin
    // Energy: 0.5 (1 - (1 - jt)^2) of translation minus 0.5 I w^2 of rotation.
    EXPECT_NEAR(dissipated, 0.5 * (1 - (1 - jt) * (1 - jt)) - 0.5 * 0.1 * w.y * w.y, 1e-15);
  }
  // beta = 1: the contact point's tangential velocity reverses and energy is kept.
  Vec3d w{0.3, -2, 1};
  double dissipated = 1;
  bool sliding = true;
  const Vec3d v{0.7, -0.2, -1};
  const Vec3d dv = kernel::wall_tangential(Vec3d{0, 0, 1}, v, w, 1.0, 0.5, 2.0, law(1.0), dissipated, sliding);
  EXPECT_FALSE(sliding);
  EXPECT_NEAR(dissipated, 0.0, 1e-15);
  const Vec3d w0{0.3, -2, 1};
  const Vec3d g0 = v - 0.5 * cross(w0, Vec3d{0, 0, 1}), g1 = v + dv - 0.5 * cross(w, Vec3d{0, 0, 1});
  EXPECT_NEAR(g1.x, -g0.x, 1e-15);
  EXPECT_NEAR(g1.y, -g0.y, 1e-15);
  EXPECT_EQ(w.z, 1.0);  // spin about the normal is untouched
}

namespace {

Physics rough(double beta, double mu = kInf, double e = 1.0) {
  Physics p;
  p.tangential_restitution = beta;
  p.friction = mu;
  p.restitution = e;
  if (e < 1) p.contact_time = kDefaultContactTime;
  return p;
}

//! The head-on case of the kernel test, at 1 apart along x at t = 0, colliding at t = 1.5 (the
//! gap 1.5 closes at speed 1): the engines' state at t = 3 against the kernel's result.
ParticleSystem spinning_head_on(bool swapped) {
  ParticleSystem s = swapped ? test::two({4.0, 5, 5}, {0, 0, 0}, {6.5, 5, 5}, {-1, 0, 0})
                             : test::two({6.5, 5, 5}, {-1, 0, 0}, {4.0, 5, 5}, {0, 0, 0});
  s.omega = {{0, 0, 0}, {0, 0, 0}};
  s.omega[swapped ? 1 : 0] = {0, 0, 2};
  return s;
}

void expect_head_on_result(const ParticleSystem& out, bool swapped, double beta, double e, const char* engine) {
  const std::size_t spun = swapped ? 1 : 0, rest = 1 - spun;
  const double jt = (1 + beta) / 7;
  expect_vec_near(out.vel[spun], {-1 + (1 + e) / 2, jt, 0}, 1e-12, engine);
  expect_vec_near(out.vel[rest], {-(1 + e) / 2, -jt, 0}, 1e-12, engine);
  expect_vec_near(out.omega[spun], {0, 0, 2 - 5 * jt}, 1e-12, engine);
  expect_vec_near(out.omega[rest], {0, 0, -5 * jt}, 1e-12, engine);
}

}  // namespace

TEST(RoughEngines, HeadOnCollisionOfASpinningSphereInBothEngines) {
  for (const double beta : {-1.0, 0.0, 1.0})
    for (const bool swapped : {false, true}) {
      const ParticleSystem s = spinning_head_on(swapped);
      StepperConfig cfg;
      cfg.dt = 0.01;
      auto st = make_stepper(s, rough(beta), cfg);
      st->run(300);
      EventEngine ev(s, rough(beta));
      ev.advance(3.0);
      if (beta == -1.0) {  // smooth: the spin is kept as given, the collision is the smooth one
        EXPECT_EQ(st->state().omega[swapped ? 1 : 0].z, 2.0);
        EXPECT_EQ(ev.state().omega[swapped ? 1 : 0].z, 2.0);
        EXPECT_NEAR(st->state().vel[swapped ? 1 : 0].x, 0.0, 1e-12);
        continue;
      }
      expect_head_on_result(st->state(), swapped, beta, 1.0, "stepper");
      expect_head_on_result(ev.state(), swapped, beta, 1.0, "event");
      EXPECT_EQ(st->counters().collisions, 1);
      EXPECT_EQ(ev.counters().collisions, 1);
    }
  // Single precision: the same result to its rounding.
  const ParticleSystem s = spinning_head_on(false);
  StepperConfig cfg;
  cfg.dt = 0.01;
  auto st = make_stepper(s, rough(0.5), cfg, Precision::Float);
  st->run(300);
  const ParticleSystem out = st->state();
  EXPECT_NEAR(out.omega[0].z, 2 - 5 * 1.5 / 7, 1e-5);
  EXPECT_NEAR(out.vel[1].y, -1.5 / 7, 1e-6);
}

TEST(RoughEngines, WallBounceTakesTheTangentialImpulseInBothEngines) {
  // A sphere hitting the floor of a box walled in z at v = (1, 0, -1) without spin, beta = 0.5:
  // it leaves at (1 - 1.5/3.5, 0, 1) with w = (0, 1.5/0.7, 0), in both engines and with
  // Walton's friction mu = 0.1 at (1 - 0.2, 0, 1), w = (0, 1, 0).
  for (const double mu : {kInf, 0.1}) {
    ParticleSystem s =
        test::two({5, 5, 2.0}, {1, 0, -1}, {2, 2, 8}, {0, 0, 0}, 0.5, 0.5, 1, 1, 10, {true, true, false});
    const double jt = mu < kInf ? 0.2 : 1.5 / 3.5;
    StepperConfig cfg;
    cfg.dt = 0.01;
    auto st = make_stepper(s, rough(0.5, mu), cfg);
    st->run(200);
    EventEngine ev(s, rough(0.5, mu));
    ev.advance(2.0);
    for (const ParticleSystem& out : {st->state(), ev.state()}) {
      expect_vec_near(out.vel[0], {1 - jt, 0, 1}, 1e-12, "velocity after the bounce");
      expect_vec_near(out.omega[0], {0, jt / 0.2, 0}, 1e-12, "spin after the bounce");
      // Lands at t = 1.5 at x = 6.5; then moves at 1 - jt for 0.5.
      EXPECT_NEAR(out.pos[0].x, 6.5 + 0.5 * (1 - jt), 1e-12);
      EXPECT_NEAR(out.pos[0].z, 0.5 + 0.5, 1e-12);
    }
    EXPECT_EQ(st->counters().wall_collisions, 1);
    EXPECT_EQ(ev.counters().wall_collisions, 1);
    const double loss = 0.5 * (1 - (1 - jt) * (1 - jt)) - 0.5 * 0.1 * (jt / 0.2) * (jt / 0.2);
    EXPECT_NEAR(st->counters().dissipated_tangential, loss, 1e-12);
    EXPECT_NEAR(ev.counters().dissipated_tangential, loss, 1e-12);
  }
}

namespace {

ParticleSystem rough_gas(std::int64_t n, double phi, std::uint64_t seed,
                         std::array<bool, 3> periodic = {true, true, true}) {
  InitSpec spec;
  spec.n = n;
  const double l = std::cbrt(double(n) * M_PI / 6.0 / phi);
  spec.box = Box::from_lengths({l, l, l}, periodic);
  spec.seed = seed;
  spec.rotational_temperature = 1.0;
  return make_initial_state(spec);
}

double total_energy(const ParticleSystem& s) { return kinetic_energy(s) + rotational_kinetic_energy(s, 0.4); }

}  // namespace

TEST(RoughEngines, PerfectlyRoughElasticGasKeepsItsEnergyAndMomentum) {
  // 1000 spheres at phi 0.3, periodic, e = 1, beta = 1: over 1e6 collisions per engine the total
  // kinetic energy (translation + rotation) drifts by less than 2e-13 of itself (a random walk of
  // roundings; a kernel that leaned one ulp per collision, as one normalising n without its rounding
  // did, reaches 4e-13), momentum stays at rounding level, and energy flows between the channels
  // (the initial temperatures differ by the draw).
  const ParticleSystem s = rough_gas(1000, 0.3, 7);
  const double e0 = total_energy(s);
  StepperConfig cfg;
  cfg.dt = 0.01;
  auto st = make_stepper(s, rough(1.0), cfg);
  EventEngine ev(s, rough(1.0));
  while (st->counters().collisions < 1000000) st->run(500);
  while (ev.counters().collisions < 1000000) ev.advance(5.0);
  for (const ParticleSystem& out : {st->state(), ev.state()}) {
    EXPECT_NEAR(total_energy(out) / e0, 1.0, 2e-13);
    EXPECT_LT(norm(total_momentum(out)), 1e-10);
    EXPECT_NE(rotational_kinetic_energy(out, 0.4), rotational_kinetic_energy(s, 0.4));
  }
  EXPECT_NEAR(st->counters().dissipated_tangential, 0.0, 1e-12 * e0);
  EXPECT_NEAR(ev.counters().dissipated_tangential, 0.0, 1e-12 * e0);
}

TEST(RoughEngines, IsolatedCloudKeepsItsAngularMomentumAboutTheOrigin) {
  // Periodic images make the angular momentum about a point ill-defined; an isolated cloud is
  // free of them: 500 spheres at phi 0.3 placed in the middle of a box five times wider, run until
  // t = 3 (no sphere reaches the box's faces), e = 1 and beta = 0.7 (energy is lost, angular
  // momentum sum m r x v + I w about the origin is not).
  ParticleSystem s = rough_gas(500, 0.3, 9);
  const double l = s.box.length(0);
  ParticleSystem cloud = s;
  cloud.box = Box::from_lengths({5 * l, 5 * l, 5 * l}, {true, true, true});
  for (auto& p : cloud.pos) p += Vec3d{2 * l, 2 * l, 2 * l};
  cloud.image.assign(cloud.size(), {0, 0, 0});
  const Vec3d l0 = angular_momentum(cloud, 0.4);
  double scale = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) scale += norm(cloud.pos[i]) * norm(cloud.vel[i]);
  StepperConfig cfg;
  cfg.dt = 0.01;
  auto st = make_stepper(cloud, rough(0.7), cfg);
  st->run(300);
  EventEngine ev(cloud, rough(0.7));
  ev.advance(3.0);
  for (const ParticleSystem& out : {st->state(), ev.state()}) {
    for (const auto& img : out.image) EXPECT_EQ(img, (std::array<std::int32_t, 3>{0, 0, 0}));
    const Vec3d l1 = angular_momentum(out, 0.4);
    expect_vec_near(l1, l0, 1e-12 * scale, "angular momentum about the origin");
    EXPECT_LT(total_energy(out), total_energy(cloud) * (1 - 1e-3));  // beta < 1 took energy
  }
  EXPECT_GT(st->counters().collisions, 1000);
  EXPECT_GT(ev.counters().collisions, 1000);
}

TEST(RoughEngines, RoughScenesAreValidated) {
  const ParticleSystem s = test::gas(100, 0.1, 1);
  EXPECT_THROW(make_stepper(s, rough(1.5), StepperConfig{}), InputError);
  EXPECT_THROW(make_stepper(s, rough(0.5, -1), StepperConfig{}), InputError);
  EXPECT_THROW(make_stepper(s, rough(-1, 0.5), StepperConfig{}), InputError);
  Physics q = rough(0.5);
  q.inertia = 0.7;
  EXPECT_THROW(EventEngine(s, q, EventConfig{}), InputError);
  q.inertia = 0;
  EXPECT_THROW(EventEngine(s, q, EventConfig{}), InputError);
  ParticleSystem bad = s;
  bad.omega[3].y = std::nan("");
  EXPECT_THROW(validate_and_wrap(bad, "test"), InputError);
}

TEST(RoughEngines, StateExchangeCarriesTheAngularVelocities) {
  const ParticleSystem s = rough_gas(200, 0.2, 4);
  auto st = make_stepper(s, rough(0.5), StepperConfig{});
  StateExchange& x = state_exchange(*st);
  EXPECT_NEAR(x.iw2_sum(), 2 * rotational_kinetic_energy(s, 0.4), 1e-12 * rotational_kinetic_energy(s, 0.4));
  std::vector<std::uint32_t> slots(x.size()), input(x.size());
  for (std::uint32_t k = 0; k < slots.size(); ++k) slots[k] = k;
  x.copy_input_index(input.data());
  std::vector<Vec3d> w(x.size());
  x.copy(SphereField::Omega, slots.data(), slots.size(), w.data());
  for (std::size_t k = 0; k < w.size(); ++k) EXPECT_EQ(w[k].x, s.omega[input[k]].x);
  // Set one slot, read it back through the flat-array scatter and the state.
  const Vec3d spin{1, 2, 3};
  x.set(SphereField::Omega, slots.data() + 5, 1, &spin);
  std::vector<double> flat(3 * x.size(), -1);
  x.scatter(SphereField::Omega, slots.data(), flat.data());
  EXPECT_EQ(flat[15], 1.0);
  EXPECT_EQ(flat[17], 3.0);
  EXPECT_EQ(st->state().omega[input[5]].y, 2.0);
  flat[16] = 7;
  x.gather(SphereField::Omega, slots.data(), flat.data());
  EXPECT_EQ(st->state().omega[input[5]].y, 7.0);
  // A smooth stepper carries the spins unchanged and counts no rotational energy.
  auto smooth = make_stepper(s, Physics{}, StepperConfig{});
  StateExchange& y = state_exchange(*smooth);
  EXPECT_EQ(y.iw2_sum(), 0.0);
  y.set(SphereField::Omega, slots.data() + 5, 1, &spin);
  y.copy(SphereField::Omega, slots.data(), slots.size(), w.data());
  EXPECT_EQ(w[5].z, 3.0);
}
