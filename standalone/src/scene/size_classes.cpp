#include "scene/size_classes.hpp"

#include <algorithm>
#include <numeric>

namespace hardsphere {

SizeSplit split_by_size(const ParticleSystem& sys) {
  SizeSplit out;
  const std::size_t n = sys.size();
  if (n == 0) return out;
  // Nothing is big when no diameter exceeds kBigOverMedian smallest ones: skip the sort.
  const auto [lo, hi] = std::minmax_element(sys.radius.begin(), sys.radius.end());
  if (*hi <= kBigOverMedian * *lo) {
    out.grid_diameter = 2 * *hi;
    return out;
  }
  std::vector<std::uint32_t> idx(n);
  std::iota(idx.begin(), idx.end(), 0u);
  // Largest first; ties by index so the split does not depend on the sort's stability.
  std::sort(idx.begin(), idx.end(), [&](std::uint32_t a, std::uint32_t b) {
    return sys.radius[a] != sys.radius[b] ? sys.radius[a] > sys.radius[b] : a < b;
  });
  const double median = 2 * sys.radius[idx[n / 2]];
  std::size_t k = 0;
  while (k < n && k < kMaxBigSpheres && 2 * sys.radius[idx[k]] > kBigOverMedian * median) ++k;
  // Spheres of the same size as the last big one stay big together, or the grid would be
  // sized for one of them anyway.
  while (k > 0 && k < n && sys.radius[idx[k]] == sys.radius[idx[k - 1]]) --k;
  out.big.assign(idx.begin(), idx.begin() + std::ptrdiff_t(k));
  out.grid_diameter = 2 * sys.radius[idx[k < n ? k : n - 1]];
  return out;
}

}  // namespace hardsphere
