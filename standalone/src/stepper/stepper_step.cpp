//! The fixed-step engine's step loop: each step drifts, rebuilds the pair list when due, finds the
//! pairs that touch and resolves them (ContactResolver), in sub-steps where the step is long for the
//! skin; the scene's features pick a specialised kernel for a stretch of steps.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>

#include "stepper/close_pairs_row.hpp"
#include "stepper/distance_filter.hpp"
#include "stepper/gap_search.hpp"
#include "stepper/stepper_engine.hpp"

namespace hardsphere::detail {

template <class Real, bool Mono>
void Stepper<Real, Mono>::run_steps(std::int64_t steps) {
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
template <bool Sweep, bool Walls>
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
    if (dot(d, d) < lim * lim) resolver_.template consider<Walls>(i, j, image, d, sg, !Sweep);
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
  if (has_gravity_) kick(Real(0.5) * h_), keep_kinematic();
  drift();
  if (transport_) transport_->advance(double(h_));
  if (has_gravity_) {
    kick(Real(0.5) * h_), keep_kinematic();
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
  // Moving walls' predictions need the step's end on the clock.
  resolver_.set_step_end(clock_ + double(h_));
  scan_pair_list<Sweep, !AllPeriodic>();  // kinematic spheres never take the all-periodic kernel
  if constexpr (!AllPeriodic) resolver_.predict_all_walls();
  Real cut = ContactResolver<Real, Mono>::kWholeStep;
  if (resolver_.has_candidates()) {
    Hooks hooks{*this};
    cut = resolver_.resolve(hooks, tally_);
  }
  if (cut != ContactResolver<Real, Mono>::kWholeStep) {
    // The step ends at the collision that stopped it: every sphere goes back along its path.
    for (std::size_t k = 0; k < pos_.size(); ++k) pos_[k] -= cut * vel_[k];
    if (transport_) transport_->advance(-double(cut));  // the collisions' changes counted from the old end
    if (has_gravity_) {  // back along the parabolas: x(t - c) = x - v c + g c^2 / 2, v - g c
      const V3<Real> g{gravity_[0], gravity_[1], gravity_[2]};
      for (std::size_t k = 0; k < pos_.size(); ++k) {
        pos_[k] += (Real(0.5) * cut * cut) * g;
        vel_[k] -= cut * g;
      }
      for (const std::uint32_t k : kin_at_) pos_[k] -= (Real(0.5) * cut * cut) * g;  // on straight lines
      keep_kinematic();
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
void Stepper<Real, Mono>::check_kinematic_reach(std::int64_t steps) const {
  // A kinematic sphere is not stopped by a wall (it has infinite mass): a run that would carry one
  // into a wall is refused before it starts, so nothing passes through a wall unseen.
  const double t = double(steps) * double(dt_);
  for (const std::uint32_t k : kin_at_)
    for (int d = 0; d < 3; ++d) {
      if (box_.periodic[d] || vel_[k][d] == Real(0)) continue;
      const double x = double(pos_[k][d]) + double(vel_[k][d]) * t, r = double(r_[k]);
      if (x - r >= box_.lo[d] && x + r <= box_.hi[d]) continue;
      const double wall = vel_[k][d] > Real(0) ? box_.hi[d] - r : box_.lo[d] + r;
      std::ostringstream m;
      m << "kinematic atom " << id_[slot_[k]] << " moving at " << double(vel_[k][d]) << " along "
        << "xyz"[d] << " reaches the wall after " << (wall - double(pos_[k][d])) / double(vel_[k][d])
        << " time units, within this run of " << steps << " steps (" << t
        << "): kinematic spheres pass through nothing, so shorten the run or stop the sphere before the wall";
      throw InputError(m.str());
    }
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::index_kinematic() {
  kin_at_.clear();
  if (kin_rank_.empty()) return;
  kin_.resize(pos_.size());
  for (std::uint32_t k = 0; k < pos_.size(); ++k) {
    kin_[k] = kin_rank_[slot_[k]];
    if (kin_[k]) kin_at_.push_back(k);
  }
}

template void Stepper<float, true>::check_kinematic_reach(std::int64_t) const;
template void Stepper<float, true>::index_kinematic();
template void Stepper<float, false>::check_kinematic_reach(std::int64_t) const;
template void Stepper<float, false>::index_kinematic();
template void Stepper<double, true>::check_kinematic_reach(std::int64_t) const;
template void Stepper<double, true>::index_kinematic();
template void Stepper<double, false>::check_kinematic_reach(std::int64_t) const;
template void Stepper<double, false>::index_kinematic();
template void Stepper<float, true>::run_steps(std::int64_t);
template void Stepper<float, false>::run_steps(std::int64_t);
template void Stepper<double, true>::run_steps(std::int64_t);
template void Stepper<double, false>::run_steps(std::int64_t);

}  // namespace hardsphere::detail
