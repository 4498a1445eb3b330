#include "init/fire_quench.hpp"

#include <algorithm>
#include <cmath>

#include "scene/cell_grid.hpp"

namespace hardsphere {

namespace {

// FIRE parameters (Bitzek et al. 2006), time in units of sqrt(mass / stiffness).
// Steps above kDtMax overshoot the stiffest cages and reset FIRE often.
constexpr double kDtStart = 0.1, kDtMax = 0.4, kDtMin = 0.002;
constexpr double kAlphaStart = 0.1, kAlphaShrink = 0.99, kDtGrow = 1.1, kDtShrink = 0.5;
constexpr int kPositiveStepsBeforeGrowth = 5;
// Pair-list skin in diameters: rebuilt once any sphere has moved half of it.
constexpr double kSkin = 0.3;
// Largest force (in radii: force is overlap) at which a state with overlaps counts as jammed.
constexpr double kJammedForce = 1e-10;

struct Pair {
  std::uint32_t i, j;
};
struct WrappedPair {
  std::uint32_t i, j;
  Vec3d shift;  // periodic image: the pair vector is x[i] - x[j] + shift
};

class Quench {
 public:
  Quench(const Box& box, std::vector<Vec3d> x, double radius, double eps)
      : box_(box),
        x_(std::move(x)),
        sigma_(2 * radius * (1 + eps)),
        r_(radius * (1 + eps)),
        pair_tol_(eps * radius),
        wall_tol_(0.5 * eps * radius),
        cutoff_(sigma_ + kSkin * 2 * radius) {
    v_.assign(x_.size(), Vec3d{});
    f_.assign(x_.size(), Vec3d{});
    build();
    compute_forces();
  }

  bool separated() const { return worst_pair_ <= pair_tol_ && worst_wall_ <= wall_tol_; }
  // At a minimum with overlaps left the forces balance: FIRE cannot go on from there.
  bool jammed() const { return !separated() && max_force_ <= kJammedForce * r_; }
  double energy() const { return energy_; }
  std::int64_t builds() const { return builds_; }
  double max_force() const { return max_force_; }

  // One FIRE step (FIRE 2.0 ordering: Guenole et al. 2020, semi-implicit Euler).
  void step() {
    double p = 0;
    for (std::size_t i = 0; i < x_.size(); ++i) p += dot(f_[i], v_[i]);
    if (p > 0) {
      if (++positive_ > kPositiveStepsBeforeGrowth) {
        dt_ = std::min(dt_ * kDtGrow, kDtMax);
        alpha_ *= kAlphaShrink;
      }
    } else {
      positive_ = 0;
      dt_ = std::max(dt_ * kDtShrink, kDtMin);
      alpha_ = kAlphaStart;
      for (std::size_t i = 0; i < x_.size(); ++i) {
        x_[i] -= (0.5 * dt_) * v_[i];
        v_[i] = {};
      }
    }
    double vv = 0, ff = 0;
    for (std::size_t i = 0; i < x_.size(); ++i) {
      v_[i] += dt_ * f_[i];
      vv += dot(v_[i], v_[i]);
      ff += dot(f_[i], f_[i]);
    }
    const double mix = ff > 0 ? alpha_ * std::sqrt(vv / ff) : 0.0;
    double moved = 0;
    for (std::size_t i = 0; i < x_.size(); ++i) {
      v_[i] = (1 - alpha_) * v_[i] + mix * f_[i];
      x_[i] += dt_ * v_[i];
      const Vec3d d = x_[i] - x_ref_[i];
      moved = std::max(moved, dot(d, d));
    }
    const double half_skin = 0.5 * (cutoff_ - sigma_);
    if (moved > half_skin * half_skin) build();
    compute_forces();
  }

  std::vector<Vec3d> positions() {
    wrap();
    return x_;
  }

 private:
  void wrap() {
    for (auto& p : x_)
      for (int d = 0; d < 3; ++d) {
        if (!box_.periodic[d]) continue;
        const double len = box_.length(d);
        p[d] -= len * std::floor((p[d] - box_.lo[d]) / len);
        if (p[d] >= box_.hi[d]) p[d] = box_.lo[d];
      }
  }

  // Every pair (and every periodic image of it) closer than the cutoff. The spheres are
  // renumbered in cell order first, so pairs touch nearby memory (they are interchangeable).
  void build() {
    ++builds_;
    wrap();
    const std::size_t n = x_.size();
    const CellGrid grid = CellGrid::with_min_width(box_, cutoff_, std::int64_t(2 * n + 27));
    grid.sort(
        n, [&](std::size_t i) { return x_[i]; }, cell_, start_, order_);
    x_ref_.resize(n);
    scratch_.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      x_ref_[k] = x_[order_[k]];
      scratch_[k] = v_[order_[k]];
    }
    x_ = x_ref_;
    v_.swap(scratch_);
    // Periodic axes of one or two cells: a pair can be within the cutoff through two images.
    std::array<bool, 3> short_axis{};
    for (int d = 0; d < 3; ++d) short_axis[d] = box_.periodic[d] && grid.counts()[d] < 3;
    const double c2 = cutoff_ * cutoff_;
    pairs_.clear();
    wrapped_.clear();
    for (std::int64_t c = 0; c < grid.size(); ++c) {
      grid.for_each_neighbour(int(c), [&](int nb) {
        if (nb < c) return;
        for (std::uint32_t i = start_[c]; i < start_[c + 1]; ++i)
          for (std::uint32_t j = (nb == c ? i + 1 : start_[nb]); j < start_[nb + 1]; ++j) {
            const Vec3d dr = x_[i] - x_[j];
            Vec3d s{}, alt{};
            int alts = 0;
            for (int d = 0; d < 3; ++d) {
              if (!box_.periodic[d]) continue;
              const double len = box_.length(d);
              s[d] = -len * std::nearbyint(dr[d] / len);
              if (short_axis[d]) {
                alt[d] = dr[d] + s[d] >= 0 ? s[d] - len : s[d] + len;
                alts |= 1 << d;
              }
            }
            for (int m = 0; m < 8; ++m) {
              if ((m & alts) != m) continue;
              Vec3d t = s;
              for (int d = 0; d < 3; ++d)
                if (m >> d & 1) t[d] = alt[d];
              const Vec3d e = dr + t;
              if (dot(e, e) >= c2) continue;
              if (t.x == 0 && t.y == 0 && t.z == 0)
                pairs_.push_back({i, j});
              else
                wrapped_.push_back({i, j, t});
            }
          }
      });
    }
  }

  void compute_forces() {
    std::fill(f_.begin(), f_.end(), Vec3d{});
    double e = 0, worst_pair = 0, worst_wall = 0;
    const double s2 = sigma_ * sigma_;
    auto pair_force = [&](std::uint32_t i, std::uint32_t j, const Vec3d& dr) {
      const double d2 = dot(dr, dr);
      if (d2 >= s2) return;
      const double d = std::sqrt(d2), ov = sigma_ - d;
      e += 0.5 * ov * ov;
      worst_pair = std::max(worst_pair, ov);
      // Coincident centres have no direction between them: take one, so they cannot stall.
      const Vec3d push = d > 0 ? (ov / d) * dr : Vec3d{ov, 0, 0};
      f_[i] += push;
      f_[j] -= push;
    };
    for (const Pair& p : pairs_) pair_force(p.i, p.j, x_[p.i] - x_[p.j]);
    for (const WrappedPair& p : wrapped_) pair_force(p.i, p.j, x_[p.i] - x_[p.j] + p.shift);
    for (int d = 0; d < 3; ++d) {
      if (box_.periodic[d]) continue;
      const double lo = box_.lo[d] + r_, hi = box_.hi[d] - r_;
      for (std::size_t i = 0; i < x_.size(); ++i) {
        const double below = lo - x_[i][d], above = x_[i][d] - hi;
        if (below > 0) {
          e += 0.5 * below * below;
          f_[i][d] += below;
          worst_wall = std::max(worst_wall, below);
        }
        if (above > 0) {
          e += 0.5 * above * above;
          f_[i][d] -= above;
          worst_wall = std::max(worst_wall, above);
        }
      }
    }
    double fmax = 0;
    for (const auto& f : f_) fmax = std::max(fmax, dot(f, f));
    max_force_ = std::sqrt(fmax);
    energy_ = e;
    worst_pair_ = worst_pair;
    worst_wall_ = worst_wall;
  }

  Box box_;
  std::vector<Vec3d> x_, v_, f_, x_ref_, scratch_;
  double sigma_, r_, pair_tol_, wall_tol_, cutoff_;
  // Pairs inside the box need no image shift: listed apart, they take a quarter of the memory.
  std::vector<Pair> pairs_;
  std::vector<WrappedPair> wrapped_;
  std::vector<int> cell_;
  std::vector<std::uint32_t> start_, order_;
  double dt_ = kDtStart, alpha_ = kAlphaStart;
  int positive_ = 0;
  double energy_ = 0, worst_pair_ = 0, worst_wall_ = 0, max_force_ = 0;
  std::int64_t builds_ = 0;
};

}  // namespace

bool separate_spheres(const Box& box, std::vector<Vec3d>& x, double radius, const QuenchConfig& cfg,
                      QuenchStats* stats) {
  Quench q(box, std::move(x), radius, cfg.inflation);
  std::int64_t it = 0;
  for (; it < cfg.max_iterations && !q.separated() && !q.jammed(); ++it) q.step();
  if (stats) {
    stats->iterations += it;
    stats->list_builds += q.builds();
    stats->energy = q.energy();
    stats->jammed = q.jammed();
  }
  x = q.positions();
  return q.separated();
}

}  // namespace hardsphere
