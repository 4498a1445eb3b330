// The contact laws both engines evaluate (contact_law.hpp): analytic one- and two-body results.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hardsphere/contact_law.hpp"

using hardsphere::Vec3d;
namespace k = hardsphere::kernel;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

//! The contact points' relative velocity g = v1 - v2 - (a1 w1 + a2 w2) x n, n = dr / |dr|.
Vec3d contact_velocity(Vec3d dr, Vec3d v1, Vec3d v2, Vec3d w1, Vec3d w2, double a1, double a2) {
  const Vec3d n = (1 / std::sqrt(dot(dr, dr))) * dr;
  return v1 - v2 - cross(a1 * w1 + a2 * w2, n);
}
Vec3d tangential(Vec3d g, Vec3d n) { return g - dot(g, n) * n; }

void expect_near(Vec3d a, Vec3d b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

//! A smooth collision through the law, as either engine calls it (Exact: the event engine).
template <bool Exact>
k::ContactOutcome smooth(const k::PairLaw<double>& law, k::PairRule rule, Vec3d dr, Vec3d& v1, Vec3d& v2, double m1,
                         double m2, bool equal_mass) {
  return k::collide_pair<false, Exact>(law, rule, dr, v1, v2, nullptr, nullptr, m1, m2, 0.5, 0.5, equal_mass);
}
}  // namespace

TEST(PairRule, TcModelDecidesRestitutionAndRoughness) {
  k::PairLaw<double> law;  // elastic: the TC clock is never asked
  bool asked = false;
  k::PairRule r = k::pair_rule(law, [&] { return asked = true; });
  EXPECT_FALSE(asked);
  EXPECT_FALSE(r.restituted);
  EXPECT_TRUE(r.full);
  law.restitution = 0.5;
  r = k::pair_rule(law, [] { return false; });  // no recent collision: restituted, the whole law
  EXPECT_TRUE(r.restituted);
  EXPECT_TRUE(r.full);
  r = k::pair_rule(law, [] { return true; });  // within the contact time: elastic and smooth
  EXPECT_FALSE(r.restituted);
  EXPECT_FALSE(r.full);
}

TEST(PairLaw, SmoothHeadOnExchangesVelocitiesTimesE) {
  // Sphere 1 at x = 0 moving +1, sphere 2 at x = 1 moving -1 (dr = r1 - r2 = -x): they swap
  // velocities scaled by e = 0.5; the virial is (1+e) mu |dv.n| = 1.5 * 0.5 * 2 (unit masses).
  const k::PairLaw<double> law{0.5, {}};
  for (const bool equal_mass : {true, false}) {
    Vec3d v1{1, 0, 0}, v2{-1, 0, 0};
    const k::ContactOutcome out = smooth<false>(law, {true, true}, Vec3d{-1, 0, 0}, v1, v2, 1.0, 1.0, equal_mass);
    EXPECT_TRUE(out.changed);
    EXPECT_DOUBLE_EQ(out.virial, 1.5);
    EXPECT_DOUBLE_EQ(v1.x, -0.5);
    EXPECT_DOUBLE_EQ(v2.x, 0.5);
    EXPECT_EQ(out.dissipated_normal, 0.0);  // energy by channel: rough spheres only
  }
  // The TC model's elastic fallback swaps them whole, in the event engine's form too.
  Vec3d v1{1, 0, 0}, v2{-1, 0, 0};
  const k::ContactOutcome out = smooth<true>(law, {false, false}, Vec3d{-1, 0, 0}, v1, v2, 1.0, 1.0, true);
  EXPECT_TRUE(out.changed);
  EXPECT_DOUBLE_EQ(out.virial, 2.0);
  EXPECT_DOUBLE_EQ(v1.x, -1.0);
  EXPECT_DOUBLE_EQ(v2.x, 1.0);
}

TEST(PairLaw, UnequalMassesFollowTheOneDimensionalFormula) {
  // m1 = 1 at +2 on m2 = 3 at rest, e = 0.5: v1' = (m1 - e m2) v1 / (m1 + m2) = -0.25,
  // v2' = (1 + e) m1 v1 / (m1 + m2) = 0.75; momentum 2 is kept.
  const k::PairLaw<double> law{0.5, {}};
  Vec3d v1{2, 0, 0}, v2{0, 0, 0};
  const k::ContactOutcome out = smooth<false>(law, {true, true}, Vec3d{-1, 0, 0}, v1, v2, 1.0, 3.0, false);
  EXPECT_TRUE(out.changed);
  EXPECT_DOUBLE_EQ(v1.x, -0.25);
  EXPECT_DOUBLE_EQ(v2.x, 0.75);
  EXPECT_DOUBLE_EQ(v1.x + 3 * v2.x, 2.0);
}

TEST(PairLaw, RecedingPairIsLeftAloneByBothForms) {
  const k::PairLaw<double> law{0.5, {}};
  Vec3d v1{-1, 0, 0}, v2{1, 0, 0};
  EXPECT_FALSE(smooth<false>(law, {true, true}, Vec3d{-1, 0, 0}, v1, v2, 1.0, 1.0, true).changed);
  EXPECT_FALSE(smooth<true>(law, {true, true}, Vec3d{-1, 0, 0}, v1, v2, 1.0, 1.0, true).changed);
  EXPECT_EQ(v1.x, -1.0);
  EXPECT_EQ(v2.x, 1.0);
}

TEST(PairLaw, ExactFormReportsAnImpulseBelowTheRoundingAsNoChange) {
  // Approaching at one ulp of 3 nearly side on (b = dr.dv ~ -4e-36): the impulse changes no bit.
  const k::PairLaw<double> law;
  const Vec3d dr{1, 0, 1e-20};
  Vec3d v1{5, 0, 3}, v2{5, 0, std::nextafter(3.0, 4.0)};
  const Vec3d v2_0 = v2;
  ASSERT_LT(dot(dr, v1 - v2), 0.0);
  const k::ContactOutcome exact = smooth<true>(law, {false, true}, dr, v1, v2, 1.0, 1.0, true);
  EXPECT_FALSE(exact.changed);
  EXPECT_EQ(v1.x, 5.0);
  EXPECT_EQ(v1.z, 3.0);
  EXPECT_EQ(v2.z, v2_0.z);
  // The stepper's form counts it (virial != 0): it resolves contacts by time order, not again.
  const k::ContactOutcome plain = smooth<false>(law, {false, true}, dr, v1, v2, 1.0, 1.0, true);
  EXPECT_TRUE(plain.changed);
  EXPECT_GT(plain.virial, 0.0);
}

TEST(PairLaw, RoughTangentialRestitutionKeepsOrReversesTheContactVelocity) {
  // Equal spheres (m = 1, a = 0.5, q = 0.4) meeting obliquely and spinning: beta = -1 keeps the
  // contact points' tangential relative velocity, beta = 1 reverses it; the normal one is
  // reversed and scaled by e in both; momentum is conserved; beta = +-1 takes no tangential energy.
  const Vec3d dr{-1, 0, 0}, n{-1, 0, 0};
  for (const bool exact : {false, true}) {
    for (const double beta : {-1.0, 1.0}) {
      const k::PairLaw<double> law{0.5, {beta, kInf, 0.4}};
      Vec3d v1{1, 0.3, 0}, v2{-1, -0.1, 0.2}, w1{0.1, 0.2, -0.3}, w2{0, 0.5, 0.4};
      const Vec3d g0 = contact_velocity(dr, v1, v2, w1, w2, 0.5, 0.5);
      const Vec3d p0 = v1 + v2;
      const k::ContactOutcome out =
          exact ? k::collide_pair<true, true>(law, {true, true}, dr, v1, v2, &w1, &w2, 1.0, 1.0, 0.5, 0.5, true)
                : k::collide_pair<true, false>(law, {true, true}, dr, v1, v2, &w1, &w2, 1.0, 1.0, 0.5, 0.5, true);
      EXPECT_TRUE(out.changed);
      const Vec3d g1 = contact_velocity(dr, v1, v2, w1, w2, 0.5, 0.5);
      expect_near(tangential(g1, n), beta == 1 ? -1.0 * tangential(g0, n) : tangential(g0, n), 1e-15);
      EXPECT_NEAR(dot(g1, n), -0.5 * dot(g0, n), 1e-15);
      expect_near(v1 + v2, p0, 1e-15);
      EXPECT_NEAR(out.dissipated_tangential, 0.0, 1e-15);
      // Normal channel: (1 - e^2) mu (g.n)^2 / 2 with mu = 1/2, g.n = -2.
      EXPECT_NEAR(out.dissipated_normal, 0.5 * 0.75 * 0.5 * 4, 1e-15);
      EXPECT_NEAR(out.virial, 1.5, 1e-15);
    }
  }
}

TEST(PairLaw, RoughTcElasticCollisionIsSmooth) {
  // The TC model's elastic fallback neither restitutes nor turns the spheres.
  const k::PairLaw<double> law{0.5, {1.0, kInf, 0.4}};
  Vec3d v1{1, 0.3, 0}, v2{-1, -0.1, 0.2}, w1{0.1, 0.2, -0.3}, w2{0, 0.5, 0.4};
  const Vec3d w1_0 = w1, w2_0 = w2;
  const k::ContactOutcome out =
      k::collide_pair<true, false>(law, {false, false}, Vec3d{-1, 0, 0}, v1, v2, &w1, &w2, 1.0, 1.0, 0.5, 0.5, true);
  EXPECT_TRUE(out.changed);
  EXPECT_DOUBLE_EQ(v1.x, -1.0);
  EXPECT_DOUBLE_EQ(v1.y, 0.3);
  EXPECT_DOUBLE_EQ(v2.x, 1.0);
  EXPECT_TRUE(w1.x == w1_0.x && w1.y == w1_0.y && w1.z == w1_0.z);
  EXPECT_TRUE(w2.x == w2_0.x && w2.y == w2_0.y && w2.z == w2_0.z);
}

TEST(RestingContact, EitherSideOfTheThresholdOnBothWallsForBothSignsOfG) {
  // |g| resting_time = 0.25 (exact): a contact at |v| <= 0.25 on the wall gravity pulls towards rests.
  const double rt = 0.125, below = 0.25, above = std::nextafter(0.25, 1.0);
  for (const double g : {-2.0, 2.0}) {
    const int pulled = g < 0 ? -1 : 1;  // the lower wall under g < 0, the upper one under g > 0
    const double into = g < 0 ? -1.0 : 1.0;
    EXPECT_TRUE(k::resting_contact(into * below, g, pulled, rt)) << g;
    EXPECT_TRUE(k::resting_contact(0.0, g, pulled, rt)) << g;
    EXPECT_FALSE(k::resting_contact(into * above, g, pulled, rt)) << g;
    // The other wall: gravity pulls away from it, so even a slow contact bounces.
    EXPECT_FALSE(k::resting_contact(-into * 0.01, g, -pulled, rt)) << g;
    EXPECT_FALSE(k::resting_contact(0.0, g, -pulled, rt)) << g;
  }
  EXPECT_FALSE(k::resting_contact(0.0, 0.0, -1, rt));  // no gravity: never resting
  EXPECT_FALSE(k::resting_contact(0.0, 0.0, 1, rt));
}

//! The TC clock of a sphere that collided long ago.
static bool never() { return false; }

TEST(WallLaw, ReflectionOrRestWithTheirImpulses) {
  const k::WallLaw<double> smooth_law;
  // Onto the floor (axis 2, side -1) at -3 under g = -2: far above the threshold 2 * 0.125, a
  // bounce taking 2 |v| per unit mass.
  k::WallOutcome<double> out =
      k::collide_wall<false>(smooth_law, 2, -1, Vec3d{1, 0, -3}, -2.0, 0.125, 0.5, nullptr, 1.0, 0.5, never);
  EXPECT_FALSE(out.rested);
  EXPECT_DOUBLE_EQ(out.impulse, 6.0);
  EXPECT_EQ(out.dv.x, 0.0);
  // At -0.25: resting; it leaves at -g hop / 2 = 0.5 (hop 0.5), the wall takes 0.25 + 0.5.
  out = k::collide_wall<false>(smooth_law, 2, -1, Vec3d{1, 0, -0.25}, -2.0, 0.125, 0.5, nullptr, 1.0, 0.5, never);
  EXPECT_TRUE(out.rested);
  EXPECT_DOUBLE_EQ(out.leave, 0.5);
  EXPECT_DOUBLE_EQ(out.impulse, 0.75);
  // The same contact on the ceiling under g = +2 leaves downwards.
  out = k::collide_wall<false>(smooth_law, 2, 1, Vec3d{1, 0, 0.25}, 2.0, 0.125, 0.5, nullptr, 1.0, 0.5, never);
  EXPECT_TRUE(out.rested);
  EXPECT_DOUBLE_EQ(out.leave, -0.5);
}

TEST(WallLaw, RoughBetaKeepsOrReversesTheContactPointVelocity) {
  // A sphere (m = 2, a = 0.5, q = 0.4) onto the upper wall of axis 1 (inward normal -y), sliding
  // and spinning: with beta = -1 nothing tangential changes, with beta = 1 the contact point's
  // tangential velocity v - a w x n is reversed. (Resting contacts: below.)
  const Vec3d n{0, -1, 0}, v{0.7, 1.5, -0.2};
  for (const double beta : {-1.0, 1.0}) {
    const k::WallLaw<double> law{1.0, {beta, kInf, 0.4}};
    Vec3d w{0.3, -0.4, 1.1};
    const Vec3d gt0 = tangential(v - 0.5 * cross(w, n), n);
    const k::WallOutcome<double> out = k::collide_wall<true>(law, 1, 1, v, 0.0, 0.125, 0.0, &w, 2.0, 0.5, never);
    EXPECT_FALSE(out.rested);
    EXPECT_DOUBLE_EQ(out.impulse, 3.0);
    EXPECT_EQ(out.dv.y, 0.0);  // tangential only: the normal reflection is the engine's
    const Vec3d reflected{v.x, -v.y, v.z};
    const Vec3d gt1 = tangential(reflected + out.dv - 0.5 * cross(w, n), n);
    expect_near(gt1, beta == 1 ? -1.0 * gt0 : gt0, 1e-15);
    EXPECT_NEAR(out.contact.dissipated_tangential, 0.0, 1e-15);
  }
}

TEST(WallLaw, RestingContactTakesTheWallsTangentialLaw) {
  // A resting contact on the upper wall of axis 1 (g = +1 pulls into it) arriving at 0.1 and
  // leaving at g hop / 2 = 0.05: its normal impulse per unit mass is 0.15. Sticking (mu = inf,
  // beta = 1) reverses the contact point's tangential velocity; with mu = 0.1 the tangential
  // impulse per unit mass is capped at mu 0.15 against it.
  const Vec3d n{0, -1, 0}, v{0.7, 0.1, 0};
  const Vec3d w0{0.3, -0.4, 1.1};
  const Vec3d gt0 = tangential(v - 0.5 * cross(w0, n), n);
  Vec3d w = w0;
  const k::WallOutcome<double> stick =
      k::collide_wall<true>(k::WallLaw<double>{1.0, {1.0, kInf, 0.4}}, 1, 1, v, 1.0, 0.125, 0.1, &w, 2.0, 0.5, never);
  EXPECT_TRUE(stick.rested);
  EXPECT_DOUBLE_EQ(stick.leave, -0.05);
  expect_near(tangential(v + stick.dv - 0.5 * cross(w, n), n), -1.0 * gt0, 1e-15);
  w = w0;
  const k::WallOutcome<double> slide =
      k::collide_wall<true>(k::WallLaw<double>{1.0, {1.0, 0.1, 0.4}}, 1, 1, v, 1.0, 0.125, 0.1, &w, 2.0, 0.5, never);
  EXPECT_TRUE(slide.contact.sliding);
  EXPECT_NEAR(norm(slide.dv), 0.1 * 0.15, 1e-15);
  EXPECT_NEAR(dot(slide.dv, gt0), -norm(slide.dv) * norm(gt0), 1e-15);  // against the slip
}

TEST(WallLaw, RestitutionLeavesAtEwTimesTheNormalSpeedWithTheTcFallback) {
  // Onto the floor at -3 with e_w = 0.5 (m = 2): it leaves at 1.5, the wall takes 4.5 per unit
  // mass and the kinetic energy 1/2 m (1 - e_w^2) 9 = 6.75. Within the contact time of its last
  // collision (the TC rule), elastic: leaves at 3, nothing dissipated.
  const k::WallLaw<double> law{0.5, {}};
  k::WallOutcome<double> out =
      k::collide_wall<false>(law, 2, -1, Vec3d{1, 0, -3}, 0.0, 0.0, 0.0, nullptr, 2.0, 0.5, never);
  EXPECT_TRUE(out.restituted);
  EXPECT_EQ(out.leave, 1.5);
  EXPECT_EQ(out.impulse, 4.5);
  EXPECT_EQ(out.contact.dissipated_normal, 6.75);
  out = k::collide_wall<false>(law, 2, -1, Vec3d{1, 0, -3}, 0.0, 0.0, 0.0, nullptr, 2.0, 0.5, [] { return true; });
  EXPECT_FALSE(out.restituted);
  EXPECT_EQ(out.leave, 3.0);
  EXPECT_EQ(out.contact.dissipated_normal, 0.0);
  // A resting contact's net energy: arriving at 0.25, leaving at 0.5 (hop 0.5 under g = -2).
  out = k::collide_wall<false>(law, 2, -1, Vec3d{1, 0, -0.25}, -2.0, 0.125, 0.5, nullptr, 2.0, 0.5, never);
  EXPECT_TRUE(out.rested);
  EXPECT_DOUBLE_EQ(out.contact.dissipated_normal, 0.25 * 0.25 - 0.5 * 0.5);
}
