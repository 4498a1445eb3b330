#pragma once
//! The fixed-step engine behind make_stepper, declared once for the files that each do one of its
//! jobs: stepper_build.cpp (construction and validation), stepper_step.cpp (the step loop),
//! stepper_rebuild.cpp (cell sort, permutation and pair list) and stepper_exchange.cpp (the
//! StateExchange interface and the state out).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/jam_guard.hpp"
#include "hardsphere/collision.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/state_exchange.hpp"
#include "hardsphere/stepper.hpp"
#include "scene/cell_grid.hpp"
#include "scene/size_classes.hpp"
#include "stepper/contact_resolver.hpp"
#include "stepper/drift_kernel.hpp"
#include "stepper/grid_choice.hpp"
#include "stepper/list_guard.hpp"
#include "stepper/pair_list.hpp"
#include "stepper/smooth_spins.hpp"

namespace hardsphere::detail {

template <class Real>
using V3 = Vec3<Real>;

//! Mono: every sphere has the same radius and mass (chosen from the scene by make_stepper).
template <class Real, bool Mono>
class Stepper final : public StepperBase, public StateExchange {
 public:
  //! `physics` as validated() returns it.
  Stepper(const ParticleSystem& sys, const Physics& physics, const StepperConfig& cfg);

  void run(std::int64_t steps) override {
    if (!kin_at_.empty()) check_kinematic_reach(steps);
    try {
      run_steps(steps);
    } catch (const JammedSpheres& e) {  // completed in the face's words
      if (collapse_advice_.empty()) throw;
      throw JammedSpheres(e.what() + collapse_advice_);
    }
  }
  void set_gravity(const std::array<double, 3>& g) override;
  std::array<double, 3> gravity() const override { return gravity_in_; }
  void set_shape_rotation(std::size_t k, double omega) override { resolver_.set_shape_rotation(k, omega); }
  //! Runs the steps in stretches of one specialised kernel (stepper_step.cpp).
  void run_steps(std::int64_t steps);
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
    counters_.wall_dissipated_normal = tally_.wall_dissipated_normal;
    counters_.wall_dissipated_tangential = tally_.wall_dissipated_tangential;
    counters_.kinematic_collisions = tally_.kinematic_collisions;
    counters_.kinematic_work = tally_.kinematic_work;
    counters_.wall_work = tally_.wall_work;
    if (!resolver_.shape_totals().empty()) counters_.shapes = resolver_.shape_totals();
    return counters_;
  }
  void reset_counters() override {
    counters_ = StepCounters{};
    tally_ = ContactTally{};
    resolver_.reset_shape_totals();
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
  void set_transport(TransportTally* tally) override {
    transport_ = tally;
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
  void copy(SphereField field, const std::uint32_t* slots, std::size_t count, Vec3d* out) const override;
  void set(SphereField field, const std::uint32_t* slots, std::size_t count, const Vec3d* in) override;
  void scatter(SphereField field, const std::uint32_t* dest, double* out) const override;
  void gather(SphereField field, const std::uint32_t* src, const double* in) override;
  void scatter_state(const std::uint32_t* dest, const Vec3d* shift, double* x, double* v) const override;
  double mv2_sum() const override;
  double iw2_sum() const override;
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
  // The engine's SphereField list (stepper_exchange.cpp): each field's value in slot k, as
  // StateExchange reads and writes it. A new per-sphere quantity is one more accessor and one
  // more case in with_field().
  struct PositionField;
  struct VelocityField;
  struct OmegaField;
  template <class Fn>
  static void with_field(SphereField field, Fn&& fn);
  //! After set() or gather() wrote a field: velocities set from outside clear the kick residual
  //! and bound the speeds (recomputed when all were written, raised by the given ones otherwise).
  void field_written(SphereField field, const std::uint32_t* slots, std::size_t count);

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
      s.template scan_pair_list<true, true>();
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
  //! Gravity does not act on kinematic spheres: their velocities are put back after each kick.
  void keep_kinematic() {
    for (const std::uint32_t k : kin_at_) vel_[k] = kin_vel_[slot_[k]];
  }
  void check_kinematic_reach(std::int64_t steps) const;
  void index_kinematic();
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
  template <bool Sweep, bool Walls>
  void scan_pair_list();
  void rebuild();
  void bind_resolver();
  // Construction in named steps (stepper_build.cpp), run by the constructor in this order.
  static void check_config(const ParticleSystem& sys, const Physics& physics, const StepperConfig& cfg);
  void set_detection(const ParticleSystem& sys, const StepperConfig& cfg);
  //! The cell grid and the pair-list skin; refuses a scene no grid can serve.
  GridChoice choose_cells(const ParticleSystem& sys, const Physics& physics, const StepperConfig& cfg, double phi_gas,
                          const SizeSplit& split);
  void set_lengths(double skin, const StepperConfig& cfg);
  void load_spheres(const ParticleSystem& sys, const Physics& physics, const StepperConfig& cfg);
  void mark_big(const SizeSplit& split, bool big_pass);
  void configure_resolver(const Physics& physics, const StepperConfig& cfg);
  void configure_lists(const StepperConfig& cfg, double phi_gas);
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
  TransportTally* transport_ = nullptr;       // set_transport
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
  // Kinematic spheres (ParticleSystem::kinematic; all empty when none): flags and constant
  // velocities by id rank, flags in cell order (bound in the resolver) and their cell positions.
  std::vector<std::uint8_t> kin_rank_, kin_;
  std::vector<V3<Real>> kin_vel_;
  std::vector<std::uint32_t> kin_at_;
  std::string collapse_advice_;         // added to a jam refusal (inelastic collisions)
  PhysicsNames names_;                  // the adapter's names, for set_gravity's refusals
  std::array<double, 3> gravity_in_{};  // gravity as validated (gravity_ is it in Real)
  double inertia_ = 0.4;                // q of I = q m r^2
};

}  // namespace hardsphere::detail
