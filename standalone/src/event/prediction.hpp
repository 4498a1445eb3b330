#pragma once
//! The event-driven engine's predictions: each sphere's earliest pair collision (from its
//! neighbour list) and its boundary event (leaving its shell, which calls for a list rebuild, or
//! touching a wall). The second-best collision is kept too: when the best turns stale (its
//! partner collided elsewhere) the second, if still valid, is the sphere's next collision without
//! a rescan (every partner that changed course since has predicted its own events with this
//! sphere). A prediction naming a partner is stale once that partner has collided since: each
//! sphere counts its changes of course, and a prediction records its partner's count.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/always_inline.hpp"
#include "common/neighbour_entry.hpp"
#include "event/geometry.hpp"
#include "event/renumbering.hpp"
#include "event/trajectories.hpp"
#include "hardsphere/collision.hpp"

namespace hardsphere::event {

class Predictions {
 public:
  Predictions() = default;
  //! No events predicted yet; the list centres at the spheres' positions.
  Predictions(const EventGeometry& geo, bool mono, const Trajectories& tr);

  bool collision_first(int i) const { return pred_[std::size_t(i)].col_time <= pred_[std::size_t(i)].bnd_time; }
  int partner(int i) const { return pred_[std::size_t(i)].col_partner; }
  //! Sphere i's best candidate, with partner j, is stale: j has changed course since.
  bool stale(int i, int j) const { return count_[std::size_t(j)] != pred_[std::size_t(i)].col_count; }
  //! The same test where the best candidate may be none.
  bool best_is_stale(int i) const {
    const int j = pred_[std::size_t(i)].col_partner;
    return pred_[std::size_t(i)].col_time < kInf && count_[std::size_t(j)] != pred_[std::size_t(i)].col_count;
  }
  //! The axis of the wall sphere i touches at its boundary event, or -1 for a list rebuild.
  int wall_axis(int i) const {
    const int code = bnd_code_[std::size_t(i)];
    return code / 8 == kRebuild ? -1 : (code / 2) % 4;
  }
  double next_time(int i) const { return std::min(pred_[std::size_t(i)].col_time, pred_[std::size_t(i)].bnd_time); }
  std::vector<double> next_times() const;
  HS_ALWAYS_INLINE void prefetch(int i) const { __builtin_prefetch(&pred_[std::size_t(i)]); }

  //! Sphere i has changed course: the predictions naming it are stale.
  void course_changed(int i) { ++count_[std::size_t(i)]; }
  void set_list_centre(int i, double x, double y, double z) {
    Pred& p = pred_[std::size_t(i)];
    p.cx = x;
    p.cy = y;
    p.cz = z;
  }

  //! Every event of sphere i (synced to now) predicted afresh from the m entries of its list.
  void predict(int i, const Trajectories& tr, const std::uint32_t* list, int m, double now) {
    pred_[std::size_t(i)].col_time = pred_[std::size_t(i)].col2_time = kInf;
    pred_[std::size_t(i)].col_partner = pred_[std::size_t(i)].col2_partner = i;  // "none": counts irrelevant at +inf
    scan_entries(i, tr, list, m, now);
    predict_boundary(i, tr, now);
  }
  //! After a list rebuild of sphere i (synced) that kept its trajectory and valid candidates:
  //! the m new list members scanned and the boundary event predicted from the new centre.
  void predict_new_members(int i, const Trajectories& tr, const std::uint32_t* entries, int m, double now) {
    scan_entries(i, tr, entries, m, now);
    predict_boundary(i, tr, now);
  }
  //! Replaces a stale best candidate by the second best if that one is still valid. The second
  //! slot is then unknown (partner -1) until the next full scan: a partial scan cannot know
  //! what came third, so a later stale best forces a rescan.
  bool promote_second(int i) {
    const std::size_t u = std::size_t(i);
    const int j = pred_[u].col2_partner;
    if (j < 0) return false;
    if (pred_[u].col2_time < kInf && count_[std::size_t(j)] != pred_[u].col2_count) return false;
    pred_[u].col_time = pred_[u].col2_time;
    pred_[u].col_partner = j;
    pred_[u].col_count = pred_[u].col2_count;
    pred_[u].col2_time = kInf;
    pred_[u].col2_partner = -1;
    return true;
  }

  //! Every predicted time made `shift` earlier (the clock is re-based).
  void shift_times(double shift);
  void permute(const Renumbering& r);

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  //! Boundary event codes: kind * 8 + axis * 2 + (direction > 0); a rebuild has no axis.
  enum : std::uint8_t { kRebuild = 0, kWall = 1 };

  //! What an event reads and writes about a sphere besides its motion, in one cache line: the
  //! best and second-best predicted collisions, the next boundary event and the list centre.
  struct alignas(64) Pred {
    double col_time, col2_time, bnd_time;
    double cx, cy, cz;  // list centre
    int col_partner, col2_partner;
    std::uint32_t col_count, col2_count;  // partners' collision counters when predicted
  };

  //! Scans the m list entries `cand` of sphere i (synced to now) for a pair collision earlier
  //! than its current best and second-best candidates.
  template <bool Mono>
  void scan(int i, const Trajectories& tr, const std::uint32_t* cand, int m, double now) {
    const Body& s = tr[std::size_t(i)];
    const std::array<double, 3>& g = tr.gravity();
    const double sigma0 = 2 * s.r;
    // Pass 1: request the partners' states (and collision counters, read for the few that
    // pass the screen) at once, so their cache misses overlap.
    for (int u = 0; u < m; ++u) {
      tr.prefetch(adj_partner(cand[u]));
      __builtin_prefetch(&count_[adj_partner(cand[u])]);
    }
    // Pass 2: relative positions and velocities into flat arrays.
    const std::size_t stride = std::size_t(m + 8) & ~std::size_t(7);
    if (soa_.size() < 6 * stride) soa_.resize(6 * stride);
    if (hits_.size() < stride) hits_.resize(stride);
    double* __restrict rx = soa_.data();
    double* __restrict ry = rx + stride;
    double* __restrict rz = ry + stride;
    double* __restrict ux = rz + stride;
    double* __restrict uy = ux + stride;
    double* __restrict uz = uy + stride;
    if (tr.has_gravity()) {  // partners advanced to now on their parabolas
      for (int u = 0; u < m; ++u) {
        const Body& q = tr[adj_partner(cand[u])];
        const auto& sh = geo_.image_shift(adj_image(cand[u]));
        const double dtj = now - q.t;
        rx[u] = s.x - (q.x + (q.vx + 0.5 * g[0] * dtj) * dtj + sh[0]);
        ry[u] = s.y - (q.y + (q.vy + 0.5 * g[1] * dtj) * dtj + sh[1]);
        rz[u] = s.z - (q.z + (q.vz + 0.5 * g[2] * dtj) * dtj + sh[2]);
        ux[u] = s.vx - (q.vx + g[0] * dtj);
        uy[u] = s.vy - (q.vy + g[1] * dtj);
        uz[u] = s.vz - (q.vz + g[2] * dtj);
      }
    } else {
      for (int u = 0; u < m; ++u) {
        const Body& q = tr[adj_partner(cand[u])];
        const auto& sh = geo_.image_shift(adj_image(cand[u]));
        const double dtj = now - q.t;
        rx[u] = s.x - (q.x + q.vx * dtj + sh[0]);
        ry[u] = s.y - (q.y + q.vy * dtj + sh[1]);
        rz[u] = s.z - (q.z + q.vz * dtj + sh[2]);
        ux[u] = s.vx - q.vx;
        uy[u] = s.vy - q.vy;
        uz[u] = s.vz - q.vz;
      }
    }
    // Pass 3: a branch-free screen of the contact condition: approaching and the lines pass
    // within sigma. Survivors get their contact time from the kernel in pass 4.
    int* __restrict hit = hits_.data();
    int nh = 0;
    for (int u = 0; u < m; ++u) {
      const double sigma = Mono ? sigma0 : s.r + tr[adj_partner(cand[u])].r;
      const double bb = rx[u] * ux[u] + ry[u] * uy[u] + rz[u] * uz[u];
      const double rr = rx[u] * rx[u] + ry[u] * ry[u] + rz[u] * rz[u];
      const double vv = ux[u] * ux[u] + uy[u] * uy[u] + uz[u] * uz[u];
      const double disc = bb * bb - vv * (rr - sigma * sigma);
      hit[nh] = u;
      nh += (bb < 0) & (disc > 0);
    }
    keep_earliest<Mono>(i, tr, cand, nh, now, stride);
  }
  //! scan()'s pass 4: the contact times of the nh candidates that passed the screen (hits_, their
  //! relative states in soa_), kept when earlier than sphere i's best and second-best ones.
  template <bool Mono>
  HS_ALWAYS_INLINE void keep_earliest(int i, const Trajectories& tr, const std::uint32_t* cand, int nh, double now,
                                      std::size_t stride) {
    const Body& s = tr[std::size_t(i)];
    const double sigma0 = 2 * s.r;
    const double* rx = soa_.data();
    const double *ry = rx + stride, *rz = ry + stride, *ux = rz + stride, *uy = ux + stride, *uz = uy + stride;
    const int* hit = hits_.data();
    // Best and second-best candidates (time from now, partner, partner's counter when found).
    double best = pred_[std::size_t(i)].col_time - now, best2 = pred_[std::size_t(i)].col2_time - now;
    int partner = pred_[std::size_t(i)].col_partner, partner2 = pred_[std::size_t(i)].col2_partner;
    std::uint32_t cnt = pred_[std::size_t(i)].col_count, cnt2 = pred_[std::size_t(i)].col2_count;
    const bool second_known = partner2 >= 0;
    for (int h = 0; h < nh; ++h) {
      const int u = hit[h];
      const int j = int(adj_partner(cand[u]));
      const double sigma = Mono ? sigma0 : s.r + tr[std::size_t(j)].r;
      const double t = kernel::contact_time(Vec3d{rx[u], ry[u], rz[u]}, Vec3d{ux[u], uy[u], uz[u]}, sigma);
      if (t < best2) {  // best2 = +inf when the second is unknown
        if (t < best) {
          if (second_known) {
            best2 = best;
            partner2 = partner;
            cnt2 = cnt;
          }
          best = t;
          partner = j;
          cnt = count_[std::size_t(j)];
        } else if (second_known) {
          best2 = t;
          partner2 = j;
          cnt2 = count_[std::size_t(j)];
        }
      }
    }
    if (partner != pred_[std::size_t(i)].col_partner || best + now < pred_[std::size_t(i)].col_time) {
      pred_[std::size_t(i)].col_time = now + best;
      pred_[std::size_t(i)].col_partner = partner;
      pred_[std::size_t(i)].col_count = cnt;
    }
    if (partner2 != pred_[std::size_t(i)].col2_partner || best2 + now < pred_[std::size_t(i)].col2_time) {
      pred_[std::size_t(i)].col2_time = now + best2;
      pred_[std::size_t(i)].col2_partner = partner2;
      pred_[std::size_t(i)].col2_count = cnt2;
    }
  }
  void scan_entries(int i, const Trajectories& tr, const std::uint32_t* cand, int m, double now) {
    if (mono_)
      scan<true>(i, tr, cand, m, now);
    else
      scan<false>(i, tr, cand, m, now);
  }

  //! Next boundary event of sphere i (synced to now): leaving the ball of radius exit_r around
  //! its list centre, or touching a wall that it can reach inside that ball.
  void predict_boundary(int i, const Trajectories& tr, double now) {
    const Body& s = tr[std::size_t(i)];
    const Pred& p = pred_[std::size_t(i)];
    const std::array<double, 3>& g = tr.gravity();
    const bool has_g = tr.has_gravity();
    const double exit_r = geo_.exit_r(), shell = geo_.shell();
    const double pos[3] = {s.x, s.y, s.z}, vel[3] = {s.vx, s.vy, s.vz}, ctr[3] = {p.cx, p.cy, p.cz};
    // |d + v t| = exit_r with d = pos - centre: the positive root of a t^2 + 2 b t + c = 0,
    // c <= 0 inside the ball; each branch is a ratio of same-signed terms (no cancellation).
    const double dx = s.x - p.cx, dy = s.y - p.cy, dz = s.z - p.cz;
    const double a = s.vx * s.vx + s.vy * s.vy + s.vz * s.vz;
    const double b = dx * s.vx + dy * s.vy + dz * s.vz;
    const double cc0 = dx * dx + dy * dy + dz * dz - exit_r * exit_r;
    const double root = std::sqrt(std::max(0.0, b * b - a * cc0));
    double best = kInf;
    if (has_g) {
      // A parabola leaves the ball no earlier than |d| + |v| t + |g| t^2 / 2 = exit_r: a safe
      // (early) rebuild time.
      const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
      const double left = exit_r - std::sqrt(dx * dx + dy * dy + dz * dz), speed = std::sqrt(a);
      best = left <= 0 ? 0.0 : 2 * left / (speed + std::sqrt(speed * speed + 2 * gn * left));
    } else if (a > 0) {
      best = b <= 0 ? (root - b) / a : -cc0 / (b + root);
    }
    std::uint8_t code = kRebuild * 8;
    for (int d = 0; d < 3; ++d) {
      if (geo_.periodic(std::size_t(d))) continue;
      const double v = vel[d];
      const double lo = geo_.lo(std::size_t(d)), hi = lo + geo_.len(std::size_t(d));
      double t;
      if (has_g && g[std::size_t(d)] != 0) {  // the first wall its parabola reaches, moving into it
        if (ctr[d] + shell + s.r < hi && ctr[d] - shell - s.r > lo) continue;
        const double gd = g[std::size_t(d)];
        const double t_lo = kernel::wall_back_time(pos[d], -v, gd, lo + s.r, +1, kInf);
        const double t_hi = kernel::wall_back_time(pos[d], -v, gd, hi - s.r, -1, kInf);
        // Forward in time is backward with the velocity reversed; the side flips with it.
        double tl = t_lo >= 0 ? t_lo : kInf, th = t_hi >= 0 ? t_hi : kInf;
        // On the contact plane (or a hair beyond it) and not leaving: touching now, also at rest
        // with gravity pulling into the wall, where the parabola's double root counts as no crossing.
        if (pos[d] <= lo + s.r && (v < 0 || (v == 0 && gd < 0))) tl = 0;
        if (pos[d] >= hi - s.r && (v > 0 || (v == 0 && gd > 0))) th = 0;
        t = std::min(tl, th);
        if (t < best) {
          best = t;
          code = std::uint8_t(kWall * 8 + d * 2 + (th < tl ? 1 : 0));
        }
        continue;
      }
      // A wall further than exit_r + radius from the centre cannot be reached before the
      // rebuild (tested with the whole shell as margin); the rebuild re-predicts.
      if (v > 0 && ctr[d] + shell + s.r >= hi)
        t = (hi - s.r - pos[d]) / v;
      else if (v < 0 && ctr[d] - shell - s.r <= lo)
        t = (lo + s.r - pos[d]) / v;
      else
        continue;
      if (t < best) {
        best = t;
        code = std::uint8_t(kWall * 8 + d * 2 + (v > 0 ? 1 : 0));
      }
    }
    pred_[std::size_t(i)].bnd_time = now + std::max(0.0, best);
    bnd_code_[std::size_t(i)] = code;
  }

  EventGeometry geo_;
  bool mono_ = true;
  std::vector<Pred> pred_;
  std::vector<std::uint8_t> bnd_code_;
  std::vector<std::uint32_t> count_;  // changes of course so far (stale-prediction test)
  std::vector<double> soa_;           // relative positions/velocities of the candidates of a scan
  std::vector<int> hits_;             // candidates passing the contact screen
};

}  // namespace hardsphere::event
