#include "hardsphere/stepper.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <numeric>
#include <sstream>
#include <utility>
#include <vector>

#include "common/default_init_allocator.hpp"
#include "hardsphere/collision.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/scene_limits.hpp"
#include "hardsphere/state_exchange.hpp"
#include "scene/cell_grid.hpp"
#include "scene/size_classes.hpp"
#include "stepper/close_pairs_row.hpp"
#include "stepper/contact_resolver.hpp"
#include "stepper/distance_filter.hpp"
#include "stepper/drift_kernel.hpp"
#include "stepper/gap_search.hpp"
#include "stepper/list_guard.hpp"

namespace hardsphere {

Precision parse_precision(const std::string& s) {
  if (s == "double") return Precision::Double;
  if (s == "float") return Precision::Float;
  throw InputError("unknown precision '" + s + "' (expected double or float)");
}

Detect parse_detect(const std::string& s) {
  if (s == "overlap") return Detect::Overlap;
  if (s == "sweep") return Detect::Sweep;
  if (s == "auto") return Detect::Auto;
  throw InputError("unknown detection mode '" + s + "' (expected auto, overlap or sweep)");
}

namespace {
double rms_speed(const ParticleSystem& sys) {
  double v2 = 0;
  for (const auto& v : sys.vel) v2 += dot(v, v);
  return sys.size() ? std::sqrt(v2 / double(sys.size())) : 0.0;
}
}  // namespace

bool detects_by_sweep(Detect d, const ParticleSystem& sys, double dt) {
  if (d != Detect::Auto) return d == Detect::Sweep;
  // Overlap detection misses grazes (pairs that touch and part within one step), which matter only for
  // long steps; sweeping costs more, so it is chosen only beyond kOverlapDetectionLimit (see docs/performance.md).
  double smallest = std::numeric_limits<double>::infinity();
  for (const double r : sys.radius) smallest = std::min(smallest, 2 * r);
  return rms_speed(sys) * dt > kOverlapDetectionLimit * smallest;
}

//! Indices that put the ids in ascending order, stable for equal ids. Ids that span a range
//! of a few times their number (atom tags) are counted into place in O(n).
std::vector<std::size_t> order_by_id(const std::vector<std::int64_t>& id) {
  const std::size_t n = id.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t(0));
  if (std::is_sorted(id.begin(), id.end())) return order;
  const auto [lo, hi] = std::minmax_element(id.begin(), id.end());
  const std::uint64_t span = std::uint64_t(*hi) - std::uint64_t(*lo);
  if (span >= 4 * std::uint64_t(n) + 1024) {
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return id[a] < id[b]; });
    return order;
  }
  std::vector<std::size_t> start(std::size_t(span) + 2, 0);
  for (const std::int64_t v : id) ++start[std::size_t(std::uint64_t(v) - std::uint64_t(*lo)) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  for (std::size_t i = 0; i < n; ++i) order[start[std::size_t(std::uint64_t(id[i]) - std::uint64_t(*lo))]++] = i;
  return order;
}

double auto_skin(const ParticleSystem& sys, double dt, double phi_gas) {
  // A thin skin means frequent rebuilds, a thick one longer scans and neighbour sweeps.
  // (1) A rebuild every ~4 steps at most for the fastest spheres (~2.5 rms speeds): skin >=
  // 20 v_rms dt; more frequent rebuilds also fall mid-step in dense gases. (2) The list costs
  // ~ phi s per step for a skin s and a rebuild ~ N (plus the pair build) every ~ s / (v dt)
  // steps, so the sum is least near s ~ sqrt(v dt d / phi): thicker skins pay in dilute gases.
  // The larger of the two, within [0.3, 0.6] diameters (prefactors fitted, see docs/performance.md).
  // (3) With the pairwise list guard a list outlives the first sphere to cross half the skin,
  // so dense gases do better with thinner skins: the upper bound falls from 0.6 at phi 0.2 to
  // 0.4 at phi >= 0.3 (see docs/performance.md).
  // (4) Long steps overrule (3): no sphere may move more than 0.85 skins between rebuilds, so a
  // skin below a few v_rms dt lets the fast spheres expire the list every step, and in the
  // middle of steps, at a multiple of the cost (see docs/performance.md). skin >= 6 v_rms dt
  // gives a sphere at 3 v_rms about two steps to cross it.
  // The diameter is the median one: the skin is a distance a typical sphere travels between
  // rebuilds, so neither big spheres nor the tail of a size distribution may thicken it.
  const double v_rms = rms_speed(sys);
  std::vector<double> radii(sys.radius);
  const auto mid = radii.begin() + std::ptrdiff_t(radii.size() / 2);
  if (!radii.empty()) std::nth_element(radii.begin(), mid, radii.end());
  const double diameter = radii.empty() ? 0.0 : 2 * *mid;
  const double phi = std::max(phi_gas, 1e-3);
  const double skin = std::max(20.0 * v_rms * dt, 1.75 * std::sqrt(v_rms * dt * diameter / phi));
  const double thickest = std::clamp(0.6 - 2.0 * (phi - 0.2), 0.4, 0.6);
  return std::max(std::clamp(skin, 0.3 * diameter, thickest * diameter), 6.0 * v_rms * dt);
}

namespace {

template <class Real>
using V3 = Vec3<Real>;

//! Whether big spheres can find their partners by minimum image: every periodic axis longer
//! than twice the farthest a big sphere's pairs and list-guard threats reach (sigma + 2 skins).
bool big_pass_fits(const ParticleSystem& sys, const SizeSplit& split, double skin) {
  const double partner = split.big.size() > 1 ? sys.radius[split.big[1]] : split.grid_diameter / 2;
  const double reach = sys.radius[split.big[0]] + partner + 2 * skin;
  for (int d = 0; d < 3; ++d)
    if (sys.box.periodic[d] && !(sys.box.length(d) > 2 * reach)) return false;
  return true;
}

//! Mono: every sphere has the same radius and mass (chosen from the scene by make_stepper).
template <class Real, bool Mono>
class Stepper final : public StepperBase, public StateExchange {
 public:
  Stepper(const ParticleSystem& sys, const StepperConfig& cfg);

  void run(std::int64_t steps) override {
    std::fill(met_owned_.begin(), met_owned_.end(), std::uint8_t(0));
    // Scene features select a specialised kernel once per run, not per pair.
    const int key = (all_periodic_ ? 2 : 0) + (sweep_ ? 1 : 0);
    switch (key) {
      case 0:
        run_impl<false, false>(steps);
        break;
      case 1:
        run_impl<false, true>(steps);
        break;
      case 2:
        run_impl<true, false>(steps);
        break;
      default:
        run_impl<true, true>(steps);
        break;
    }
  }
  ParticleSystem state() const override;
  const StepCounters& counters() const override {
    counters_.collisions = tally_.collisions;
    counters_.wall_collisions = tally_.wall_collisions;
    counters_.wall_impulse = tally_.wall_impulse;
    counters_.pair_virial = tally_.virial;
    counters_.pair_virial_tensor = tally_.virial_tensor;
    counters_.unresolved_steps = tally_.unresolved_steps;
    return counters_;
  }
  void reset_counters() override {
    counters_ = StepCounters{};
    tally_ = ContactTally{};
    std::fill(pair_collisions_.begin(), pair_collisions_.end(), std::int64_t(0));
  }
  SphereSample sphere(std::size_t index) const override;
  std::vector<std::int64_t> pair_collisions_per_sphere() const override {
    std::vector<std::int64_t> out(pair_collisions_.size());
    for (std::size_t k = 0; k < out.size(); ++k) out[slot_[k]] = pair_collisions_[k];
    return out;
  }
  std::array<int, 3> cells_per_dim() const override { return grid_.counts(); }
  double skin() const override { return double(skin_); }
  std::size_t size() const override { return pos_.size(); }
  void copy_ids(std::int64_t* out) const override {
    for (std::size_t k = 0; k < slot_.size(); ++k) out[k] = id_[slot_[k]];
  }
  void copy_input_index(std::uint32_t* out) const override {
    for (std::size_t k = 0; k < slot_.size(); ++k) out[k] = input_of_rank_[slot_[k]];
  }
  void set_owned(const std::uint8_t* owned) override {
    // In slot order, permuted at each rebuild: the resolver reads both at every collision.
    owned_.resize(slot_.size());
    for (std::size_t k = 0; k < owned_.size(); ++k) owned_[k] = owned[input_of_rank_[slot_[k]]];
    met_owned_.assign(owned_.size(), 0);
    bind_resolver();
  }
  void set_sphere_virial(bool on) override {
    if (on == !sphere_virial_.empty()) return;
    if (on)
      sphere_virial_.assign(6 * pos_.size(), 0.0);
    else
      sphere_virial_ = {};
    bind_resolver();
  }
  void take_sphere_virial(const std::uint32_t* dest, double scale, double* out) override {
    if (sphere_virial_.empty()) return;
    for (std::size_t k = 0; k < slot_.size(); ++k) {
      double* w = &sphere_virial_[6 * k];
      if (dest[k] != kNoRow)
        for (std::size_t c = 0; c < 6; ++c) out[6 * std::size_t(dest[k]) + c] += scale * w[c];
      std::fill(w, w + 6, 0.0);
    }
  }
  void copy_met_owned(const std::uint32_t* slots, std::size_t count, std::uint8_t* out) const override {
    for (std::size_t i = 0; i < count; ++i) out[i] = met_owned_.empty() ? 0 : met_owned_[slots[i]];
  }
  const OwnedCounters& owned_counters() const override {
    owned_counters_.collisions = tally_.owned_collisions;
    owned_counters_.wall_collisions = tally_.owned_wall_collisions;
    owned_counters_.pair_virial = tally_.owned_virial;
    owned_counters_.pair_virial_tensor = tally_.owned_virial_tensor;
    return owned_counters_;
  }
  void copy_images(std::int32_t* out) const override {
    for (std::size_t k = 0; k < slot_.size(); ++k)
      for (std::size_t d = 0; d < 3; ++d) out[3 * k + d] = image_[slot_[k]][d];
  }
  void copy_state(Vec3d* pos, Vec3d* vel) const override {
    for (std::size_t k = 0; k < pos_.size(); ++k) {
      pos[k] = user_position(k);
      vel[k] = {double(vel_[k].x), double(vel_[k].y), double(vel_[k].z)};
    }
  }
  void scatter_state(const std::uint32_t* dest, const Vec3d* shift, double* x, double* v) const override {
    const std::size_t n = pos_.size(), ahead = 16;  // rows are scattered: request them early
    for (std::size_t k = 0; k < n; ++k) {
      if (k + ahead < n && dest[k + ahead] != kNoRow) {
        __builtin_prefetch(x + 3 * std::size_t(dest[k + ahead]), 1);
        __builtin_prefetch(v + 3 * std::size_t(dest[k + ahead]), 1);
      }
      if (dest[k] == kNoRow) continue;
      double* xo = x + 3 * std::size_t(dest[k]);
      double* vo = v + 3 * std::size_t(dest[k]);
      const Vec3d p = user_position(k);
      xo[0] = p.x + shift[k].x, xo[1] = p.y + shift[k].y, xo[2] = p.z + shift[k].z;
      vo[0] = double(vel_[k].x), vo[1] = double(vel_[k].y), vo[2] = double(vel_[k].z);
    }
  }
  double mv2_sum() const override {
    double sum = 0;
    for (std::size_t k = 0; k < vel_.size(); ++k) sum += double(m_[k]) * double(dot(vel_[k], vel_[k]));
    return sum;
  }
  void set_velocities(const Vec3d* vel) override {
    for (std::size_t k = 0; k < vel_.size(); ++k) vel_[k] = {Real(vel[k].x), Real(vel[k].y), Real(vel[k].z)};
    refresh_speed_bound();
  }
  void copy_velocities(const std::uint32_t* slots, std::size_t count, Vec3d* out) const override {
    for (std::size_t i = 0; i < count; ++i) {
      const auto& u = vel_[slots[i]];
      out[i] = {double(u.x), double(u.y), double(u.z)};
    }
  }
  void set_spheres(const std::uint32_t* slots, std::size_t count, const Vec3d* pos, const Vec3d* vel) override {
    // A changed position is a displacement like any other: the next drift measures it from the
    // rebuild position, so the list guard sees it. The speed bound stays an upper bound if
    // raised by the new speeds (the other spheres' are below it): no pass over every sphere.
    Real v2 = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t k = slots[i];
      pos_[k] = {Real(pos[i].x - origin_[0]), Real(pos[i].y - origin_[1]), Real(pos[i].z - origin_[2])};
      vel_[k] = {Real(vel[i].x), Real(vel[i].y), Real(vel[i].z)};
      v2 = std::max(v2, dot(vel_[k], vel_[k]));
    }
    resolver_.set_speed_bound(std::max(resolver_.speed_bound(), std::sqrt(v2) + path_bend()));
  }
  void gather_velocities(const std::uint32_t* src, const double* v) override {
    for (std::size_t k = 0; k < vel_.size(); ++k) {
      const double* vi = v + 3 * std::size_t(src[k]);
      vel_[k] = {Real(vi[0]), Real(vi[1]), Real(vi[2])};
    }
    refresh_speed_bound();
  }
  void set_rebuild_agreement(std::function<bool(bool)> agree) override { agree_ = std::move(agree); }
  bool sweep_detection() const override { return sweep_; }
  double substeps_per_step() const override {
    return std::max(1.0, std::ceil(double(resolver_.speed_bound()) * double(dt_) / double(half_skin_)));
  }
  std::string scene_kernel() const override {
    return std::string(all_periodic_ ? "periodic" : "walls") + (Mono ? ",mono" : ",poly") +
           (sizeof(Real) == sizeof(float) ? ",float" : ",double") + (sweep_ ? ",sweep" : ",overlap");
  }

 private:
  //! Sphere k's position (internal order) in the caller's coordinates.
  Vec3d user_position(std::size_t k) const {
    return {double(pos_[k].x) + origin_[0], double(pos_[k].y) + origin_[1], double(pos_[k].z) + origin_[2]};
  }
  static Box relative_box(const Box& b) {
    Box r = b;
    for (int d = 0; d < 3; ++d) r.lo[d] = 0, r.hi[d] = b.length(d);
    return r;
  }

  //! What the shared resolver needs from this engine after each collision.
  struct Hooks {
    Stepper& s;
    void after_collision(std::uint32_t k, Real) { s.note_displacement(k); }
    void after_bounce(std::uint32_t k) { s.note_displacement(k); }
    HS_ALWAYS_INLINE void prefetch(std::uint32_t k) const {
      __builtin_prefetch(&s.pos0_[k]);
      s.guard_.prefetch(k);
    }
    bool must_rescan() const { return s.list_expired(); }
    bool rescan(Real) {
      // Collisions moved spheres past the skin: rebuild (indices change) and re-predict all
      // over each sphere's window. A list made now covers the windows only if no sphere
      // travels half the skin in its window; otherwise the step is cut here.
      if (!s.windows_fit_skin()) return false;
      s.rebuild();
      s.cover_windows(true);
      s.template scan_pair_list<true>();
      return true;
    }
  };

  template <bool AllPeriodic, bool Sweep>
  void run_impl(std::int64_t steps) {
    for (std::int64_t s = 0; s < steps; ++s) step<AllPeriodic, Sweep>();
  }
  template <bool AllPeriodic, bool Sweep>
  void step();
  template <bool AllPeriodic, bool Sweep>
  void split_step();
  //! One sub-step of length h_; returns the time it covered (less than h_ if it was cut).
  template <bool AllPeriodic, bool Sweep>
  Real substep();
  void set_substep(Real h) {
    h_ = h;
    resolver_.set_step(h);
  }
  //! Refuses to go on if the sub-steps the current step needs would exceed the work limit.
  void check_work(double substeps) const {
    if ((substeps_total_ + substeps) * double(pos_.size()) > max_particle_steps_) {
      std::ostringstream m;
      m << "the run needs more than " << max_particle_steps_ << " particle-steps: with dt = " << double(dt_)
        << " the fastest sphere (speed " << double(resolver_.speed_bound()) << ") needs " << substeps
        << " sub-steps per step to move less than half the pair-list skin (" << double(skin_)
        << ") in each; use a smaller dt";
      throw InputError(m.str());
    }
  }
  void refresh_speed_bound() {
    Real v2 = 0;
    for (const auto& v : vel_) v2 = std::max(v2, dot(v, v));
    resolver_.set_speed_bound(std::sqrt(v2) + path_bend());
  }
  //! Under gravity a path over a step bends by at most |g| h^2 / 2: |g| h more speed covers it.
  Real path_bend() const {
    if (!has_gravity_) return Real(0);
    const V3<Real> g{gravity_[0], gravity_[1], gravity_[2]};
    return std::sqrt(dot(g, g)) * h_;
  }
  void kick(Real t) {
    const V3<Real> dv{gravity_[0] * t, gravity_[1] * t, gravity_[2] * t};
    for (auto& v : vel_) v += dv;
  }
  //! Whether every sphere's path over its window (back to its last velocity change in the
  //! step) stays within half the skin of where it is now.
  bool windows_fit_skin() const {
    const Real limit = guard_.quarter_skin2();
    for (std::uint32_t k = 0; k < pos_.size(); ++k) {
      const Real w = resolver_.window(k);
      if (dot(vel_[k], vel_[k]) * w * w >= limit) return false;
    }
    return true;
  }
  //! After a rebuild inside a step: the resolver may still look back along each sphere's path
  //! over its window (the whole sub-step, or per sphere), so the guard starts from those lengths.
  void cover_windows(bool per_sphere) {
    Real* d2 = guard_.displacements();
    Real mx = 0;
    for (std::uint32_t k = 0; k < pos_.size(); ++k) {
      const Real w = per_sphere ? resolver_.window(k) : h_;
      d2[k] = dot(vel_[k], vel_[k]) * w * w;
      mx = std::max(mx, d2[k]);
    }
    guard_.set_max_displacement2(mx);
    rebuilt_in_step_ = true;
  }
  //! At the end of a step that rebuilt: the paths before the rebuild are behind us, so each
  //! displacement is again the distance from the rebuild position.
  void uncover_windows() {
    Real* d2 = guard_.displacements();
    Real mx = 0;
    for (std::size_t k = 0; k < pos_.size(); ++k) {
      const V3<Real> d = pos_[k] - pos0_[k];
      d2[k] = dot(d, d);
      mx = std::max(mx, d2[k]);
    }
    guard_.set_max_displacement2(mx);
    rebuilt_in_step_ = false;
  }
  void drift() {
    if (speeds_)
      drift_impl<true>();
    else
      drift_impl<false>();
  }
  template <bool Speeds>
  void drift_impl();
  template <bool Sweep>
  void scan_pair_list();
  void rebuild();
  void bind_resolver();
  struct CellRun;
  int stencil_runs(std::int64_t c, const std::array<int, 3>& at, CellRun* out) const;
  void build_pairs_half_stencil();
  void build_pairs_any_grid();
  void build_adjacency();
  void build_big_pairs();
  //! Calls push(b, gap) for each big sphere b != i with gap_lo <= gap_ib < gap_hi (minimum image).
  template <class Push>
  void for_each_big_gap(std::uint32_t i, Real gap_lo, Real gap_hi, Push&& push) const;
  //! Adds a pair found outside the block kernel (which counts its own) and counts it.
  void push_pair(std::uint32_t i, std::uint32_t j, std::uint8_t image) {
    ++adj_start_[i + 1], ++adj_start_[j + 1];
    if (image == kNoImage)
      near_.push_back({i, j});
    else {
      wrap_.push_back({i, j});
      wrap_image_.push_back(image);
    }
  }
  //! Lists i and j if their nearest images are within the list's reach (pair builds that do not
  //! go by the half stencil: any grid, big spheres among themselves).
  void push_if_near(std::uint32_t i, std::uint32_t j) {
    V3<Real> d = pos_[i] - pos_[j];
    int k[3] = {0, 0, 0};
    for (int a = 0; a < 3; ++a)
      if (box_.periodic[a]) {
        k[a] = int(std::nearbyint(d[a] / length_[a]));
        d[a] -= Real(k[a]) * length_[a];
      }
    const Real cut = list_cut(r_[i] + r_[j]);
    if (dot(d, d) < cut * cut) push_pair(i, j, image_code(k[0], k[1], k[2]));
  }
  //! Candidate cut-off of a pair: contact distance plus skin (an infinite skin takes all).
  Real list_cut(Real contact) const {
    return std::isinf(skin_) ? std::numeric_limits<Real>::max() / 4 : contact + skin_;
  }
  void note_displacement(std::uint32_t i) {
    const V3<Real> d = pos_[i] - pos0_[i];
    guard_.note(i, dot(d, d), threats_of());
  }
  bool list_expired() const { return guard_.expired(); }
  //! For the guard: the spheres j with skin <= gap_ij < 2 kMaxMove skin of sphere i at the last rebuild.
  auto threats_of() {
    return [this](std::uint32_t i, auto&& push) { for_each_threat(i, push); };
  }
  template <class Push>
  void for_each_threat(std::uint32_t i, Push& push) const;

  // The engine works in coordinates relative to the box's lower corner (box_ runs from 0 to
  // L), so single precision resolves a box far from the origin as well as one at it; user_box_
  // and origin_ restore the caller's coordinates on the way out.
  Box box_, user_box_;
  std::array<double, 3> origin_{};
  CellGrid grid_;
  bool all_periodic_, sweep_;
  Real dt_, skin_;
  Real h_;  // the current sub-step (dt_ unless steps are split)
  // Sub-steps are at most this over the speed bound: a list built at a sub-step's end then
  // covers every path of the sub-step (kept under skin / 2 for rounding).
  Real half_skin_;
  bool rebuilt_in_step_ = false;
  double substeps_total_ = 0, max_particle_steps_;
  detail::ListGuard<Real> guard_;
  std::vector<std::uint32_t> flagged_;  // drift(): spheres past the guard's skin / 2
  Real sigma_ = 0;                      // monodisperse diameter
  Real max_radius_ = 0;
  Real cell_radius_ = 0;  // largest radius of the spheres filed in cells (max_radius_ without big ones)
  // Big spheres (split_by_size) are filed in no cell: they follow the last cell, from
  // big_begin_ on, and a pass of their own finds their pairs. big_ flags them by id rank;
  // empty when there are none, or when a periodic axis is too short for that pass.
  std::vector<std::uint8_t> big_;
  std::uint32_t big_begin_ = 0;
  std::array<Real, 3> length_{};
  V3<Real> image_shift_[27];  // by image code: (kx Lx, ky Ly, kz Lz)

  // Per-field arrays in cell order: a neighbour's position or velocity is one cache line.
  std::vector<V3<Real>> pos_, vel_, pos0_;  // pos0_: positions at the last rebuild
  // |vel_|, set by drift(), kept by the resolver, for the neighbour sweeps' per-pair speed bound. Only where
  // sweeps are a large part of the loop and speeds stay in cache do their loads pay (see docs/performance.md).
  bool speeds_ = false;
  std::vector<Real> speed_;
  std::vector<Real> r_, m_;
  // Fields the steps never read stay in id order and are reached through slot_ (the id rank
  // of the sphere at each position of the cell order), so a rebuild moves 4 bytes, not 24.
  std::vector<std::uint32_t> slot_;
  std::vector<std::int64_t> id_;
  std::vector<std::array<std::int32_t, 3>> image_;   // box lengths removed by wrapping, per axis
  std::vector<std::array<std::int32_t, 3>> image0_;  // id order: the input's image flags
  std::vector<int> type_, cell_;
  std::vector<std::uint32_t> cell_start_, order_;
  // Candidate pairs within r_i + r_j + skin at the last rebuild: those inside the box (most)
  // need no image shift; pairs across a periodic face carry their image code.
  struct Pair {
    std::uint32_t i, j;
  };
  std::vector<Pair, detail::DefaultInitAllocator<Pair>> near_;  // grown and cut back at every rebuild
  std::vector<Pair> wrap_;
  std::vector<std::uint8_t> wrap_image_;
  std::vector<Real> soa_x_, soa_y_, soa_z_;  // pos_ as coordinate arrays (filled at rebuild) for the pair build
  std::vector<std::uint32_t> wrap_row_;      // one row's pairs across a periodic face
  mutable std::vector<std::uint32_t> threat_scratch_;  // for_each_threat(): one row's spheres within reach
  // Half stencil as runs of consecutive cells: the 13 forward neighbours of a cell are one
  // cell and four rows of three along x, contiguous in cell order (so in memory) unless a row
  // wraps through a periodic x face. Up to kMaxRuns runs [begin, end) + image per cell, made
  // when the pair list is built: a table of them would be larger than the spheres' own data.
  struct CellRun {
    int begin, end;
    std::uint8_t image;
  };
  static constexpr int kMaxRuns = 10;
  std::vector<V3<Real>> scratch_v3_;
  std::vector<Real> scratch_real_;
  std::vector<std::uint32_t> scratch_u32_;
  // For each sphere s, its list partners q and the image of r_s - r_q (CSR), for local sweeps.
  std::vector<std::uint32_t> adj_start_, adj_, adj_cursor_;  // adj_: adj_entry(partner, image)
  std::vector<std::uint32_t> adj_plain_end_;                 // per row, the end of its entries without an image
  ContactResolver<Real, Mono> resolver_;
  ContactTally tally_;
  mutable StepCounters counters_;
  mutable OwnedCounters owned_counters_;
  std::vector<std::uint8_t> owned_;           // slot order; empty: no ownership accounting
  std::vector<std::uint8_t> met_owned_;       // slot order: not owned, collided with an owned sphere in this run()
  std::function<bool(bool)> agree_;           // set_rebuild_agreement
  bool vote_due_ = false;                     // this step has not asked agree_ yet
  std::vector<std::uint32_t> input_of_rank_;  // id rank -> index in the constructor's input
  std::vector<double> last_collision_;        // id order: each sphere's last collision time (restitution < 1)
  // Cell order, like pos_, so a collision's two increments hit lines its spheres' neighbours use too.
  std::vector<std::int64_t> pair_collisions_, scratch_i64_;  // since reset_counters() (if counted)
  // Cell order, 6 per sphere: collision virial since the last take_sphere_virial (if on).
  std::vector<double> sphere_virial_, scratch_virial_;
  std::vector<std::uint8_t> scratch_u8_;
  mutable std::size_t sampled_at_ = 0;    // sphere()'s last cell-order position: valid until a rebuild
  double clock_ = 0;                      // time since construction, for the collision times
  std::array<Real, 3> gravity_{0, 0, 0};  // uniform acceleration (wall axes only)
  bool has_gravity_ = false;
};

template <class Real, bool Mono>
Stepper<Real, Mono>::Stepper(const ParticleSystem& sys, const StepperConfig& cfg)
    : box_(relative_box(sys.box)),
      user_box_(sys.box),
      origin_(sys.box.lo),
      all_periodic_(cfg.specialise && sys.box.all_periodic()),
      sweep_(detects_by_sweep(cfg.detect, sys, cfg.dt)),
      dt_(Real(cfg.dt)) {
  if (!(std::isfinite(cfg.dt) && cfg.dt > 0)) {
    std::ostringstream m;
    m << "time step dt = " << cfg.dt << " must be positive and finite";
    throw InputError(m.str());
  }
  if (cfg.max_events_per_step < 1) throw InputError("max events per step must be >= 1");
  check_restitution(cfg.restitution, cfg.contact_time);
  check_gravity(cfg.gravity, sys.box.periodic);
  check_scene_numbers(sys, "stepper");
  check_engine_numbers<Real>(sys, cfg.dt, sizeof(Real) == sizeof(float) ? "stepper in single precision" : "stepper");
  const std::size_t n = sys.size();
  if (n > std::size_t(kMaxAdjIndex) + 1)
    throw InputError("too many particles for one stepper: " + std::to_string(n) + " (at most " +
                     std::to_string(std::size_t(kMaxAdjIndex) + 1) + ")");
  const bool auto_cells = cfg.cells[0] == 0 && cfg.cells[1] == 0 && cfg.cells[2] == 0;
  if (!auto_cells)
    for (int d = 0; d < 3; ++d)
      if (cfg.cells[d] < 1) throw InputError("cells per axis must be >= 1, got " + std::to_string(cfg.cells[d]));
  if (!(cfg.packing_fraction >= 0 && cfg.packing_fraction < 1))
    throw InputError("packing fraction hint " + std::to_string(cfg.packing_fraction) + " must be in [0, 1)");
  const double phi_gas = cfg.packing_fraction > 0 ? cfg.packing_fraction : sys.packing_fraction();
  auto grid_for = [&](double diameter) {
    return auto_cells
               ? CellGrid::with_min_width(box_, diameter + auto_skin(sys, cfg.dt, phi_gas), std::int64_t(2 * n + 27))
               : CellGrid(box_, cfg.cells);
  };
  auto skin_of = [](const CellGrid& g, double diameter) {
    const double reach = g.reach();
    return std::isinf(reach) ? std::numeric_limits<double>::infinity() : reach - diameter;
  };
  // Big spheres get a pass of their own when the grid sized without them has a finite skin and
  // the box is long enough for it; otherwise the grid is sized by the largest sphere, as before.
  double diameter = 2 * sys.max_radius();
  const SizeSplit split = split_by_size(sys);
  bool big_pass = false;
  if (!split.big.empty()) {
    const CellGrid g = grid_for(split.grid_diameter);
    const double skin = skin_of(g, split.grid_diameter);
    if (g.half_stencil_ok() && std::isfinite(skin) && skin > 0 && big_pass_fits(sys, split, skin)) {
      big_pass = true;
      grid_ = g;
      diameter = split.grid_diameter;
    }
  }
  if (!big_pass) grid_ = grid_for(diameter);
  const double skin = skin_of(grid_, diameter);
  if (!(skin > 0) && !split.big.empty() && auto_cells) {
    // Neither a grid over the largest sphere nor the pass for big spheres fits the box.
    int axis = -1;  // the shortest periodic axis
    for (int d = 0; d < 3; ++d)
      if (sys.box.periodic[d] && (axis < 0 || sys.box.length(d) < sys.box.length(axis))) axis = d;
    axis = std::max(axis, 0);
    std::ostringstream m;
    m << "periodic box length " << sys.box.length(axis) << " (axis "
      << "xyz"[axis] << ") is too short for a sphere of diameter " << 2 * sys.max_radius()
      << ": a periodic axis must be longer than twice the largest diameter, or than twice the reach of a big"
      << " sphere's pairs (its diameter plus its largest partner's and two list skins)";
    throw InputError(m.str());
  }
  if (!(skin > 0)) {
    std::ostringstream m;
    m << "cells " << grid_.counts()[0] << "," << grid_.counts()[1] << "," << grid_.counts()[2]
      << " give a cell width of " << grid_.reach() << ", not more than the largest diameter " << diameter
      << "; use fewer cells or --cells auto";
    throw InputError(m.str());
  }
  skin_ = Real(skin);
  half_skin_ = Real(0.4995) * skin_;
  h_ = dt_;
  max_particle_steps_ = cfg.max_particle_steps;
  for (int d = 0; d < 3; ++d) length_[d] = Real(box_.length(d));
  for (int kx = -1; kx <= 1; ++kx)
    for (int ky = -1; ky <= 1; ++ky)
      for (int kz = -1; kz <= 1; ++kz)
        image_shift_[image_code(kx, ky, kz)] = {Real(kx) * length_[0], Real(ky) * length_[1], Real(kz) * length_[2]};

  pos_.resize(n);
  vel_.resize(n);
  r_.resize(n);
  m_.resize(n);
  slot_.resize(n);
  id_.resize(n);
  type_.resize(n);
  image_.assign(n, {0, 0, 0});
  image0_.assign(n, {0, 0, 0});
  if (cfg.count_per_sphere) pair_collisions_.assign(n, 0);
  // Internal order starts from the ids, not the input order: the cell sorts are stable, so the
  // same spheres give the same run bit for bit in whatever order an adapter hands them over.
  const std::vector<std::size_t> by_id = order_by_id(sys.id);
  input_of_rank_.assign(by_id.begin(), by_id.end());
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t s = by_id[i];
    slot_[i] = std::uint32_t(i);
    id_[i] = sys.id[s];
    type_[i] = sys.type[s];
    if (s < sys.image.size()) image0_[i] = sys.image[s];
    pos_[i] = {Real(sys.pos[s].x - origin_[0]), Real(sys.pos[s].y - origin_[1]), Real(sys.pos[s].z - origin_[2])};
    vel_[i] = {Real(sys.vel[s].x), Real(sys.vel[s].y), Real(sys.vel[s].z)};
    r_[i] = Real(sys.radius[s]);
    m_[i] = Real(sys.mass[s]);
  }
  if (n) sigma_ = Real(2) * r_[0];
  max_radius_ = Real(sys.max_radius());
  cell_radius_ = Real(diameter / 2);
  if (big_pass) {
    big_.assign(n, 0);
    std::vector<std::uint32_t> rank_of_input(n);
    for (std::size_t r = 0; r < n; ++r) rank_of_input[input_of_rank_[r]] = std::uint32_t(r);
    for (const std::uint32_t b : split.big) big_[rank_of_input[b]] = 1;
    big_begin_ = std::uint32_t(n - split.big.size());
  }
  resolver_.reset(n, dt_);
  resolver_.set_uniform(sigma_, n ? m_[0] : Real(0));
  resolver_.set_event_limit(cfg.max_events_per_step);
  if (cfg.restitution != 1.0) {
    last_collision_.assign(n, -std::numeric_limits<double>::infinity());
    resolver_.set_restitution(Real(cfg.restitution), cfg.contact_time, last_collision_.data());
  }
  std::array<Real, 3> wall_lo{}, wall_hi{};
  for (std::size_t d = 0; d < 3; ++d) wall_lo[d] = Real(box_.lo[d]), wall_hi[d] = Real(box_.hi[d]);
  resolver_.set_walls(box_.periodic, wall_lo, wall_hi);
  gravity_ = {Real(cfg.gravity[0]), Real(cfg.gravity[1]), Real(cfg.gravity[2])};
  has_gravity_ = cfg.gravity != std::array<double, 3>{0, 0, 0};
  resolver_.set_gravity(gravity_);
  // Threats are enumerated from the cells within two of a sphere's: every periodic axis needs
  // 3 cells (so a cell is at least sigma + skin wide).
  guard_.configure(skin_, cfg.pairwise_list_check && grid_.half_stencil_ok(), std::max<std::size_t>(n / 32, 16));
  // Speeds pay where the sweeps' extra loads hit the cache: positions and speeds within ~1 MiB
  // (the L2 of this machine's cores); beyond it each speed is one more miss (see docs/performance.md).
  // Under gravity speeds change during the step, so the per-sphere bounds are not used.
  speeds_ = !has_gravity_ && phi_gas >= 0.3 && double(n) * double(sizeof(V3<Real>) + sizeof(Real)) <= 1048576.0;
  rebuild();
  counters_.rebuilds = 0;
  refresh_speed_bound();
}

template <class Real, bool Mono>
int Stepper<Real, Mono>::stencil_runs(std::int64_t c, const std::array<int, 3>& at, CellRun* const first) const {
  // Every periodic axis has >= 3 cells: the 13 forward neighbours of a cell are distinct, and
  // wrapping a neighbour's cell coordinate gives exactly the pair's minimum image, so each
  // unordered pair of neighbouring cells is met once and no pair needs a division.
  // Forward rows (dy, dz) whose x range is [dx_lo, 1]: the cell's own row only ahead of it.
  static const int rows[5][3] = {{1, 0, 0}, {-1, 1, 0}, {-1, -1, 1}, {-1, 0, 1}, {-1, 1, 1}};
  const auto k = grid_.counts();
  const int cx = at[0], cy = at[1], cz = at[2];  // cell c's coordinates
  if (cx >= 1 && cx + 1 < k[0] && k[0] >= 4 && cy >= 1 && cy + 1 < k[1] && cz + 1 < k[2]) {
    // Inside the grid the five runs are offsets (with 4 or more cells along x none of them
    // touch, so none merge).
    const int row = k[0], layer = k[0] * k[1], ci = int(c);
    for (int r = 0; r < 5; ++r) {
      const int begin = ci + rows[r][0] + rows[r][1] * row + rows[r][2] * layer;
      first[r] = {begin, ci + 2 + rows[r][1] * row + rows[r][2] * layer, kNoImage};
    }
    return 5;
  }
  CellRun* out = first;
  for (const auto& row : rows) {
    int ny = cy + row[1], nz = cz + row[2], iy = 0, iz = 0;
    if (ny < 0 || ny >= k[1]) {
      if (!box_.periodic[1]) continue;
      iy = ny < 0 ? -1 : 1;  // across the lower face j's nearest image is one box down
      ny = (ny + k[1]) % k[1];
    }
    if (nz < 0 || nz >= k[2]) {
      if (!box_.periodic[2]) continue;
      iz = nz < 0 ? -1 : 1;
      nz = (nz + k[2]) % k[2];
    }
    // Split the x range [cx + dx_lo, cx + 1] where it leaves the box.
    for (int x = cx + row[0]; x <= cx + 1; ++x) {
      int nx = x, ix = 0;
      if (nx < 0 || nx >= k[0]) {
        if (!box_.periodic[0]) continue;
        ix = nx < 0 ? -1 : 1;
        nx = (nx + k[0]) % k[0];
      }
      const int cell = grid_.index(nx, ny, nz);
      const std::uint8_t image = image_code(ix, iy, iz);
      if (out != first && out[-1].end == cell && out[-1].image == image)
        ++out[-1].end;  // extends the previous run
      else
        *out++ = {cell, cell + 1, image};
    }
  }
  return int(out - first);
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::build_pairs_half_stencil() {
  const Real mono_cut = list_cut(sigma_), mono_cut2 = mono_cut * mono_cut;
  const std::int64_t ncell = grid_.size();
  // A cell's spheres against each run of consecutive spheres go to append_close_block
  // (vectorised where the CPU allows); pairs across a periodic face (rare) take push_pair.
  static_assert(sizeof(Pair) == 2 * sizeof(std::uint32_t) && offsetof(Pair, j) == sizeof(std::uint32_t));
  std::size_t n_near = 0;
  near_.resize(std::max<std::size_t>(near_.size(), 1024));
  std::uint32_t* degree = adj_start_.data() + 1;  // list lengths, see rebuild()
  const detail::RowSoA<Real> soa{soa_x_.data(), soa_y_.data(), soa_z_.data(), r_.data()};
  const auto counts = grid_.counts();
  std::array<int, 3> at{-1, 0, 0};  // cell c's coordinates, x fastest
  for (std::int64_t c = 0; c < ncell; ++c) {
    if (++at[0] == counts[0]) {
      at[0] = 0;
      if (++at[1] == counts[1]) at[1] = 0, ++at[2];
    }
    const std::uint32_t b0 = cell_start_[c], b1 = cell_start_[c + 1];
    if (b0 == b1) continue;
    CellRun runs[kMaxRuns];
    const int nruns = stencil_runs(c, at, runs);
    std::size_t reach = b1 - b0;  // an upper bound of the pairs this cell can add
    for (int r = 0; r < nruns; ++r) reach += cell_start_[runs[r].end] - cell_start_[runs[r].begin];
    const std::size_t need = n_near + (b1 - b0) * reach + detail::kRowSlack;
    if (need > near_.size()) near_.resize(2 * need);
    // The cell's own row (after i) and a first run that starts at the next cell without an
    // image (the +x neighbour, unless x wraps) are contiguous: one row.
    int first = 0;
    std::uint32_t own_end = b1;
    if (nruns > 0 && runs[0].begin == c + 1 && runs[0].image == kNoImage) {
      own_end = cell_start_[runs[0].end];
      first = 1;
    }
    auto* out = reinterpret_cast<std::uint32_t*>(near_.data());
    n_near = detail::append_close_block<Real, Mono>(soa, b0, b1, b0 + 1, own_end, true, skin_, mono_cut2, out, n_near,
                                                    degree);
    for (int r = first; r < nruns; ++r) {
      const std::uint32_t e0 = cell_start_[runs[r].begin], e1 = cell_start_[runs[r].end];
      if (runs[r].image == kNoImage) {
        n_near =
            detail::append_close_block<Real, Mono>(soa, b0, b1, e0, e1, false, skin_, mono_cut2, out, n_near, degree);
        continue;
      }
      // Across a periodic face (rare): the row test with i's image, into a scratch buffer.
      for (std::uint32_t i = b0; i < b1; ++i) {
        const V3<Real> pis = pos_[i] - image_shift_[runs[r].image];
        wrap_row_.resize(2 * (e1 - e0 + detail::kRowSlack));
        const std::size_t hits = detail::append_close_row<Real, Mono>(
            soa, i, pis.x, pis.y, pis.z, Mono ? Real(0) : r_[i], skin_, mono_cut2, e0, e1, wrap_row_.data(), 0);
        for (std::size_t k = 0; k < hits; ++k) push_pair(i, wrap_row_[2 * k + 1], runs[r].image);
      }
    }
  }
  near_.resize(n_near);
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::build_pairs_any_grid() {
  // General grids (an axis with 1 or 2 periodic cells): neighbour cells may repeat, so take
  // each unordered cell pair once by index and the minimum image per pair.
  const std::int64_t ncell = grid_.size();
  for (std::int64_t c = 0; c < ncell; ++c) {
    const std::uint32_t b0 = cell_start_[c], b1 = cell_start_[c + 1];
    if (b0 == b1) continue;
    grid_.for_each_neighbour(int(c), [&](int nb) {
      if (nb < c) return;
      const std::uint32_t e1 = cell_start_[nb + 1];
      for (std::uint32_t i = b0; i < b1; ++i) {
        for (std::uint32_t j = (nb == c ? i + 1 : cell_start_[nb]); j < e1; ++j) push_if_near(i, j);
      }
    });
  }
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::rebuild() {
  const std::size_t n = pos_.size();
  const Real lo[3] = {Real(box_.lo[0]), Real(box_.lo[1]), Real(box_.lo[2])};
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) {
      Real& p = pos_[i][d];
      const Real len = length_[d];
      if (!box_.periodic[d] || (p >= lo[d] && p < lo[d] + len)) continue;
      const Real wraps = std::floor((p - lo[d]) / len);
      p -= len * wraps;
      // Sub-steps keep |wraps| <= 1 between rebuilds; counts wrap around modulo 2^32 (as
      // LAMMPS's image flags do modulo 1024) in runs long enough to pass that.
      std::uint32_t image = std::uint32_t(image_[slot_[i]][std::size_t(d)]) + std::uint32_t(std::int32_t(wraps));
      if (p >= lo[d] + len) p -= len, ++image;  // floor rounding at the top edge
      image_[slot_[i]][std::size_t(d)] = std::int32_t(image);
    }
  }
  if (big_.empty())
    grid_.sort(
        n, [this](std::size_t i) { return pos_[i]; }, cell_, cell_start_, order_);
  else
    grid_.sort(
        n, [this](std::size_t i) { return pos_[i]; }, [this](std::size_t i) { return big_[slot_[i]] != 0; }, cell_,
        cell_start_, order_);
  auto permute = [&](auto& a, auto& scratch) {
    scratch.resize(n);
    for (std::size_t k = 0; k < n; ++k) scratch[k] = a[order_[k]];
    a.swap(scratch);
  };
  // Positions also go to the rebuild reference and to coordinate arrays for the pair build,
  // in the same pass.
  scratch_v3_.resize(n), pos0_.resize(n), soa_x_.resize(n), soa_y_.resize(n), soa_z_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const V3<Real> p = pos_[order_[k]];
    scratch_v3_[k] = p, pos0_[k] = p, soa_x_[k] = p.x, soa_y_[k] = p.y, soa_z_[k] = p.z;
  }
  pos_.swap(scratch_v3_);
  permute(vel_, scratch_v3_);
  if constexpr (!Mono) {  // equal radii and masses need no reordering
    permute(r_, scratch_real_);
    permute(m_, scratch_real_);
  }
  permute(slot_, scratch_u32_);
  if (!pair_collisions_.empty()) permute(pair_collisions_, scratch_i64_);
  if (!sphere_virial_.empty()) {
    scratch_virial_.resize(6 * n);
    for (std::size_t k = 0; k < n; ++k)
      std::copy_n(&sphere_virial_[6 * std::size_t(order_[k])], 6, &scratch_virial_[6 * k]);
    sphere_virial_.swap(scratch_virial_);
  }
  if (!owned_.empty()) permute(owned_, scratch_u8_), permute(met_owned_, scratch_u8_);
  resolver_.permute(order_);
  guard_.reset(n);

  // Candidate list: every pair that could touch before the next rebuild.
  near_.clear();
  wrap_.clear();
  wrap_image_.clear();
  adj_start_.assign(n + 1, 0);  // each sphere's list length, counted where its pairs are found
  if (grid_.half_stencil_ok())
    build_pairs_half_stencil();
  else
    build_pairs_any_grid();
  if (!big_.empty()) build_big_pairs();
  build_adjacency();
  if (speeds_) {  // in the new order (a rebuild inside a step needs the current speeds)
    speed_.resize(n);
    for (std::size_t k = 0; k < n; ++k) speed_[k] = norm(vel_[k]);
  }
  bind_resolver();
  ++counters_.rebuilds;
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::bind_resolver() {
  resolver_.bind({pos_.data(), vel_.data(), r_.data(), m_.data(), id_.data(), slot_.data(), adj_start_.data(),
                  adj_.data(), image_shift_, speeds_ ? speed_.data() : nullptr, adj_plain_end_.data(),
                  owned_.empty() ? nullptr : owned_.data(), owned_.empty() ? nullptr : met_owned_.data(),
                  pair_collisions_.empty() ? nullptr : pair_collisions_.data(),
                  sphere_virial_.empty() ? nullptr : sphere_virial_.data()});
}

template <class Real, bool Mono>
template <class Push>
void Stepper<Real, Mono>::for_each_threat(std::uint32_t i, Push& push) const {
  // The guard's window, gap < 2 kMaxMove skin, keeps sigma + gap below sigma + 2 skin: two cell
  // widths, or half a periodic axis for big spheres (big_pass_fits). Gaps are computed again here, so a margin covers
  // their rounding against the pair build's: pairs at the list's edge count as threats, and gaps are rounded down.
  const Real eps = Real(1e-4) * (Real(2) * max_radius_ + skin_);
  const Real window = Real(2) * detail::ListGuard<Real>::kMaxMove * skin_;
  const detail::CellSorted<Real> cells{
      &grid_, &box_, cell_start_.data(), {soa_x_.data(), soa_y_.data(), soa_z_.data(), r_.data()}, image_shift_};
  detail::for_each_gap_between<Real, Mono>(cells, i, sigma_, cell_radius_, skin_ - eps, window + eps, threat_scratch_,
                                           [&](std::uint32_t j, Real gap, std::uint8_t) { push(j, gap - eps); });
  for_each_big_gap(i, skin_ - eps, window + eps, [&](std::uint32_t b, Real gap) { push(b, gap - eps); });
}

template <class Real, bool Mono>
template <class Push>
void Stepper<Real, Mono>::for_each_big_gap(std::uint32_t i, Real gap_lo, Real gap_hi, Push&& push) const {
  // The box is longer than twice any big sphere's reach (big_pass_fits), so the minimum image
  // is the only one that can be this close.
  const std::uint32_t n = std::uint32_t(pos_.size());
  if (big_.empty()) return;
  for (std::uint32_t b = big_begin_; b < n; ++b) {
    if (b == i) continue;
    V3<Real> d{soa_x_[i] - soa_x_[b], soa_y_[i] - soa_y_[b], soa_z_[i] - soa_z_[b]};
    for (int a = 0; a < 3; ++a)
      if (box_.periodic[a]) d[a] -= std::nearbyint(d[a] / length_[a]) * length_[a];
    const Real gap = std::sqrt(dot(d, d)) - (r_[i] + r_[b]);
    if (gap >= gap_lo && gap < gap_hi) push(b, gap);
  }
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::build_big_pairs() {
  // Each big sphere against the small ones in every cell its reach overlaps, then big against
  // big by all pairs; minimum images, stored lower index first like every pair.
  const std::uint32_t n = std::uint32_t(pos_.size());
  const detail::CellSorted<Real> cells{
      &grid_, &box_, cell_start_.data(), {soa_x_.data(), soa_y_.data(), soa_z_.data(), r_.data()}, image_shift_};
  for (std::uint32_t b = big_begin_; b < n; ++b) {
    detail::for_each_gap_between<Real, false>(
        cells, b, sigma_, cell_radius_, -std::numeric_limits<Real>::infinity(), skin_, threat_scratch_,
        [&](std::uint32_t j, Real, std::uint8_t image) { push_pair(j, b, std::uint8_t(26 - image)); });
    for (std::uint32_t c = b + 1; c < n; ++c) push_if_near(b, c);
  }
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::build_adjacency() {
  // Both directions, CSR, for sweeping one sphere's neighbours; (j, i) carries the mirrored image.
  const std::size_t n = pos_.size(), np = near_.size() + wrap_.size();
  // adj_start_[i + 1] holds sphere i's list length, counted by the pair build.
  for (std::size_t i = 0; i < n; ++i) adj_start_[i + 1] += adj_start_[i];
  adj_.resize(2 * np);
  adj_cursor_.assign(adj_start_.begin(), adj_start_.end() - 1);
  auto add = [&](std::uint32_t i, std::uint32_t j, std::uint8_t image) {
    adj_[adj_cursor_[i]++] = adj_entry(j, image);
    adj_[adj_cursor_[j]++] = adj_entry(i, std::uint8_t(26 - image));
  };
  for (const auto& p : near_) add(p.i, p.j, kNoImage);
  adj_plain_end_.assign(adj_cursor_.begin(), adj_cursor_.end());  // each row: pairs without an image first
  for (std::size_t k = 0; k < wrap_.size(); ++k) add(wrap_[k].i, wrap_[k].j, wrap_image_[k]);
}

template <class Real, bool Mono>
template <bool Speeds>
void Stepper<Real, Mono>::drift_impl() {
  static_assert(sizeof(V3<Real>) == 3 * sizeof(Real), "xyz triples without padding");
  // Speeds are refreshed in every drift: velocities may have been set since the last step.
  flagged_.resize(pos_.size());
  std::size_t n_flagged = 0;
  const auto mx = detail::drift_spheres<Real>(
      &pos_.data()->x, &vel_.data()->x, &pos0_.data()->x, guard_.displacements(), Speeds ? speed_.data() : nullptr,
      pos_.size(), h_, guard_.max_displacement2(), guard_.candidate_d2(), flagged_.data(), n_flagged);
  const Real m = mx.d2, v2max = mx.v2;
  guard_.valid_after_drift(m, flagged_.data(), n_flagged, threats_of());  // list_expired() tells the step
  // Spheres may now be beyond a wall: the resolver bounces them in time order with the
  // contacts (walls flip velocities, speeds stay).
  resolver_.set_speed_bound(std::sqrt(v2max));
}

template <class Real, bool Mono>
template <bool Sweep>
void Stepper<Real, Mono>::scan_pair_list() {
  resolver_.clear_candidates();
  const V3<Real>* __restrict pos = pos_.data();
  // Sweep: a pair can have touched within the step only if its gap is below |dv| dt; bound
  // |dv| by twice the fastest speed so the cheap distance test still rejects most pairs.
  Real reach = 0;
  if constexpr (Sweep) {
    Real v2 = 0;
    for (const auto& v : vel_) v2 = std::max(v2, dot(v, v));
    reach = Real(2) * std::sqrt(v2) * h_;
  }
  auto test = [&](std::uint32_t i, std::uint32_t j, std::uint8_t image, V3<Real> d) {
    const Real sg = Mono ? sigma_ : r_[i] + r_[j];
    const Real lim = Sweep ? sg + reach : sg;
    if (dot(d, d) < lim * lim) resolver_.consider(i, j, image, d, sg, !Sweep);
  };
  // Branch-free distance filter over a chunk of the list, then test() (exact) for the few
  // hits: a rejected pair costs no branch and the position loads of a chunk overlap.
  constexpr std::size_t kChunk = 256;
  std::uint32_t hits[kChunk + 4];
  const Pair* __restrict pairs = near_.data();
  static_assert(sizeof(Pair) == 2 * sizeof(std::uint32_t), "pairs as (i, j) words");
  for (std::size_t c0 = 0; c0 < near_.size(); c0 += kChunk) {
    const std::size_t len = std::min(kChunk, near_.size() - c0);
    std::uint32_t n = 0;
    if constexpr (Mono) {
      const Real lim = Sweep ? sigma_ + reach : sigma_;
      n = detail::filter_pairs(pos, reinterpret_cast<const std::uint32_t*>(pairs + c0), std::uint32_t(len),
                               lim * lim * detail::kDistanceFilterSlack<Real>, hits);
    } else {
      for (std::size_t k = 0; k < len; ++k) {
        const Pair p = pairs[c0 + k];
        const Real sg = r_[p.i] + r_[p.j];
        const Real lim = Sweep ? sg + reach : sg;
        hits[n] = std::uint32_t(k);
        n += detail::distance2_filter(pos[p.i], pos[p.j]) < lim * lim * detail::kDistanceFilterSlack<Real>;
      }
    }
    for (std::uint32_t h = 0; h < n; ++h) {
      const Pair p = pairs[c0 + hits[h]];
      test(p.i, p.j, kNoImage, pos[p.i] - pos[p.j]);
    }
  }
  for (std::size_t k = 0; k < wrap_.size(); ++k) {
    const Pair p = wrap_[k];
    test(p.i, p.j, wrap_image_[k], pos[p.i] - pos[p.j] - image_shift_[wrap_image_[k]]);
  }
}

template <class Real, bool Mono>
template <bool AllPeriodic, bool Sweep>
void Stepper<Real, Mono>::step() {
  vote_due_ = bool(agree_);
  // The speed bound is an upper bound of every speed now (set at the drift, raised by each
  // collision), so one comparison tells whether a whole step keeps every path within half
  // the skin; only long steps for the skin are split.
  if (!(resolver_.speed_bound() * dt_ >= half_skin_)) {
    check_work(1);
    if (h_ != dt_) set_substep(dt_);
    substep<AllPeriodic, Sweep>();
  } else {
    split_step<AllPeriodic, Sweep>();
  }
  ++counters_.steps;
  counters_.sim_time += double(dt_);
}

template <class Real, bool Mono>
template <bool AllPeriodic, bool Sweep>
void Stepper<Real, Mono>::split_step() {
  double left = double(dt_);
  while (left > 0) {
    // Collisions may raise the bound: take the sub-step count afresh for what is left.
    const double m = std::max(1.0, std::ceil(left * double(resolver_.speed_bound()) / double(half_skin_)));
    check_work(m);
    const Real h = Real(left / m);
    if (!(h > Real(0)))
      throw InputError("time step dt = " + std::to_string(double(dt_)) +
                       " cannot be split finely enough in this precision");
    set_substep(h);
    const Real done = substep<AllPeriodic, Sweep>();
    left = (m == 1 && done == h) ? 0.0 : left - double(done);
  }
}

template <class Real, bool Mono>
template <bool AllPeriodic, bool Sweep>
Real Stepper<Real, Mono>::substep() {
  // Under gravity the drift is a kick-drift-kick: x += (v + g h/2) h, v += g h, exact for a
  // uniform acceleration; the displacement guard sees the true positions.
  if (has_gravity_) kick(Real(0.5) * h_);
  drift();
  if (has_gravity_) {
    kick(Real(0.5) * h_);
    refresh_speed_bound();
  }
  bool rebuild_due = list_expired();
  if (vote_due_) {  // the first sub-step of a step asks the other engines
    vote_due_ = false;
    rebuild_due = agree_(rebuild_due) || rebuild_due;
  }
  if (rebuild_due) {
    rebuild();
    cover_windows(false);
  }
  scan_pair_list<Sweep>();
  if constexpr (!AllPeriodic) resolver_.predict_all_walls();
  resolver_.set_step_end(clock_ + double(h_));
  Real cut = ContactResolver<Real, Mono>::kWholeStep;
  if (resolver_.has_candidates()) {
    Hooks hooks{*this};
    cut = resolver_.resolve(hooks, tally_);
  }
  if (cut != ContactResolver<Real, Mono>::kWholeStep) {
    // The step ends at the collision that stopped it: every sphere goes back along its path.
    for (std::size_t k = 0; k < pos_.size(); ++k) pos_[k] -= cut * vel_[k];
    if (has_gravity_) {  // back along the parabolas: x(t - c) = x - v c + g c^2 / 2, v - g c
      const V3<Real> g{gravity_[0], gravity_[1], gravity_[2]};
      for (std::size_t k = 0; k < pos_.size(); ++k) {
        pos_[k] += (Real(0.5) * cut * cut) * g;
        vel_[k] -= cut * g;
      }
    }
    ++counters_.step_cuts;
  }
  if (rebuilt_in_step_) uncover_windows();
  resolver_.end_step();
  ++counters_.substeps;
  ++substeps_total_;
  const Real covered = cut == ContactResolver<Real, Mono>::kWholeStep ? h_ : h_ - cut;
  clock_ += double(covered);
  return covered;
}

template <class Real, bool Mono>
ParticleSystem Stepper<Real, Mono>::state() const {
  const std::size_t n = pos_.size();
  std::vector<std::size_t> by_id(n);  // slots are id ranks
  for (std::size_t k = 0; k < n; ++k) by_id[slot_[k]] = k;
  ParticleSystem out;
  out.box = user_box_;
  out.reserve(n);
  for (std::size_t s = 0; s < n; ++s) {
    const std::size_t k = by_id[s];
    Vec3d p = user_position(k);
    for (int d = 0; d < 3; ++d)  // rounding back to the caller's coordinates must not leave a wall
      if (!user_box_.periodic[d])
        p[d] = std::clamp(p[d], user_box_.lo[d] + double(r_[k]), user_box_.hi[d] - double(r_[k]));
    std::array<std::int32_t, 3> image{};
    for (std::size_t d = 0; d < 3; ++d)
      image[d] = std::int32_t(
          std::clamp(std::int64_t(image0_[s][d]) + image_[s][d], std::int64_t(INT32_MIN), std::int64_t(INT32_MAX)));
    out.push_back(id_[s], type_[s], double(r_[k]), double(m_[k]), p,
                  {double(vel_[k].x), double(vel_[k].y), double(vel_[k].z)}, image);
  }
  wrap_periodic(out);
  return out;
}

template <class Real, bool Mono>
SphereSample Stepper<Real, Mono>::sphere(std::size_t index) const {
  const std::size_t n = pos_.size();
  if (index >= n)
    throw InputError("sphere index " + std::to_string(index) + " is out of range (" + std::to_string(n) + " spheres)");
  // Rebuilds move spheres in the cell order; only then is the position searched for again.
  if (slot_[sampled_at_] != index)
    sampled_at_ = std::size_t(std::find(slot_.begin(), slot_.end(), std::uint32_t(index)) - slot_.begin());
  const std::size_t k = sampled_at_;
  SphereSample out;
  out.unwrapped = user_position(k);
  for (std::size_t d = 0; d < 3; ++d)
    if (user_box_.periodic[d])
      out.unwrapped[int(d)] += double(std::int64_t(image0_[index][d]) + image_[index][d]) * user_box_.length(int(d));
  out.velocity = {double(vel_[k].x), double(vel_[k].y), double(vel_[k].z)};
  out.pair_collisions = pair_collisions_.empty() ? -1 : pair_collisions_[k];
  return out;
}

template <class Real>
std::unique_ptr<StepperBase> make_stepper_for(const ParticleSystem& sys, const StepperConfig& cfg) {
  if (cfg.specialise && sys.monodisperse()) return std::make_unique<Stepper<Real, true>>(sys, cfg);
  return std::make_unique<Stepper<Real, false>>(sys, cfg);
}

}  // namespace

std::unique_ptr<StepperBase> make_stepper(const ParticleSystem& sys, const StepperConfig& cfg, Precision precision) {
  if (precision == Precision::Float) return make_stepper_for<float>(sys, cfg);
  return make_stepper_for<double>(sys, cfg);
}

StateExchange& state_exchange(StepperBase& stepper) {
  // Every engine make_stepper builds implements both interfaces.
  return dynamic_cast<StateExchange&>(stepper);
}

}  // namespace hardsphere
