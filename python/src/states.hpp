#pragma once
//! Python values into the library's inputs: boxes, states (given, generated, read), physics and
//! cell grids, checked by the library's own validation. InputError is raised as ValueError,
//! FileError as OSError (module.cpp).
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "hardsphere/box.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/init.hpp"
#include "hardsphere/physics.hpp"
#include "simulation.hpp"

namespace hardsphere::python {

//! A refusal about a file (cannot open, cannot write): raised as OSError.
struct FileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

//! Runs `f`, turning its InputErrors into FileErrors (for calls whose every refusal is a file's).
template <class F>
auto file_call(F&& f) {
  try {
    return f();
  } catch (const FormatError&) {
    throw;
  } catch (const InputError& e) {
    throw FileError(e.what());
  }
}

//! hs.Box(lengths, boundary, lo): lengths and lo one number or three.
Box make_box(const pybind11::object& lengths, const std::string& boundary, const pybind11::object& lo);

//! hs.System(box, positions, ...), checked as a data file is.
std::shared_ptr<SystemData> make_system(const Box& box, const pybind11::object& positions,
                                        const pybind11::object& velocities, const pybind11::object& radii,
                                        const pybind11::object& masses, const pybind11::object& ids,
                                        const pybind11::object& types, const pybind11::object& images,
                                        const pybind11::object& omegas);

//! A generated state as the CLI's --n/--phi/--box/... make it (temperature 1 and inertia 0.4
//! when not given; either is refused where it would be ignored).
std::shared_ptr<SystemData> generate(InitMethod method, std::int64_t n, std::optional<double> phi,
                                     const pybind11::object& box, std::uint64_t seed, double radius, double mass,
                                     std::optional<double> temperature, std::optional<double> speed,
                                     const std::string& boundary, std::optional<double> rotational_temperature,
                                     std::optional<double> inertia, const pybind11::object& walls = pybind11::none());

//! A data file as --read-data reads it; FileError if it cannot be opened. `kinematic_types`
//! (None or a sequence of atom types): those atoms' spheres are kinematic, as --kinematic-types.
std::shared_ptr<SystemData> from_data(const std::string& path, const std::string& boundary,
                                      const std::string& precision, const pybind11::object& kinematic_types);

//! The keywords' names of the physics settings, for the library's messages.
const PhysicsNames& physics_names();

//! The wall keywords as given: None, one number for every wall, the CLI's text ('zlo=0.5,zhi=0.9')
//! or a dict {face: value}.
struct WallArgs {
  pybind11::object restitution = pybind11::none(), tangential_restitution = pybind11::none(),
                   friction = pybind11::none();
  //! walls=[...]: shaped walls, each the CLI's --wall words (parse_wall_shape()).
  pybind11::object shapes = pybind11::none();
};

//! The physics keywords, validated with the keywords' names in messages.
Physics physics_of(const Box& box, double restitution, std::optional<double> contact_time,
                   std::optional<std::array<double, 3>> gravity, std::optional<double> resting_time,
                   double tangential_restitution, std::optional<double> friction, std::optional<double> inertia,
                   const WallArgs& walls = {});

//! work_limit: positive and finite (a NaN or infinity would be no limit at all).
double work_limit_of(double limit);

//! "auto", K or (Kx, Ky, Kz).
std::array<int, 3> cells_of(const pybind11::object& cells);

}  // namespace hardsphere::python
