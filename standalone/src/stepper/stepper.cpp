#include "hardsphere/stepper.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "common/default_init_allocator.hpp"
#include "common/jam_guard.hpp"
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
#include "stepper/grid_choice.hpp"
#include "stepper/list_guard.hpp"
#include "stepper/pair_list.hpp"
#include "stepper/smooth_spins.hpp"

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
  // long steps; sweeping costs more, so it is chosen only beyond kOverlapDetectionLimit (see docs/dev/performance.md).
  double smallest = std::numeric_limits<double>::infinity();
  for (const double r : sys.radius) smallest = std::min(smallest, 2 * r);
  return rms_speed(sys) * dt > kOverlapDetectionLimit * smallest;
}

namespace {

template <class Real>
using V3 = Vec3<Real>;

//! Mono: every sphere has the same radius and mass (chosen from the scene by make_stepper).
template <class Real, bool Mono>
class Stepper final : public StepperBase, public StateExchange {
 public:
  //! `physics` as validated() returns it.
  Stepper(const ParticleSystem& sys, const Physics& physics, const StepperConfig& cfg);

  void run(std::int64_t steps) override {
    try {
      run_steps(steps);
    } catch (const JammedSpheres& e) {  // completed in the face's words
      if (collapse_advice_.empty()) throw;
      throw JammedSpheres(e.what() + collapse_advice_);
    }
  }
  void run_steps(std::int64_t steps) {
    // Scene features select a specialised kernel for a stretch of steps, not per pair; Detect::Auto
    // may change the detection mode at a rebuild, which ends the stretch.
    while (steps > 0) {
      const int key = (all_periodic_ ? 2 : 0) + (sweep_ ? 1 : 0);
      switch (key) {
        case 0:
          steps -= run_impl<false, false>(steps);
          break;
        case 1:
          steps -= run_impl<false, true>(steps);
          break;
        case 2:
          steps -= run_impl<true, false>(steps);
          break;
        default:
          steps -= run_impl<true, true>(steps);
          break;
      }
    }
  }
  ParticleSystem state() const override;
  const StepCounters& counters() const override {
    counters_.collisions = tally_.collisions;
    counters_.wall_collisions = tally_.wall_collisions;
    counters_.resting_contacts = tally_.resting_contacts;
    counters_.wall_impulse = tally_.wall_impulse;
    counters_.pair_virial = tally_.virial;
    counters_.pair_virial_tensor = tally_.virial_tensor;
    counters_.unresolved_steps = tally_.unresolved_steps;
    counters_.dissipated_normal = tally_.dissipated_normal;
    counters_.dissipated_tangential = tally_.dissipated_tangential;
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
  void set_collision_observer(CollisionObserver* observer) override {
    observer_ = observer;
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
    clear_kick_residual();
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
      if (!kick_residual_.empty()) kick_residual_[k] = {};
      v2 = std::max(v2, dot(vel_[k], vel_[k]));
    }
    resolver_.set_speed_bound(std::max(resolver_.speed_bound(), std::sqrt(v2) + path_bend()));
  }
  void gather_velocities(const std::uint32_t* src, const double* v) override {
    for (std::size_t k = 0; k < vel_.size(); ++k) {
      const double* vi = v + 3 * std::size_t(src[k]);
      vel_[k] = {Real(vi[0]), Real(vi[1]), Real(vi[2])};
    }
    clear_kick_residual();
    refresh_speed_bound();
  }
  void scatter_omega(const std::uint32_t* dest, double* omega) const override {
    if (omega_.empty()) {  // smooth: the spins carried
      for (std::size_t k = 0; k < slot_.size(); ++k)
        if (dest[k] != kNoRow) {
          const Vec3d w = spins_.at(slot_[k]);
          double* o = omega + 3 * std::size_t(dest[k]);
          o[0] = w.x, o[1] = w.y, o[2] = w.z;
        }
      return;
    }
    for (std::size_t k = 0; k < omega_.size(); ++k) {
      if (dest[k] == kNoRow) continue;
      double* o = omega + 3 * std::size_t(dest[k]);
      o[0] = double(omega_[k].x), o[1] = double(omega_[k].y), o[2] = double(omega_[k].z);
    }
  }
  void gather_omega(const std::uint32_t* src, const double* omega) override {
    if (omega_.empty()) {
      for (std::size_t k = 0; k < slot_.size(); ++k) {
        const double* o = omega + 3 * std::size_t(src[k]);
        spins_.set(slot_[k], {o[0], o[1], o[2]}, slot_.size());
      }
      return;
    }
    for (std::size_t k = 0; k < omega_.size(); ++k) {
      const double* o = omega + 3 * std::size_t(src[k]);
      omega_[k] = {Real(o[0]), Real(o[1]), Real(o[2])};
    }
  }
  void copy_omega(const std::uint32_t* slots, std::size_t count, Vec3d* out) const override {
    for (std::size_t i = 0; i < count; ++i) {
      if (omega_.empty()) {
        out[i] = spins_.at(slot_[slots[i]]);
        continue;
      }
      const auto& w = omega_[slots[i]];
      out[i] = {double(w.x), double(w.y), double(w.z)};
    }
  }
  void set_omega(const std::uint32_t* slots, std::size_t count, const Vec3d* w) override {
    if (omega_.empty()) {
      for (std::size_t i = 0; i < count; ++i) spins_.set(slot_[slots[i]], w[i], slot_.size());
      return;
    }
    for (std::size_t i = 0; i < count; ++i) omega_[slots[i]] = {Real(w[i].x), Real(w[i].y), Real(w[i].z)};
  }
  double iw2_sum() const override {
    double sum = 0;
    for (std::size_t k = 0; k < omega_.size(); ++k)
      sum += inertia_ * double(m_[Mono ? 0 : k]) * double(r_[Mono ? 0 : k]) * double(r_[Mono ? 0 : k]) *
             double(dot(omega_[k], omega_[k]));
    return sum;
  }
  void set_rebuild_agreement(std::function<bool(bool)> agree) override { agree_ = std::move(agree); }
  bool sweep_detection() const override { return sweep_; }
  double step_speed_bound() const override { return double(std::max(step_speed_max_, resolver_.speed_bound())); }
  double substeps_per_step() const override { return substeps_at(double(resolver_.speed_bound())); }
  double substeps_at(double speed) const override {
    return std::max(1.0, std::ceil(speed * double(dt_) / double(half_skin_)));
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

  //! Runs steps while the detection mode stays Sweep; returns the steps taken.
  template <bool AllPeriodic, bool Sweep>
  std::int64_t run_impl(std::int64_t steps) {
    std::int64_t s = 0;
    while (s < steps && sweep_ == Sweep) {
      step<AllPeriodic, Sweep>();
      ++s;
    }
    return s;
  }
  //! Detect::Auto's rule (detects_by_sweep) on the current speeds: v_rms dt against the limit.
  bool sweep_wanted() const {
    double v2 = 0;
    for (const auto& v : vel_) v2 += double(dot(v, v));
    return vel_.empty() ? sweep_ : std::sqrt(v2 / double(vel_.size())) * double(dt_) > sweep_above_;
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
      std::size_t fastest = 0;
      for (std::size_t k = 1; k < vel_.size(); ++k)
        if (dot(vel_[k], vel_[k]) > dot(vel_[fastest], vel_[fastest])) fastest = k;
      std::ostringstream m;
      m << "the run needs more than " << max_particle_steps_ << " particle-steps: with dt = " << double(dt_)
        << " the fastest sphere";
      if (!vel_.empty()) m << ", atom " << id_[slot_[fastest]];
      m << " (speed " << double(resolver_.speed_bound())
        << (omega_.empty() ? "" : ", which rough collisions take from rotation too") << "), needs " << substeps
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
    if (!kick_residual_.empty()) {  // float: see kick_compensated()
      for (int d = 0; d < 3; ++d)
        if (dv[d] != Real(0))
          detail::kick_compensated(&vel_.data()->x, &kick_residual_.data()->x, vel_.size(), d, dv[d]);
      return;
    }
    for (auto& v : vel_) v += dv;
  }
  //! Velocities set from outside: what earlier kicks' rounding lost is not theirs.
  void clear_kick_residual() { std::fill(kick_residual_.begin(), kick_residual_.end(), V3<Real>{}); }
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
  void note_displacement(std::uint32_t i) {
    const V3<Real> d = pos_[i] - pos0_[i];
    guard_.note(i, dot(d, d), threats_of());
  }
  bool list_expired() const { return guard_.expired(); }
  //! For the guard: the spheres j with skin <= gap_ij < 2 kMaxMove skin of sphere i at the last rebuild.
  auto threats_of() {
    return [this](std::uint32_t i, auto&& push) { pairs_.for_each_threat(i, detail::ListGuard<Real>::kMaxMove, push); };
  }

  // The engine works in coordinates relative to the box's lower corner (box_ runs from 0 to
  // L), so single precision resolves a box far from the origin as well as one at it; user_box_
  // and origin_ restore the caller's coordinates on the way out.
  Box box_, user_box_;
  std::array<double, 3> origin_{};
  CellGrid grid_;
  bool all_periodic_, sweep_;
  // Detect::Auto decides again at every rebuild, as speeds change (a mixture heading for
  // equipartition, a gas heated or cooled): sweep once v_rms dt exceeds sweep_above_.
  bool detect_auto_ = false;
  double sweep_above_ = 0;
  Real dt_, skin_;
  Real h_;  // the current sub-step (dt_ unless steps are split)
  // Sub-steps are at most this over the speed bound: a list built at a sub-step's end then
  // covers every path of the sub-step (kept under skin / 2 for rounding).
  Real half_skin_;
  bool rebuilt_in_step_ = false;
  double substeps_total_ = 0, max_particle_steps_;
  Real step_speed_max_ = 0;  //!< the speed bound's largest value in the current step's sub-steps
  std::array<bool, 3> unreached_walls_{false, false, false};
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
  // sweeps are a large part of the loop and speeds stay in cache do their loads pay (see docs/dev/performance.md).
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
  // Candidate pairs within r_i + r_j + skin at the last rebuild, and their adjacency.
  detail::PairList<Real, Mono> pairs_;
  std::vector<V3<Real>> scratch_v3_;
  std::vector<Real> scratch_real_;
  std::vector<std::uint32_t> scratch_u32_;
  ContactResolver<Real, Mono> resolver_;
  ContactTally tally_;
  mutable StepCounters counters_;
  CollisionObserver* observer_ = nullptr;     // set_collision_observer
  std::function<bool(bool)> agree_;           // set_rebuild_agreement
  bool vote_due_ = false;                     // this step has not asked agree_ yet
  std::vector<std::uint32_t> input_of_rank_;  // id rank -> index in the constructor's input
  std::vector<double> last_collision_;        // id order: each sphere's last collision time (restitution < 1)
  // Cell order, like pos_, so a collision's two increments hit lines its spheres' neighbours use too.
  std::vector<std::int64_t> pair_collisions_, scratch_i64_;  // since reset_counters() (if counted)
  // Cell order, 6 per sphere: collision virial since the last take_sphere_virial (if on).
  std::vector<double> sphere_virial_, scratch_virial_;
  mutable std::size_t sampled_at_ = 0;    // sphere()'s last cell-order position: valid until a rebuild
  double clock_ = 0;                      // time since construction, for the collision times
  std::array<Real, 3> gravity_{0, 0, 0};  // uniform acceleration (wall axes only)
  bool has_gravity_ = false;
  std::vector<V3<Real>> kick_residual_;  // cell order, float under gravity only: see kick_compensated()
  std::vector<V3<Real>> omega_;          // angular velocities in cell order, rough scenes only (else empty)
  detail::SmoothSpins spins_;            // smooth scenes: the spins given, unchanged, by id rank
  std::string collapse_advice_;          // added to a jam refusal (inelastic collisions)
  double inertia_ = 0.4;                 // q of I = q m r^2
};

template <class Real, bool Mono>
Stepper<Real, Mono>::Stepper(const ParticleSystem& sys, const Physics& physics, const StepperConfig& cfg)
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
  detect_auto_ = cfg.detect == Detect::Auto;
  if (detect_auto_) {
    double smallest = std::numeric_limits<double>::infinity();
    for (const double r : sys.radius) smallest = std::min(smallest, 2 * r);
    sweep_above_ = kOverlapDetectionLimit * smallest;
  }
  check_scene_numbers(sys, "stepper");
  const double g_norm = std::sqrt(physics.gravity[0] * physics.gravity[0] + physics.gravity[1] * physics.gravity[1] +
                                  physics.gravity[2] * physics.gravity[2]);
  check_engine_numbers<Real>(sys, cfg.dt, sizeof(Real) == sizeof(float) ? "stepper in single precision" : "stepper",
                             g_norm, physics.rough());
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
  const SizeSplit split = split_by_size(sys);
  const detail::GridChoice choice = detail::choose_grid(sys, box_, cfg.cells, cfg.dt, phi_gas, split, physics.gravity);
  grid_ = choice.grid;
  const double diameter = choice.diameter, skin = choice.skin;
  const bool big_pass = choice.big_pass;
  if (!(skin > 0)) {
    // The box is the cause when no grid could do: the grid is automatic, or the axis that limits
    // the reach is a periodic one covered by one or two cells (half its length is all they reach).
    bool box_too_short = auto_cells;
    for (int d = 0; d < 3; ++d)
      if (sys.box.periodic[d] && grid_.counts()[d] < 3 && !(0.5 * sys.box.length(d) > diameter)) box_too_short = true;
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
      m << "cells " << grid_.counts()[0] << "," << grid_.counts()[1] << "," << grid_.counts()[2]
        << " give a cell width of " << grid_.reach() << ", not more than the largest diameter " << diameter
        << "; use fewer cells or --cells auto";
    }
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
  if (physics.rough()) {
    omega_.assign(n, V3<Real>{});
    for (std::size_t i = 0; i < n && sys.omega.size() == n; ++i) {
      const Vec3d& w = sys.omega[by_id[i]];
      omega_[i] = {Real(w.x), Real(w.y), Real(w.z)};
    }
    inertia_ = physics.inertia;
    resolver_.set_roughness({Real(physics.tangential_restitution), Real(physics.friction), Real(physics.inertia)});
  } else {
    spins_.take(sys.omega, by_id);
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
  collapse_advice_ = collapse_advice(physics, cfg.names);
  if (!physics.elastic()) {
    last_collision_.assign(n, -std::numeric_limits<double>::infinity());
    resolver_.set_restitution(Real(physics.restitution), physics.contact_time, last_collision_.data());
  }
  std::array<Real, 3> wall_lo{}, wall_hi{};
  for (std::size_t d = 0; d < 3; ++d) wall_lo[d] = Real(box_.lo[d]), wall_hi[d] = Real(box_.hi[d]);
  unreached_walls_ = cfg.unreached_walls;
  std::array<bool, 3> no_tests = box_.periodic;
  for (std::size_t d = 0; d < 3; ++d) no_tests[d] = no_tests[d] || unreached_walls_[d];
  resolver_.set_walls(no_tests, wall_lo, wall_hi);
  gravity_ = {Real(physics.gravity[0]), Real(physics.gravity[1]), Real(physics.gravity[2])};
  has_gravity_ = physics.has_gravity();
  if (sizeof(Real) == sizeof(float) && has_gravity_) kick_residual_.assign(n, V3<Real>{});
  resolver_.set_gravity(gravity_);
  resolver_.set_resting_time(Real(physics.resting_time));
  pairs_.configure({&grid_, &box_, length_, image_shift_, skin_, sigma_, cell_radius_, max_radius_});
  // Threats are enumerated from the cells within two of a sphere's: every periodic axis needs
  // 3 cells (so a cell is at least sigma + skin wide).
  guard_.configure(skin_, cfg.pairwise_list_check && grid_.half_stencil_ok(), std::max<std::size_t>(n / 32, 16));
  // Speeds pay where the sweeps' extra loads hit the cache: positions and speeds within ~1 MiB
  // (the L2 of this machine's cores); beyond it each speed is one more miss (see docs/dev/performance.md).
  // Under gravity speeds change during the step, so the per-sphere bounds are not used.
  speeds_ = !has_gravity_ && phi_gas >= 0.3 && double(n) * double(sizeof(V3<Real>) + sizeof(Real)) <= 1048576.0;
  rebuild();
  counters_.rebuilds = 0;
  refresh_speed_bound();
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::rebuild() {
  const std::size_t n = pos_.size();
  const Real lo[3] = {Real(box_.lo[0]), Real(box_.lo[1]), Real(box_.lo[2])};
  for (int d = 0; d < 3; ++d)
    if (unreached_walls_[std::size_t(d)])
      for (std::size_t i = 0; i < n; ++i)
        if (!(pos_[i][d] >= lo[d] && pos_[i][d] <= lo[d] + length_[d]))
          throw std::logic_error("stepper: a sphere reached a wall its adapter declared unreached");
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
  scratch_v3_.resize(n), pos0_.resize(n);
  Real *const sx = pairs_.x(n), *const sy = pairs_.y(n), *const sz = pairs_.z(n);
  for (std::size_t k = 0; k < n; ++k) {
    const V3<Real> p = pos_[order_[k]];
    scratch_v3_[k] = p, pos0_[k] = p, sx[k] = p.x, sy[k] = p.y, sz[k] = p.z;
  }
  pos_.swap(scratch_v3_);
  permute(vel_, scratch_v3_);
  if (!kick_residual_.empty()) permute(kick_residual_, scratch_v3_);
  if (!omega_.empty()) permute(omega_, scratch_v3_);
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
  if (observer_) observer_->reordered(order_.data(), n);
  resolver_.permute(order_);
  guard_.reset(n);

  // Candidate list: every pair that could touch before the next rebuild.
  pairs_.build(pos_.data(), r_.data(), cell_start_.data(), n, big_.empty() ? std::uint32_t(n) : big_begin_);
  if (speeds_) {  // in the new order (a rebuild inside a step needs the current speeds)
    speed_.resize(n);
    for (std::size_t k = 0; k < n; ++k) speed_[k] = norm(vel_[k]);
  }
  bind_resolver();
  if (detect_auto_) sweep_ = sweep_wanted();
  ++counters_.rebuilds;
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::bind_resolver() {
  resolver_.bind({pos_.data(), vel_.data(), r_.data(), m_.data(), id_.data(), slot_.data(), pairs_.adj_start(),
                  pairs_.adj(), image_shift_, speeds_ ? speed_.data() : nullptr, pairs_.adj_plain_end(),
                  pair_collisions_.empty() ? nullptr : pair_collisions_.data(),
                  sphere_virial_.empty() ? nullptr : sphere_virial_.data(), observer_,
                  omega_.empty() ? nullptr : omega_.data()});
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
  using Pair = typename detail::PairList<Real, Mono>::Pair;
  const auto& near = pairs_.near();
  const Pair* __restrict pairs = near.data();
  static_assert(sizeof(Pair) == 2 * sizeof(std::uint32_t), "pairs as (i, j) words");
  for (std::size_t c0 = 0; c0 < near.size(); c0 += kChunk) {
    const std::size_t len = std::min(kChunk, near.size() - c0);
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
  const auto& wrap = pairs_.wrap();
  const auto& wrap_image = pairs_.wrap_image();
  for (std::size_t k = 0; k < wrap.size(); ++k) {
    const Pair p = wrap[k];
    test(p.i, p.j, wrap_image[k], pos[p.i] - pos[p.j] - image_shift_[wrap_image[k]]);
  }
}

template <class Real, bool Mono>
template <bool AllPeriodic, bool Sweep>
void Stepper<Real, Mono>::step() {
  vote_due_ = bool(agree_);
  step_speed_max_ = 0;
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
  // The bound as collisions raised it covers this sub-step's speeds; the next drift resets it.
  step_speed_max_ = std::max(step_speed_max_, resolver_.speed_bound());
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
    const Vec3d w =
        omega_.empty() ? spins_.at(s) : Vec3d{double(omega_[k].x), double(omega_[k].y), double(omega_[k].z)};
    out.push_back(id_[s], type_[s], double(r_[k]), double(m_[k]), p,
                  {double(vel_[k].x), double(vel_[k].y), double(vel_[k].z)}, image, w);
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
std::unique_ptr<StepperBase> make_stepper_for(const ParticleSystem& sys, const Physics& physics,
                                              const StepperConfig& cfg) {
  if (cfg.specialise && sys.monodisperse()) return std::make_unique<Stepper<Real, true>>(sys, physics, cfg);
  return std::make_unique<Stepper<Real, false>>(sys, physics, cfg);
}

}  // namespace

std::unique_ptr<StepperBase> make_stepper(const ParticleSystem& sys, const Physics& physics, const StepperConfig& cfg,
                                          Precision precision) {
  const Physics checked = validated(physics, sys.box.periodic);
  if (precision == Precision::Float) return make_stepper_for<float>(sys, checked, cfg);
  return make_stepper_for<double>(sys, checked, cfg);
}

StateExchange& state_exchange(StepperBase& stepper) {
  // Every engine make_stepper builds implements both interfaces.
  return dynamic_cast<StateExchange&>(stepper);
}

}  // namespace hardsphere
