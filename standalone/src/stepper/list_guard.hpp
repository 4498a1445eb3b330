#pragma once
//! When must the stepper's pair list be rebuilt? The list holds every pair closer than
//! sigma_ij + skin at the last rebuild, so it stays complete while every unlisted pair has
//! d_i + d_j < gap_ij = |X_i - X_j| - sigma_ij (>= skin), d the displacement since the rebuild.
//! The classic sufficient test, every d < skin / 2, expires as soon as the fastest sphere of
//! all has moved half the skin, while a typical sphere has moved far less. This guard asks the
//! pairwise question instead, for the few spheres past skin / 2 ("movers"):
//!  - two non-movers are safe (each d < skin / 2);
//!  - every d must stay below kMaxMove skin, so only pairs with gap_ij < 2 kMaxMove skin can
//!    ever touch: a mover i is checked against these, its "threats", listed once when i
//!    becomes a mover.
//! So the list outlives the classic test's half skin and rebuilds are rarer (see docs/dev/performance.md).
//! d is each sphere's largest recorded displacement since the rebuild (recorded at every step
//! end and after every velocity change; in between a sphere moves on straight segments whose
//! distance from X is largest at an end), so the test covers the whole time since the rebuild.
//! Within a step only colliding spheres move on: a mover that collides is checked again, and
//! any other sphere against a cap, the displacement at which it would meet a mover's margin.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/always_inline.hpp"

namespace hardsphere::detail {

template <class Real>
class ListGuard {
 public:
  //! Largest displacement allowed, in skins (a larger one needs longer threat lists).
  static constexpr Real kMaxMove = Real(0.85);

  //! pairwise = false keeps the classic test (grids where threats cannot be enumerated).
  void configure(Real skin, bool pairwise, std::size_t max_movers) {
    skin2_ = skin * skin;
    quarter_skin2_ = skin2_ / Real(4);
    max_move2_ = kMaxMove * kMaxMove * skin2_;
    pairwise_ = pairwise;
    max_movers_ = max_movers;
  }
  //! At a rebuild: nothing has moved.
  void reset(std::size_t n) {
    d2_.assign(n, Real(0));
    limit_.assign(n, quarter_skin2_);
    mover_.assign(n, 0);
    movers_.clear();
    threats_.clear();
    max_d2_ = 0;
    expired_ = false;
  }

  Real* displacements() { return d2_.data(); }  //!< d^2 per sphere, raised by the engine's drift
  Real max_displacement2() const { return max_d2_; }
  //! After the engine wrote displacements() itself: their largest. Right after reset() every
  //! d^2 written must stay below skin^2 / 4 (no movers yet), e.g. the paths of the current step
  //! before a rebuild, which the resolver may still look back along.
  void set_max_displacement2(Real max_d2) { max_d2_ = max_d2; }
  Real quarter_skin2() const { return quarter_skin2_; }
  //! What note(k) will read (for engines that request it ahead, see always_inline.hpp).
  HS_ALWAYS_INLINE void prefetch(std::uint32_t k) const {
    __builtin_prefetch(&d2_[k]);
    __builtin_prefetch(&limit_[k]);
  }

  //! After every sphere has drifted and raised its d^2 (the largest of them given): is the
  //! list still complete? `threats(i, push)` must call push(j, gap_ij) for every sphere j
  //! with skin <= gap_ij < 2 kMaxMove skin (a few listed ones more do no harm; gap rounded down).
  template <class Threats>
  bool valid_after_drift(Real max_d2, Threats&& threats) {
    return after_drift(max_d2, threats, [&](auto&& visit) {
      for (std::uint32_t i = 0; i < d2_.size(); ++i)
        if (!visit(i)) return false;
      return true;
    });
  }
  //! The same, told which spheres may be past skin / 2 (in index order; more do no harm):
  //! the engine's drift collects them, so a step does not look at every sphere again.
  template <class Threats>
  bool valid_after_drift(Real max_d2, const std::uint32_t* candidates, std::size_t n_candidates, Threats&& threats) {
    return after_drift(max_d2, threats, [&](auto&& visit) {
      for (std::size_t k = 0; k < n_candidates; ++k)
        if (!visit(candidates[k])) return false;
      return true;
    });
  }
  //! The squared displacement past which the drift must report a sphere to the overload above.
  Real candidate_d2() const { return quarter_skin2_; }

  //! Sphere k moved on after a velocity change inside the step; d2 is its new displacement^2.
  template <class Threats>
  void note(std::uint32_t k, Real d2, Threats&& threats) {
    if (expired_ || d2 <= d2_[k]) return;
    d2_[k] = d2;
    max_d2_ = std::max(max_d2_, d2);
    if (d2 < limit_[k]) return;  // a non-mover within its cap
    if (d2 < quarter_skin2_) {   // past the cap a mover set
      expired_ = true;
      return;
    }
    if (!pairwise_ || d2 >= max_move2_) {
      expired_ = true;
      return;
    }
    if (!mover_[k] && !add_mover(k, threats)) return;
    check(movers_[mover_[k] - 1]);
  }

  bool expired() const { return expired_; }
  std::size_t movers() const { return movers_.size(); }

 private:
  struct Mover {
    std::uint32_t i, first, last;  // threats_[first, last)
  };
  struct Threat {
    std::uint32_t j;
    Real gap;
  };
  static constexpr Real kInf = std::numeric_limits<Real>::infinity();

  template <class Threats, class ForEachCandidate>
  bool after_drift(Real max_d2, Threats& threats, ForEachCandidate&& for_each_candidate) {
    max_d2_ = max_d2;
    if (Real(4) * max_d2 < skin2_) return !expired_;  // no movers: the classic test holds
    if (!pairwise_ || max_d2 >= max_move2_) return !(expired_ = true);
    const bool added = for_each_candidate(
        [&](std::uint32_t i) { return !(d2_[i] >= quarter_skin2_ && !mover_[i] && !add_mover(i, threats)); });
    if (!added) return false;
    for (const Mover& m : movers_)  // caps are set afresh from the movers' new displacements
      for (std::uint32_t t = m.first; t < m.last; ++t)
        if (!mover_[threats_[t].j]) limit_[threats_[t].j] = quarter_skin2_;
    for (const Mover& m : movers_)
      if (!check(m)) return false;
    return !expired_;
  }

  template <class Threats>
  bool add_mover(std::uint32_t i, Threats& threats) {
    if (movers_.size() >= max_movers_) return !(expired_ = true);  // a rebuild is cheaper now
    const std::uint32_t first = std::uint32_t(threats_.size());
    threats(i, [this](std::uint32_t j, Real gap) { threats_.push_back({j, gap}); });
    movers_.push_back({i, first, std::uint32_t(threats_.size())});
    mover_[i] = std::uint32_t(movers_.size());
    limit_[i] = -kInf;  // every move of a mover is checked
    return true;
  }

  //! d_i + d_j < gap for each threat j of mover m, and j's cap for the rest of the step.
  bool check(const Mover& m) {
    const Real di = std::sqrt(d2_[m.i]);
    for (std::uint32_t t = m.first; t < m.last; ++t) {
      const Threat& th = threats_[t];
      const Real room = th.gap - di;  // what j may still move
      if (!(room > Real(0)) || d2_[th.j] >= room * room) return !(expired_ = true);
      if (!mover_[th.j]) limit_[th.j] = std::min(limit_[th.j], room * room);
    }
    return true;
  }

  Real skin2_ = 0, quarter_skin2_ = 0, max_move2_ = 0, max_d2_ = 0;
  bool pairwise_ = false, expired_ = false;
  std::size_t max_movers_ = 0;
  std::vector<Real> d2_;
  //! Per sphere, the d^2 up to which note() has nothing to check: skin^2 / 4 lowered to the
  //! caps of the movers near it, -inf for a mover.
  std::vector<Real> limit_;
  std::vector<std::uint32_t> mover_;  // 1 + index into movers_, 0 if not a mover
  std::vector<Mover> movers_;
  std::vector<Threat> threats_;
};

}  // namespace hardsphere::detail
