#include "hardsphere/stepper.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <vector>

#include "hardsphere/cell_grid.hpp"
#include "hardsphere/collision.hpp"
#include "hardsphere/errors.hpp"

namespace hardsphere {

Precision parse_precision(const std::string& s) {
  if (s == "double") return Precision::Double;
  if (s == "float") return Precision::Float;
  throw InputError("unknown precision '" + s + "' (expected double or float)");
}

Detect parse_detect(const std::string& s) {
  if (s == "overlap") return Detect::Overlap;
  if (s == "sweep") return Detect::Sweep;
  throw InputError("unknown detection mode '" + s + "' (expected overlap or sweep)");
}

double auto_skin(const ParticleSystem& sys, double dt) {
  // Rebuilding costs about as much as ten list scans, so aim for a rebuild every ~10 steps
  // for the fastest spheres (about 4 rms speeds in a Maxwellian gas of 1e5), within
  // [0.1, 1] largest diameters so neither the list nor the rebuild rate explodes.
  double v2 = 0;
  for (const auto& v : sys.vel) v2 += dot(v, v);
  const double v_rms = sys.size() ? std::sqrt(v2 / double(sys.size())) : 0.0;
  const double diameter = 2 * sys.max_radius();
  const double skin = 2.0 * 10.0 * 2.5 * v_rms * dt;
  return std::clamp(skin, 0.1 * diameter, 0.6 * diameter);
}

namespace {

template <class Real>
using V3 = Vec3<Real>;

template <class Real>
class Stepper final : public StepperBase {
 public:
  Stepper(const ParticleSystem& sys, const StepperConfig& cfg);

  void run(std::int64_t steps) override {
    // Scene features select a specialised kernel once per run, not per pair.
    const int key = (all_periodic_ ? 4 : 0) + (mono_ ? 2 : 0) + (sweep_ ? 1 : 0);
    switch (key) {
      case 0: run_impl<false, false, false>(steps); break;
      case 1: run_impl<false, false, true>(steps); break;
      case 2: run_impl<false, true, false>(steps); break;
      case 3: run_impl<false, true, true>(steps); break;
      case 4: run_impl<true, false, false>(steps); break;
      case 5: run_impl<true, false, true>(steps); break;
      case 6: run_impl<true, true, false>(steps); break;
      default: run_impl<true, true, true>(steps); break;
    }
  }
  ParticleSystem state() const override;
  const StepCounters& counters() const override { return counters_; }
  void reset_counters() override { counters_ = StepCounters{}; }
  std::array<int, 3> cells_per_dim() const override { return grid_.counts(); }
  double skin() const override { return double(skin_); }
  std::string scene_kernel() const override {
    return std::string(all_periodic_ ? "periodic" : "walls") + (mono_ ? ",mono" : ",poly") +
           (sizeof(Real) == sizeof(float) ? ",float" : ",double") + (sweep_ ? ",sweep" : ",overlap");
  }

 private:
  struct Candidate {
    std::uint32_t i, j;  // i < j (cell order)
    std::uint8_t image;
    Real back;  // time back from the end of the step to the contact
    std::uint32_t count_i, count_j;  // velocity-change counters when predicted (lazy invalidation)
  };

  template <bool AllPeriodic, bool Mono, bool Sweep>
  void run_impl(std::int64_t steps) {
    for (std::int64_t s = 0; s < steps; ++s) step<AllPeriodic, Mono, Sweep>();
  }
  template <bool AllPeriodic, bool Mono, bool Sweep> void step();
  template <bool AllPeriodic> void drift();
  template <bool Mono, bool Sweep> void scan_pair_list();
  template <bool Mono> void sweep_neighbours(std::uint32_t i);
  template <bool Mono> void expand_candidates();
  template <bool AllPeriodic, bool Mono> bool resolve_one(const Candidate& c);
  template <bool AllPeriodic, bool Mono> void resolve_in_time_order();
  //! Heap order: the earliest contact (largest back time) on top; ties by atom ids.
  bool later(const Candidate& a, const Candidate& b) const {
    if (a.back != b.back) return a.back < b.back;
    return std::minmax(id_[a.i], id_[a.j]) > std::minmax(id_[b.i], id_[b.j]);
  }
  void rebuild();
  void reflect(std::uint32_t i);
  void note_displacement(std::uint32_t i) {
    const Real dx = x_[i] - x0_[i], dy = y_[i] - y0_[i], dz = z_[i] - z0_[i];
    max_disp2_ = std::max(max_disp2_, dx * dx + dy * dy + dz * dz);
  }
  void mark_changed(std::uint32_t i, Real back) {
    change_stamp_[i] = step_no_;
    change_back_[i] = back;
    ++change_count_[i];
  }
  //! Each sphere moved in a straight line for the last window(i) of this step: all of it, or
  //! the time since its last collision or wall bounce.
  Real window(std::uint32_t i) const { return change_stamp_[i] == step_no_ ? change_back_[i] : dt_; }
  //! Adds (i, j) if the pair touched while approaching within its common straight-line window;
  //! it is rewound to its entry into contact, or to the window's start if overlapping then.
  void consider(std::uint32_t i, std::uint32_t j, std::uint8_t image, V3<Real> dr, Real sigma, bool overlap_only) {
    const V3<Real> dv{vx_[i] - vx_[j], vy_[i] - vy_[j], vz_[i] - vz_[j]};
    const Real w = std::min(window(i), window(j));
    if (kernel::touched_within(dr, dv, sigma, w, overlap_only))
      candidates_.push_back({i, j, image, std::min(kernel::rewind_time(dr, dv, sigma), w), change_count_[i], change_count_[j]});
  }
  bool list_expired() const { return Real(4) * max_disp2_ >= skin_ * skin_; }
  Real contact_distance(std::uint32_t i, std::uint32_t j) const { return r_[i] + r_[j]; }
  static std::uint8_t image_code(int kx, int ky, int kz) { return std::uint8_t((kx + 1) * 9 + (ky + 1) * 3 + (kz + 1)); }

  Box box_;
  CellGrid grid_;
  bool all_periodic_, mono_, sweep_;
  Real dt_, skin_, max_disp2_ = 0;
  Real sigma_ = 0, mass_ = 0;  // monodisperse constants
  std::int64_t max_events_;
  std::array<Real, 3> length_{};
  Real image_shift_[27][3];

  // Structure of arrays in cell order.
  std::vector<Real> x_, y_, z_, vx_, vy_, vz_, x0_, y0_, z0_, r_, m_;
  std::vector<std::int64_t> id_;
  std::vector<int> type_, cell_;
  std::vector<std::uint32_t> cell_start_, order_;
  // Candidate pairs within r_i + r_j + skin at the last rebuild, with their periodic image.
  std::vector<std::uint32_t> pair_i_, pair_j_;
  std::vector<std::uint8_t> pair_image_;
  // For each sphere, the indices of the list pairs it belongs to (CSR), for local sweeps.
  std::vector<std::uint32_t> adj_start_, adj_pair_;
  std::vector<Candidate> candidates_, heap_;
  // When each sphere last changed velocity (step number, time back from the step's end), how
  // often, and in which expansion its neighbours were last swept.
  std::uint64_t step_no_ = 1, sweep_no_ = 1;
  std::vector<std::uint64_t> change_stamp_, swept_stamp_;
  std::vector<std::uint32_t> change_count_;
  std::vector<Real> change_back_;
  StepCounters counters_;
};

template <class Real>
Stepper<Real>::Stepper(const ParticleSystem& sys, const StepperConfig& cfg)
    : box_(sys.box), all_periodic_(sys.box.all_periodic()), mono_(sys.monodisperse()),
      sweep_(cfg.detect == Detect::Sweep), dt_(Real(cfg.dt)),
      max_events_(cfg.max_events_per_step) {
  if (!(std::isfinite(cfg.dt) && cfg.dt > 0)) {
    std::ostringstream m;
    m << "time step dt = " << cfg.dt << " must be positive and finite";
    throw InputError(m.str());
  }
  if (cfg.max_events_per_step < 1) throw InputError("max events per step must be >= 1");
  const std::size_t n = sys.size();
  if (n >= std::numeric_limits<std::uint32_t>::max() / 2) throw InputError("too many particles for one engine");
  const double diameter = 2 * sys.max_radius();

  bool auto_cells = cfg.cells[0] == 0 && cfg.cells[1] == 0 && cfg.cells[2] == 0;
  if (auto_cells) {
    const double skin = auto_skin(sys, cfg.dt);
    grid_ = CellGrid::with_min_width(box_, diameter + skin, std::int64_t(2 * n + 27));
  } else {
    for (int d = 0; d < 3; ++d)
      if (cfg.cells[d] < 1) throw InputError("cells per axis must be >= 1, got " + std::to_string(cfg.cells[d]));
    grid_ = CellGrid(box_, cfg.cells);
  }
  const double reach = grid_.reach();
  const double skin = std::isinf(reach) ? std::numeric_limits<double>::infinity() : reach - diameter;
  if (!(skin > 0)) {
    std::ostringstream m;
    m << "cells " << grid_.counts()[0] << "," << grid_.counts()[1] << "," << grid_.counts()[2]
      << " give a cell width of " << reach << ", not more than the largest diameter " << diameter
      << "; use fewer cells or --cells auto";
    throw InputError(m.str());
  }
  skin_ = Real(skin);
  for (int d = 0; d < 3; ++d) length_[d] = Real(box_.length(d));
  for (int kx = -1; kx <= 1; ++kx)
    for (int ky = -1; ky <= 1; ++ky)
      for (int kz = -1; kz <= 1; ++kz) {
        auto* s = image_shift_[image_code(kx, ky, kz)];
        s[0] = Real(kx) * length_[0];
        s[1] = Real(ky) * length_[1];
        s[2] = Real(kz) * length_[2];
      }

  auto fill = [n](std::vector<Real>& a) { a.resize(n); };
  for (auto* a : {&x_, &y_, &z_, &vx_, &vy_, &vz_, &x0_, &y0_, &z0_, &r_, &m_}) fill(*a);
  id_ = sys.id;
  type_ = sys.type;
  for (std::size_t i = 0; i < n; ++i) {
    x_[i] = Real(sys.pos[i].x);
    y_[i] = Real(sys.pos[i].y);
    z_[i] = Real(sys.pos[i].z);
    vx_[i] = Real(sys.vel[i].x);
    vy_[i] = Real(sys.vel[i].y);
    vz_[i] = Real(sys.vel[i].z);
    r_[i] = Real(sys.radius[i]);
    m_[i] = Real(sys.mass[i]);
  }
  if (n) {
    sigma_ = Real(2) * r_[0];
    mass_ = m_[0];
  }
  change_count_.assign(n, 0);
  change_stamp_.assign(n, 0);
  swept_stamp_.assign(n, 0);
  change_back_.assign(n, Real(0));
  rebuild();
  counters_.rebuilds = 0;
}

template <class Real>
void Stepper<Real>::rebuild() {
  const std::size_t n = x_.size();
  for (int d = 0; d < 3; ++d) {
    if (!box_.periodic[d]) continue;
    auto& a = d == 0 ? x_ : (d == 1 ? y_ : z_);
    const Real lo = Real(box_.lo[d]), len = length_[d];
    for (auto& v : a) {
      v -= len * std::floor((v - lo) / len);
      if (v >= lo + len) v -= len;  // floor rounding at the top edge
    }
  }
  grid_.sort(x_.data(), y_.data(), z_.data(), n, cell_, cell_start_, order_);
  auto permute = [&](auto& a) {
    auto tmp = a;
    for (std::size_t k = 0; k < n; ++k) tmp[k] = a[order_[k]];
    a.swap(tmp);
  };
  for (auto* a : {&x_, &y_, &z_, &vx_, &vy_, &vz_, &r_, &m_, &change_back_}) permute(*a);
  permute(change_stamp_);
  permute(change_count_);
  std::fill(swept_stamp_.begin(), swept_stamp_.end(), 0);
  permute(id_);
  permute(type_);
  permute(cell_);
  x0_ = x_;
  y0_ = y_;
  z0_ = z_;
  max_disp2_ = 0;

  // Candidate list: every pair that could touch before the next rebuild.
  pair_i_.clear();
  pair_j_.clear();
  pair_image_.clear();
  const Real skin = std::isinf(skin_) ? std::numeric_limits<Real>::max() / 4 : skin_;
  const std::int64_t ncell = grid_.size();
  for (std::int64_t c = 0; c < ncell; ++c) {
    const std::uint32_t b0 = cell_start_[c], b1 = cell_start_[c + 1];
    if (b0 == b1) continue;
    grid_.for_each_neighbour(int(c), [&](int nb) {
      if (nb < c) return;  // each unordered cell pair once
      const std::uint32_t e1 = cell_start_[nb + 1];
      for (std::uint32_t i = b0; i < b1; ++i) {
        for (std::uint32_t j = (nb == c ? i + 1 : cell_start_[nb]); j < e1; ++j) {
          Real d[3] = {x_[i] - x_[j], y_[i] - y_[j], z_[i] - z_[j]};
          int k[3] = {0, 0, 0};
          for (int a = 0; a < 3; ++a)
            if (box_.periodic[a]) {
              k[a] = int(std::nearbyint(d[a] / length_[a]));
              d[a] -= Real(k[a]) * length_[a];
            }
          const Real cut = r_[i] + r_[j] + skin;
          if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cut * cut) {
            pair_i_.push_back(i);
            pair_j_.push_back(j);
            pair_image_.push_back(image_code(k[0], k[1], k[2]));
          }
        }
      }
    });
  }
  // Adjacency (both directions) for sweeping one sphere's neighbours.
  adj_start_.assign(n + 1, 0);
  for (std::size_t p = 0; p < pair_i_.size(); ++p) {
    ++adj_start_[pair_i_[p] + 1];
    ++adj_start_[pair_j_[p] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) adj_start_[i + 1] += adj_start_[i];
  adj_pair_.resize(2 * pair_i_.size());
  order_.assign(adj_start_.begin(), adj_start_.end() - 1);  // reuse as fill cursors
  for (std::size_t p = 0; p < pair_i_.size(); ++p) {
    adj_pair_[order_[pair_i_[p]]++] = std::uint32_t(p);
    adj_pair_[order_[pair_j_[p]]++] = std::uint32_t(p);
  }
  ++counters_.rebuilds;
}

template <class Real>
template <bool AllPeriodic>
void Stepper<Real>::drift() {
  const std::size_t n = x_.size();
  const Real dt = dt_;
  Real* __restrict x = x_.data();
  Real* __restrict y = y_.data();
  Real* __restrict z = z_.data();
  const Real* __restrict vx = vx_.data();
  const Real* __restrict vy = vy_.data();
  const Real* __restrict vz = vz_.data();
  const Real* __restrict x0 = x0_.data();
  const Real* __restrict y0 = y0_.data();
  const Real* __restrict z0 = z0_.data();
  Real m = max_disp2_;
  for (std::size_t i = 0; i < n; ++i) {
    x[i] += vx[i] * dt;
    y[i] += vy[i] * dt;
    z[i] += vz[i] * dt;
    const Real dx = x[i] - x0[i], dy = y[i] - y0[i], dz = z[i] - z0[i];
    const Real d2 = dx * dx + dy * dy + dz * dz;
    m = d2 > m ? d2 : m;
  }
  max_disp2_ = m;
  if constexpr (!AllPeriodic) {
    for (std::uint32_t i = 0; i < n; ++i) reflect(i);
  }
}

template <class Real>
void Stepper<Real>::reflect(std::uint32_t i) {
  Real* pos[3] = {&x_[i], &y_[i], &z_[i]};
  Real* vel[3] = {&vx_[i], &vy_[i], &vz_[i]};
  for (int d = 0; d < 3; ++d) {
    if (box_.periodic[d]) continue;
    const Real before = *pos[d], v = *vel[d];
    const Real dp = kernel::reflect_from_walls(*pos[d], *vel[d], Real(box_.lo[d]), Real(box_.hi[d]), r_[i]);
    if (dp != Real(0)) {
      ++counters_.wall_collisions;
      counters_.wall_impulse[d] += double(m_[i]) * std::abs(double(dp));
      note_displacement(i);
      // The bounce happened half the mirror distance ago.
      mark_changed(i, std::min(window(i), std::abs(*pos[d] - before) / (Real(2) * std::abs(v))));
    }
  }
}

template <class Real>
template <bool Mono, bool Sweep>
void Stepper<Real>::scan_pair_list() {
  candidates_.clear();
  const std::size_t np = pair_i_.size();
  const std::uint32_t* __restrict pi = pair_i_.data();
  const std::uint32_t* __restrict pj = pair_j_.data();
  const std::uint8_t* __restrict img = pair_image_.data();
  const Real* __restrict x = x_.data();
  const Real* __restrict y = y_.data();
  const Real* __restrict z = z_.data();
  // Sweep: a pair can have touched within the step only if its gap is below |dv| dt; bound
  // |dv| by twice the fastest speed so the cheap distance test still rejects most pairs.
  Real reach2 = 0;
  if constexpr (Sweep) {
    Real v2 = 0;
    for (std::size_t i = 0; i < vx_.size(); ++i) v2 = std::max(v2, vx_[i] * vx_[i] + vy_[i] * vy_[i] + vz_[i] * vz_[i]);
    reach2 = Real(2) * std::sqrt(v2) * dt_;
  }
  for (std::size_t p = 0; p < np; ++p) {
    const std::uint32_t i = pi[p], j = pj[p];
    const Real* s = image_shift_[img[p]];
    const Real dx = x[i] - x[j] - s[0], dy = y[i] - y[j] - s[1], dz = z[i] - z[j] - s[2];
    const Real d2 = dx * dx + dy * dy + dz * dz;
    const Real sg = Mono ? sigma_ : r_[i] + r_[j];
    const Real lim = Sweep ? sg + reach2 : sg;
    if (d2 < lim * lim) consider(i, j, img[p], {dx, dy, dz}, sg, !Sweep);
  }
}

template <class Real>
template <bool Mono>
void Stepper<Real>::sweep_neighbours(std::uint32_t sphere) {
  for (std::uint32_t k = adj_start_[sphere]; k < adj_start_[sphere + 1]; ++k) {
    const std::uint32_t p = adj_pair_[k], i = pair_i_[p], j = pair_j_[p];
    const Real* s = image_shift_[pair_image_[p]];
    const Real sg = Mono ? sigma_ : contact_distance(i, j);
    consider(i, j, pair_image_[p], {x_[i] - x_[j] - s[0], y_[i] - y_[j] - s[1], z_[i] - z_[j] - s[2]}, sg, false);
  }
}

template <class Real>
template <bool Mono>
void Stepper<Real>::expand_candidates() {
  // A sphere that collides in this step may also have grazed a neighbour earlier in the step,
  // which the end-of-step overlap test cannot see: sweep the neighbours of every sphere in a
  // contact (and of theirs, transitively) so contacts are resolved in true time order.
  ++sweep_no_;
  for (std::size_t k = 0; k < candidates_.size(); ++k) {
    for (const std::uint32_t p : {candidates_[k].i, candidates_[k].j})
      if (swept_stamp_[p] != sweep_no_) {
        swept_stamp_[p] = sweep_no_;
        sweep_neighbours<Mono>(p);
      }
  }
}

template <class Real>
template <bool AllPeriodic, bool Mono>
bool Stepper<Real>::resolve_one(const Candidate& c) {
  const std::uint32_t i = c.i, j = c.j;
  const Real* s = image_shift_[c.image];
  V3<Real> ri{x_[i], y_[i], z_[i]}, rj{x_[j], y_[j], z_[j]};
  V3<Real> vi{vx_[i], vy_[i], vz_[i]}, vj{vx_[j], vy_[j], vz_[j]};
  const V3<Real> shift{s[0], s[1], s[2]};
  const V3<Real> dr = ri - rj - shift, dv = vi - vj;
  const Real sg = Mono ? sigma_ : contact_distance(i, j);
  const Real w = std::min(window(i), window(j));
  if (!kernel::touched_within(dr, dv, sg, w, false)) return false;
  const Real back = std::min(kernel::rewind_time(dr, dv, sg), w);
  ri -= back * vi;
  rj -= back * vj;
  const V3<Real> contact = ri - rj - shift;
  double virial;
  if constexpr (Mono) virial = double(mass_) * double(kernel::collide_equal_mass(contact, vi, vj));
  else virial = double(kernel::collide(contact, vi, vj, m_[i], m_[j]));
  if (virial == 0.0) return false;  // receding at the rewound contact: nothing to resolve
  ri += back * vi;
  rj += back * vj;
  x_[i] = ri.x; y_[i] = ri.y; z_[i] = ri.z;
  x_[j] = rj.x; y_[j] = rj.y; z_[j] = rj.z;
  vx_[i] = vi.x; vy_[i] = vi.y; vz_[i] = vi.z;
  vx_[j] = vj.x; vy_[j] = vj.y; vz_[j] = vj.z;
  ++counters_.collisions;
  counters_.pair_virial += virial;
  for (const std::uint32_t k : {i, j}) {
    mark_changed(k, back);
    note_displacement(k);
    if constexpr (!AllPeriodic) reflect(k);
  }
  return true;
}

template <class Real>
template <bool AllPeriodic, bool Mono>
void Stepper<Real>::resolve_in_time_order() {
  // A small event loop inside the step: contacts come off a heap earliest first; each
  // collision invalidates the predictions of its two spheres (counters) and re-predicts their
  // contacts over the rest of the step, so a sphere deflected into a neighbour meets it in order.
  auto cmp = [this](const Candidate& a, const Candidate& b) { return later(a, b); };
  heap_.assign(candidates_.begin(), candidates_.end());
  std::make_heap(heap_.begin(), heap_.end(), cmp);
  std::int64_t events = 0;
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), cmp);
    const Candidate c = heap_.back();
    heap_.pop_back();
    if (c.count_i != change_count_[c.i] || c.count_j != change_count_[c.j]) continue;  // stale
    if (++events > max_events_) {
      ++counters_.unresolved_steps;
      heap_.clear();
      break;
    }
    if (!resolve_one<AllPeriodic, Mono>(c)) continue;
    candidates_.clear();
    if (list_expired()) {
      // Collisions moved spheres past the skin: rebuild (indices change) and re-predict all.
      rebuild();
      heap_.clear();
      scan_pair_list<Mono, true>();
    } else {
      sweep_neighbours<Mono>(c.i);
      sweep_neighbours<Mono>(c.j);
    }
    for (const auto& n : candidates_) {
      heap_.push_back(n);
      std::push_heap(heap_.begin(), heap_.end(), cmp);
    }
  }
}

template <class Real>
template <bool AllPeriodic, bool Mono, bool Sweep>
void Stepper<Real>::step() {
  drift<AllPeriodic>();
  if (list_expired()) rebuild();
  scan_pair_list<Mono, Sweep>();
  if (!candidates_.empty()) {
    if constexpr (!Sweep) expand_candidates<Mono>();
    resolve_in_time_order<AllPeriodic, Mono>();
  }
  ++counters_.steps;
  ++step_no_;
  counters_.sim_time += double(dt_);
}

template <class Real>
ParticleSystem Stepper<Real>::state() const {
  const std::size_t n = x_.size();
  std::vector<std::size_t> by_id(n);
  std::iota(by_id.begin(), by_id.end(), std::size_t(0));
  std::sort(by_id.begin(), by_id.end(), [this](std::size_t a, std::size_t b) { return id_[a] < id_[b]; });
  ParticleSystem out;
  out.box = box_;
  out.reserve(n);
  for (const std::size_t k : by_id)
    out.push_back(id_[k], type_[k], double(r_[k]), double(m_[k]), {double(x_[k]), double(y_[k]), double(z_[k])},
                  {double(vx_[k]), double(vy_[k]), double(vz_[k])});
  wrap_periodic(out);
  return out;
}

}  // namespace

std::unique_ptr<StepperBase> make_stepper(const ParticleSystem& sys, const StepperConfig& cfg, Precision precision) {
  if (precision == Precision::Float) return std::make_unique<Stepper<float>>(sys, cfg);
  return std::make_unique<Stepper<double>>(sys, cfg);
}

}  // namespace hardsphere
