// Python values into the library's inputs. Every check that the library makes is left to it, so
// the messages are the CLI's; only what the CLI's parser checks before the library (a box from
// phi, the shapes of arrays) is checked here.
#include "states.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include "hardsphere/format.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/simulation.hpp"
#include "hardsphere/stepper.hpp"
#include "values.hpp"

namespace py = pybind11;

namespace hardsphere::python {

namespace {

std::array<double, 3> three(const py::object& v, const char* what) {
  const auto x = one_or_three(v, what);
  return {x[0], x[1], x[2]};
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
  const auto pos = real_array(positions, kAnyRows, 3, "positions", false);
  const std::size_t n = pos.size() / 3;
  auto data = std::make_shared<SystemData>();
  ParticleSystem& s = data->sys;
  s.box = box;
  s.resize(n);
  const auto r = real_array(radii, n, 1, "radii", true), m = real_array(masses, n, 1, "masses", true);
  auto vec3 = [](const std::vector<double>& a, std::size_t i) { return Vec3d{a[3 * i], a[3 * i + 1], a[3 * i + 2]}; };
  for (std::size_t i = 0; i < n; ++i) {
    s.id[i] = std::int64_t(i + 1), s.type[i] = 1, s.radius[i] = r[i], s.mass[i] = m[i];
    s.pos[i] = vec3(pos, i), s.vel[i] = {0, 0, 0}, s.image[i] = {0, 0, 0};
  }
  if (!velocities.is_none()) {
    const auto v = real_array(velocities, n, 3, "velocities", false);
    for (std::size_t i = 0; i < n; ++i) s.vel[i] = vec3(v, i);
  }
  if (!omegas.is_none()) {
    const auto w = real_array(omegas, n, 3, "omegas", false);
    for (std::size_t i = 0; i < n; ++i) s.omega[i] = vec3(w, i);
  }
  // Integers as a data file has them: whole, in range, refused naming the value as given.
  if (!images.is_none()) {
    const auto im = whole_array(images, n, 3, "images", INT32_MIN, INT32_MAX, "32-bit integers");
    // A wall axis has no images: set to 0, as the data reader does (and LAMMPS's read_data).
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t d = 0; d < 3; ++d) s.image[i][d] = box.periodic[d] ? std::int32_t(im[3 * i + d]) : 0;
  }
  if (!ids.is_none()) {
    const auto id = whole_array(ids, n, 1, "ids", 1, INT64_MAX, "ids are 1 to " + std::to_string(INT64_MAX));
    for (std::size_t i = 0; i < n; ++i) s.id[i] = id[i];
  }
  if (!types.is_none()) {
    const auto t = whole_array(types, n, 1, "types", 1, INT32_MAX, "types are 1 to " + std::to_string(INT32_MAX));
    for (std::size_t i = 0; i < n; ++i) s.type[i] = int(t[i]);
  }
  validate_and_wrap(s, "System");
  return data;
}

namespace {
//! walls=[...]: each the CLI's --wall words, named in messages as walls 'SPEC'.
std::vector<WallShape> shapes_of(const py::object& walls) {
  std::vector<WallShape> out;
  if (walls.is_none()) return out;
  if (py::isinstance<py::str>(walls) || !py::isinstance<py::sequence>(walls))
    throw InputError("walls must be a list of wall specs (strings), got " + py::repr(walls).cast<std::string>());
  for (const auto item : walls.cast<py::sequence>()) {
    if (!py::isinstance<py::str>(item))
      throw InputError("walls: each wall is a spec string, got " + py::repr(item).cast<std::string>());
    const std::string spec = item.cast<std::string>();
    out.push_back(parse_wall_shape(spec, "walls '" + spec + "'"));
  }
  return out;
}

}  // namespace

std::shared_ptr<SystemData> generate(InitMethod method, std::int64_t n, std::optional<double> phi,
                                     const py::object& box, std::uint64_t seed, double radius, double mass,
                                     std::optional<double> temperature, std::optional<double> speed,
                                     const std::string& boundary, std::optional<double> rotational_temperature,
                                     std::optional<double> inertia, const py::object& walls) {
  // Keywords that would be ignored are refused, as the CLI refuses --temperature with --init-speed.
  if (temperature && speed) throw InputError("temperature and speed both set the velocities; give one");
  if (inertia && !rotational_temperature)
    throw InputError("inertia " + format_exact(*inertia) +
                     " sets the spins' distribution: it needs rotational_temperature (without it the spheres do "
                     "not spin)");
  InitSpec spec;
  spec.rotational_temperature = rotational_temperature, spec.inertia = inertia.value_or(0.4);
  spec.n = n, spec.radius = radius, spec.mass = mass, spec.temperature = temperature.value_or(1.0), spec.speed = speed;
  spec.seed = seed, spec.method = method;
  const auto periodic = parse_boundary(boundary);
  spec.walls = shapes_of(walls);
  if (!(radius > 0) || !std::isfinite(radius))
    throw InputError("radius " + format_exact(radius) + " must be positive and finite");
  if (!box.is_none()) {
    if (phi) throw InputError("phi and box both set the box size; give one");
    spec.box = make_box(box, boundary, py::none());
  } else {
    const double p = phi.value_or(0.2);
    if (!(p > 0) || !std::isfinite(p)) throw InputError("phi " + format_exact(p) + " must be positive and finite");
    // n < 1: any box, make_initial_state refuses the count with its own message.
    const double l = n < 1 ? 1.0 : std::cbrt(double(n) * 4.0 / 3.0 * M_PI * radius * radius * radius / p);
    if (!(std::isfinite(l) && l > 0))  // as the CLI's --phi
      throw InputError("phi " + format_exact(p) + " with radius " + format_number(radius) + " and n " +
                       std::to_string(n) + " gives a box length " + format_number(l) +
                       " that is not a positive finite number");
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
                                      const std::string& precision, const py::object& kinematic_types) {
  std::vector<int> types;
  if (!kinematic_types.is_none()) {
    if (py::isinstance<py::str>(kinematic_types) || !py::isinstance<py::sequence>(kinematic_types))
      throw InputError("kinematic_types takes a sequence of atom types, e.g. [2, 3]");
    for (const py::handle t : kinematic_types) {
      const int v = int(whole_arg(t, "kinematic_types", 1, INT_MAX));
      if (std::find(types.begin(), types.end(), v) != types.end())
        throw InputError("kinematic_types: type " + std::to_string(v) + " is given twice");
      types.push_back(v);
    }
  }
  const double eps = rounding_epsilon(parse_precision(precision));
  const auto periodic = parse_boundary(boundary);
  auto data = std::make_shared<SystemData>();
  data->rounding_eps = eps;
  // A file that cannot be opened (or is a directory): read_data's refusal, as an OSError.
  if (!std::ifstream(path) || std::filesystem::is_directory(path))
    file_call([&] { return read_data(path, periodic, eps); });
  data->sys = read_data(path, periodic, eps, nullptr, types.empty());
  if (!types.empty()) {  // kinematic spheres may overlap each other: the pairs checked once they are marked
    set_kinematic_types(data->sys, types, "kinematic_types", path);
    validate_and_wrap(data->sys, path, &data->sys.source_line, eps);
  }
  return data;
}

namespace {
double number_arg(const py::handle& v, const std::string& name) {
  if (py::isinstance<py::bool_>(v) || !(py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v)))
    throw InputError(name + " takes a number, 'face=value,...' text or a dict {face: value}, got " +
                     py::repr(v).cast<std::string>());
  return v.cast<double>();
}

//! One wall keyword into p (see WallArgs).
void take_wall_arg(Physics& p, PhysicsGiven& given, WallSetting setting, const py::object& value,
                   const std::string& name) {
  if (value.is_none()) return;
  if (py::isinstance<py::str>(value)) return parse_wall_setting(p, given, setting, value.cast<std::string>(), name);
  if (py::isinstance<py::dict>(value)) {
    for (const auto item : value.cast<py::dict>()) {
      if (!py::isinstance<py::str>(item.first) || item.first.cast<std::string>().empty())
        throw InputError(name + ": the keys are faces (xlo xhi ylo yhi zlo zhi), got " +
                         py::repr(item.first).cast<std::string>());
      set_wall_law(p, given, setting, item.first.cast<std::string>(), number_arg(item.second, name), name);
    }
    return;
  }
  set_wall_law(p, given, setting, "", number_arg(value, name), name);
}
}  // namespace

Physics physics_of(const Box& box, double restitution, std::optional<double> contact_time,
                   std::optional<std::array<double, 3>> gravity, std::optional<double> resting_time,
                   double tangential_restitution, std::optional<double> friction, std::optional<double> inertia,
                   const WallArgs& walls) {
  Physics p;
  PhysicsGiven given;
  take_wall_arg(p, given, WallSetting::Restitution, walls.restitution, "wall_restitution");
  take_wall_arg(p, given, WallSetting::TangentialRestitution, walls.tangential_restitution,
                "wall_tangential_restitution");
  take_wall_arg(p, given, WallSetting::Friction, walls.friction, "wall_friction");
  p.shapes = shapes_of(walls.shapes);
  p.tangential_restitution = tangential_restitution;
  p.friction = friction.value_or(p.friction), p.inertia = inertia.value_or(p.inertia);
  p.restitution = restitution;
  p.contact_time = contact_time.value_or(restitution < 1 || p.inelastic_walls() ? kDefaultContactTime : 0.0);
  if (gravity) p.gravity = *gravity;
  p.resting_time = resting_time.value_or(0.0);
  // The library's option rules refuse a keyword given where it has no effect.
  given.contact_time = contact_time.has_value(), given.resting_time = resting_time.has_value();
  given.friction = friction.has_value(), given.inertia = inertia.has_value();
  p = validated(p, box.periodic, physics_names(), given);
  // A scene that runs but cannot settle (a chute without wall friction) is said, not refused.
  const std::string flow = unbounded_flow(p, box.periodic, physics_names());
  if (!flow.empty() && PyErr_WarnEx(PyExc_UserWarning, flow.c_str(), 1) != 0) throw py::error_already_set();
  return p;
}

const PhysicsNames& physics_names() {
  static const PhysicsNames names{"restitution",      "contact_time",
                                  "gravity",          "walls on that axis (boundary ...,w)",
                                  "resting_time",     "tangential_restitution",
                                  "friction",         "inertia",
                                  "wall_restitution", "wall_tangential_restitution",
                                  "wall_friction"};
  return names;
}

double work_limit_of(double limit) {
  if (!(limit > 0) || !std::isfinite(limit))
    throw InputError("work_limit " + format_exact(limit) +
                     " must be positive and finite (the most particle-steps or events a run may take)");
  return limit;
}

std::array<int, 3> cells_of(const py::object& cells) {
  if (py::isinstance<py::str>(cells)) {
    const std::string text = text_arg(cells, "cells");
    if (text == "auto") return {0, 0, 0};
    throw InputError("cells '" + text + "' must be auto, K or (Kx, Ky, Kz)");
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
