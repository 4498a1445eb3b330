#pragma once
//! In-step contact resolution of the stepper (which the CLI, Python and the LAMMPS fix run).
//!
//! After every sphere has drifted by dt, an engine hands the resolver the pairs that touched
//! within the step (`consider`). The resolver rewinds each to its exact contact time, applies
//! the elastic impulse from the kernel and re-advances, earliest contact first
//! (ties broken by atom ids, so every engine and every MPI rank orders them alike). A collision
//! changes two velocities: their pending predictions are invalidated by per-sphere counters and
//! their contacts over the rest of the step are predicted again from the neighbour lists.
//! The collisions' physics is the kernel's (contact_law.hpp), as in the event engine.
//! Bounces off reflecting walls are events in the same order: a sphere whose straight path ends
//! beyond a wall is mirrored at its wall contact time, and only then are its contacts on the
//! path after the bounce predicted (mirroring at once would skip the path up to the wall).
//!
//! Indices are the engine's local ones (cell order in the stepper, owned + ghost atoms in
//! LAMMPS). Engines own the arrays; the resolver keeps per-sphere windows and counters.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/always_inline.hpp"
#include "common/jam_guard.hpp"
#include "common/neighbour_entry.hpp"
#include "hardsphere/collision.hpp"
#include "hardsphere/contact_law.hpp"
#include "hardsphere/state_exchange.hpp"
#include "hardsphere/vec3.hpp"
#include "stepper/contact_arrays.hpp"
#include "stepper/contact_queue.hpp"
#include "stepper/contact_tally.hpp"
#include "stepper/distance_filter.hpp"
#include "stepper/shape_events.hpp"
#include "stepper/wall_events.hpp"

namespace hardsphere {

//! Mono: every sphere has the diameter `sigma` and mass `mass` given to set_uniform().
template <class Real, bool Mono>
class ContactResolver {
 public:
  //! A pair contact (i < j), or a wall bounce of sphere i (j == kWall, image = the axis, or
  //! kShape + k for shaped wall k).
  struct Candidate {
    std::uint32_t i, j;              // i < j
    std::uint8_t image;              // of r_i - r_j
    Real back;                       // time back from the end of the step to the contact
    std::uint32_t count_i, count_j;  // velocity-change counters when predicted
  };

  //! Per-sphere record packed into one word pair: `back` is the straight-line window (time
  //! since the sphere's last velocity change in this step, dt if none), `count` its changes.
  struct Change {
    Real back;
    std::uint32_t count;
  };

  void reset(std::size_t n, Real dt) {
    dt_ = dt;
    change_.assign(n, Change{dt, 0});
    changed_.clear();
  }
  //! Between steps: the next steps last `dt` (an engine that splits a step into sub-steps).
  void set_step(Real dt) {
    dt_ = dt;
    for (Change& c : change_) c.back = dt;
    changed_.clear();
  }
  Real step() const { return dt_; }
  //! Sphere k's straight-line window: time back from the end of the step to its last velocity
  //! change in this step (the whole step if none).
  Real window(std::uint32_t k) const { return change_[k].back; }
  //! The spheres whose velocity changed in this step so far.
  const std::vector<std::uint32_t>& changed() const { return changed_; }
  //! No contact was left unresolved: resolve() ran the whole step.
  static constexpr Real kWholeStep = Real(-1);
  //! Normal restitution e (1: elastic) with the TC model of inelastic collapse: a collision
  //! within `contact_time` of either sphere's previous one is elastic. `last` (indexed like id)
  //! holds each sphere's last collision time on the clock of set_step_end().
  void set_restitution(Real e, double contact_time, double* last) {
    law_.restitution = e;
    contact_time_ = contact_time;
    last_collision_ = last;
  }
  //! The time at the end of the current step, on the clock of the last collision times.
  void set_step_end(double t) {
    step_end_ = t;
    shapes_.set_step_end(t);
  }
  //! The tangential law of rough spheres, used while ContactArrays::omega is set.
  void set_roughness(const kernel::Roughness<Real>& k) { law_.roughness = k; }
  //! The box faces' laws (kernel::wall_laws()); the default: elastic and smooth.
  void set_wall_laws(const std::array<kernel::WallLaw<Real>, 6>& laws) { wall_laws_ = laws; }
  void set_uniform(Real sigma, Real mass) {
    sigma_ = sigma;
    mass_ = mass;
  }
  void set_event_limit(std::int64_t max_events) { max_events_ = max_events; }
  //! Reflecting walls, gravity and the resting time: see WallEvents (wall_events.hpp).
  void set_walls(const std::array<bool, 3>& periodic, const std::array<Real, 3>& lo, const std::array<Real, 3>& hi) {
    walls_.set_walls(periodic, lo, hi);
  }
  void set_resting_time(Real t) { walls_.set_resting_time(t); }
  void set_gravity(const std::array<Real, 3>& g) {
    walls_.set_gravity(g);
    kinematic_gravity_ = a_.kinematic && (g[0] != Real(0) || g[1] != Real(0) || g[2] != Real(0));
    shapes_.set_gravity(g);
  }
  static constexpr std::uint32_t kWall = 0xffffffffu;
  static constexpr int kShape = 3;
  //! Shaped walls (shape_events.hpp), in the engine's coordinates (origin: its box's lower corner).
  void set_shapes(const Physics& p, const std::array<double, 3>& origin, double extent) {
    shapes_.set_shapes(p, origin, extent);
    shapes_.set_gravity(walls_.gravity());
  }
  void set_shape_rotation(std::size_t k, double omega) { shapes_.set_rotation(k, omega); }
  const std::vector<WallShapeTotals>& shape_totals() const { return shapes_.totals(); }
  void reset_shape_totals() {
    for (WallShapeTotals& t : shapes_.totals()) t = WallShapeTotals{};
  }
  //! An upper bound of every sphere's speed in this step (the resolver raises it after each
  //! collision). It lets neighbour sweeps reject distant partners early; +inf (the default)
  //! disables that, which is always correct.
  void set_speed_bound(Real v_max) { speed_bound_ = v_max; }
  Real speed_bound() const { return speed_bound_; }
  void bind(const ContactArrays<Real>& a) {
    a_ = a;
    const auto& g = walls_.gravity();
    kinematic_gravity_ = a_.kinematic && (g[0] != Real(0) || g[1] != Real(0) || g[2] != Real(0));
  }

  //! After the engine reorders its spheres (new[k] = old[order[k]]), reorder the records too.
  template <class Order>
  void permute(const Order& order) {
    // Between steps every window is the whole step; the counters only tag predictions in
    // flight, and there are none (a rebuild inside resolve() predicts everything anew).
    if (changed_.empty()) return;
    moved_.resize(change_.size());
    for (std::size_t k = 0; k < moved_.size(); ++k) moved_[k] = change_[order[k]];
    change_.swap(moved_);
    changed_.clear();
    for (std::uint32_t k = 0; k < change_.size(); ++k)
      if (change_[k].back != dt_) changed_.push_back(k);
  }

  Real sigma(std::uint32_t i, std::uint32_t j) const {
    if constexpr (Mono)
      return sigma_;
    else
      return a_.radius[i] + a_.radius[j];
  }
  Real radius(std::uint32_t i) const {
    if constexpr (Mono)
      return sigma_ / Real(2);
    else
      return a_.radius[i];
  }
  Real mass(std::uint32_t i) const {
    if constexpr (Mono)
      return mass_;
    else
      return a_.mass[i];
  }

  //! Queues a bounce of sphere s for each wall its path over its window ends beyond.
  void predict_walls(std::uint32_t s) {
    const Change cs = change_[s];
    walls_.predict(a_.pos[s], a_.vel[s], radius(s), cs.back, [&](int d, Real back) {
      candidates_.push_back({s, kWall, std::uint8_t(d), back, cs.count, 0});
    });
    if (shapes_.any()) predict_shapes(s);
  }
  //! The shaped walls' part of predict_walls(), out of line: the faces' part stays small enough
  //! to be inlined into the step loop (scenes without shaped walls cost what they did).
  [[gnu::noinline]] void predict_shapes(std::uint32_t s) {
    const Change cs = change_[s];
    shapes_.predict(a_.pos[s], a_.vel[s], radius(s), cs.back, [&](std::size_t k, Real back) {
      candidates_.push_back({s, kWall, std::uint8_t(kShape + k), back, cs.count, 0});
    });
  }
  //! predict_walls() for every sphere (after a scan).
  void predict_all_walls() {
    if (!walls_.any() && !shapes_.any()) return;
    for (std::uint32_t s = 0; s < change_.size(); ++s) predict_walls(s);
  }

  //! Queues (i, j), i < j, if the pair touched while approaching within its common
  //! straight-line window; `overlap_only` is the seed's test (the pair overlaps now).
  //! Walls: the general loops, where kinematic spheres under gravity may be (their pairs go to
  //! consider_kinematic()); the all-periodic scan and the loop without walls never test for them.
  template <bool Walls = true>
  HS_ALWAYS_INLINE void consider(std::uint32_t i, std::uint32_t j, std::uint8_t image, Vec3<Real> dr, Real sigma,
                                 bool overlap_only) {
    const Vec3<Real> dv = a_.vel[i] - a_.vel[j];
    const Change ci = change_[i], cj = change_[j];
    const Real w = std::min(ci.back, cj.back);
    const Real back = kernel::touched_back_time(dr, dv, sigma, w, overlap_only);
    if (kinematic_gravity_ && (a_.kinematic[i] | a_.kinematic[j]))
      return consider_kinematic(i, j, image, dr, sigma, back);
    if (back >= Real(0)) candidates_.push_back({i, j, image, std::min(back, w), ci.count, cj.count});
  }
  //! consider() for a free and a kinematic sphere under gravity (kinematic_contacts.hpp).
  void consider_kinematic(std::uint32_t i, std::uint32_t j, std::uint8_t image, Vec3<Real> dr, Real sigma,
                          Real straight);

  //! Predicts every contact of sphere s with its list partners over its window.
  void sweep_neighbours(std::uint32_t s) {
    const std::uint32_t none[1] = {kWall};
    if (a_.speed)
      sweep_neighbours<true, 1>(&s, none);
    else
      sweep_neighbours<false, 1>(&s, none);
  }
  //! The same for both spheres of a collision, except with each other: they recede on straight
  //! lines for their whole windows (the test would only reject them, at a consider() each).
  template <bool Walls = true>
  void sweep_collided(std::uint32_t i, std::uint32_t j) {
    const std::uint32_t s[2] = {i, j}, skip[2] = {j, i};
    if (a_.speed)
      sweep_neighbours<true, 2, Walls>(s, skip);
    else
      sweep_neighbours<false, 2, Walls>(s, skip);
  }

  //! A partner can have touched s within s's window w only if their gap is below the closing
  //! distance |v_s - v_q| w <= (|v_s| + |v_q|) w, or (|v_s| + v_max) w without per-sphere
  //! speeds: that test needs no velocity vector or window of q, so most partners are rejected
  //! cheaply (the 1.001 absorbs rounding; the bound is loose by far more). It runs branch-free
  //! over the whole lists of all `Count` spheres first (a rejected partner costs no mispredicted
  //! branch, and the loads of both lists overlap); only the survivors go to consider().
  template <bool Speeds, int Count, bool Walls = true>
  void sweep_neighbours(const std::uint32_t* sphere, const std::uint32_t* skip) {
    const std::uint32_t* __restrict adj = a_.adj;
    const Vec3<Real>* __restrict pos = a_.pos;
    const Vec3<Real>* __restrict shift = a_.image_shift;
    std::uint32_t len = 0;
    for (int t = 0; t < Count; ++t) len += a_.adj_start[sphere[t] + 1] - a_.adj_start[sphere[t]];
    if (near_.size() < len + 4) near_.resize(2 * len + 8);  // the vector filter stores four at a time
    std::uint32_t* __restrict hits = near_.data();
    // Appends the list entries of s that pass the filter to hits[m...], returns the new m.
    auto filter = [&](const std::uint32_t s, const std::uint32_t skip_s, std::uint32_t m) {
      const Vec3<Real> ps = a_.pos[s];
      const Real w = Real(1.001) * change_[s].back;
      const Real reach = Speeds ? Real(0) : (norm(a_.vel[s]) + speed_bound_) * w;
      const Real reach_s = Speeds ? a_.speed[s] * w : Real(0);
      const std::uint32_t k0 = a_.adj_start[s], k1 = a_.adj_start[s + 1];
      const std::uint32_t plain = a_.adj_plain_end ? a_.adj_plain_end[s] : k0;
      std::uint32_t k = k0;
#ifdef HS_DISTANCE_FILTER_SIMD
      if constexpr (Mono && Speeds && sizeof(Real) == sizeof(float)) {  // four at a time (distance_filter.hpp)
        m = detail::filter_partners(ps, sigma_ + reach_s, w, skip_s, adj, pos, a_.speed, k, plain, hits, m);
        k = plain;
      }
#endif
      // Entries [from, to); Shifted: with their images (entries without one need no shift, and
      // skipping the zero shift gives the same dr bit for bit).
      auto scalar = [&](auto shifted, std::uint32_t from, std::uint32_t to) {
        for (std::uint32_t k = from; k < to; ++k) {
          const std::uint32_t e = adj[k], q = adj_partner(e);
          Vec3<Real> dr = ps - pos[q];
          if constexpr (decltype(shifted)::value) dr -= shift[adj_image(e)];
          const Real far = Speeds ? (sigma(s, q) + reach_s) + a_.speed[q] * w : sigma(s, q) + reach;
          hits[m] = k;
          m += (dot(dr, dr) < far * far) & (q != skip_s);
        }
      };
      scalar(std::false_type{}, k, plain);
      scalar(std::true_type{}, plain, k1);
      return m;
    };
    std::uint32_t n[Count + 1] = {0};
    for (int t = 0; t < Count; ++t) n[t + 1] = filter(sphere[t], skip[t], n[t]);
    for (int t = 0; t < Count; ++t) {
      const std::uint32_t s = sphere[t];
      const Vec3<Real> ps = a_.pos[s];
      for (std::uint32_t h = n[t]; h < n[t + 1]; ++h) {
        const std::uint32_t e = adj[hits[h]], q = adj_partner(e);
        const std::uint8_t img = adj_image(e);
        const Vec3<Real> dr = ps - pos[q] - shift[img];
        // Candidates keep the lower index first so their order matches a full scan.
        if (s < q)
          consider<Walls>(s, q, img, dr, sigma(s, q), false);
        else
          consider<Walls>(q, s, std::uint8_t(26 - img), -dr, sigma(s, q), false);
      }
    }
  }

  bool has_candidates() const { return !candidates_.empty(); }
  void clear_candidates() { candidates_.clear(); }

  //! Resolves the queued contacts and bounces in time order. Hooks (engine specific):
  //!   void after_collision(std::uint32_t k, Real back)  sphere k changed velocity at `back`
  //!   void after_bounce(std::uint32_t k)  sphere k bounced off a wall
  //!   void prefetch(std::uint32_t k) const  request what the two above will read of sphere k
  //!                        (called a few contacts ahead; must be forced inline, see always_inline.hpp)
  //!   bool must_rescan()   the neighbour lists are no longer valid (e.g. skin exceeded)
  //!   bool rescan(Real back)  rebuild them, bind() again and consider() every touching pair;
  //!                        false if lists cannot cover the spheres' windows (a sphere too fast)
  //! Returns kWholeStep, or the back time of the collision after which rescan() refused: the
  //! step then ends there, with every contact after it dropped; the engine moves every sphere
  //! back by that time (its positions are end-of-step positions) and runs the rest again.
  template <class Hooks>
  Real resolve(Hooks& hooks, ContactTally& tally) {
    // Periodic scenes skip every wall test; smooth ones every rough test (their loop is the one
    // they had before rough spheres).
    // Kinematic spheres under gravity take the walls' loop, whose sweeps test their pairs (consider()).
    const bool walls = walls_.any() || shapes_.any() || kinematic_gravity_;
    if (a_.omega) return walls ? resolve_impl<true, true>(hooks, tally) : resolve_impl<false, true>(hooks, tally);
    if (walls) return resolve_impl<true, false>(hooks, tally);
    return resolve_impl<false, false>(hooks, tally);
  }

  //! Every sphere starts the next step with a whole-step straight-line window.
  void end_step() {
    for (const std::uint32_t i : changed_) change_[i].back = dt_;
    changed_.clear();
  }

 private:
  template <bool Walls, bool Rough, class Hooks>
  Real resolve_impl(Hooks& hooks, ContactTally& tally) {
    // The contacts found by the scan are sorted once; those predicted after collisions go to
    // a queue (contact_queue.hpp), and the earlier of the two fronts is taken each time.
    auto cmp = [this](const Candidate& x, const Candidate& y) { return later(x, y); };
    auto start_run = [&] {
      order_by_time(candidates_, sorted_);
      candidates_.clear();
      queue_.reset(dt_);
      return std::size_t(0);
    };
    std::size_t next = start_run();
    std::int64_t events = 0;
    JamGuard jam(1e-9 * double(dt_), change_.size());
    Real cut = kWholeStep;
    while (next < sorted_.size() || !queue_.empty()) {
      Candidate c;
      if (queue_.empty() || (next < sorted_.size() && !later(sorted_[next], queue_.top()))) {
        prefetch_ahead<Rough>(next, hooks);
        c = sorted_[next++];
      } else {
        c = queue_.pop(cmp);
      }
      const bool wall = Walls && c.j == kWall;
      if (c.count_i != change_[c.i].count || (!wall && c.count_j != change_[c.j].count)) continue;  // stale
      if (jam.jammed(-double(c.back))) jam.refuse("stepper", id(c.i), wall ? -1 : id(c.j));
      if (++events > max_events_) {
        ++tally.unresolved_steps;
        settle_walls<Rough>(hooks, tally);
        break;
      }
      if constexpr (Walls) {
        if (wall ? !bounce<Rough>(c, hooks, tally) : !collide<Rough>(c, hooks, tally)) continue;
      } else if (!collide<Rough>(c, hooks, tally)) {
        continue;
      }
      if (hooks.must_rescan()) {
        if (!hooks.rescan(c.back)) {
          cut = c.back;
          break;
        }
        predict_all_walls();  // rescan() refilled candidates_ from the rebuilt lists
        next = start_run();
        continue;
      }
      const std::uint32_t moved = wall ? c.i : free_of(c.i, c.j);
      if (moved == kWall) {
        sweep_collided<Walls>(c.i, c.j);
      } else {  // a bounce, or a free sphere off a kinematic one: only it moved
        const std::uint32_t skip[1] = {moved == c.i ? c.j : c.i};
        if (a_.speed)
          sweep_neighbours<true, 1, Walls>(&moved, skip);
        else
          sweep_neighbours<false, 1, Walls>(&moved, skip);
      }
      if constexpr (Walls) {
        predict_walls(c.i);
        if (!wall) predict_walls(c.j);
      }
      for (const auto& n : candidates_) queue_.push(n, cmp);
      candidates_.clear();
    }
    candidates_.clear();
    sorted_.clear();
    queue_.reset(dt_);
    return cut;
  }

  //! In a large system the scan's contacts, taken in time order, land anywhere in memory, and a
  //! collision then waits on its spheres' records, list rows and partners' positions in turn
  //! (see docs/dev/performance.md). Request them for the contacts a few places ahead in three
  //! stages, each reading only what the stage before brought in.
  template <bool Rough, class Hooks>
  HS_ALWAYS_INLINE void prefetch_ahead(std::size_t next, const Hooks& hooks) const {
    constexpr std::size_t kRecords = 6, kRows = 4, kPartners = 2, kPrefetchPartnersAbove = 16384;
    const std::size_t n = sorted_.size();
    if (next + kRecords < n) {
      const Candidate& c = sorted_[next + kRecords];
      for (const std::uint32_t k : {c.i, c.j}) {
        if (k == kWall) continue;
        __builtin_prefetch(&a_.adj_start[k]);
        __builtin_prefetch(&a_.pos[k]);
        __builtin_prefetch(&a_.vel[k]);
        if constexpr (Rough) __builtin_prefetch(&a_.omega[k]);
        __builtin_prefetch(&change_[k]);
        hooks.prefetch(k);
      }
    }
    if (next + kRows < n) {
      const Candidate& c = sorted_[next + kRows];
      for (const std::uint32_t k : {c.i, c.j})
        if (k != kWall) __builtin_prefetch(&a_.adj[a_.adj_start[k]]);
    }
    // Partners only in systems whose positions do not sit in L2 anyway: in smaller ones the loop
    // over every partner costs more than it hides (see docs/dev/performance.md).
    if (next + kPartners < n && change_.size() > kPrefetchPartnersAbove) {
      const Candidate& c = sorted_[next + kPartners];
      for (const std::uint32_t k : {c.i, c.j}) {
        if (k == kWall) continue;
        for (std::uint32_t e = a_.adj_start[k]; e < a_.adj_start[k + 1]; ++e) {
          const std::uint32_t q = adj_partner(a_.adj[e]);
          __builtin_prefetch(&a_.pos[q]);
          if (a_.speed) __builtin_prefetch(&a_.speed[q]);
        }
      }
    }
  }

  //! Records a velocity change of sphere i that happened `back` before the end of the step.
  void mark_changed(std::uint32_t i, Real back) {
    if (change_[i].back == dt_) changed_.push_back(i);  // first change this step
    change_[i].back = back;
    ++change_[i].count;
  }

  //! Heap order: the earliest contact (largest back time) on top; ties by atom ids.
  bool later(const Candidate& x, const Candidate& y) const {
    if (x.back != y.back) return x.back < y.back;
    return tie_key(x) > tie_key(y);
  }
  //! (lower id, higher id) of a pair; (id, -1 - axis) of a bounce, so no pair shares its key.
  std::pair<std::int64_t, std::int64_t> tie_key(const Candidate& c) const {
    if (c.j == kWall) return {id(c.i), -1 - std::int64_t(c.image)};
    return std::minmax(id(c.i), id(c.j));
  }
  std::int64_t id(std::uint32_t i) const { return a_.id_slot ? a_.id[a_.id_slot[i]] : a_.id[i]; }
  std::uint32_t id_index(std::uint32_t i) const { return a_.id_slot ? a_.id_slot[i] : i; }
  //! TC model: a collision `back` before the step's end is elastic if either sphere collided
  //! within contact_time_ before it.
  bool collided_recently(std::uint32_t i, std::uint32_t j, Real back) const {
    return kernel::tc_elastic(step_end_ - double(back), last_collision_[id_index(i)], last_collision_[id_index(j)],
                              contact_time_);
  }

  //! Sphere c.i's bounce off the wall of axis c.image, `c.back` before the end of the step: the
  //! wall law at the contact (kernel::collide_wall()), then its end-of-step position and velocity.
  template <bool Rough, class Hooks>
  bool bounce(const Candidate& c, Hooks& hooks, ContactTally& tally) {
    if (c.image >= kShape) return bounce_shape<Rough>(c, hooks, tally);
    const std::uint32_t i = c.i;
    const int d = c.image;
    const Real back = c.back;
    Real &x = a_.pos[i][d], &v = a_.vel[i][d];
    const auto& gravity = walls_.gravity();
    const Vec3<Real> g{gravity[0], gravity[1], gravity[2]};
    const auto wall = walls_.contact(x, v, d, radius(i), back);
    const kernel::WallLaw<Real>& law = wall_laws_[std::size_t(2 * d + (wall.side > 0))];
    // The law sees the velocity at contact; a resting sphere hops for the rest of the step.
    const auto out = kernel::collide_wall<Rough>(law, d, wall.side, a_.vel[i] - back * g, g[d],
                                                 walls_.resting_time(dt_), back, Rough ? a_.omega + i : nullptr,
                                                 mass(i), radius(i), [&] { return collided_recently(i, i, back); });
    if (law.restitution != Real(1) && !out.rested) last_collision_[id_index(i)] = step_end_ - double(back);
    walls_.reflect(x, v, d, radius(i), back, wall, out);
    tally.wall_dissipated_normal += out.contact.dissipated_normal;
    tally.wall_dissipated_tangential += out.contact.dissipated_tangential;
    // Rough spheres: the tangential change at contact moves the position by back times it.
    if constexpr (Rough) {
      a_.vel[i] += out.dv;
      a_.pos[i] += back * out.dv;
      tally.dissipated_normal += out.contact.dissipated_normal;
      tally.dissipated_tangential += out.contact.dissipated_tangential;
      const Real speed = norm(a_.vel[i]);
      speed_bound_ = std::max(speed_bound_, speed);
      if (a_.speed) a_.speed[i] = speed;
    }
    if (out.rested) {
      ++tally.resting_contacts;
    } else {
      ++tally.wall_collisions;
      if (a_.observer) a_.observer->bounce(i);
    }
    tally.wall_impulse[std::size_t(d)] += double(Mono ? mass_ : a_.mass[i]) * out.impulse;
    mark_changed(i, back);
    hooks.after_bounce(i);
    return true;
  }

  //! Sphere c.i's contact with shaped wall c.image - kShape, `c.back` before the end of the step
  //! (ShapeEvents::collide()), then the tallies and re-predictions as for a face.
  template <bool Rough, class Hooks>
  bool bounce_shape(const Candidate& c, Hooks& hooks, ContactTally& tally) {
    const std::uint32_t i = c.i;
    const std::size_t k = std::size_t(c.image - kShape);
    const auto out = shapes_.template collide<Rough>(k, a_.pos[i], a_.vel[i], Rough ? a_.omega + i : nullptr, radius(i),
                                                     mass(i), c.back, walls_.resting_time(dt_),
                                                     [&] { return collided_recently(i, i, c.back); });
    if (!out.changed) return false;  // receding at the contact
    if (out.placed) {                // only put back on the surface: no contact
      tally.wall_work += out.work;
      mark_changed(i, c.back);
      hooks.after_bounce(i);
      return true;
    }
    if (shapes_.law(k).restitution != 1 && !out.rested) last_collision_[id_index(i)] = step_end_ - double(c.back);
    if constexpr (Rough) {
      tally.dissipated_normal += out.dissipated_normal;
      tally.dissipated_tangential += out.dissipated_tangential;
    }
    tally.wall_dissipated_normal += out.dissipated_normal;
    tally.wall_dissipated_tangential += out.dissipated_tangential;
    tally.wall_work += out.work;
    const Real speed = norm(a_.vel[i]);
    speed_bound_ = std::max(speed_bound_, speed);
    if (a_.speed) a_.speed[i] = speed;
    if (out.rested) {
      ++tally.resting_contacts;
    } else {
      ++tally.wall_collisions;
      if (a_.observer) a_.observer->bounce(i);
    }
    mark_changed(i, c.back);
    hooks.after_bounce(i);
    return true;
  }

  //! When the event limit stops a step, spheres may still be beyond a wall: mirror them (their
  //! paths are not checked again, as for the contacts left).
  template <bool Rough, class Hooks>
  void settle_walls(Hooks& hooks, ContactTally& tally) {
    const std::size_t mark = candidates_.size();
    predict_all_walls();
    for (std::size_t k = mark; k < candidates_.size(); ++k) {
      Candidate c = candidates_[k];
      c.back = std::min(c.back, change_[c.i].back);  // another axis of c.i may have bounced first
      bounce<Rough>(c, hooks, tally);
    }
    candidates_.resize(mark);
  }

  void order_by_time(const std::vector<Candidate>& in, std::vector<Candidate>& out) {
    auto earlier = [this](const Candidate& x, const Candidate& y) { return later(y, x); };
    hardsphere::order_by_time(in, out, dt_, earlier, bucket_start_, bucket_fill_);
  }

  //! A pair collision at its contact, `c.back` before the end of the step: the pair law
  //! (contact_law.hpp) at the rewound positions, then commit_collision(). Rough: in the loop
  //! instantiated for rough spheres, so the smooth loop compiles as it did without them.
  template <bool Rough, class Hooks>
  bool collide(const Candidate& c, Hooks& hooks, ContactTally& tally) {
    const std::uint32_t i = c.i, j = c.j;
    if (a_.kinematic && (a_.kinematic[i] | a_.kinematic[j])) return collide_kinematic<Rough>(c, hooks, tally);
    Vec3<Real> ri = a_.pos[i], rj = a_.pos[j], vi = a_.vel[i], vj = a_.vel[j];
    const Vec3<Real> shift = a_.image_shift[c.image];
    // A candidate that is not stale was predicted from this very state and these windows, so
    // its rewind time stands. (Computing it again put a square root and a division on the
    // critical path of every collision; the two evaluations could also differ in the last bit.)
    const Real back = c.back;
    ri -= back * vi;
    rj -= back * vj;
    const Vec3<Real> contact = ri - rj - shift;
    const Vec3<Real> vi_before = vi;
    const kernel::PairRule rule = kernel::pair_rule(law_, [&] { return collided_recently(i, j, back); });
    Vec3<Real> wi{}, wj{};
    if constexpr (Rough) wi = a_.omega[i], wj = a_.omega[j];
    const kernel::ContactOutcome out = kernel::collide_pair<Rough, false>(law_, rule, contact, vi, vj, &wi, &wj,
                                                                          mass(i), mass(j), radius(i), radius(j), Mono);
    // Summed before the check, as the reference totals were: a float virial that rounds to 0 (the
    // double one tiny) still counts the energy its uncommitted collision would have taken.
    if constexpr (Rough) {
      tally.dissipated_normal += out.dissipated_normal;
      tally.dissipated_tangential += out.dissipated_tangential;
    }
    if (!out.changed) return false;  // receding at the rewound contact: nothing to resolve
    if constexpr (Rough) a_.omega[i] = wi, a_.omega[j] = wj;
    return commit_collision(i, j, ri, rj, vi, vj, vi_before, contact, back, out.virial, hooks, tally);
  }

  //! The free sphere of a pair with a kinematic one; kWall for two free spheres (or two kinematic ones).
  std::uint32_t free_of(std::uint32_t i, std::uint32_t j) const {
    if (!a_.kinematic || a_.kinematic[i] == a_.kinematic[j]) return kWall;
    return a_.kinematic[i] ? j : i;
  }

  //! A free sphere's contact with a kinematic one (kinematic_contacts.hpp).
  template <bool Rough, class Hooks>
  bool collide_kinematic(const Candidate& c, Hooks& hooks, ContactTally& tally);

  //! What every resolved pair collision records: the TC clock, the virial, the new positions and
  //! velocities at the end of the step, the speed bound, counts, observers and re-predictions.
  template <class Hooks>
  HS_ALWAYS_INLINE bool commit_collision(std::uint32_t i, std::uint32_t j, Vec3<Real> ri, Vec3<Real> rj, Vec3<Real> vi,
                                         Vec3<Real> vj, Vec3<Real> vi_before, Vec3<Real> contact, Real back,
                                         double virial, Hooks& hooks, ContactTally& tally) {
    if (law_.restitution != Real(1))
      last_collision_[id_index(i)] = last_collision_[id_index(j)] = step_end_ - double(back);
    const double mi = Mono ? double(mass_) : double(a_.mass[i]);
    const Vec3<Real> dvi = vi - vi_before;
    const double dp[3] = {mi * double(dvi.x), mi * double(dvi.y), mi * double(dvi.z)};
    const double r[3] = {double(contact.x), double(contact.y), double(contact.z)};
    tally.virial_tensor[0] += r[0] * dp[0];
    tally.virial_tensor[1] += r[1] * dp[1];
    tally.virial_tensor[2] += r[2] * dp[2];
    tally.virial_tensor[3] += r[0] * dp[1];
    tally.virial_tensor[4] += r[0] * dp[2];
    tally.virial_tensor[5] += r[1] * dp[2];
    // a_.vel still holds both velocities before the collision.
    if (a_.transport)
      a_.transport->collision(double(back), r, mi, to_double(a_.vel[i]), to_double(vi),
                              Mono ? double(mass_) : double(a_.mass[j]), to_double(a_.vel[j]), to_double(vj));
    a_.pos[i] = ri + back * vi;
    a_.pos[j] = rj + back * vj;
    a_.vel[i] = vi;
    a_.vel[j] = vj;
    const Real speed_i = norm(vi), speed_j = norm(vj);
    speed_bound_ = std::max({speed_bound_, speed_i, speed_j});
    if (a_.speed) a_.speed[i] = speed_i, a_.speed[j] = speed_j;
    ++tally.collisions;
    tally.virial += virial;
    if (a_.pair_collisions) ++a_.pair_collisions[i], ++a_.pair_collisions[j];
    if (a_.sphere_virial || a_.observer) {
      const double t[6] = {r[0] * dp[0], r[1] * dp[1], r[2] * dp[2], r[0] * dp[1], r[0] * dp[2], r[1] * dp[2]};
      if (a_.sphere_virial) add_sphere_virial(i, j, t);
      if (a_.observer) a_.observer->collision(i, j, t, virial);
    }
    for (const std::uint32_t k : {i, j}) {
      mark_changed(k, back);
      hooks.after_collision(k, back);
    }
    return true;
  }

  static Vec3d to_double(const Vec3<Real>& v) { return {double(v.x), double(v.y), double(v.z)}; }

  //! Half of a collision's r (x) dp to each of its spheres (ContactArrays::sphere_virial).
  void add_sphere_virial(std::uint32_t i, std::uint32_t j, const double* t) {
    for (const std::uint32_t s : {i, j})
      for (std::size_t k = 0; k < 6; ++k) a_.sphere_virial[6 * std::size_t(s) + k] += 0.5 * t[k];
  }

  ContactArrays<Real> a_;
  Real dt_ = 0, sigma_ = 0, mass_ = 0;
  kernel::PairLaw<Real> law_;  // normal restitution (1: elastic); the tangential law while a_.omega is set
  std::array<kernel::WallLaw<Real>, 6> wall_laws_{};  // the box faces' (kFaceNames order)
  double contact_time_ = 0, step_end_ = 0;
  double* last_collision_ = nullptr;  // id-indexed last collision times (law_.restitution < 1 only)
  Real speed_bound_ = std::numeric_limits<Real>::infinity();
  std::int64_t max_events_ = 100000000;
  std::vector<Change> change_, moved_;  // moved_: scratch for permute()
  std::vector<std::uint32_t> changed_;
  std::vector<Candidate> candidates_, sorted_;
  ContactQueue<Candidate, Real> queue_;
  std::vector<std::uint32_t> bucket_start_, bucket_fill_;  // order_by_time() scratch
  std::vector<std::uint32_t> near_;                        // sweep scratch: list entries that pass the distance test
  WallEvents<Real> walls_;
  bool kinematic_gravity_ = false;  // kinematic spheres under gravity: consider_kinematic()
  ShapeEvents<Real> shapes_;
};

}  // namespace hardsphere

#include "stepper/kinematic_contacts.hpp"  // NOLINT: the kinematic members, defined after the class
