#include "hardsphere/event_engine.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hardsphere/collision.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/event_calendar.hpp"

namespace hardsphere {

Engine parse_engine(const std::string& s) {
  if (s == "stepper") return Engine::Stepper;
  if (s == "event") return Engine::Event;
  throw InputError("engine '" + s + "' is not one of: stepper, event");
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

//! Everything a pair prediction reads about a sphere, in one cache line.
struct alignas(64) Body {
  double x, y, z;     // position at time t
  double t;           // time of the last update (delayed state)
  double vx, vy, vz;
  double r;           // radius
};

//! A pair candidate gathered by a scan: partner and the periodic image shift of its cell.
struct Candidate {
  int j;
  double sx, sy, sz;
};

//! Boundary event codes: kind * 8 + axis * 2 + (direction > 0).
enum : std::uint8_t { kCrossing = 0, kWall = 1 };

}  // namespace

struct EventEngine::Impl {
  // Scene
  std::array<double, 3> lo{}, len{}, width{};
  std::array<int, 3> nc{};
  std::array<bool, 3> periodic{};
  bool mono = true;
  double mass0 = 1;
  ParticleSystem proto;  // ids, types, radii, masses in input order (positions unused)

  // Spheres in internal (cell-sorted) order
  std::vector<Body> body;
  std::vector<double> mass;
  std::vector<std::uint32_t> count;  // collisions so far (stale-event test)
  std::vector<std::array<int, 3>> cc;  // cell coordinates
  // Cell contents: fixed-capacity slot arrays (grown when a cell overflows), so a scan reads
  // indices sequentially instead of chasing links.
  std::vector<int> slots;               // cell c holds slots[c * cap .. c * cap + fill[c])
  std::vector<int> fill, slot_of;
  int cap = 8;
  int reach = 1;    // stencil half-width in cells
  int stencil = 27; // (2 reach + 1)^3
  std::vector<Candidate> scratch;  // candidate buffer of scan() (stencil * cap entries)
  std::vector<double> soa;         // relative positions/velocities of the candidates
  std::vector<int> hits;           // candidates passing the contact screen
  std::vector<std::uint32_t> orig;     // internal index -> input index

  // Per-sphere predictions: best pair collision and the boundary (crossing or wall) event.
  // The second-best collision is kept too: when the best turns stale (its partner collided
  // elsewhere) the second, if still valid, is the sphere's next collision without a rescan
  // (every partner that changed course since has predicted its own events with this sphere).
  std::vector<double> col_time, bnd_time, col2_time;
  std::vector<int> col_partner, col2_partner;
  std::vector<std::uint32_t> col_count, col2_count;
  std::vector<std::uint8_t> bnd_code;
  EventCalendar calendar;

  double now = 0, base = 0, reset_time = 0;
  std::int64_t events_since_rebase = 0, rebase_every = 0;
  EventCounters c;

  int cell_index(const std::array<int, 3>& k) const { return (k[2] * nc[1] + k[1]) * nc[0] + k[0]; }

  void link(int i) {
    const std::size_t h = std::size_t(cell_index(cc[std::size_t(i)]));
    if (fill[h] == cap) grow();
    slots[h * std::size_t(cap) + std::size_t(fill[h])] = i;
    slot_of[std::size_t(i)] = fill[h]++;
  }
  void unlink(int i) {
    const std::size_t h = std::size_t(cell_index(cc[std::size_t(i)]));
    const int k = slot_of[std::size_t(i)];
    const int last = slots[h * std::size_t(cap) + std::size_t(--fill[h])];
    slots[h * std::size_t(cap) + std::size_t(k)] = last;
    slot_of[std::size_t(last)] = k;
  }
  void grow() {
    const int old = cap;
    cap *= 2;
    std::vector<int> s(fill.size() * std::size_t(cap), -1);
    for (std::size_t h = 0; h < fill.size(); ++h)
      for (int k = 0; k < fill[h]; ++k) s[h * std::size_t(cap) + std::size_t(k)] = slots[h * std::size_t(old) + std::size_t(k)];
    slots.swap(s);
  }

  void sync(Body& s) const {
    const double dt = now - s.t;
    s.x += s.vx * dt;
    s.y += s.vy * dt;
    s.z += s.vz * dt;
    s.t = now;
  }

  //! Cells at offsets lo_off..hi_off from cell c0 along axis d: coordinates and periodic image
  //! shifts (cells beyond a wall are skipped). Returns the count.
  int axis_cells(int c0, int d, int lo_off, int hi_off, int* cells, double* shift) const {
    int k = 0;
    for (int o = lo_off; o <= hi_off; ++o) {
      int c = c0 + o;
      double s = 0;
      if (c < 0) {
        if (!periodic[std::size_t(d)]) continue;
        c += nc[std::size_t(d)];
        s = -len[std::size_t(d)];
      } else if (c >= nc[std::size_t(d)]) {
        if (!periodic[std::size_t(d)]) continue;
        c -= nc[std::size_t(d)];
        s = len[std::size_t(d)];
      }
      cells[k] = c;
      shift[k] = s;
      ++k;
    }
    return k;
  }

  //! Scans the cells at offsets [olo[d], ohi[d]] around sphere i (synced to now) for a pair
  //! collision earlier than its current candidate.
  template <bool Mono>
  void scan(int i, const std::array<int, 3>& olo, const std::array<int, 3>& ohi) {
    const Body& s = body[std::size_t(i)];
    const auto& k = cc[std::size_t(i)];
    int cx[5], cy[5], cz[5];
    double sx[5], sy[5], sz[5];
    const int kx = axis_cells(k[0], 0, olo[0], ohi[0], cx, sx);
    const int ky = axis_cells(k[1], 1, olo[1], ohi[1], cy, sy);
    const int kz = axis_cells(k[2], 2, olo[2], ohi[2], cz, sz);
    // Best and second-best candidates (time from now, partner, partner's counter when found).
    double best = col_time[std::size_t(i)] - now, best2 = col2_time[std::size_t(i)] - now;
    int partner = col_partner[std::size_t(i)], partner2 = col2_partner[std::size_t(i)];
    std::uint32_t cnt = col_count[std::size_t(i)], cnt2 = col2_count[std::size_t(i)];
    const bool second_known = partner2 >= 0;
    const double sigma0 = 2 * s.r;
    // Pass 1: gather the candidates (sequential slot reads) and prefetch their states, so the
    // cache misses of pass 2 overlap instead of queuing behind each other.
    if (scratch.size() < std::size_t(stencil * cap)) scratch.resize(std::size_t(stencil * cap));
    Candidate* cand = scratch.data();
    for (int a = 0; a < kz; ++a)  // the cell rows' slots and fill counts, all requested at once
      for (int b = 0; b < ky; ++b) {
        const int row = (cz[a] * nc[1] + cy[b]) * nc[0];
        for (int e = 0; e < kx; ++e) {
          __builtin_prefetch(&slots[std::size_t(row + cx[e]) * std::size_t(cap)]);
          __builtin_prefetch(&fill[std::size_t(row + cx[e])]);
        }
      }
    int m = 0;
    for (int a = 0; a < kz; ++a)
      for (int b = 0; b < ky; ++b) {
        const int row = (cz[a] * nc[1] + cy[b]) * nc[0];
        for (int e = 0; e < kx; ++e) {
          const std::size_t h = std::size_t(row + cx[e]);
          const int* cell = &slots[h * std::size_t(cap)];
          const int f = fill[h];
          for (int u = 0; u < f; ++u) {
            const int j = cell[u];
            __builtin_prefetch(&body[std::size_t(j)]);
            cand[m] = Candidate{j, sx[e], sy[b], sz[a]};
            m += (j != i);
          }
        }
      }
    // Pass 2: relative positions and velocities into flat arrays (the loads hit prefetched lines).
    if (soa.size() < std::size_t(6 * stencil * cap + 8)) soa.resize(std::size_t(6 * stencil * cap + 8));
    const std::size_t stride = std::size_t(stencil * cap);
    double* __restrict rx = soa.data();
    double* __restrict ry = rx + stride;
    double* __restrict rz = ry + stride;
    double* __restrict ux = rz + stride;
    double* __restrict uy = ux + stride;
    double* __restrict uz = uy + stride;
    for (int u = 0; u < m; ++u) {
      const Body& q = body[std::size_t(cand[u].j)];
      const double dtj = now - q.t;
      rx[u] = s.x - (q.x + q.vx * dtj + cand[u].sx);
      ry[u] = s.y - (q.y + q.vy * dtj + cand[u].sy);
      rz[u] = s.z - (q.z + q.vz * dtj + cand[u].sz);
      ux[u] = s.vx - q.vx;
      uy[u] = s.vy - q.vy;
      uz[u] = s.vz - q.vz;
    }
    // Pass 3: a branch-free (vectorisable) screen of the contact condition: approaching and the
    // lines pass within sigma. Survivors get their contact time from the kernel in pass 4.
    int* __restrict hit = hits.data();
    if (hits.size() < stride) {
      hits.resize(stride);
      hit = hits.data();
    }
    int nh = 0;
    for (int u = 0; u < m; ++u) {
      const double sigma = Mono ? sigma0 : s.r + body[std::size_t(cand[u].j)].r;
      const double bb = rx[u] * ux[u] + ry[u] * uy[u] + rz[u] * uz[u];
      const double rr = rx[u] * rx[u] + ry[u] * ry[u] + rz[u] * rz[u];
      const double vv = ux[u] * ux[u] + uy[u] * uy[u] + uz[u] * uz[u];
      const double disc = bb * bb - vv * (rr - sigma * sigma);
      hit[nh] = u;
      nh += (bb < 0) & (disc > 0);
    }
    // Pass 4: contact times of the survivors, best and second best.
    for (int h = 0; h < nh; ++h) {
      const int u = hit[h];
      const int j = cand[u].j;
      const double sigma = Mono ? sigma0 : s.r + body[std::size_t(j)].r;
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
          cnt = count[std::size_t(j)];
        } else if (second_known) {
          best2 = t;
          partner2 = j;
          cnt2 = count[std::size_t(j)];
        }
      }
    }
    if (partner != col_partner[std::size_t(i)] || best + now < col_time[std::size_t(i)]) {
      col_time[std::size_t(i)] = now + best;
      col_partner[std::size_t(i)] = partner;
      col_count[std::size_t(i)] = cnt;
    }
    if (partner2 != col2_partner[std::size_t(i)] || best2 + now < col2_time[std::size_t(i)]) {
      col2_time[std::size_t(i)] = now + best2;
      col2_partner[std::size_t(i)] = partner2;
      col2_count[std::size_t(i)] = cnt2;
    }
  }

  //! Next cell crossing or wall contact of sphere i (synced to now).
  void predict_boundary(int i) {
    const Body& s = body[std::size_t(i)];
    const double pos[3] = {s.x, s.y, s.z}, vel[3] = {s.vx, s.vy, s.vz};
    double best = kInf;
    std::uint8_t code = 0;
    for (int d = 0; d < 3; ++d) {
      const double v = vel[d];
      const int k = cc[std::size_t(i)][std::size_t(d)];
      double t;
      std::uint8_t kind;
      if (v > 0) {
        if (!periodic[std::size_t(d)] && k == nc[std::size_t(d)] - 1) {
          t = (lo[std::size_t(d)] + len[std::size_t(d)] - s.r - pos[d]) / v;
          kind = kWall;
        } else {
          t = (lo[std::size_t(d)] + double(k + 1) * width[std::size_t(d)] - pos[d]) / v;
          kind = kCrossing;
        }
      } else if (v < 0) {
        if (!periodic[std::size_t(d)] && k == 0) {
          t = (lo[std::size_t(d)] + s.r - pos[d]) / v;
          kind = kWall;
        } else {
          t = (lo[std::size_t(d)] + double(k) * width[std::size_t(d)] - pos[d]) / v;
          kind = kCrossing;
        }
      } else {
        continue;
      }
      if (t < best) {
        best = t;
        code = std::uint8_t(kind * 8 + d * 2 + (v > 0 ? 1 : 0));
      }
    }
    bnd_time[std::size_t(i)] = now + std::max(0.0, best);
    bnd_code[std::size_t(i)] = code;
  }

  void full_predict(int i) {
    ++c.full_predictions;
    sync(body[std::size_t(i)]);
    col_time[std::size_t(i)] = col2_time[std::size_t(i)] = kInf;
    col_partner[std::size_t(i)] = col2_partner[std::size_t(i)] = i;  // "none": counts irrelevant at +inf
    if (mono) scan<true>(i, {-reach, -reach, -reach}, {reach, reach, reach});
    else scan<false>(i, {-reach, -reach, -reach}, {reach, reach, reach});
    predict_boundary(i);
  }

  void schedule(int i) {
    calendar.update(std::uint32_t(i), std::min(col_time[std::size_t(i)], bnd_time[std::size_t(i)]));
  }

  //! Replaces a stale best candidate by the second best if that one is still valid. The second
  //! slot is then unknown (partner -1) until the next full scan: a partial scan cannot know
  //! what came third, so a later stale best forces a rescan.
  bool promote_second(int i) {
    const std::size_t u = std::size_t(i);
    const int j = col2_partner[u];
    if (j < 0) return false;
    if (col2_time[u] < kInf && count[std::size_t(j)] != col2_count[u]) return false;
    col_time[u] = col2_time[u];
    col_partner[u] = j;
    col_count[u] = col2_count[u];
    col2_time[u] = kInf;
    col2_partner[u] = -1;
    return true;
  }

  bool candidate_stale(int i) const {
    const int j = col_partner[std::size_t(i)];
    return col_time[std::size_t(i)] < kInf && count[std::size_t(j)] != col_count[std::size_t(i)];
  }

  void collide(int i, int j) {
    Body& a = body[std::size_t(i)];
    Body& b = body[std::size_t(j)];
    sync(a);
    sync(b);
    Vec3d dr{a.x - b.x, a.y - b.y, a.z - b.z};
    for (int d = 0; d < 3; ++d)  // at contact |dr| <= largest diameter <= L/3: minimum image
      if (periodic[std::size_t(d)]) dr[d] -= len[std::size_t(d)] * std::nearbyint(dr[d] / len[std::size_t(d)]);
    Vec3d va{a.vx, a.vy, a.vz}, vb{b.vx, b.vy, b.vz};
    const double w = mono ? mass0 * kernel::collide_equal_mass(dr, va, vb)
                          : kernel::collide(dr, va, vb, mass[std::size_t(i)], mass[std::size_t(j)]);
    a.vx = va.x; a.vy = va.y; a.vz = va.z;
    b.vx = vb.x; b.vy = vb.y; b.vz = vb.z;
    c.pair_virial += w;
    ++c.collisions;
    ++count[std::size_t(i)];
    ++count[std::size_t(j)];
    full_predict(i);
    full_predict(j);
    schedule(i);
    schedule(j);
  }

  void boundary_event(int i) {
    Body& s = body[std::size_t(i)];
    sync(s);
    const int code = bnd_code[std::size_t(i)];
    const int kind = code / 8, d = (code / 2) % 4, up = code % 2;
    double* pos = d == 0 ? &s.x : (d == 1 ? &s.y : &s.z);
    double* vel = d == 0 ? &s.vx : (d == 1 ? &s.vy : &s.vz);
    if (kind == kWall) {
      c.wall_impulse[std::size_t(d)] += 2 * mass[std::size_t(i)] * std::abs(*vel);
      *vel = -*vel;
      ++c.wall_collisions;
      ++count[std::size_t(i)];
      full_predict(i);
      schedule(i);
      return;
    }
    ++c.cell_crossings;
    unlink(i);
    int& k = cc[std::size_t(i)][std::size_t(d)];
    k += up ? 1 : -1;
    if (k < 0) {
      k += nc[std::size_t(d)];
      *pos += len[std::size_t(d)];
    } else if (k >= nc[std::size_t(d)]) {
      k -= nc[std::size_t(d)];
      *pos -= len[std::size_t(d)];
    }
    link(i);
    if (candidate_stale(i) && !promote_second(i)) {
      full_predict(i);
    } else {
      // The old candidate still holds; only the slab of cells that entered the stencil is new.
      std::array<int, 3> olo{-reach, -reach, -reach}, ohi{reach, reach, reach};
      olo[std::size_t(d)] = ohi[std::size_t(d)] = up ? reach : -reach;
      if (mono) scan<true>(i, olo, ohi);
      else scan<false>(i, olo, ohi);
      predict_boundary(i);
    }
    schedule(i);
  }

  //! Processes the calendar's first entry.
  void step() {
    const int i = int(calendar.top());
    now = calendar.top_key();
    ++c.events;
    if (col_time[std::size_t(i)] <= bnd_time[std::size_t(i)]) {
      const int j = col_partner[std::size_t(i)];
      if (count[std::size_t(j)] != col_count[std::size_t(i)]) {
        ++c.stale_events;
        if (!promote_second(i)) full_predict(i);
        schedule(i);
      } else {
        collide(i, j);
      }
    } else {
      boundary_event(i);
    }
    if (++events_since_rebase >= rebase_every) rebase();
  }

  //! Moves every sphere to the current time and shifts the clock so that now = 0.
  void rebase() {
    events_since_rebase = 0;
    if (now == 0) return;
    for (std::size_t i = 0; i < body.size(); ++i) {
      sync(body[i]);
      body[i].t = 0;
      col_time[i] -= now;
      col2_time[i] -= now;
      bnd_time[i] -= now;
    }
    calendar.shift_keys(now);
    base += now;
    now = 0;
    renumber();
  }

  //! Cells in Morton (Z-curve) order of their coordinates, so cells close in space are close
  //! in this list; spheres are renumbered in this order for memory locality.
  std::vector<int> cell_order;
  void build_cell_order() {
    std::vector<std::pair<std::uint64_t, int>> key;
    key.reserve(fill.size());
    for (int z = 0; z < nc[2]; ++z)
      for (int y = 0; y < nc[1]; ++y)
        for (int x = 0; x < nc[0]; ++x) {
          std::uint64_t m = 0;
          for (int bit = 0; bit < 21; ++bit)
            m |= (std::uint64_t((x >> bit) & 1) << (3 * bit)) | (std::uint64_t((y >> bit) & 1) << (3 * bit + 1)) |
                 (std::uint64_t((z >> bit) & 1) << (3 * bit + 2));
          key.emplace_back(m, cell_index({x, y, z}));
        }
    std::sort(key.begin(), key.end());
    cell_order.resize(key.size());
    for (std::size_t k = 0; k < key.size(); ++k) cell_order[k] = key[k].second;
  }

  //! Renumbers the spheres in cell order (Morton order of the cells). Spheres wander away from
  //! their neighbours in memory as they diffuse; this restores locality. Needs now == 0 or
  //! any time: only indices change, not the physics.
  void renumber() {
    const std::size_t n = body.size();
    std::vector<int> old_of;
    old_of.reserve(n);
    for (int h : cell_order)
      for (int k = 0; k < fill[std::size_t(h)]; ++k) old_of.push_back(slots[std::size_t(h) * std::size_t(cap) + std::size_t(k)]);
    std::vector<int> new_of(n);
    for (std::size_t k = 0; k < n; ++k) new_of[std::size_t(old_of[k])] = int(k);
    auto permute = [&](auto& v) {
      auto w = v;
      for (std::size_t k = 0; k < n; ++k) w[k] = v[std::size_t(old_of[k])];
      v.swap(w);
    };
    permute(body);
    permute(mass);
    permute(count);
    permute(cc);
    permute(orig);
    permute(col_time);
    permute(bnd_time);
    permute(col_partner);
    permute(col_count);
    permute(col2_time);
    permute(col2_partner);
    permute(col2_count);
    permute(bnd_code);
    permute(slot_of);
    for (auto& p : col_partner) p = new_of[std::size_t(p)];
    for (auto& p : col2_partner)
      if (p >= 0) p = new_of[std::size_t(p)];
    for (std::size_t h = 0; h < fill.size(); ++h)
      for (int k = 0; k < fill[h]; ++k) {
        int& x = slots[h * std::size_t(cap) + std::size_t(k)];
        x = new_of[std::size_t(x)];
      }
    std::vector<double> keys(n);
    for (std::size_t k = 0; k < n; ++k) keys[k] = std::min(col_time[k], bnd_time[k]);
    calendar.build(keys);
  }

  void run_until(double t_end_abs) {
    // t_end_abs is measured from construction; the calendar from `base`.
    while (!calendar.empty() && calendar.top_key() <= t_end_abs - base) step();
    now = t_end_abs - base;
  }
};

EventEngine::EventEngine(const ParticleSystem& sys, const EventConfig& cfg) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  const std::size_t n = sys.size();
  if (n > std::size_t(std::numeric_limits<int>::max() / 2)) throw InputError("too many spheres for the event engine");
  if (sys.radius.size() != n || sys.mass.size() != n || sys.vel.size() != n)
    throw InputError("event engine: inconsistent particle arrays");
  m.proto = sys;
  m.mono = sys.monodisperse();
  m.mass0 = n ? sys.mass[0] : 1.0;
  if (cfg.reach < 1 || cfg.reach > 2) throw InputError("event engine: reach " + std::to_string(cfg.reach) + " must be 1 or 2");
  m.reach = cfg.reach;
  m.stencil = (2 * m.reach + 1) * (2 * m.reach + 1) * (2 * m.reach + 1);
  const int min_cells = 2 * m.reach + 1;
  const double dmax = 2 * sys.max_radius();
  const double wmin = dmax / m.reach;
  double cells_total = 1;
  for (std::size_t d = 0; d < 3; ++d) {
    m.lo[d] = sys.box.lo[d];
    m.len[d] = sys.box.length(d);
    m.periodic[d] = sys.box.periodic[d];
    int k = cfg.cells[d];
    if (k == 0) k = int(std::min(1e6, std::floor(m.len[d] / std::max(wmin, 1e-300))));
    if (m.periodic[d] && k < min_cells)
      throw InputError("event engine: periodic axis " + std::string(1, char('x' + d)) + " of length " +
                       std::to_string(m.len[d]) + " needs at least " + std::to_string(min_cells) +
                       " cells of width >= the largest diameter / reach " + std::to_string(wmin));
    k = std::max(k, 1);
    if (cfg.cells[d] > 0 && m.len[d] / k < wmin * (1 - 1e-12))
      throw InputError("event engine: " + std::to_string(k) + " cells on axis " + std::string(1, char('x' + d)) +
                       " are narrower than the largest diameter / reach " + std::to_string(wmin));
    m.nc[d] = k;
    cells_total *= k;
  }
  if (cfg.cells == std::array<int, 3>{0, 0, 0}) {
    const double cap = std::max(double(m.stencil), cfg.max_cells_per_sphere * m.reach * m.reach * m.reach * double(n));
    if (cells_total > cap) {
      const double f = std::cbrt(cells_total / cap);
      for (std::size_t d = 0; d < 3; ++d) m.nc[d] = std::max(m.periodic[d] ? min_cells : 1, int(double(m.nc[d]) / f));
    }
  }
  for (std::size_t d = 0; d < 3; ++d) m.width[d] = m.len[d] / m.nc[d];
  m.fill.assign(std::size_t(m.nc[0]) * std::size_t(m.nc[1]) * std::size_t(m.nc[2]), 0);
  m.cap = m.reach == 1 ? 8 : 2;  // a cell half a diameter wide holds one sphere of that size
  m.slots.assign(m.fill.size() * std::size_t(m.cap), -1);
  m.slot_of.assign(n, 0);

  // Cell of every sphere; internal order sorted by cell for locality.
  std::vector<std::array<int, 3>> k0(n);
  std::vector<Vec3d> p0(sys.pos);
  std::vector<std::int64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) {
      double& x = p0[i][d];
      if (m.periodic[std::size_t(d)]) x -= m.len[std::size_t(d)] * std::floor((x - m.lo[std::size_t(d)]) / m.len[std::size_t(d)]);
      int c = int(std::floor((x - m.lo[std::size_t(d)]) / m.width[std::size_t(d)]));
      k0[i][std::size_t(d)] = std::clamp(c, 0, m.nc[std::size_t(d)] - 1);
    }
    key[i] = m.cell_index(k0[i]);
  }
  m.orig.resize(n);
  for (std::size_t i = 0; i < n; ++i) m.orig[i] = std::uint32_t(i);
  std::stable_sort(m.orig.begin(), m.orig.end(), [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });

  m.body.resize(n);
  m.mass.resize(n);
  m.cc.resize(n);
  m.count.assign(n, 0);
  m.col_time.assign(n, kInf);
  m.bnd_time.assign(n, kInf);
  m.col_partner.assign(n, 0);
  m.col_count.assign(n, 0);
  m.col2_time.assign(n, kInf);
  m.col2_partner.assign(n, 0);
  m.col2_count.assign(n, 0);
  m.bnd_code.assign(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = m.orig[k];
    m.body[k] = Body{p0[i].x, p0[i].y, p0[i].z, 0.0, sys.vel[i].x, sys.vel[i].y, sys.vel[i].z, sys.radius[i]};
    m.mass[k] = sys.mass[i];
    m.cc[k] = k0[i];
    m.link(int(k));
  }
  m.build_cell_order();
  m.renumber();
  for (std::size_t k = 0; k < n; ++k) m.full_predict(int(k));
  std::vector<double> keys(n);
  for (std::size_t k = 0; k < n; ++k) keys[k] = std::min(m.col_time[k], m.bnd_time[k]);
  m.calendar.build(keys);
  m.rebase_every = std::max<std::int64_t>(1000, cfg.rebase_events_per_sphere * std::int64_t(n));
}

EventEngine::~EventEngine() = default;

void EventEngine::advance(double duration) {
  if (!(duration >= 0) || !std::isfinite(duration))
    throw InputError("event engine: run time " + std::to_string(duration) + " must be finite and >= 0");
  impl_->run_until(time() + duration);
}

void EventEngine::advance_events(std::int64_t count) {
  Impl& m = *impl_;
  for (std::int64_t e = 0; e < count && !m.calendar.empty() && m.calendar.top_key() < kInf; ++e) m.step();
}

ParticleSystem EventEngine::state() const {
  const Impl& m = *impl_;
  ParticleSystem out = m.proto;
  for (std::size_t k = 0; k < m.body.size(); ++k) {
    const Body& s = m.body[k];
    const double dt = m.now - s.t;
    const std::size_t i = m.orig[k];
    out.pos[i] = {s.x + s.vx * dt, s.y + s.vy * dt, s.z + s.vz * dt};
    out.vel[i] = {s.vx, s.vy, s.vz};
  }
  wrap_periodic(out);
  return out;
}

const EventCounters& EventEngine::counters() const {
  impl_->c.sim_time = time() - impl_->reset_time;
  return impl_->c;
}

void EventEngine::reset_counters() {
  impl_->c = EventCounters{};
  impl_->reset_time = time();
}

double EventEngine::time() const { return impl_->base + impl_->now; }

std::array<int, 3> EventEngine::cells_per_dim() const { return impl_->nc; }

std::string EventEngine::scene_kernel() const {
  return std::string(impl_->proto.box.all_periodic() ? "periodic" : "walls") + (impl_->mono ? ",mono" : ",poly");
}

}  // namespace hardsphere
