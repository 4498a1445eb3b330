#include "hardsphere/particles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <unordered_set>

#include "hardsphere/errors.hpp"
#include "hardsphere/scene_limits.hpp"
#include "scene/cell_grid.hpp"
#include "scene/size_classes.hpp"

namespace hardsphere {

void ParticleSystem::resize(std::size_t n) {
  id.resize(n);
  type.resize(n, 1);
  radius.resize(n);
  mass.resize(n);
  pos.resize(n);
  vel.resize(n);
  image.resize(n, {0, 0, 0});
  omega.resize(n);
  if (!kinematic.empty()) kinematic.resize(n, 0);
}

void ParticleSystem::reserve(std::size_t n) {
  id.reserve(n);
  type.reserve(n);
  radius.reserve(n);
  mass.reserve(n);
  pos.reserve(n);
  vel.reserve(n);
  image.reserve(n);
  omega.reserve(n);
}

void ParticleSystem::push_back(std::int64_t i, int t, double r, double m, Vec3d p, Vec3d v,
                               std::array<std::int32_t, 3> img, Vec3d w) {
  id.push_back(i);
  type.push_back(t);
  radius.push_back(r);
  mass.push_back(m);
  pos.push_back(p);
  vel.push_back(v);
  image.push_back(img);
  omega.push_back(w);
  if (!kinematic.empty()) kinematic.push_back(0);
}

std::size_t ParticleSystem::kinematic_count() const {
  std::size_t k = 0;
  for (const std::uint8_t f : kinematic) k += f != 0;
  return k;
}

bool ParticleSystem::monodisperse() const {
  for (std::size_t i = 1; i < size(); ++i)
    if (radius[i] != radius[0] || mass[i] != mass[0]) return false;
  return true;
}

double ParticleSystem::max_radius() const {
  double r = 0;
  for (double x : radius) r = std::max(r, x);
  return r;
}

double ParticleSystem::packing_fraction() const {
  double v = 0;
  for (double r : radius) v += 4.0 / 3.0 * M_PI * r * r * r;
  return v / box.volume();
}

void wrap_periodic(ParticleSystem& sys) {
  sys.image.resize(sys.size(), {0, 0, 0});
  for (std::size_t i = 0; i < sys.size(); ++i) {
    Vec3d& p = sys.pos[i];
    for (int d = 0; d < 3; ++d) {
      if (!sys.box.periodic[d]) continue;
      const double lo = sys.box.lo[d], hi = sys.box.hi[d], len = sys.box.length(d);
      if (p[d] >= lo && p[d] < hi) continue;
      // fmod is exact, so even far coordinates land in the box (rounding can still reach hi).
      const double before = p[d];
      double r = std::fmod(p[d] - lo, len);
      if (r < 0) r += len;
      p[d] = lo + r;
      if (!(p[d] >= lo && p[d] < hi)) p[d] = lo;
      std::int32_t& img = sys.image[i][std::size_t(d)];
      const double shifted = double(img) + std::nearbyint((before - p[d]) / len);
      img = std::int32_t(std::clamp(shifted, double(INT32_MIN), double(INT32_MAX)));
    }
  }
}

namespace {

// Calls f(i, j, dr) for every pair closer than its contact distance r_i + r_j (and some
// farther ones), minimum image. A cell grid finds the pairs of spheres that are not big (see
// size_classes.hpp), so one big sphere does not make every cell as wide as itself; big
// spheres are tested against every sphere, after the grid's pairs.
template <class F>
void for_each_close_pair(const ParticleSystem& sys, F&& f) {
  const std::size_t n = sys.size();
  if (n < 2) return;
  const SizeSplit split = split_by_size(sys);
  std::vector<char> big(n, 0);
  for (const std::uint32_t b : split.big) big[b] = 1;
  const double cutoff = split.grid_diameter;
  const CellGrid grid = CellGrid::with_min_width(sys.box, cutoff, std::int64_t(2 * n + 27));
  std::vector<int> cell;
  std::vector<std::uint32_t> start, order;
  grid.sort(
      n, [&](std::size_t i) { return sys.pos[i]; }, [&](std::size_t i) { return big[i] != 0; }, cell, start, order);
  auto min_image = [&](std::size_t i, std::size_t j) {
    Vec3d dr = sys.pos[i] - sys.pos[j];
    for (int d = 0; d < 3; ++d)
      if (sys.box.periodic[d]) dr[d] -= sys.box.length(d) * std::nearbyint(dr[d] / sys.box.length(d));
    return dr;
  };
  for (std::int64_t c = 0; c < grid.size(); ++c) {
    grid.for_each_neighbour(int(c), [&](int nb) {
      if (nb < c) return;
      for (std::uint32_t a = start[c]; a < start[c + 1]; ++a)
        for (std::uint32_t b = (nb == c ? a + 1 : start[nb]); b < start[nb + 1]; ++b) {
          const std::uint32_t i = order[a], j = order[b];
          const Vec3d dr = min_image(i, j);
          if (dot(dr, dr) < cutoff * cutoff) f(i, j, dr);
        }
    });
  }
  for (std::size_t k = 0; k < split.big.size(); ++k) {
    const std::uint32_t i = split.big[k];
    big[i] = 0;  // each pair of big spheres once
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i || big[j]) continue;
      const Vec3d dr = min_image(i, j);
      const double contact = sys.radius[i] + sys.radius[j];
      if (dot(dr, dr) < contact * contact) f(i, j, dr);
    }
  }
}

bool finite(Vec3d v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

double max_overlap(const ParticleSystem& sys) {
  double worst = 0;
  for_each_close_pair(sys, [&](std::size_t i, std::size_t j, Vec3d dr) {
    if (sys.is_kinematic(i) && sys.is_kinematic(j)) return;
    worst = std::max(worst, sys.radius[i] + sys.radius[j] - norm(dr));
  });
  return worst;
}

std::optional<Overlap> find_overlap(const ParticleSystem& sys, double slack) {
  std::optional<Overlap> found;
  for_each_close_pair(sys, [&](std::size_t i, std::size_t j, Vec3d dr) {
    if (sys.is_kinematic(i) && sys.is_kinematic(j)) return;
    const double dist = norm(dr), contact = sys.radius[i] + sys.radius[j];
    if (!found && dist < contact - slack) found = Overlap{i, j, dist, contact};
  });
  return found;
}

namespace {
//! "source[: file]:LINE: atom ID" for a line the system records.
std::string recorded_origin(const ParticleSystem& sys, std::size_t i, const std::string& source, long line) {
  std::string where = source;
  if (sys.source != source) where += (where.empty() ? "" : ": ") + sys.source;
  return where + ":" + std::to_string(line) + ": atom " + std::to_string(sys.id[i]);
}
}  // namespace

std::string atom_origin(const ParticleSystem& sys, std::size_t i, const std::string& source,
                        const std::vector<long>* atom_lines) {
  if (atom_lines && i < atom_lines->size())
    return source + ":" + std::to_string((*atom_lines)[i]) + ": atom " + std::to_string(sys.id[i]);
  if (sys.source_line.size() == sys.size() && !sys.source.empty())
    return recorded_origin(sys, i, source, sys.source_line[i]);
  return source + ": atom " + std::to_string(sys.id[i]);
}

std::string velocity_origin(const ParticleSystem& sys, std::size_t i, const std::string& source,
                            const std::vector<long>* atom_lines) {
  if (sys.velocity_line.size() == sys.size() && sys.velocity_line[i] > 0 && !sys.source.empty())
    return recorded_origin(sys, i, source, sys.velocity_line[i]);
  return atom_origin(sys, i, source, atom_lines);
}

double overlap_tolerance(const ParticleSystem& sys, double eps) {
  double len = 0, far = 0;
  for (int d = 0; d < 3; ++d) {
    len = std::max(len, sys.box.length(d));
    far = std::max({far, std::abs(sys.box.lo[d]), std::abs(sys.box.hi[d])});
  }
  return 16 * (eps * (len + 2 * sys.max_radius()) + std::numeric_limits<double>::epsilon() * far);
}

void validate_and_wrap(ParticleSystem& sys, const std::string& source, const std::vector<long>* atom_lines,
                       double rounding_eps, bool check_pairs) {
  validate_box(sys.box, source);
  if (sys.omega.size() < sys.size()) sys.omega.resize(sys.size());
  if (!sys.kinematic.empty() && sys.kinematic.size() != sys.size())
    throw InputError(source + ": " + std::to_string(sys.kinematic.size()) + " kinematic flags for " +
                     std::to_string(sys.size()) + " spheres");
  static const char* axis = "xyz";
  std::unordered_set<std::int64_t> seen;
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const std::string where = atom_origin(sys, i, source, atom_lines);
    auto fail = [&](const std::string& what) { throw InputError(where + ": " + what); };
    if (!seen.insert(sys.id[i]).second) fail("duplicate atom id");
    if (sys.id[i] < 1) fail("atom id must be >= 1");
    if (sys.type[i] < 1) fail("atom type " + std::to_string(sys.type[i]) + " must be >= 1");
    if (!(std::isfinite(sys.radius[i]) && sys.radius[i] > 0)) {
      std::ostringstream m;
      m << "radius " << sys.radius[i] << " must be positive and finite";
      fail(m.str());
    }
    if (!(std::isfinite(sys.mass[i]) && sys.mass[i] > 0)) {
      std::ostringstream m;
      m << "mass " << sys.mass[i] << " must be positive and finite";
      fail(m.str());
    }
    if (!finite(sys.pos[i])) fail("position is not finite (NaN or inf)");
    if (!finite(sys.vel[i])) fail("velocity is not finite (NaN or inf)");
    if (!finite(sys.omega[i])) fail("angular velocity is not finite (NaN or inf)");
  }
  check_scene_numbers(sys, source, atom_lines);
  // A sphere resting on a wall may end a run a rounding error past it, as a pair may overlap.
  const double slack = rounding_eps > 0 ? overlap_tolerance(sys, rounding_eps) : 0.0;
  for (std::size_t i = 0; i < sys.size(); ++i)
    for (int d = 0; d < 3; ++d) {
      if (sys.box.periodic[d]) continue;
      const double p = sys.pos[i][d], r = sys.radius[i];
      if (p - r < sys.box.lo[d] - slack || p + r > sys.box.hi[d] + slack) {
        std::ostringstream m;
        m.precision(17);
        m << atom_origin(sys, i, source, atom_lines) << ": " << axis[d] << " = " << p << " with radius " << r
          << " is outside the wall-bounded box [" << sys.box.lo[d] << ", " << sys.box.hi[d] << "]";
        throw InputError(m.str());
      }
    }
  const double diameter = 2 * sys.max_radius();
  for (int d = 0; d < 3; ++d)
    if (!sys.box.periodic[d] && sys.size() && !(sys.box.length(d) > diameter)) {
      std::ostringstream m;
      m.precision(17);
      m << source << ": walls along " << axis[d] << " are " << sys.box.length(d)
        << " apart, not more than the largest diameter " << diameter
        << " (a sphere that fills the gap would bounce between them infinitely often)";
      throw InputError(m.str());
    }
  for (int d = 0; d < 3; ++d)
    if (sys.box.periodic[d] && sys.box.length(d) < 2 * diameter) {
      std::ostringstream m;
      m << source << ": periodic box length " << sys.box.length(d) << " along " << axis[d]
        << " is less than twice the largest diameter " << diameter << " (minimum image would be ambiguous)";
      throw InputError(m.str());
    }
  wrap_periodic(sys);
  if (!check_pairs) return;
  if (const auto o = find_overlap(sys, slack)) {
    std::ostringstream m;
    m.precision(17);
    // The atom met first names the line; the other's line follows.
    m << atom_origin(sys, o->i, source, atom_lines) << " overlaps atom " << sys.id[o->j];
    if (atom_lines && o->j < atom_lines->size()) m << " (line " << (*atom_lines)[o->j] << ")";
    m << ": distance " << o->distance << " < contact distance " << o->contact;
    // Only a data file read by a double run can hold a float run's state.
    const double float_eps = std::numeric_limits<float>::epsilon();
    const double float_slack = overlap_tolerance(sys, float_eps);
    if (atom_lines && rounding_eps > 0 && rounding_eps < float_eps && o->contact - o->distance <= float_slack)
      m << " (within a float run's rounding, " << float_slack
        << ": a state written by --precision float is read by float runs only)";
    throw InputError(m.str());
  }
}

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

}  // namespace hardsphere
