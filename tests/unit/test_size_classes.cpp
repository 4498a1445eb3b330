#include <gtest/gtest.h>

#include "scene/size_classes.hpp"

using namespace hardsphere;

namespace {
ParticleSystem with_diameters(const std::vector<double>& d) {
  ParticleSystem s;
  s.box = Box::from_lengths({100, 100, 100}, {true, true, true});
  for (std::size_t i = 0; i < d.size(); ++i) s.push_back(std::int64_t(i + 1), 1, 0.5 * d[i], 1, {}, {});
  return s;
}
}  // namespace

TEST(SizeSplit, OneBigSphereLeavesTheGridToTheSmallOnes) {
  std::vector<double> d(1000, 1.0);
  d[17] = 20;
  const auto split = split_by_size(with_diameters(d));
  ASSERT_EQ(split.big.size(), 1u);
  EXPECT_EQ(split.big[0], 17u);
  EXPECT_EQ(split.grid_diameter, 1.0);
}

TEST(SizeSplit, NarrowPolydispersityHasNoBigSpheres) {
  std::vector<double> d;
  for (int i = 0; i < 1000; ++i) d.push_back(0.5 + i / 999.0);  // uniform in [0.5, 1.5]
  const auto split = split_by_size(with_diameters(d));
  EXPECT_TRUE(split.big.empty());
  EXPECT_EQ(split.grid_diameter, 1.5);
}

TEST(SizeSplit, AtMostTheLargestFewAreBigAndEqualSizesStayTogether) {
  std::vector<double> d(100000, 1.0);
  for (std::size_t i = 0; i < 300; ++i) d[i] = 3.0 + double(i) / 300;  // 300 distinct big sizes
  auto split = split_by_size(with_diameters(d));
  ASSERT_EQ(split.big.size(), kMaxBigSpheres);
  EXPECT_EQ(split.big[0], 299u);  // largest first
  EXPECT_DOUBLE_EQ(split.grid_diameter, 3.0 + double(300 - kMaxBigSpheres - 1) / 300);
  for (std::size_t i = 0; i < 300; ++i) d[i] = 4.0;  // 300 of one size: too many to be big
  split = split_by_size(with_diameters(d));
  EXPECT_TRUE(split.big.empty());
  EXPECT_EQ(split.grid_diameter, 4.0);
}
