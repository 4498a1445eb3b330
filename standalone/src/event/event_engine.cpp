#include "hardsphere/event_engine.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/neighbour_entry.hpp"
#include "event/event_calendar.hpp"
#include "hardsphere/collision.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/format.hpp"
#include "hardsphere/scene_limits.hpp"
#include "scene/size_classes.hpp"

namespace hardsphere {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

//! Everything a pair prediction reads about a sphere, in one cache line.
struct alignas(64) Body {
  double x, y, z;  // position at time t
  double t;        // time of the last update (delayed state)
  double vx, vy, vz;
  double r;  // radius
};

//! A sphere's list centre (its position when its neighbour list was built) and radius: what a
//! rebuild reads about each sphere of the cells around, two per cache line.
struct Centre {
  double x, y, z, r;
};

//! What an event reads and writes about a sphere besides its motion, in one cache line: the
//! best and second-best predicted collisions, the next boundary event and the list centre.
struct alignas(64) Pred {
  double col_time, col2_time, bnd_time;
  double cx, cy, cz;  // list centre
  int col_partner, col2_partner;
  std::uint32_t col_count, col2_count;  // partners' collision counters when predicted
};

//! Neighbour-list entries are adj_entry(j, image) (neighbour_entry.hpp) with
//! image = (sx+1) + 3 (sy+1) + 9 (sz+1), s = -1, 0, 1 the box lengths added to the partner's
//! position per axis. The partner's entry for the owner has image kImages - 1 - image (all
//! shifts negated).
constexpr int kImages = 27;

//! Neighbour lists start on cache-line boundaries, so a list of up to 16 entries is one line.
constexpr std::size_t kPerLine = 64 / sizeof(std::uint32_t);

//! Boundary event codes: kind * 8 + axis * 2 + (direction > 0); a rebuild has no axis.
enum : std::uint8_t { kRebuild = 0, kWall = 1 };

}  // namespace

struct EventEngine::Impl {
  // Scene
  std::array<double, 3> lo{}, len{}, width{};
  std::array<int, 3> nc{};
  std::array<bool, 3> periodic{};
  bool mono = true;
  // Uniform acceleration along wall axes: flights are parabolas; relative motion stays straight.
  std::array<double, 3> g{0, 0, 0};
  bool has_g = false;
  double mass0 = 1;
  double shell = 0;      // neighbour-list shell (length units)
  double exit_r = 0;     // displacement from the list centre that triggers a rebuild (< shell / 2)
  ParticleSystem proto;  // ids, types, radii, masses in input order (positions unused)
  std::array<std::array<double, 3>, kImages> image_shift{};  // image code -> shift of the partner

  // Spheres in internal (cell-sorted) order
  std::vector<Body> body;
  std::vector<double> mass;
  std::vector<std::uint32_t> count;    // collisions so far (stale-event test)
  std::vector<std::array<int, 3>> cc;  // cell coordinates of the list centre
  // Cell contents (by list centre): fixed-capacity slot arrays, grown when a cell overflows.
  // The centres are stored in the cells too, so a rebuild reads each cell sequentially
  // instead of chasing one cache line per sphere.
  std::vector<int> slots;        // cell c holds slots[c * cap .. c * cap + fill[c])
  std::vector<Centre> cell_ctr;  // the centres of those spheres, same layout
  std::vector<int> fill, slot_of;
  int cap = 8;
  int reach = 1;  // stencil half-width in cells
  // Big spheres (split_by_size) are not filed in cells, which are sized for the others: they
  // take the indices [nsmall, n) in every order, every rebuild tests their centres in one pass,
  // and a big sphere's own rebuild scans every cell its range overlaps.
  int nsmall = 0;
  double grid_r = 0;                                // largest radius of the spheres in cells
  std::vector<double> big_x, big_y, big_z, big_r;   // list centres of the big spheres (i - nsmall)
  std::vector<double> big_gap;                      // scratch: squared distance - squared range
  std::vector<std::vector<std::uint32_t>> big_nbr;  // their lists, long and sized one by one
  // Neighbour lists: sphere i holds nbr[i * ncap .. i * ncap + nfill[i]) (grown on overflow).
  // Symmetric: j is in i's list iff i is in j's.
  std::vector<std::uint32_t> nbr;  // list i starts at nbr[nbase + i * ncap], nbase aligns it
  std::size_t nbase = 0;
  std::vector<int> nfill;
  int ncap = 16;
  std::vector<std::uint64_t> mark;  // rebuild bookkeeping: stamp of the last rebuild that saw j
  std::uint64_t stamp = 0;
  std::vector<std::uint32_t> old_list, fresh;      // rebuild buffers
  std::vector<double> soa;                         // relative positions/velocities of the candidates of a scan
  std::vector<int> hits;                           // candidates passing the contact screen
  std::vector<std::uint32_t> orig;                 // internal index -> input index
  std::vector<std::array<std::int64_t, 3>> wraps;  // input index: box lengths removed by wrapping
  std::vector<std::int64_t> pair_collisions;       // input index: pair collisions since reset_counters()
  mutable std::size_t sampled_at = 0;              // sphere()'s last internal index: valid until a renumber
  double restitution = 1.0, contact_time = 0.0;
  std::vector<double> last_collision;  // input index: time of the last collision (restitution < 1)

  // Per-sphere predictions: best pair collision and the boundary (rebuild or wall) event.
  // The second-best collision is kept too: when the best turns stale (its partner collided
  // elsewhere) the second, if still valid, is the sphere's next collision without a rescan
  // (every partner that changed course since has predicted its own events with this sphere).
  std::vector<Pred> pred;
  std::vector<std::uint8_t> bnd_code;
  EventCalendar calendar;

  double now = 0, base = 0, reset_time = 0;
  std::int64_t events_since_rebase = 0, rebase_every = 0;
  EventCounters c;

  Centre ctr_of(int i) const {
    const Pred& p = pred[std::size_t(i)];
    return {p.cx, p.cy, p.cz, body[std::size_t(i)].r};
  }

  int cell_index(const std::array<int, 3>& k) const { return (k[2] * nc[1] + k[1]) * nc[0] + k[0]; }

  std::array<int, 3> cell_of(double x, double y, double z) const {
    const double p[3] = {x, y, z};
    std::array<int, 3> k{};
    for (std::size_t d = 0; d < 3; ++d) k[d] = std::clamp(int(std::floor((p[d] - lo[d]) / width[d])), 0, nc[d] - 1);
    return k;
  }

  void link(int i) {
    const std::size_t h = std::size_t(cell_index(cc[std::size_t(i)]));
    if (fill[h] == cap) grow();
    slots[h * std::size_t(cap) + std::size_t(fill[h])] = i;
    cell_ctr[h * std::size_t(cap) + std::size_t(fill[h])] = ctr_of(i);
    slot_of[std::size_t(i)] = fill[h]++;
  }
  void unlink(int i) {
    const std::size_t h = std::size_t(cell_index(cc[std::size_t(i)]));
    const int k = slot_of[std::size_t(i)];
    const std::size_t from = h * std::size_t(cap) + std::size_t(--fill[h]);
    const int last = slots[from];
    slots[h * std::size_t(cap) + std::size_t(k)] = last;
    cell_ctr[h * std::size_t(cap) + std::size_t(k)] = cell_ctr[from];
    slot_of[std::size_t(last)] = k;
  }
  void grow() {
    const int old = cap;
    cap *= 2;
    std::vector<int> s(fill.size() * std::size_t(cap), -1);
    std::vector<Centre> p(fill.size() * std::size_t(cap));
    for (std::size_t h = 0; h < fill.size(); ++h)
      for (int k = 0; k < fill[h]; ++k) {
        s[h * std::size_t(cap) + std::size_t(k)] = slots[h * std::size_t(old) + std::size_t(k)];
        p[h * std::size_t(cap) + std::size_t(k)] = cell_ctr[h * std::size_t(old) + std::size_t(k)];
      }
    slots.swap(s);
    cell_ctr.swap(p);
  }

  // --- Neighbour lists -------------------------------------------------------------------------
  bool is_big(int i) const { return i >= nsmall; }
  void set_big_centre(int i) {
    const std::size_t b = std::size_t(i - nsmall);
    big_x[b] = pred[std::size_t(i)].cx, big_y[b] = pred[std::size_t(i)].cy, big_z[b] = pred[std::size_t(i)].cz;
    big_r[b] = body[std::size_t(i)].r;
  }
  std::uint32_t* list(int i) {
    return is_big(i) ? big_nbr[std::size_t(i - nsmall)].data() : &nbr[nbase + std::size_t(i) * std::size_t(ncap)];
  }
  //! Storage for n lists of capacity ncap (a multiple of kPerLine), each on a line boundary.
  void alloc_lists(std::vector<std::uint32_t>& v, std::size_t& base, std::size_t n) const {
    v.assign(n * std::size_t(ncap) + kPerLine, 0);
    const auto addr = reinterpret_cast<std::uintptr_t>(v.data());
    base = ((64 - addr % 64) % 64) / sizeof(std::uint32_t);
  }

  void add_neighbour(int i, std::uint32_t entry) {
    if (is_big(i)) {
      auto& v = big_nbr[std::size_t(i - nsmall)];
      if (std::size_t(nfill[std::size_t(i)]) == v.size()) v.resize(std::max<std::size_t>(kPerLine, 2 * v.size()));
    } else if (nfill[std::size_t(i)] == ncap) {
      grow_lists();
    }
    list(i)[nfill[std::size_t(i)]++] = entry;
  }
  //! Removes j from i's list (swap with the last entry; order does not matter).
  void remove_neighbour(int i, int j) {
    std::uint32_t* l = list(i);
    int& f = nfill[std::size_t(i)];
    for (int u = 0; u < f; ++u)
      if (int(adj_partner(l[u])) == j) {
        l[u] = l[--f];
        return;
      }
  }
  //! Rewrites the image code of j in i's list (j was wrapped back into the box).
  void reimage_neighbour(int i, int j, std::uint32_t image) {
    std::uint32_t* l = list(i);
    for (int u = 0; u < nfill[std::size_t(i)]; ++u)
      if (int(adj_partner(l[u])) == j) {
        l[u] = adj_entry(std::uint32_t(j), std::uint8_t(image));
        return;
      }
  }
  void grow_lists() {
    const int old = ncap;
    ncap *= 2;
    std::vector<std::uint32_t> s;
    std::size_t base = 0;
    alloc_lists(s, base, std::size_t(nsmall));
    for (std::size_t i = 0; i < std::size_t(nsmall); ++i)
      std::copy_n(&nbr[nbase + i * std::size_t(old)], nfill[i], &s[base + i * std::size_t(ncap)]);
    nbr.swap(s);
    nbase = base;
  }

  void sync(Body& s) const {
    const double dt = now - s.t;
    if (has_g) {
      s.x += (s.vx + 0.5 * g[0] * dt) * dt, s.vx += g[0] * dt;
      s.y += (s.vy + 0.5 * g[1] * dt) * dt, s.vy += g[1] * dt;
      s.z += (s.vz + 0.5 * g[2] * dt) * dt, s.vz += g[2] * dt;
    } else {
      s.x += s.vx * dt;
      s.y += s.vy * dt;
      s.z += s.vz * dt;
    }
    s.t = now;
  }

  //! Cells at offsets -reach..reach from cell c0 along axis d: cell coordinates and periodic
  //! image signs (cells beyond a wall are skipped). Returns the count.
  int axis_cells(int c0, int d, int* cells, int* sign) const {
    int k = 0;
    for (int o = -reach; o <= reach; ++o) {
      int c = c0 + o, s = 0;
      if (c < 0) {
        if (!periodic[std::size_t(d)]) continue;
        c += nc[std::size_t(d)];
        s = -1;
      } else if (c >= nc[std::size_t(d)]) {
        if (!periodic[std::size_t(d)]) continue;
        c -= nc[std::size_t(d)];
        s = 1;
      }
      cells[k] = c;
      sign[k] = s;
      ++k;
    }
    return k;
  }

  //! Calls f(j, image) for every sphere j != i whose list centre is closer than sigma_ij + shell
  //! to i's: the members of i's neighbour list.
  template <class F>
  void for_each_in_range(int i, F&& f) {
    if (is_big(i))
      for_each_small_near_big(i, f);
    else
      for_each_small_in_stencil(i, f);
    for_each_big_in_range(i, f);
  }

  //! The big spheres (other than i) whose centres are closer than sigma_ij + shell to i's, at
  //! their nearest periodic image: the box is longer than twice every such range, so no other
  //! image can be in range.
  template <class F>
  void for_each_big_in_range(int i, F& f) {
    const Centre p = ctr_of(i);
    const std::size_t nb = big_x.size();
    // Every rebuild runs this: a branch-free pass over all big spheres first, then the few in range.
    double half[3], l[3];
    for (std::size_t a = 0; a < 3; ++a) half[a] = periodic[a] ? 0.5 * len[a] : kInf, l[a] = len[a];
    double* __restrict gap = big_gap.data();
    for (std::size_t b = 0; b < nb; ++b) {
      double dx = p.x - big_x[b], dy = p.y - big_y[b], dz = p.z - big_z[b];
      dx = dx > half[0] ? dx - l[0] : (dx < -half[0] ? dx + l[0] : dx);
      dy = dy > half[1] ? dy - l[1] : (dy < -half[1] ? dy + l[1] : dy);
      dz = dz > half[2] ? dz - l[2] : (dz < -half[2] ? dz + l[2] : dz);
      const double range = p.r + big_r[b] + shell;
      gap[b] = dx * dx + dy * dy + dz * dz - range * range;
    }
    for (std::size_t b = 0; b < nb; ++b) {
      const int j = nsmall + int(b);
      if (!(gap[b] < 0) || j == i) continue;
      const double d[3] = {p.x - big_x[b], p.y - big_y[b], p.z - big_z[b]};
      int sgn[3];
      for (std::size_t a = 0; a < 3; ++a) sgn[a] = d[a] > half[a] ? 1 : (d[a] < -half[a] ? -1 : 0);
      f(j, std::uint32_t((sgn[0] + 1) + 3 * (sgn[1] + 1) + 9 * (sgn[2] + 1)));
    }
  }

  //! The spheres in cells whose centres are closer than sigma_ij + shell to big sphere i's: every
  //! cell within its largest such range, with the periodic image of each cell's offset.
  template <class F>
  void for_each_small_near_big(int i, F& f) const {
    const Centre p = ctr_of(i);
    const double pc[3] = {p.x, p.y, p.z};
    const double far = p.r + grid_r + shell;
    int from[3], to[3];
    for (std::size_t d = 0; d < 3; ++d) {
      // A margin of a millionth of a cell for the rounding of cell_of.
      from[d] = int(std::floor((pc[d] - far - lo[d]) / width[d] - 1e-6));
      to[d] = int(std::floor((pc[d] + far - lo[d]) / width[d] + 1e-6));
      if (!periodic[d]) from[d] = std::max(from[d], 0), to[d] = std::min(to[d], nc[d] - 1);
    }
    // An offset o is cell o mod nc of the image floor(o / nc); range < L / 2 keeps it in -1..1.
    auto wrap = [&](int o, std::size_t d, int& sg) {
      sg = o < 0 ? -1 : (o >= nc[d] ? 1 : 0);
      return o - sg * nc[d];
    };
    for (int oz = from[2]; oz <= to[2]; ++oz) {
      int sz;
      const int z = wrap(oz, 2, sz);
      for (int oy = from[1]; oy <= to[1]; ++oy) {
        int sy;
        const int y = wrap(oy, 1, sy);
        for (int ox = from[0]; ox <= to[0]; ++ox) {
          int sx;
          const int x = wrap(ox, 0, sx);
          const std::uint32_t img = std::uint32_t((sx + 1) + 3 * (sy + 1) + 9 * (sz + 1));
          const auto& sh = image_shift[img];
          const double px = p.x - sh[0], py = p.y - sh[1], pz = p.z - sh[2];
          const std::size_t h = std::size_t((z * nc[1] + y) * nc[0] + x);
          const std::size_t h0 = h * std::size_t(cap);
          for (int u = 0; u < fill[h]; ++u) {
            const Centre& o = cell_ctr[h0 + std::size_t(u)];
            const double dx = px - o.x, dy = py - o.y, dz = pz - o.z;
            const double range = p.r + o.r + shell;
            if (dx * dx + dy * dy + dz * dz < range * range) f(slots[h0 + std::size_t(u)], img);
          }
        }
      }
    }
  }

  //! The spheres in the cells around small sphere i's whose centres are in range.
  template <class F>
  void for_each_small_in_stencil(int i, F& f) const {
    const Centre p = ctr_of(i);
    const auto& k = cc[std::size_t(i)];
    int cx[5], cy[5], cz[5], sx[5], sy[5], sz[5];
    const int kx = axis_cells(k[0], 0, cx, sx);
    const int ky = axis_cells(k[1], 1, cy, sy);
    const int kz = axis_cells(k[2], 2, cz, sz);
    // Pass 1: the stencil's cells and image codes; their lines are requested at once so the
    // cache misses overlap.
    int cell[125];
    std::uint32_t img[125];
    int nc_ = 0;
    for (int a = 0; a < kz; ++a)
      for (int b = 0; b < ky; ++b) {
        const int row = (cz[a] * nc[1] + cy[b]) * nc[0];
        for (int e = 0; e < kx; ++e) {
          const std::size_t h = std::size_t(row + cx[e]);
          __builtin_prefetch(&fill[h]);
          __builtin_prefetch(&slots[h * std::size_t(cap)]);
          __builtin_prefetch(&cell_ctr[h * std::size_t(cap)]);
          cell[nc_] = int(h);
          img[nc_++] = std::uint32_t((sx[e] + 1) + 3 * (sy[b] + 1) + 9 * (sz[a] + 1));
        }
      }
    // Pass 2: distance test of the centres, cell by cell.
    for (int q = 0; q < nc_; ++q) {
      const std::size_t h0 = std::size_t(cell[q]) * std::size_t(cap);
      const auto& sh = image_shift[img[q]];
      const double px = p.x - sh[0], py = p.y - sh[1], pz = p.z - sh[2];
      const int f_ = fill[std::size_t(cell[q])];
      for (int u = 0; u < f_; ++u) {
        const Centre& o = cell_ctr[h0 + std::size_t(u)];
        const double dx = px - o.x, dy = py - o.y, dz = pz - o.z;
        const double range = p.r + o.r + shell;
        if (dx * dx + dy * dy + dz * dz < range * range) {
          const int j = slots[h0 + std::size_t(u)];
          if (j != i) f(j, img[q]);
        }
      }
    }
  }

  //! Scans the m list entries `cand` of sphere i (synced to now) for a pair collision earlier
  //! than its current best and second-best candidates.
  template <bool Mono>
  void scan(int i, const std::uint32_t* cand, int m) {
    const Body& s = body[std::size_t(i)];
    // Best and second-best candidates (time from now, partner, partner's counter when found).
    double best = pred[std::size_t(i)].col_time - now, best2 = pred[std::size_t(i)].col2_time - now;
    int partner = pred[std::size_t(i)].col_partner, partner2 = pred[std::size_t(i)].col2_partner;
    std::uint32_t cnt = pred[std::size_t(i)].col_count, cnt2 = pred[std::size_t(i)].col2_count;
    const bool second_known = partner2 >= 0;
    const double sigma0 = 2 * s.r;
    // Pass 1: request the partners' states (and collision counters, read for the few that
    // pass the screen) at once, so their cache misses overlap.
    for (int u = 0; u < m; ++u) {
      __builtin_prefetch(&body[adj_partner(cand[u])]);
      __builtin_prefetch(&count[adj_partner(cand[u])]);
    }
    // Pass 2: relative positions and velocities into flat arrays.
    const std::size_t stride = std::size_t(m + 8) & ~std::size_t(7);
    if (soa.size() < 6 * stride) soa.resize(6 * stride);
    if (hits.size() < stride) hits.resize(stride);
    double* __restrict rx = soa.data();
    double* __restrict ry = rx + stride;
    double* __restrict rz = ry + stride;
    double* __restrict ux = rz + stride;
    double* __restrict uy = ux + stride;
    double* __restrict uz = uy + stride;
    if (has_g) {  // partners advanced to now on their parabolas
      for (int u = 0; u < m; ++u) {
        const Body& q = body[adj_partner(cand[u])];
        const auto& sh = image_shift[adj_image(cand[u])];
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
        const Body& q = body[adj_partner(cand[u])];
        const auto& sh = image_shift[adj_image(cand[u])];
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
    int* __restrict hit = hits.data();
    int nh = 0;
    for (int u = 0; u < m; ++u) {
      const double sigma = Mono ? sigma0 : s.r + body[adj_partner(cand[u])].r;
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
      const int j = int(adj_partner(cand[u]));
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
    if (partner != pred[std::size_t(i)].col_partner || best + now < pred[std::size_t(i)].col_time) {
      pred[std::size_t(i)].col_time = now + best;
      pred[std::size_t(i)].col_partner = partner;
      pred[std::size_t(i)].col_count = cnt;
    }
    if (partner2 != pred[std::size_t(i)].col2_partner || best2 + now < pred[std::size_t(i)].col2_time) {
      pred[std::size_t(i)].col2_time = now + best2;
      pred[std::size_t(i)].col2_partner = partner2;
      pred[std::size_t(i)].col2_count = cnt2;
    }
  }
  void scan_entries(int i, const std::uint32_t* cand, int m) {
    if (mono)
      scan<true>(i, cand, m);
    else
      scan<false>(i, cand, m);
  }

  //! Next boundary event of sphere i (synced to now): leaving the ball of radius exit_r around
  //! its list centre, or touching a wall that it can reach inside that ball.
  void predict_boundary(int i) {
    const Body& s = body[std::size_t(i)];
    const Centre p = ctr_of(i);
    const double pos[3] = {s.x, s.y, s.z}, vel[3] = {s.vx, s.vy, s.vz}, ctr[3] = {p.x, p.y, p.z};
    // |d + v t| = exit_r with d = pos - centre: the positive root of a t^2 + 2 b t + c = 0,
    // c <= 0 inside the ball; each branch is a ratio of same-signed terms (no cancellation).
    const double dx = s.x - p.x, dy = s.y - p.y, dz = s.z - p.z;
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
      if (periodic[std::size_t(d)]) continue;
      const double v = vel[d];
      const double hi = lo[std::size_t(d)] + len[std::size_t(d)];
      double t;
      if (has_g && g[std::size_t(d)] != 0) {  // the first wall its parabola reaches, moving into it
        if (ctr[d] + shell + s.r < hi && ctr[d] - shell - s.r > lo[std::size_t(d)]) continue;
        const double gd = g[std::size_t(d)];
        const double t_lo = kernel::wall_back_time(pos[d], -v, gd, lo[std::size_t(d)] + s.r, +1, kInf);
        const double t_hi = kernel::wall_back_time(pos[d], -v, gd, hi - s.r, -1, kInf);
        // Forward in time is backward with the velocity reversed; the side flips with it.
        const double tl = t_lo >= 0 ? t_lo : kInf, th = t_hi >= 0 ? t_hi : kInf;
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
      else if (v < 0 && ctr[d] - shell - s.r <= lo[std::size_t(d)])
        t = (lo[std::size_t(d)] + s.r - pos[d]) / v;
      else
        continue;
      if (t < best) {
        best = t;
        code = std::uint8_t(kWall * 8 + d * 2 + (v > 0 ? 1 : 0));
      }
    }
    pred[std::size_t(i)].bnd_time = now + std::max(0.0, best);
    bnd_code[std::size_t(i)] = code;
  }

  void full_predict(int i) {
    ++c.full_predictions;
    sync(body[std::size_t(i)]);
    pred[std::size_t(i)].col_time = pred[std::size_t(i)].col2_time = kInf;
    pred[std::size_t(i)].col_partner = pred[std::size_t(i)].col2_partner = i;  // "none": counts irrelevant at +inf
    scan_entries(i, list(i), nfill[std::size_t(i)]);
    predict_boundary(i);
  }

  void schedule(int i) {
    calendar.update(std::uint32_t(i), std::min(pred[std::size_t(i)].col_time, pred[std::size_t(i)].bnd_time));
  }

  //! Replaces a stale best candidate by the second best if that one is still valid. The second
  //! slot is then unknown (partner -1) until the next full scan: a partial scan cannot know
  //! what came third, so a later stale best forces a rescan.
  bool promote_second(int i) {
    const std::size_t u = std::size_t(i);
    const int j = pred[u].col2_partner;
    if (j < 0) return false;
    if (pred[u].col2_time < kInf && count[std::size_t(j)] != pred[u].col2_count) return false;
    pred[u].col_time = pred[u].col2_time;
    pred[u].col_partner = j;
    pred[u].col_count = pred[u].col2_count;
    pred[u].col2_time = kInf;
    pred[u].col2_partner = -1;
    return true;
  }

  bool candidate_stale(int i) const {
    const int j = pred[std::size_t(i)].col_partner;
    return pred[std::size_t(i)].col_time < kInf && count[std::size_t(j)] != pred[std::size_t(i)].col_count;
  }

  void collide(int i, int j) {
    // Both lists are requested before either is scanned, so their misses overlap. The neighbourhoods are
    // not: each scan requests its partners itself, and doing it here too was slower (see docs/dev/performance.md).
    __builtin_prefetch(list(i));
    __builtin_prefetch(list(j));
    __builtin_prefetch(&nfill[std::size_t(i)]);
    __builtin_prefetch(&nfill[std::size_t(j)]);
    __builtin_prefetch(&pred[std::size_t(j)]);
    calendar.prefetch(std::uint32_t(i));
    calendar.prefetch(std::uint32_t(j));
    Body& a = body[std::size_t(i)];
    Body& b = body[std::size_t(j)];
    sync(a);
    sync(b);
    Vec3d dr{a.x - b.x, a.y - b.y, a.z - b.z};
    for (int d = 0; d < 3; ++d)  // at contact |dr| <= r_i + r_j < L/2: minimum image
      if (periodic[std::size_t(d)]) dr[d] -= len[std::size_t(d)] * std::nearbyint(dr[d] / len[std::size_t(d)]);
    Vec3d va{a.vx, a.vy, a.vz}, vb{b.vx, b.vy, b.vz};
    double w;
    if (restitution != 1.0) {
      const double t = base + now;
      double& ti = last_collision[orig[std::size_t(i)]];
      double& tj = last_collision[orig[std::size_t(j)]];
      const double e = kernel::tc_elastic(t, ti, tj, contact_time) ? 1.0 : restitution;
      w = mono ? mass0 * kernel::collide_equal_mass(dr, va, vb, e)
               : kernel::collide(dr, va, vb, mass[std::size_t(i)], mass[std::size_t(j)], e);
      ti = tj = t;
    } else {
      w = mono ? mass0 * kernel::collide_equal_mass(dr, va, vb)
               : kernel::collide(dr, va, vb, mass[std::size_t(i)], mass[std::size_t(j)]);
    }
    a.vx = va.x;
    a.vy = va.y;
    a.vz = va.z;
    b.vx = vb.x;
    b.vy = vb.y;
    b.vz = vb.z;
    c.pair_virial += w;
    ++c.collisions;
    ++count[std::size_t(i)];
    ++count[std::size_t(j)];
    ++pair_collisions[orig[std::size_t(i)]];
    ++pair_collisions[orig[std::size_t(j)]];
    full_predict(i);
    full_predict(j);
    schedule(i);
    schedule(j);
  }

  //! Sphere i (synced) has left its shell: new list centre at its position (wrapped into the
  //! box), new list, and the symmetric update of the lists it joins or leaves. Its trajectory
  //! is unchanged, so its candidates stay valid and only the new members are scanned.
  void rebuild(int i) {
    ++c.neighbour_list_rebuilds;
    Body& s = body[std::size_t(i)];
    double* pos[3] = {&s.x, &s.y, &s.z};
    bool wrapped = false;
    for (std::size_t d = 0; d < 3; ++d) {
      if (!periodic[d]) continue;
      if (*pos[d] < lo[d])
        *pos[d] += len[d], wrapped = true, --wraps[orig[std::size_t(i)]][d];
      else if (*pos[d] >= lo[d] + len[d])
        *pos[d] -= len[d], wrapped = true, ++wraps[orig[std::size_t(i)]][d];
    }
    Pred& pi = pred[std::size_t(i)];
    pi.cx = s.x;
    pi.cy = s.y;
    pi.cz = s.z;
    if (is_big(i)) {
      set_big_centre(i);
    } else if (const auto k = cell_of(s.x, s.y, s.z); k != cc[std::size_t(i)]) {
      unlink(i);
      cc[std::size_t(i)] = k;
      link(i);
    } else {
      cell_ctr[std::size_t(cell_index(k)) * std::size_t(cap) + std::size_t(slot_of[std::size_t(i)])] = ctr_of(i);
    }
    // Old members are marked `was`; those found again become `kept`; the rest leave.
    const std::uint64_t was = ++stamp, kept = ++stamp;
    old_list.assign(list(i), list(i) + nfill[std::size_t(i)]);
    for (std::uint32_t e : old_list) mark[adj_partner(e)] = was;
    nfill[std::size_t(i)] = 0;
    fresh.clear();
    for_each_in_range(i, [&](int j, std::uint32_t image) {
      const std::uint32_t entry = adj_entry(std::uint32_t(j), std::uint8_t(image));
      const std::uint32_t back = adj_entry(std::uint32_t(i), std::uint8_t(kImages - 1 - image));
      add_neighbour(i, entry);
      if (mark[std::size_t(j)] == was) {
        mark[std::size_t(j)] = kept;
        if (wrapped) reimage_neighbour(j, i, adj_image(back));
      } else {
        add_neighbour(j, back);
        fresh.push_back(entry);
      }
    });
    for (std::uint32_t e : old_list)
      if (mark[adj_partner(e)] == was) remove_neighbour(int(adj_partner(e)), i);
    if (candidate_stale(i) && !promote_second(i)) {
      full_predict(i);
    } else {
      scan_entries(i, fresh.data(), int(fresh.size()));
      predict_boundary(i);
    }
    schedule(i);
  }

  void boundary_event(int i) {
    Body& s = body[std::size_t(i)];
    sync(s);
    const int code = bnd_code[std::size_t(i)];
    const int kind = code / 8, d = (code / 2) % 4;
    if (kind == kRebuild) return rebuild(i);
    double* vel = d == 0 ? &s.vx : (d == 1 ? &s.vy : &s.vz);
    c.wall_impulse[std::size_t(d)] += 2 * mass[std::size_t(i)] * std::abs(*vel);
    *vel = -*vel;
    if (has_g) {  // on the contact plane exactly: rounding must not leave it beyond the wall
      double* x = d == 0 ? &s.x : (d == 1 ? &s.y : &s.z);
      const double hi = lo[std::size_t(d)] + len[std::size_t(d)];
      *x = std::clamp(*x, lo[std::size_t(d)] + s.r, hi - s.r);
    }
    ++c.wall_collisions;
    ++count[std::size_t(i)];
    full_predict(i);
    schedule(i);
  }

  //! Processes the calendar's first entry.
  void step() {
    const int i = int(calendar.top());
    now = calendar.top_key();
    ++c.events;
    if (pred[std::size_t(i)].col_time <= pred[std::size_t(i)].bnd_time) {
      const int j = pred[std::size_t(i)].col_partner;
      // Most such entries are valid collisions: request the partner's lines with its counter.
      __builtin_prefetch(&body[std::size_t(j)]);
      __builtin_prefetch(&pred[std::size_t(j)]);
      __builtin_prefetch(list(j));
      __builtin_prefetch(&nfill[std::size_t(j)]);
      if (count[std::size_t(j)] != pred[std::size_t(i)].col_count) {
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
    // The next event's sphere: its lines load while the loop comes round.
    if (calendar.empty()) return;
    const std::uint32_t next = calendar.top();
    __builtin_prefetch(&pred[next]);
    __builtin_prefetch(&body[next]);
    __builtin_prefetch(list(int(next)));  // its address needs no load: scanned if it collides
    __builtin_prefetch(&nfill[next]);
    // The event after that is most likely one of the root's children: a whole event's head start.
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t q = calendar.runner_up(k);
      if (q < pred.size()) {
        __builtin_prefetch(&pred[q]);
        __builtin_prefetch(&body[q]);
        __builtin_prefetch(list(int(q)));
        __builtin_prefetch(&nfill[q]);
      }
    }
  }

  //! Moves every sphere to the current time and shifts the clock so that now = 0.
  void rebase() {
    events_since_rebase = 0;
    if (now == 0) return;
    for (std::size_t i = 0; i < body.size(); ++i) {
      sync(body[i]);
      body[i].t = 0;
      pred[i].col_time -= now;
      pred[i].col2_time -= now;
      pred[i].bnd_time -= now;
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
  //! their neighbours in memory as they diffuse; this restores locality. Any time will do:
  //! only indices change, not the physics.
  void renumber() {
    const std::size_t n = body.size();
    std::vector<int> old_of;
    old_of.reserve(n);
    for (int h : cell_order)
      for (int k = 0; k < fill[std::size_t(h)]; ++k)
        old_of.push_back(slots[std::size_t(h) * std::size_t(cap) + std::size_t(k)]);
    for (std::size_t k = std::size_t(nsmall); k < n; ++k) old_of.push_back(int(k));  // big ones stay last
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
    permute(pred);
    permute(bnd_code);
    permute(slot_of);
    permute(mark);
    for (auto& p : pred) {
      p.col_partner = new_of[std::size_t(p.col_partner)];
      if (p.col2_partner >= 0) p.col2_partner = new_of[std::size_t(p.col2_partner)];
    }
    for (std::size_t h = 0; h < fill.size(); ++h)
      for (int k = 0; k < fill[h]; ++k) {
        int& x = slots[h * std::size_t(cap) + std::size_t(k)];
        x = new_of[std::size_t(x)];
      }
    std::vector<std::uint32_t> lists;
    std::size_t base = 0;
    alloc_lists(lists, base, std::size_t(nsmall));
    std::vector<int> fills(n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t o = std::size_t(old_of[k]);
      fills[k] = nfill[o];
      const bool big = is_big(int(k));
      const std::uint32_t* from = big ? big_nbr[k - std::size_t(nsmall)].data() : &nbr[nbase + o * std::size_t(ncap)];
      std::uint32_t* to = big ? big_nbr[k - std::size_t(nsmall)].data() : &lists[base + k * std::size_t(ncap)];
      for (int u = 0; u < nfill[o]; ++u)
        to[u] = adj_entry(std::uint32_t(new_of[adj_partner(from[u])]), adj_image(from[u]));
    }
    nbr.swap(lists);
    nbase = base;
    nfill.swap(fills);
    std::vector<double> keys(n);
    for (std::size_t k = 0; k < n; ++k) keys[k] = std::min(pred[k].col_time, pred[k].bnd_time);
    calendar.build(keys);
  }

  //! Every sphere's list from scratch (list centres = current positions).
  void build_lists() {
    std::fill(nfill.begin(), nfill.end(), 0);
    for (int i = 0; i < int(body.size()); ++i)
      for_each_in_range(i, [&](int j, std::uint32_t image) {
        if (j < i) return;  // each pair once, entered in both lists
        add_neighbour(i, adj_entry(std::uint32_t(j), std::uint8_t(image)));
        add_neighbour(j, adj_entry(std::uint32_t(i), std::uint8_t(kImages - 1 - image)));
      });
  }

  void run_until(double t_end_abs) {
    // t_end_abs is measured from construction; the calendar from `base`.
    while (!calendar.empty() && calendar.top_key() <= t_end_abs - base) {
      if (++total_events > max_events) refuse_more_events(t_end_abs);
      step();
    }
    now = t_end_abs - base;
  }

  double total_events = 0, max_events = kInf;  // all events since construction, and the cap
  [[noreturn]] void refuse_more_events(double t_end_abs) const {
    std::ostringstream m;
    m << "event engine: the run needs more than " << max_events << " events (it had reached time " << base + now
      << " of " << t_end_abs << "); shorten the run";
    throw InputError(m.str());
  }
};

double auto_shell(double phi) {
  // A sphere rebuilds its list after moving shell / 2, so rebuilds per collision grow as the mean
  // free path lambda = sigma / (6 sqrt(2) phi g(sigma)) (Enskog, Carnahan-Starling g) outgrows the
  // shell. So the shell follows lambda: 1.6 lambda (where timed runs found the optimum), kept within
  // [0.6, 2] diameters (see docs/dev/performance.md).
  if (!(phi > 0)) return 0.6;
  const double g = (1 - phi / 2) / std::pow(1 - std::min(phi, 0.7), 3);
  const double lambda = 1 / (6 * std::sqrt(2.0) * phi * g);
  return std::clamp(1.6 * lambda, 0.6, 2.0);
}

namespace {
//! The spheres in id order: the engine's "input" order, so that state() comes out as the
//! stepper's does and the same spheres give the same run in whatever order they are handed over.
ParticleSystem sorted_by_id(const ParticleSystem& sys) {
  const std::vector<std::size_t> order = order_by_id(sys.id);
  bool sorted = true;
  for (std::size_t k = 0; k < order.size() && sorted; ++k) sorted = order[k] == k;
  if (sorted) return sys;
  ParticleSystem out;
  out.box = sys.box;
  out.reserve(sys.size());
  for (const std::size_t i : order)
    out.push_back(sys.id[i], sys.type[i], sys.radius[i], sys.mass[i], sys.pos[i], sys.vel[i],
                  i < sys.image.size() ? sys.image[i] : std::array<std::int32_t, 3>{0, 0, 0});
  return out;
}
}  // namespace

EventEngine::EventEngine(const ParticleSystem& sys_in, const Physics& physics_in, const EventConfig& cfg)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  if (sys_in.radius.size() != sys_in.size() || sys_in.mass.size() != sys_in.size() ||
      sys_in.vel.size() != sys_in.size() || sys_in.id.size() != sys_in.size() || sys_in.type.size() != sys_in.size())
    throw InputError("event engine: inconsistent particle arrays");
  const ParticleSystem sys = sorted_by_id(sys_in);
  const std::size_t n = sys.size();
  if (n > std::size_t(kMaxAdjIndex) + 1)  // indices 0 .. kMaxAdjIndex fit a list entry
    throw InputError("too many spheres for the event engine: " + std::to_string(n) + " (at most " +
                     std::to_string(std::size_t(kMaxAdjIndex) + 1) + ")");
  if (sys.radius.size() != n || sys.mass.size() != n || sys.vel.size() != n)
    throw InputError("event engine: inconsistent particle arrays");
  check_scene_numbers(sys, "event engine");
  check_engine_numbers<double>(sys, 0, "event engine");
  if (!(cfg.max_events > 0)) throw InputError("event engine: max_events must be positive");
  m.max_events = cfg.max_events;
  if (!(cfg.shell >= 0) || !std::isfinite(cfg.shell))
    throw InputError("event engine: shell " + std::to_string(cfg.shell) + " must be positive (or 0 for auto)");
  m.proto = sys;
  m.proto.image.resize(sys.size(), {0, 0, 0});
  const Physics physics = validated(physics_in, sys.box.periodic);
  m.g = physics.gravity;
  m.has_g = physics.has_gravity();
  m.restitution = physics.restitution;
  m.contact_time = physics.contact_time;
  if (!physics.elastic()) m.last_collision.assign(sys.size(), -std::numeric_limits<double>::infinity());
  m.mono = sys.monodisperse();
  m.mass0 = n ? sys.mass[0] : 1.0;
  if (cfg.reach < 1 || cfg.reach > 2)
    throw InputError("event engine: reach " + std::to_string(cfg.reach) + " must be 1 or 2");
  m.reach = cfg.reach;
  const int min_cells = 2 * m.reach + 1;
  // The cells and the shell are sized by the spheres filed in cells; big ones are searched apart.
  const SizeSplit split = split_by_size(sys);
  const double dmax = split.grid_diameter;
  m.grid_r = dmax / 2;
  // With big spheres, a periodic axis must be longer than twice every pair's range (the two
  // largest radii plus the shell), so that only one image of a pair is ever in range.
  double r1 = 0, r2 = 0;
  for (double r : sys.radius)
    if (r > r1)
      r2 = r1, r1 = r;
    else if (r > r2)
      r2 = r;
  const double pair_max = split.big.empty() ? 0.0 : r1 + r2;
  // The shell may not make the cells wider than a periodic axis (or a user grid) allows; the
  // cells themselves must be at least (largest diameter in cells) / reach wide, as before lists.
  double shell = (cfg.shell > 0 ? cfg.shell : auto_shell(sys.packing_fraction())) * dmax;
  for (std::size_t d = 0; d < 3; ++d) {
    const double l = sys.box.length(int(d));
    const std::string axis(1, char('x' + d));
    const double w = cfg.cells[d] > 0 ? l / cfg.cells[d] : (sys.box.periodic[d] ? l / min_cells : kInf);
    if (cfg.cells[d] > 0 && w < dmax / m.reach * (1 - 1e-12))
      throw InputError("event engine: " + std::to_string(cfg.cells[d]) + " cells on axis " + axis +
                       " are narrower than the largest diameter of the spheres filed in cells / reach " +
                       std::to_string(dmax / m.reach));
    if (sys.box.periodic[d] && (l < min_cells * dmax / m.reach || (cfg.cells[d] > 0 && cfg.cells[d] < min_cells)))
      throw InputError(
          "event engine: periodic axis " + axis + " of length " + std::to_string(l) + " needs at least " +
          std::to_string(min_cells) + " cells of width >= the largest diameter / reach " +
          std::to_string(dmax / m.reach) + " (spheres over " + format_number(kBigOverMedian) +
          " median diameters are searched apart and do not count; a sphere's partners are searched in the cells " +
          "around its own, which must be distinct periodic images); use --engine stepper, " +
          "which takes any periodic box longer than 2 largest diameters, or a box of at least " +
          std::to_string(min_cells * dmax / m.reach));
    if (sys.box.periodic[d] && !(l > 2 * pair_max))
      throw InputError("event engine: periodic axis " + axis + " of length " + std::to_string(l) +
                       " must be longer than twice the contact distance of the two largest spheres, " +
                       std::to_string(2 * pair_max) + " (a pair may have only one periodic image in range)");
    shell = std::min(shell, w * m.reach - dmax);
    if (sys.box.periodic[d] && pair_max > 0) shell = std::min(shell, 0.5 * l * (1 - 1e-9) - pair_max);
  }
  if (n > 0 && !(shell > 1e-6 * dmax))
    throw InputError("event engine: no room for a neighbour-list shell: periodic axes need at least " +
                     std::to_string(min_cells) + " cells wider than the largest diameter / reach" +
                     (pair_max > 0 ? " and more than twice the two largest radii " + std::to_string(pair_max) : ""));
  m.shell = shell;
  // Strictly inside shell / 2: a margin for the round-off of positions (a few ulps of the largest
  // coordinate) and of the exit time, so two spheres can never both overshoot.
  double extent = 0;
  for (int d = 0; d < 3; ++d)
    extent = std::max({extent, std::abs(sys.box.lo[std::size_t(d)]), std::abs(sys.box.hi[std::size_t(d)])});
  m.exit_r = 0.5 * shell * (1 - 1e-9) - 64 * std::numeric_limits<double>::epsilon() * extent;
  if (n > 0 && !(m.exit_r > 0.25 * shell))
    throw InputError("event engine: neighbour-list shell " + std::to_string(shell) +
                     " too thin for coordinates up to " + std::to_string(extent));
  const double wmin = (dmax + shell) / m.reach;
  double cells_total = 1;
  for (std::size_t d = 0; d < 3; ++d) {
    m.lo[d] = sys.box.lo[d];
    m.len[d] = sys.box.length(int(d));
    m.periodic[d] = sys.box.periodic[d];
    int k = cfg.cells[d];
    if (k == 0) k = int(std::min(1e6, std::floor(m.len[d] / std::max(wmin, 1e-300))));
    k = std::max(k, m.periodic[d] ? min_cells : 1);
    m.nc[d] = k;
    cells_total *= k;
  }
  if (cfg.cells == std::array<int, 3>{0, 0, 0}) {
    const double cap = std::max(double(min_cells * min_cells * min_cells),
                                cfg.max_cells_per_sphere * m.reach * m.reach * m.reach * double(n));
    if (cells_total > cap) {
      const double f = std::cbrt(cells_total / cap);
      for (std::size_t d = 0; d < 3; ++d) m.nc[d] = std::max(m.periodic[d] ? min_cells : 1, int(double(m.nc[d]) / f));
    }
  }
  for (std::size_t d = 0; d < 3; ++d) m.width[d] = m.len[d] / m.nc[d];
  for (int z = -1; z <= 1; ++z)
    for (int y = -1; y <= 1; ++y)
      for (int x = -1; x <= 1; ++x)
        m.image_shift[std::size_t((x + 1) + 3 * (y + 1) + 9 * (z + 1))] = {x * m.len[0], y * m.len[1], z * m.len[2]};
  m.fill.assign(std::size_t(m.nc[0]) * std::size_t(m.nc[1]) * std::size_t(m.nc[2]), 0);
  m.cap = m.reach == 1 ? 8 : 2;
  m.slots.assign(m.fill.size() * std::size_t(m.cap), -1);
  m.cell_ctr.assign(m.fill.size() * std::size_t(m.cap), Centre{0, 0, 0, 0});
  m.slot_of.assign(n, 0);

  // Cell of every sphere; internal order sorted by cell for locality.
  std::vector<std::array<int, 3>> k0(n);
  std::vector<Vec3d> p0(sys.pos);
  std::vector<std::int64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) {
      double& x = p0[i][d];
      if (m.periodic[std::size_t(d)]) {
        x -= m.len[std::size_t(d)] * std::floor((x - m.lo[std::size_t(d)]) / m.len[std::size_t(d)]);
        if (x >= m.lo[std::size_t(d)] + m.len[std::size_t(d)]) x -= m.len[std::size_t(d)];  // round-off at the top
      }
    }
    k0[i] = m.cell_of(p0[i].x, p0[i].y, p0[i].z);
    key[i] = m.cell_index(k0[i]);
  }
  // Big spheres after every cell, largest first.
  const std::int64_t ncells = std::int64_t(m.fill.size());
  for (std::size_t b = 0; b < split.big.size(); ++b) key[split.big[b]] = ncells + std::int64_t(b);
  m.nsmall = int(n - split.big.size());
  for (auto* v : {&m.big_x, &m.big_y, &m.big_z, &m.big_r, &m.big_gap}) v->resize(split.big.size());
  m.big_nbr.assign(split.big.size(), std::vector<std::uint32_t>(kPerLine));
  m.orig.resize(n);
  m.wraps.assign(n, {0, 0, 0});
  m.pair_collisions.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) m.orig[i] = std::uint32_t(i);
  std::stable_sort(m.orig.begin(), m.orig.end(), [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });

  m.body.resize(n);
  m.mass.resize(n);
  m.cc.resize(n);
  m.count.assign(n, 0);
  m.pred.assign(n, Pred{kInf, kInf, kInf, 0, 0, 0, 0, 0, 0, 0});
  m.bnd_code.assign(n, 0);
  m.mark.assign(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = m.orig[k];
    m.body[k] = Body{p0[i].x, p0[i].y, p0[i].z, 0.0, sys.vel[i].x, sys.vel[i].y, sys.vel[i].z, sys.radius[i]};
    m.pred[k].cx = p0[i].x;
    m.pred[k].cy = p0[i].y;
    m.pred[k].cz = p0[i].z;
    m.mass[k] = sys.mass[i];
    m.cc[k] = k0[i];
    if (m.is_big(int(k)))
      m.set_big_centre(int(k));
    else
      m.link(int(k));
  }
  m.nfill.assign(n, 0);
  m.alloc_lists(m.nbr, m.nbase, n);
  m.build_cell_order();
  m.build_lists();
  m.renumber();
  for (std::size_t k = 0; k < n; ++k) m.full_predict(int(k));
  std::vector<double> keys(n);
  for (std::size_t k = 0; k < n; ++k) keys[k] = std::min(m.pred[k].col_time, m.pred[k].bnd_time);
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
    if (m.has_g) {
      out.pos[i] = {s.x + (s.vx + 0.5 * m.g[0] * dt) * dt, s.y + (s.vy + 0.5 * m.g[1] * dt) * dt,
                    s.z + (s.vz + 0.5 * m.g[2] * dt) * dt};
      out.vel[i] = {s.vx + m.g[0] * dt, s.vy + m.g[1] * dt, s.vz + m.g[2] * dt};
    } else {
      out.pos[i] = {s.x + s.vx * dt, s.y + s.vy * dt, s.z + s.vz * dt};
      out.vel[i] = {s.vx, s.vy, s.vz};
    }
    for (std::size_t d = 0; d < 3; ++d)
      out.image[i][d] = std::int32_t(
          std::clamp(m.proto.image[i][d] + m.wraps[i][d], std::int64_t(INT32_MIN), std::int64_t(INT32_MAX)));
  }
  wrap_periodic(out);
  return out;
}

SphereSample EventEngine::sphere(std::size_t index) const {
  const Impl& m = *impl_;
  const std::size_t n = m.body.size();
  if (index >= n)
    throw InputError("sphere index " + std::to_string(index) + " is out of range (" + std::to_string(n) + " spheres)");
  // Renumbering moves spheres in the internal order; only then is the index searched for again.
  if (m.orig[m.sampled_at] != index)
    m.sampled_at = std::size_t(std::find(m.orig.begin(), m.orig.end(), std::uint32_t(index)) - m.orig.begin());
  const Body& s = m.body[m.sampled_at];
  const double dt = m.now - s.t;
  SphereSample out;
  if (m.has_g) {
    out.unwrapped = {s.x + (s.vx + 0.5 * m.g[0] * dt) * dt, s.y + (s.vy + 0.5 * m.g[1] * dt) * dt,
                     s.z + (s.vz + 0.5 * m.g[2] * dt) * dt};
    out.velocity = {s.vx + m.g[0] * dt, s.vy + m.g[1] * dt, s.vz + m.g[2] * dt};
  } else {
    out.unwrapped = {s.x + s.vx * dt, s.y + s.vy * dt, s.z + s.vz * dt};
    out.velocity = {s.vx, s.vy, s.vz};
  }
  for (std::size_t d = 0; d < 3; ++d)
    if (m.periodic[d]) out.unwrapped[int(d)] += double(m.proto.image[index][d] + m.wraps[index][d]) * m.len[d];
  out.pair_collisions = m.pair_collisions[index];
  return out;
}

std::vector<std::int64_t> EventEngine::pair_collisions_per_sphere() const { return impl_->pair_collisions; }

const EventCounters& EventEngine::counters() const {
  impl_->c.sim_time = time() - impl_->reset_time;
  return impl_->c;
}

void EventEngine::reset_counters() {
  impl_->c = EventCounters{};
  std::fill(impl_->pair_collisions.begin(), impl_->pair_collisions.end(), std::int64_t(0));
  impl_->reset_time = time();
}

double EventEngine::time() const { return impl_->base + impl_->now; }

std::array<int, 3> EventEngine::cells_per_dim() const { return impl_->nc; }

double EventEngine::shell() const { return impl_->shell; }

std::string EventEngine::scene_kernel() const {
  return std::string(impl_->proto.box.all_periodic() ? "periodic" : "walls") + (impl_->mono ? ",mono" : ",poly");
}

}  // namespace hardsphere
