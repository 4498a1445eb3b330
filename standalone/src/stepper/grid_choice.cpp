#include "stepper/grid_choice.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

namespace hardsphere::detail {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double rms_speed(const ParticleSystem& sys) {
  double v2 = 0;
  for (const auto& v : sys.vel) v2 += dot(v, v);
  return sys.size() ? std::sqrt(v2 / double(sys.size())) : 0.0;
}

double median_diameter(const ParticleSystem& sys) {
  std::vector<double> radii(sys.radius);
  if (radii.empty()) return 0.0;
  const auto mid = radii.begin() + std::ptrdiff_t(radii.size() / 2);
  std::nth_element(radii.begin(), mid, radii.end());
  return 2 * *mid;
}

//! Whether big spheres can find their partners by minimum image: every periodic axis longer
//! than twice the farthest a big sphere's pairs and list-guard threats reach (sigma + 2 skins).
bool big_pass_fits(const ParticleSystem& sys, const SizeSplit& split, double skin) {
  const double partner = split.big.size() > 1 ? sys.radius[split.big[1]] : split.grid_diameter / 2;
  const double reach = sys.radius[split.big[0]] + partner + 2 * skin;
  for (int d = 0; d < 3; ++d)
    if (sys.box.periodic[d] && !(sys.box.length(d) > 2 * reach)) return false;
  return true;
}

double skin_of(const CellGrid& g, double diameter) {
  const double reach = g.reach();
  return std::isinf(reach) ? kInf : reach - diameter;
}

//! The grid a target skin gives: big spheres get a pass of their own when the grid sized
//! without them has a finite skin and the box is long enough for it; otherwise the grid is
//! sized by the largest sphere.
GridChoice grid_for_skin(const ParticleSystem& sys, const Box& box, const std::array<int, 3>& cells, bool automatic,
                         double target, const SizeSplit& split) {
  const auto grid = [&](double diameter) {
    return automatic ? CellGrid::with_min_width(box, diameter + target, std::int64_t(2 * sys.size() + 27))
                     : CellGrid(box, cells);
  };
  GridChoice c;
  if (!split.big.empty()) {
    const CellGrid g = grid(split.grid_diameter);
    const double skin = skin_of(g, split.grid_diameter);
    if (g.half_stencil_ok() && std::isfinite(skin) && skin > 0 && big_pass_fits(sys, split, skin)) {
      c.grid = g, c.diameter = split.grid_diameter, c.big_pass = true, c.skin = skin;
      return c;
    }
  }
  c.diameter = 2 * sys.max_radius();
  c.grid = grid(c.diameter);
  c.skin = skin_of(c.grid, c.diameter);
  return c;
}

//! The work of one step on a grid, in units of one sphere's drift: every sub-step (the fastest
//! sphere moves at most half the skin in each) drifts every sphere and scans the pair list; the
//! list is rebuilt about once each time the fastest sphere has crossed a skin, each build sorting
//! the spheres and testing the pairs of neighbouring cells (all pairs on a grid of a few cells).
//! Prefactors are rough: the model only has to tell a collapsed grid from a working one.
double step_work(const ParticleSystem& sys, const GridChoice& c, double v_max, double dt) {
  const double n = double(sys.size());
  if (!(c.skin > 0)) return kInf;
  const double all_pairs = 0.5 * n * n;
  if (std::isinf(c.skin)) return 2 * n + all_pairs;  // one list for good, scanned every step
  const double substeps = std::max(1.0, std::ceil(v_max * dt / (0.4995 * c.skin)));
  const double rebuilds = std::min(substeps, v_max * dt / c.skin);
  const double density = n / sys.box.volume();
  const double reach = c.diameter + c.skin;
  const double listed = std::min(all_pairs, 0.5 * n * density * 4.18879 * reach * reach * reach);
  const double cells = double(c.grid.size());
  const double tested = c.grid.half_stencil_ok() ? std::min(all_pairs, 13.5 * n * n / cells) : all_pairs;
  return substeps * (2 * n + listed) + rebuilds * (10 * n + tested);
}

}  // namespace

double auto_skin(const ParticleSystem& sys, double dt, double phi_gas) {
  // A thin skin means frequent rebuilds, a thick one longer scans and neighbour sweeps.
  // (1) A rebuild every ~4 steps at most for the fastest spheres (~2.5 rms speeds): skin >=
  // 20 v_rms dt; more frequent rebuilds also fall mid-step in dense gases. (2) The list costs
  // ~ phi s per step for a skin s and a rebuild ~ N (plus the pair build) every ~ s / (v dt)
  // steps, so the sum is least near s ~ sqrt(v dt d / phi): thicker skins pay in dilute gases.
  // The larger of the two, within [0.3, 0.6] diameters (prefactors fitted, see docs/dev/performance.md).
  // (3) With the pairwise list guard a list outlives the first sphere to cross half the skin,
  // so dense gases do better with thinner skins: the upper bound falls from 0.6 at phi 0.2 to
  // 0.4 at phi >= 0.3 (see docs/dev/performance.md).
  // (4) Long steps overrule (3): no sphere may move more than 0.85 skins between rebuilds, so a
  // skin below a few v_rms dt lets the fast spheres expire the list every step, and in the
  // middle of steps, at a multiple of the cost (see docs/dev/performance.md). skin >= 6 v_rms dt
  // gives a sphere at 3 v_rms about two steps to cross it.
  // The diameter is the median one: the skin is a distance a typical sphere travels between
  // rebuilds, so neither big spheres nor the tail of a size distribution may thicken it.
  const double v_rms = rms_speed(sys);
  const double diameter = median_diameter(sys);
  const double phi = std::max(phi_gas, 1e-3);
  const double skin = std::max(20.0 * v_rms * dt, 1.75 * std::sqrt(v_rms * dt * diameter / phi));
  const double thickest = std::clamp(0.6 - 2.0 * (phi - 0.2), 0.4, 0.6);
  return std::max(std::clamp(skin, 0.3 * diameter, thickest * diameter), 6.0 * v_rms * dt);
}

GridChoice choose_grid(const ParticleSystem& sys, const Box& box, const std::array<int, 3>& cells, double dt,
                       double phi_gas, const SizeSplit& split, const std::array<double, 3>& gravity) {
  const bool automatic = cells == std::array<int, 3>{0, 0, 0};
  const double tuned = automatic ? auto_skin(sys, dt, phi_gas) : 0.0;
  GridChoice best = grid_for_skin(sys, box, cells, automatic, tuned, split);
  if (!automatic || sys.size() < 2) return best;
  // The tuned skin stays unless a thinner one makes the step much cheaper: a single very fast
  // sphere, or big spheres in a box too short for their pass, can make it collapse the grid.
  double v_max =
      std::sqrt(dot(Vec3d{gravity[0], gravity[1], gravity[2]}, Vec3d{gravity[0], gravity[1], gravity[2]})) * dt;
  double v2 = 0;
  for (const auto& v : sys.vel) v2 = std::max(v2, dot(v, v));
  v_max += std::sqrt(v2);
  const double floor = 0.02 * median_diameter(sys);
  const double tuned_work = step_work(sys, best, v_max, dt);
  double best_work = tuned_work;
  for (double target = 0.5 * tuned; target >= floor; target *= 0.5) {
    const GridChoice c = grid_for_skin(sys, box, cells, true, target, split);
    const double work = step_work(sys, c, v_max, dt);
    if (work < best_work) best = c, best_work = work;
  }
  return best_work < 0.5 * tuned_work ? best : grid_for_skin(sys, box, cells, true, tuned, split);
}

std::string grid_refusal(const ParticleSystem& sys, const GridChoice& choice, bool auto_cells, const SizeSplit& split) {
  const CellGrid& grid = choice.grid;
  const double diameter = choice.diameter;
  // The box is the cause when no grid could do: the grid is automatic, or the axis that limits
  // the reach is a periodic one covered by one or two cells (half its length is all they reach).
  bool box_too_short = auto_cells;
  for (int d = 0; d < 3; ++d)
    if (sys.box.periodic[d] && grid.counts()[d] < 3 && !(0.5 * sys.box.length(d) > diameter)) box_too_short = true;
  std::ostringstream m;
  if (box_too_short) {
    int axis = -1;  // the shortest periodic axis
    for (int d = 0; d < 3; ++d)
      if (sys.box.periodic[d] && (axis < 0 || sys.box.length(d) < sys.box.length(axis))) axis = d;
    axis = std::max(axis, 0);
    m << "periodic box length " << sys.box.length(axis) << " (axis "
      << "xyz"[axis] << ") is too short for a sphere of diameter " << 2 * sys.max_radius()
      << ": a periodic axis must be longer than twice the largest diameter";
    if (!split.big.empty())
      m << ", or than twice the reach of a big sphere's pairs (its diameter plus its largest partner's and two list"
        << " skins)";
    m << "; lengthen that axis";
  } else {
    m << "cells " << grid.counts()[0] << "," << grid.counts()[1] << "," << grid.counts()[2] << " give a cell width of "
      << grid.reach() << ", not more than the largest diameter " << diameter << "; use fewer cells or --cells auto";
  }
  return m.str();
}

}  // namespace hardsphere::detail
