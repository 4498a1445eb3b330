// Analytic two-body cases for the kernel, in both argument orders where order matters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "hardsphere/collision.hpp"

using hardsphere::Vec3d;
namespace k = hardsphere::kernel;

TEST(ContactTime, HeadOnApproachIsExact) {
  // Centres 3 apart, closing at speed 2, contact distance 1: touch after exactly 1.
  const Vec3d dr{3, 0, 0}, dv{-2, 0, 0};
  EXPECT_NEAR(k::contact_time(dr, dv, 1.0), 1.0, 1e-15);
  EXPECT_NEAR(k::contact_time(-dr, -dv, 1.0), 1.0, 1e-15);  // swapped order
}

TEST(ContactTime, RecedingOrMissingPairsNeverTouch) {
  EXPECT_TRUE(std::isinf(k::contact_time(Vec3d{3, 0, 0}, Vec3d{1, 0, 0}, 1.0)));
  EXPECT_TRUE(std::isinf(k::contact_time(Vec3d{3, 2, 0}, Vec3d{-1, 0, 0}, 1.0)));  // impact parameter 2 > 1
  EXPECT_TRUE(std::isinf(k::contact_time(Vec3d{3, 0, 0}, Vec3d{0, 0, 0}, 1.0)));   // no relative motion
}

TEST(ContactTime, OffCentreMatchesGeometry) {
  // Impact parameter b = 0.6, contact distance 1: path to contact is x0 - sqrt(1 - b^2) = 5 - 0.8.
  const double t = k::contact_time(Vec3d{5, 0.6, 0}, Vec3d{-0.5, 0, 0}, 1.0);
  EXPECT_NEAR(t, (5 - 0.8) / 0.5, 1e-12 * 8.4);
}

TEST(RewindTime, ExactForOverlappingApproachingPair) {
  // Pair touched 0.25 ago moving at relative speed 2 head on: now 0.5 deep.
  const Vec3d dr{0.5, 0, 0}, dv{-2, 0, 0};
  EXPECT_NEAR(k::rewind_time(dr, dv, 1.0), 0.25, 1e-15);
  EXPECT_NEAR(k::rewind_time(-dr, -dv, 1.0), 0.25, 1e-15);
}

TEST(RewindTime, StableForTinyOverlapAndTinyVelocity) {
  // Inputs exactly representable, so any error is the formula's. Depth 2^-20 at speed 1e3:
  // the naive root (b + sqrt(b^2 - ac)) / a cancels; the stable form keeps 1e-12 relative.
  const double depth = std::ldexp(1.0, -20), speed = 1e3;
  EXPECT_NEAR(k::rewind_time(Vec3d{1 - depth, 0, 0}, Vec3d{-speed, 0, 0}, 1.0), depth / speed, 1e-12 * depth / speed);
  // Relative speed 1e-12 from 0.25 deep: the contact was 0.25e12 ago.
  EXPECT_NEAR(k::rewind_time(Vec3d{0.75, 0, 0}, Vec3d{-1e-12, 0, 0}, 1.0), 0.25e12, 1e-12 * 0.25e12);
  EXPECT_NEAR(k::rewind_time(Vec3d{0, 0.75, 0}, Vec3d{0, -1e6, 0}, 1.0), 0.25e-6, 1e-12 * 0.25e-6);
}

TEST(RewindTime, GrazingRecedingPairFindsItsEntry) {
  // Moving along x with impact parameter 0.8: overlap while |x| < 0.6. Now at x = +0.3 (receding),
  // it entered at x = -0.6, i.e. 0.9 / speed ago.
  const double speed = 3;
  EXPECT_NEAR(k::rewind_time(Vec3d{0.3, 0.8, 0}, Vec3d{speed, 0, 0}, 1.0), 0.9 / speed, 1e-15);
}

TEST(TouchedBackTime, ApproachingOverlapGivesItsEntry) {
  // 0.1 deep, closing at speed 1: entered contact 0.1 ago, whether or not the window reaches back
  // that far (it overlapped while approaching inside it; callers clamp to the window).
  const Vec3d dr{0.9, 0, 0}, dv{-1, 0, 0};
  for (const bool overlap_only : {false, true}) {
    EXPECT_NEAR(k::touched_back_time(dr, dv, 1.0, 0.2, overlap_only), 0.1, 1e-15);
    EXPECT_NEAR(k::touched_back_time(dr, dv, 1.0, 0.05, overlap_only), 0.1, 1e-15);
    EXPECT_NEAR(k::touched_back_time(-dr, -dv, 1.0, 0.2, overlap_only), 0.1, 1e-15);
  }
}

TEST(TouchedBackTime, PassThroughWithinTheWindowIsFoundBySweepsOnly) {
  // Now 1.5 apart and receding at 10: 0.25 ago the pair entered contact head-on and crossed.
  const Vec3d dr{1.5, 0, 0}, dv{10, 0, 0};
  EXPECT_NEAR(k::touched_back_time(dr, dv, 1.0, 0.3, false), 0.25, 1e-15);
  EXPECT_LT(k::touched_back_time(dr, dv, 1.0, 0.3, true), 0.0);   // no overlap now: the seed misses it
  EXPECT_LT(k::touched_back_time(dr, dv, 1.0, 0.1, false), 0.0);  // approach ended 0.15 ago
}

TEST(TouchedBackTime, MissesAndRecedersAreNotContacts) {
  EXPECT_LT(k::touched_back_time(Vec3d{0, 2, 0}, Vec3d{1, 0, 0}, 1.0, 0.5, false), 0.0);     // passes 2 apart
  EXPECT_LT(k::touched_back_time(Vec3d{1.5, 0, 0}, Vec3d{-1, 0, 0}, 1.0, 0.5, false), 0.0);  // approaching, apart
  EXPECT_LT(k::touched_back_time(Vec3d{0.9, 0, 0}, Vec3d{0, 0, 0}, 1.0, 0.5, false), 0.0);   // resting overlap
}

TEST(TouchedBackTime, AgreesWithRewindTimeWheneverTouched) {
  // Random pairs around contact: whenever it reports a contact, the time is rewind_time's.
  std::uint64_t state = 88172645463325252ull;
  auto uniform = [&] {  // xorshift64, in [-1, 1)
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    return double(state >> 11) * 0x1.0p-52 - 1.0;
  };
  int touched = 0;
  for (int n = 0; n < 20000; ++n) {
    const Vec3d dr{1.2 * uniform(), 1.2 * uniform(), 1.2 * uniform()}, dv{3 * uniform(), 3 * uniform(), 3 * uniform()};
    const double t = k::touched_back_time(dr, dv, 1.0, 0.1, false);
    if (t < 0) continue;
    ++touched;
    const double expect = k::rewind_time(dr, dv, 1.0);
    ASSERT_NEAR(t, expect, 1e-12 * std::max(1.0, expect));
    // At the rewound time the pair is in contact and approaching.
    const Vec3d at = dr - t * dv;
    EXPECT_NEAR(std::sqrt(hardsphere::dot(at, at)), 1.0, 1e-9);
    EXPECT_LT(hardsphere::dot(at, dv), 0.0);
  }
  EXPECT_GT(touched, 1000);
}

TEST(Impulse, HeadOnEqualMassesSwapVelocities) {
  Vec3d v1{1, 0, 0}, v2{-0.5, 0, 0};
  k::collide(Vec3d{-1, 0, 0}, v1, v2, 1.0, 1.0);  // particle 1 on the left
  EXPECT_DOUBLE_EQ(v1.x, -0.5);
  EXPECT_DOUBLE_EQ(v2.x, 1.0);
  Vec3d w1{1, 0, 0}, w2{-0.5, 0, 0};
  k::collide_equal_mass(Vec3d{-1, 0, 0}, w1, w2);
  EXPECT_DOUBLE_EQ(w1.x, -0.5);
  EXPECT_DOUBLE_EQ(w2.x, 1.0);
}

TEST(Impulse, UnequalMassesFollowOneDimensionalFormulas) {
  const double m1 = 3, m2 = 1, u1 = 2, u2 = -1;
  Vec3d v1{u1, 0, 0}, v2{u2, 0, 0};
  k::collide(Vec3d{-1, 0, 0}, v1, v2, m1, m2);
  EXPECT_NEAR(v1.x, (u1 * (m1 - m2) + 2 * m2 * u2) / (m1 + m2), 1e-15);
  EXPECT_NEAR(v2.x, (u2 * (m2 - m1) + 2 * m1 * u1) / (m1 + m2), 1e-15);
  // Swapped roles give the mirrored result.
  Vec3d w2{u2, 0, 0}, w1{u1, 0, 0};
  k::collide(Vec3d{1, 0, 0}, w2, w1, m2, m1);
  EXPECT_NEAR(w1.x, v1.x, 1e-15);
  EXPECT_NEAR(w2.x, v2.x, 1e-15);
}

TEST(Impulse, ObliqueImpactKeepsTangentialComponents) {
  const Vec3d n{1 / std::sqrt(2.0), 1 / std::sqrt(2.0), 0};
  Vec3d v1{-1, 0.3, 0.7}, v2{0.2, -0.4, 0.1};
  const Vec3d dr = -1.0 * n;  // 1 sits at -n from 2
  const Vec3d t1 = v1 - dot(v1, n) * n, t2 = v2 - dot(v2, n) * n;
  const double m1 = 2, m2 = 0.5;
  const Vec3d p0 = m1 * v1 + m2 * v2;
  const double e0 = 0.5 * (m1 * dot(v1, v1) + m2 * dot(v2, v2));
  k::collide(dr, v1, v2, m1, m2);
  const Vec3d t1b = v1 - dot(v1, n) * n, t2b = v2 - dot(v2, n) * n;
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(t1b[d], t1[d], 1e-15);
    EXPECT_NEAR(t2b[d], t2[d], 1e-15);
    EXPECT_NEAR((m1 * v1 + m2 * v2)[d], p0[d], 1e-15);
  }
  EXPECT_NEAR(0.5 * (m1 * dot(v1, v1) + m2 * dot(v2, v2)), e0, 1e-14);
}

TEST(Impulse, RecedingOrCoincidentPairsAreLeftAlone) {
  Vec3d v1{-1, 0, 0}, v2{1, 0, 0};
  EXPECT_EQ(k::collide(Vec3d{-1, 0, 0}, v1, v2, 1.0, 1.0), 0.0);
  EXPECT_EQ(v1.x, -1.0);
  Vec3d w1{1, 0, 0}, w2{0, 0, 0};
  EXPECT_EQ(k::collide(Vec3d{0, 0, 0}, w1, w2, 1.0, 1.0), 0.0);  // no normal: no NaN, no change
  EXPECT_EQ(w1.x, 1.0);
  EXPECT_EQ(k::collide_equal_mass(Vec3d{0, 0, 0}, w1, w2), 0.0);
}

TEST(Walls, MirrorIsARewoundBounce) {
  double x = 0.3, v = -2;  // radius 0.5, wall at 0: contact at x = 0.5, 0.1 ago
  EXPECT_DOUBLE_EQ(k::reflect_from_walls(x, v, 0.0, 10.0, 0.5), 4.0);
  EXPECT_DOUBLE_EQ(x, 0.7);
  EXPECT_DOUBLE_EQ(v, 2.0);
  double y = 9.8, w = 1;
  k::reflect_from_walls(y, w, 0.0, 10.0, 0.5);
  EXPECT_DOUBLE_EQ(y, 9.2);
  EXPECT_DOUBLE_EQ(w, -1.0);
  double z = 0.3, u = 1;  // inside the wall's reach but already leaving: untouched
  EXPECT_EQ(k::reflect_from_walls(z, u, 0.0, 10.0, 0.5), 0.0);
}
