#include "event/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "hardsphere/errors.hpp"
#include "hardsphere/format.hpp"

namespace hardsphere::event {

EventGeometry::EventGeometry(const ParticleSystem& sys, const EventConfig& cfg, const SizeSplit& split) {
  if (cfg.reach < 1 || cfg.reach > 2)
    throw InputError("event engine: reach " + std::to_string(cfg.reach) + " must be 1 or 2");
  reach_ = cfg.reach;
  // The cells and the shell are sized by the spheres filed in cells; big ones are searched apart.
  grid_r_ = split.grid_diameter / 2;
  size_shell(sys, cfg, split);
  size_cells(sys, cfg, split);
}

void EventGeometry::size_shell(const ParticleSystem& sys, const EventConfig& cfg, const SizeSplit& split) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const std::size_t n = sys.size();
  const int min_cells = 2 * reach_ + 1;
  const double dmax = split.grid_diameter;
  // With big spheres, a periodic axis must be longer than twice every pair's range (the two
  // largest radii plus the shell), so that only one image of a pair is ever in range.
  double r1 = 0, r2 = 0;  // the largest radius and the next
  for (double r : sys.radius) r2 = std::max(r2, std::min(r, r1)), r1 = std::max(r1, r);
  const double pair_max = split.big.empty() ? 0.0 : r1 + r2;
  // The shell may not make the cells wider than a periodic axis (or a user grid) allows; the
  // cells themselves must be at least (largest diameter in cells) / reach wide, as before lists.
  double shell = (cfg.shell > 0 ? cfg.shell : auto_shell(sys.packing_fraction())) * dmax;
  for (std::size_t d = 0; d < 3; ++d) {
    const double l = sys.box.length(int(d));
    const std::string axis(1, char('x' + d));
    const double w = cfg.cells[d] > 0 ? l / cfg.cells[d] : (sys.box.periodic[d] ? l / min_cells : kInf);
    if (cfg.cells[d] > 0 && w < dmax / reach_ * (1 - 1e-12))
      throw InputError("event engine: " + std::to_string(cfg.cells[d]) + " cells on axis " + axis +
                       " are narrower than the largest diameter of the spheres filed in cells / reach " +
                       std::to_string(dmax / reach_));
    if (sys.box.periodic[d] && (l < min_cells * dmax / reach_ || (cfg.cells[d] > 0 && cfg.cells[d] < min_cells)))
      throw InputError(
          "event engine: periodic axis " + axis + " of length " + std::to_string(l) + " needs at least " +
          std::to_string(min_cells) + " cells of width >= the largest diameter / reach " +
          std::to_string(dmax / reach_) + " (spheres over " + format_number(kBigOverMedian) +
          " median diameters are searched apart and do not count; a sphere's partners are searched in the cells " +
          "around its own, which must be distinct periodic images); use --engine stepper, " +
          "which takes any periodic box longer than 2 largest diameters, or a box of at least " +
          std::to_string(min_cells * dmax / reach_));
    if (sys.box.periodic[d] && !(l > 2 * pair_max))
      throw InputError("event engine: periodic axis " + axis + " of length " + std::to_string(l) +
                       " must be longer than twice the contact distance of the two largest spheres, " +
                       std::to_string(2 * pair_max) + " (a pair may have only one periodic image in range)");
    shell = std::min(shell, w * reach_ - dmax);
    if (sys.box.periodic[d] && pair_max > 0) shell = std::min(shell, 0.5 * l * (1 - 1e-9) - pair_max);
  }
  if (n > 0 && !(shell > 1e-6 * dmax))
    throw InputError("event engine: no room for a neighbour-list shell: periodic axes need at least " +
                     std::to_string(min_cells) + " cells wider than the largest diameter / reach" +
                     (pair_max > 0 ? " and more than twice the two largest radii " + std::to_string(pair_max) : ""));
  shell_ = shell;
  // Strictly inside shell / 2: a margin for the round-off of positions (a few ulps of the largest
  // coordinate) and of the exit time, so two spheres can never both overshoot.
  double extent = 0;
  for (int d = 0; d < 3; ++d)
    extent = std::max({extent, std::abs(sys.box.lo[std::size_t(d)]), std::abs(sys.box.hi[std::size_t(d)])});
  exit_r_ = 0.5 * shell * (1 - 1e-9) - 64 * std::numeric_limits<double>::epsilon() * extent;
  if (n > 0 && !(exit_r_ > 0.25 * shell))
    throw InputError("event engine: neighbour-list shell " + std::to_string(shell) +
                     " too thin for coordinates up to " + std::to_string(extent));
}

void EventGeometry::size_cells(const ParticleSystem& sys, const EventConfig& cfg, const SizeSplit& split) {
  const std::size_t n = sys.size();
  const int min_cells = 2 * reach_ + 1;
  const double wmin = (split.grid_diameter + shell_) / reach_;
  double cells_total = 1;
  for (std::size_t d = 0; d < 3; ++d) {
    lo_[d] = sys.box.lo[d];
    len_[d] = sys.box.length(int(d));
    periodic_[d] = sys.box.periodic[d];
    int k = cfg.cells[d];
    if (k == 0) k = int(std::min(1e6, std::floor(len_[d] / std::max(wmin, 1e-300))));
    k = std::max(k, periodic_[d] ? min_cells : 1);
    nc_[d] = k;
    cells_total *= k;
  }
  if (cfg.cells == std::array<int, 3>{0, 0, 0}) {
    const double cap = std::max(double(min_cells * min_cells * min_cells),
                                cfg.max_cells_per_sphere * reach_ * reach_ * reach_ * double(n));
    if (cells_total > cap) {
      const double f = std::cbrt(cells_total / cap);
      for (std::size_t d = 0; d < 3; ++d) nc_[d] = std::max(periodic_[d] ? min_cells : 1, int(double(nc_[d]) / f));
    }
  }
  for (std::size_t d = 0; d < 3; ++d) width_[d] = len_[d] / nc_[d];
  for (int z = -1; z <= 1; ++z)
    for (int y = -1; y <= 1; ++y)
      for (int x = -1; x <= 1; ++x)
        image_shift_[std::size_t((x + 1) + 3 * (y + 1) + 9 * (z + 1))] = {x * len_[0], y * len_[1], z * len_[2]};
}

Vec3d EventGeometry::wrapped(Vec3d p) const {
  for (int d = 0; d < 3; ++d) {
    double& x = p[d];
    if (periodic_[std::size_t(d)]) {
      x -= len_[std::size_t(d)] * std::floor((x - lo_[std::size_t(d)]) / len_[std::size_t(d)]);
      if (x >= lo_[std::size_t(d)] + len_[std::size_t(d)]) x -= len_[std::size_t(d)];  // round-off at the top
    }
  }
  return p;
}

}  // namespace hardsphere::event
