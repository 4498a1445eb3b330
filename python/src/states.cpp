// Python values into the library's inputs. Every check that the library makes is left to it, so
// the messages are the CLI's; only what the CLI's parser checks before the library (a box from
// phi, the shapes of arrays) is checked here.
#include "states.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include "hardsphere/lammps_io.hpp"
#include "hardsphere/stepper.hpp"

namespace py = pybind11;

namespace hardsphere::python {

namespace {

std::array<double, 3> three(const py::object& v, const char* what) {
  if (py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v)) {
    const double x = v.cast<double>();
    return {x, x, x};
  }
  const auto list = v.cast<std::vector<double>>();
  if (list.size() != 3) throw InputError(std::string(what) + " needs one value or three (x, y, z)");
  return {list[0], list[1], list[2]};
}

//! An (N, k) float64 array's rows, or one value for all N when `v` is a number.
std::vector<double> column(const py::object& v, std::size_t n, const char* what) {
  if (py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v)) return std::vector<double>(n, v.cast<double>());
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(v);
  if (!a || a.ndim() != 1 || std::size_t(a.shape(0)) != n)
    throw InputError(std::string(what) + " must be a number or have shape (N,) with N = " + std::to_string(n));
  return std::vector<double>(a.data(), a.data() + n);
}

template <class T>
py::array_t<T, py::array::c_style | py::array::forcecast> rows3(const py::object& v, std::size_t n, const char* what) {
  auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(v);
  if (!a || a.ndim() != 2 || a.shape(1) != 3 || (n != std::size_t(-1) && std::size_t(a.shape(0)) != n))
    throw InputError(std::string(what) + " must have shape (N, 3)" +
                     (n != std::size_t(-1) ? " with N = " + std::to_string(n) : std::string()));
  return a;
}

}  // namespace

Box make_box(const py::object& lengths, const std::string& boundary, const py::object& lo) {
  const auto len = three(lengths, "Box lengths");
  Box b = Box::from_lengths(len, parse_boundary(boundary));
  if (!lo.is_none()) {
    const auto l = three(lo, "Box lo");
    for (int d = 0; d < 3; ++d) b.lo[d] = l[d], b.hi[d] = l[d] + len[d];
  }
  validate_box(b, "Box");
  return b;
}

std::shared_ptr<SystemData> make_system(const Box& box, const py::object& positions, const py::object& velocities,
                                        const py::object& radii, const py::object& masses, const py::object& ids,
                                        const py::object& types, const py::object& images, const py::object& omegas) {
  const auto pos = rows3<double>(positions, std::size_t(-1), "positions");
  const std::size_t n = std::size_t(pos.shape(0));
  auto data = std::make_shared<SystemData>();
  ParticleSystem& s = data->sys;
  s.box = box;
  s.resize(n);
  const auto r = column(radii, n, "radii"), m = column(masses, n, "masses");
  for (std::size_t i = 0; i < n; ++i) {
    s.id[i] = std::int64_t(i + 1), s.type[i] = 1, s.radius[i] = r[i], s.mass[i] = m[i];
    s.pos[i] = {pos.at(i, 0), pos.at(i, 1), pos.at(i, 2)};
    s.vel[i] = {0, 0, 0}, s.image[i] = {0, 0, 0};
  }
  if (!velocities.is_none()) {
    const auto v = rows3<double>(velocities, n, "velocities");
    for (std::size_t i = 0; i < n; ++i) s.vel[i] = {v.at(i, 0), v.at(i, 1), v.at(i, 2)};
  }
  if (!omegas.is_none()) {
    const auto w = rows3<double>(omegas, n, "omegas");
    for (std::size_t i = 0; i < n; ++i) s.omega[i] = {w.at(i, 0), w.at(i, 1), w.at(i, 2)};
  }
  if (!images.is_none()) {
    const auto im = rows3<std::int32_t>(images, n, "images");
    for (std::size_t i = 0; i < n; ++i) s.image[i] = {im.at(i, 0), im.at(i, 1), im.at(i, 2)};
  }
  if (!ids.is_none()) {
    auto a = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(ids);
    if (!a || a.ndim() != 1 || std::size_t(a.shape(0)) != n)
      throw InputError("ids must have shape (N,) with N = " + std::to_string(n));
    for (std::size_t i = 0; i < n; ++i) s.id[i] = a.at(i);
  }
  if (!types.is_none()) {
    auto a = py::array_t<int, py::array::c_style | py::array::forcecast>::ensure(types);
    if (!a || a.ndim() != 1 || std::size_t(a.shape(0)) != n)
      throw InputError("types must have shape (N,) with N = " + std::to_string(n));
    for (std::size_t i = 0; i < n; ++i) {
      if (a.at(i) < 1) throw InputError("types must be >= 1 (found " + std::to_string(a.at(i)) + ")");
      s.type[i] = a.at(i);
    }
  }
  validate_and_wrap(s, "System");
  return data;
}

std::shared_ptr<SystemData> generate(InitMethod method, std::int64_t n, std::optional<double> phi,
                                     const py::object& box, std::uint64_t seed, double radius, double mass,
                                     double temperature, std::optional<double> speed, const std::string& boundary,
                                     std::optional<double> rotational_temperature, double inertia) {
  InitSpec spec;
  spec.rotational_temperature = rotational_temperature, spec.inertia = inertia;
  spec.n = n, spec.radius = radius, spec.mass = mass, spec.temperature = temperature, spec.speed = speed;
  spec.seed = seed, spec.method = method;
  const auto periodic = parse_boundary(boundary);
  if (!(radius > 0) || !std::isfinite(radius))
    throw InputError("radius " + std::to_string(radius) + " must be positive and finite");
  if (!box.is_none()) {
    if (phi) throw InputError("phi and box both set the box size; give one");
    spec.box = make_box(box, boundary, py::none());
  } else {
    const double p = phi.value_or(0.2);
    if (!(p > 0)) throw InputError("phi " + std::to_string(p) + " must be positive");
    // n < 1: any box, make_initial_state refuses the count with its own message.
    const double l = n < 1 ? 1.0 : std::cbrt(double(n) * 4.0 / 3.0 * M_PI * radius * radius * radius / p);
    spec.box = Box::from_lengths({l, l, l}, periodic);
  }
  auto data = std::make_shared<SystemData>();
  {
    py::gil_scoped_release release;
    data->sys = make_initial_state(spec);
  }
  data->seed = seed;
  data->com_removed = true;
  return data;
}

std::shared_ptr<SystemData> from_data(const std::string& path, const std::string& boundary,
                                      const std::string& precision) {
  const double eps = parse_precision(precision) == Precision::Float ? double(std::numeric_limits<float>::epsilon())
                                                                    : std::numeric_limits<double>::epsilon();
  const auto periodic = parse_boundary(boundary);
  auto data = std::make_shared<SystemData>();
  data->rounding_eps = eps;
  // A file that cannot be opened (or is a directory): read_data's refusal, as an OSError.
  if (!std::ifstream(path) || std::filesystem::is_directory(path))
    file_call([&] { return read_data(path, periodic, eps); });
  data->sys = read_data(path, periodic, eps);
  return data;
}

Physics physics_of(const Box& box, double restitution, std::optional<double> contact_time,
                   std::optional<std::array<double, 3>> gravity, std::optional<double> resting_time,
                   double tangential_restitution, std::optional<double> friction, std::optional<double> inertia) {
  Physics p;
  p.tangential_restitution = tangential_restitution;
  p.friction = friction.value_or(p.friction), p.inertia = inertia.value_or(p.inertia);
  p.restitution = restitution;
  p.contact_time = contact_time.value_or(restitution < 1 ? kDefaultContactTime : 0.0);
  if (gravity) p.gravity = *gravity;
  p.resting_time = resting_time.value_or(0.0);
  // The library's option rules refuse a keyword given where it has no effect.
  PhysicsGiven given;
  given.contact_time = contact_time.has_value(), given.resting_time = resting_time.has_value();
  given.friction = friction.has_value(), given.inertia = inertia.has_value();
  return validated(p, box.periodic, physics_names(), given);
}

const PhysicsNames& physics_names() {
  static const PhysicsNames names{
      "restitution",  "contact_time",           "gravity",  "walls on that axis (boundary ...,w)",
      "resting_time", "tangential_restitution", "friction", "inertia"};
  return names;
}

std::array<int, 3> cells_of(const py::object& cells) {
  if (py::isinstance<py::str>(cells)) {
    if (cells.cast<std::string>() == "auto") return {0, 0, 0};
    throw InputError("cells '" + cells.cast<std::string>() + "' must be auto, K or (Kx, Ky, Kz)");
  }
  const auto v = three(cells, "cells");
  std::array<int, 3> k{};
  for (int d = 0; d < 3; ++d) {
    if (!(v[d] >= 1) || v[d] != std::floor(v[d]) || v[d] > 1e6)
      throw InputError("cells: cell counts must be whole numbers from 1 to 1000000 (or auto)");
    k[d] = int(v[d]);
  }
  return k;
}

}  // namespace hardsphere::python
