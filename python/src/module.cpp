// The compiled part of the Python package `hardsphere` (docs/python.md): Box, System, Stepper and
// EventEngine over the public headers. Options and refusals are the CLI's (standalone/cli/
// options.cpp); InputError becomes ValueError, a file that cannot be read or written OSError.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <limits>
#include <stdexcept>

#include "arrays.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/init.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/stepper.hpp"
#include "run_loop.hpp"
#include "simulation.hpp"
#include "states.hpp"

namespace py = pybind11;
using namespace py::literals;
using namespace hardsphere;
using namespace hardsphere::python;

namespace {

py::dict json_dict(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

//! The array properties common to System, Stepper and EventEngine.
template <class C, class Get>
void add_arrays(C& c, Get get, const char* what) {
  const std::pair<const char*, Field> fields[] = {{"positions", Field::Positions},
                                                  {"velocities", Field::Velocities},
                                                  {"radii", Field::Radii},
                                                  {"masses", Field::Masses},
                                                  {"ids", Field::Ids},
                                                  {"types", Field::Types},
                                                  {"images", Field::Images},
                                                  {"omegas", Field::Omegas}};
  for (const auto& [name, f] : fields) {
    const Field field = f;
    c.def_property_readonly(
        name, [get, field](py::object self) { return get(self, field); },
        (std::string(describe(field)) + what).c_str());
  }
}

template <class Sim>
void add_simulation(py::class_<Sim>& c) {
  add_arrays(
      c,
      [](py::object self, Field f) {
        auto s = self.cast<Sim&>().state();
        const ParticleSystem& ref = *s;
        return view(ref, f, owner_of(std::move(s)));
      },
      ". A read-only copy of the engine's state in id order (the engine keeps its spheres in its own order), "
      "taken once per state and shared by every array of that state; a later run does not change it.");
  c.def_property_readonly(
      "n", [](Sim& s) { return s.state()->size(); }, "number of spheres");
  c.def_property_readonly(
      "box", [](Sim& s) { return s.state()->box; }, "the box (a copy)");
  c.def_property_readonly("sim_time", &Sim::sim_time, "simulated time since construction or reset_counters()");
  c.def(
      "observables", [](Sim& s, int bins) { return json_dict(s.observables(bins)); }, "histogram_bins"_a = 40,
      "The CLI's JSON summary (docs/cli.md) of the measurement since construction or reset_counters(): "
      "compressibility_factor, pressure, temperature, collisions, collision_rate_per_particle, kinetic and "
      "potential energies, momentum, speed_histogram, ... as a dict.");
  c.def("reset_counters", &Sim::reset_counters,
        "Starts a new measurement: counters, energy and momentum references, loop CPU time.");
  c.def(
      "write_data", [](Sim& s, const std::string& p) { file_call([&] { s.write_data(p); }); }, "path"_a,
      "Writes the current state as the CLI's --write-data does (LAMMPS data file, 17 digits, atomic).");
  c.def(
      "write_dump", [](Sim& s, const std::string& p) { file_call([&] { s.write_dump(p); }); }, "path"_a,
      "Writes the current state as one frame of the CLI's --dump (LAMMPS text dump, atomic); hs.DumpWriter "
      "writes several.");
  c.def(
      "system",
      [](Sim& s) {
        return std::make_shared<SystemData>(SystemData{*s.state(), s.origin().seed, false});
      },
      "The current state as a System (a copy).");
}

}  // namespace

PYBIND11_MODULE(_hardsphere, m) {
  m.doc() = "hardsphere: time-stepped and event-driven hard-sphere simulation (docs/python.md)";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const FileError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  py::class_<Box>(m, "Box", "An axis-aligned box, periodic ('p') or walled ('w') per axis.")
      .def(py::init(&make_box), "lengths"_a, "boundary"_a = "p", "lo"_a = py::none(),
           "Box(lengths, boundary='p', lo=(0, 0, 0)): lengths one value or three; boundary 'p', 'w' or e.g. 'p,p,w'.")
      .def_property_readonly("lo", [](const Box& b) { return b.lo; })
      .def_property_readonly("hi", [](const Box& b) { return b.hi; })
      .def_property_readonly("lengths",
                             [](const Box& b) {
                               return std::array<double, 3>{b.length(0), b.length(1), b.length(2)};
                             })
      .def_property_readonly("periodic", [](const Box& b) { return b.periodic; })
      .def_property_readonly("boundary", [](const Box& b) { return boundary_string(b.periodic); })
      .def_property_readonly("volume", &Box::volume)
      .def("__repr__", [](const Box& b) {
        return "Box(lengths=(" + std::to_string(b.length(0)) + ", " + std::to_string(b.length(1)) + ", " +
               std::to_string(b.length(2)) + "), boundary='" + boundary_string(b.periodic) + "')";
      });

  py::class_<SystemData, std::shared_ptr<SystemData>> sys(
      m, "System", "A particle state: generated, read from a LAMMPS data file or given as arrays.");
  sys.def(py::init(&make_system), "box"_a, "positions"_a, "velocities"_a = py::none(), "radii"_a = 0.5,
          "masses"_a = 1.0, "ids"_a = py::none(), "types"_a = py::none(), "images"_a = py::none(),
          "omegas"_a = py::none(),
          "System(box, positions, velocities=None, radii=0.5, masses=1.0, ids=None, types=None, images=None, "
          "omegas=None): "
          "checked as a data file is (no overlaps, inside walls, ...); periodic coordinates are wrapped.");
  sys.def_static(
      "random",
      [](std::int64_t n, std::optional<double> phi, py::object box, std::uint64_t seed, double radius, double mass,
         double temperature, std::optional<double> speed, const std::string& boundary, const std::string& method,
         std::optional<double> rotational_temperature, double inertia) {
        return generate(parse_init_method(method), n, phi, box, seed, radius, mass, temperature, speed, boundary,
                        rotational_temperature, inertia);
      },
      "n"_a = 1000, "phi"_a = py::none(), "box"_a = py::none(), "seed"_a = 1, "radius"_a = 0.5, "mass"_a = 1.0,
      "temperature"_a = 1.0, "speed"_a = py::none(), "boundary"_a = "p", "method"_a = "auto",
      "rotational_temperature"_a = py::none(), "inertia"_a = 0.4,
      "A generated state as the CLI's --n/--phi/--box/--init make it: n spheres at packing fraction phi "
      "(default 0.2) or in a box of these lengths, Maxwell-Boltzmann velocities at temperature (or one speed), "
      "momentum zeroed; with rotational_temperature, angular velocities for rough spheres (each component normal "
      "with variance T/I, I = inertia m r^2; the CLI's default is the translational temperature, here none: zero). "
      "method: auto (random insertion up to phi 0.25, lattice up to 0.55, dense up to 0.64), "
      "random, lattice or dense (docs/initial_states.md).");
  sys.def_static(
      "dense",
      [](std::int64_t n, std::optional<double> phi, py::object box, std::uint64_t seed, double radius, double mass,
         double temperature, std::optional<double> speed, const std::string& boundary,
         std::optional<double> rotational_temperature, double inertia) {
        return generate(InitMethod::Dense, n, phi, box, seed, radius, mass, temperature, speed, boundary,
                        rotational_temperature, inertia);
      },
      "n"_a = 1000, "phi"_a = py::none(), "box"_a = py::none(), "seed"_a = 1, "radius"_a = 0.5, "mass"_a = 1.0,
      "temperature"_a = 1.0, "speed"_a = py::none(), "boundary"_a = "p", "rotational_temperature"_a = py::none(),
      "inertia"_a = 0.4,
      "System.random(..., method='dense'): an amorphous quench and compression (--init dense), up to phi 0.64.");
  sys.def_static("from_data", &from_data, "path"_a, "boundary"_a = "p", "precision"_a = "double",
                 "Reads a LAMMPS data file (atom_style sphere) as --read-data does; overlaps up to the rounding of "
                 "an engine of this precision are accepted. OSError if unreadable, ValueError (file:line) if "
                 "malformed or invalid.");
  add_arrays(
      sys, [](py::object self, Field f) { return view(self.cast<SystemData&>().sys, f, self); },
      ". A read-only view of the System's memory (the array keeps the System alive).");
  sys.def_property_readonly("n", [](const SystemData& d) { return d.sys.size(); })
      .def("__len__", [](const SystemData& d) { return d.sys.size(); })
      .def_property_readonly("box", [](const SystemData& d) { return d.sys.box; })
      .def_property_readonly("packing_fraction", [](const SystemData& d) { return d.sys.packing_fraction(); })
      .def_property_readonly("seed", [](const SystemData& d) { return d.seed; })
      .def(
          "write_data",
          [](const SystemData& d, const std::string& path, const std::string& title) {
            file_call([&] {
              check_output_paths({{"write_data", path}});
              write_data(path, d.sys, title);
            });
          },
          "path"_a, "title"_a = "hardsphere state", "Writes a LAMMPS data file (17 digits, atomic).");

  py::class_<DumpFile>(m, "DumpWriter",
                       "A LAMMPS text dump as the CLI's --dump writes it, one frame per write(sim); the file appears "
                       "complete at close() (a with block closes it, or discards it on an exception).")
      .def(
          py::init([](const std::string& path) { return file_call([&] { return std::make_unique<DumpFile>(path); }); }),
          "path"_a)
      .def(
          "write",
          [](DumpFile& d, py::object sim) {
            if (d.closed()) throw InputError("DumpWriter '" + d.path() + "' is closed");
            const Simulation* s = nullptr;
            if (py::isinstance<StepperSim>(sim))
              s = &sim.cast<const StepperSim&>();
            else if (py::isinstance<EventSim>(sim))
              s = &sim.cast<const EventSim&>();
            else
              throw py::type_error("DumpWriter.write takes a Stepper or an EventEngine");
            file_call([&] { d.write(*s); });
          },
          "sim"_a,
          "Appends a frame of the engine's current state (timestep: its steps or events so far, as the CLI's frames).")
      .def(
          "close", [](DumpFile& d) { file_call([&] { d.close(); }); },
          "Commits the file (renamed into place); closing twice does nothing.")
      .def("discard", &DumpFile::discard, "Removes the unfinished file; nothing is left.")
      .def_property_readonly("closed", &DumpFile::closed)
      .def_property_readonly("frames", &DumpFile::frames, "frames written")
      .def_property_readonly("path", &DumpFile::path)
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](DumpFile& d, py::object type, py::object, py::object) {
        if (type.is_none())
          file_call([&] { d.close(); });
        else
          d.discard();
        return false;
      });

  py::class_<StepperSim> st(m, "Stepper", "The time stepper (the CLI's default engine).");
  st.def(py::init([](const SystemData& s, double dt, double restitution, std::optional<double> contact_time,
                     std::optional<std::array<double, 3>> gravity, std::optional<double> resting_time,
                     const std::string& detect, const std::string& precision, py::object cells, double work_limit,
                     double tangential_restitution, std::optional<double> friction, std::optional<double> inertia) {
           StepperConfig cfg;
           cfg.dt = dt;
           cfg.detect = parse_detect(detect);
           cfg.cells = cells_of(cells);
           cfg.max_particle_steps = work_limit;
           cfg.names = physics_names();
           const Physics p = physics_of(s.sys.box, restitution, contact_time, gravity, resting_time,
                                        tangential_restitution, friction, inertia);
           return std::make_unique<StepperSim>(s, p, cfg, parse_precision(precision));
         }),
         "system"_a, py::kw_only(), "dt"_a = 0.01, "restitution"_a = 1.0, "contact_time"_a = py::none(),
         "gravity"_a = py::none(), "resting_time"_a = py::none(), "detect"_a = "auto", "precision"_a = "double",
         "cells"_a = "auto", "work_limit"_a = 1e15, "tangential_restitution"_a = -1.0, "friction"_a = py::none(),
         "inertia"_a = py::none(),
         "Stepper(system, *, dt=0.01, restitution=1, contact_time=1e-4 when restitution < 1, gravity=None, "
         "resting_time=None (with gravity; 0: the sub-step), detect='auto', precision='double', cells='auto', "
         "work_limit=1e15, tangential_restitution=-1, friction=None (inf), inertia=None (0.4; both rough spheres "
         "only)): the CLI's options.");
  st.def(
      "_run",
      [](py::object self, std::optional<std::int64_t> steps, std::optional<double> time, py::object callback,
         std::optional<std::int64_t> every,
         py::object progress) { run_stepper(self.cast<StepperSim&>(), self, steps, time, callback, every, progress); },
      "steps"_a = py::none(), "time"_a = py::none(), "callback"_a = py::none(), "every"_a = py::none(),
      "progress"_a = py::none());
  st.def_property_readonly("dt", &StepperSim::dt);
  st.def_property_readonly("steps", &StepperSim::steps, "steps since construction or reset_counters()");
  st.def_property_readonly("skin", [](const StepperSim& s) { return s.engine().skin(); });
  st.def_property_readonly("cells_per_dim", [](const StepperSim& s) { return s.engine().cells_per_dim(); });
  st.def_property_readonly("scene_kernel", [](const StepperSim& s) { return s.engine().scene_kernel(); });
  add_simulation(st);

  py::class_<EventSim> ev(m, "EventEngine", "The exact event-driven engine (the CLI's --engine event).");
  ev.def(py::init([](const SystemData& s, double restitution, std::optional<double> contact_time,
                     std::optional<std::array<double, 3>> gravity, std::optional<double> resting_time, py::object cells,
                     double shell, double work_limit, double tangential_restitution, std::optional<double> friction,
                     std::optional<double> inertia) {
           EventConfig cfg;
           cfg.cells = cells_of(cells);
           cfg.shell = shell;
           cfg.max_events = work_limit;
           cfg.names = physics_names();
           const Physics p = physics_of(s.sys.box, restitution, contact_time, gravity, resting_time,
                                        tangential_restitution, friction, inertia);
           return std::make_unique<EventSim>(s, p, cfg);
         }),
         "system"_a, py::kw_only(), "restitution"_a = 1.0, "contact_time"_a = py::none(), "gravity"_a = py::none(),
         "resting_time"_a = py::none(), "cells"_a = "auto", "shell"_a = 0.0, "work_limit"_a = 1e15,
         "tangential_restitution"_a = -1.0, "friction"_a = py::none(), "inertia"_a = py::none(),
         "EventEngine(system, *, restitution=1, contact_time=1e-4 when restitution < 1, gravity=None, "
         "resting_time=None (with gravity; 0.01 sqrt(d/|g|)), cells='auto', shell=0 (auto), work_limit=1e15, "
         "tangential_restitution=-1, friction=None (inf), inertia=None (0.4; both rough spheres only)): the CLI's "
         "options.");
  ev.def(
      "_run",
      [](py::object self, std::optional<std::int64_t> steps, std::optional<double> time, py::object callback,
         std::optional<double> every, py::object progress,
         int blocks) { run_event(self.cast<EventSim&>(), self, steps, time, callback, every, progress, blocks); },
      "steps"_a = py::none(), "time"_a = py::none(), "callback"_a = py::none(), "every"_a = py::none(),
      "progress"_a = py::none(), "blocks"_a = 20);
  ev.def_property_readonly("time", &EventSim::time, "simulated time since construction");
  ev.def_property_readonly("events", &EventSim::events, "events since construction or reset_counters()");
  ev.def_property_readonly("shell", [](const EventSim& s) { return s.engine().shell(); });
  ev.def_property_readonly("cells_per_dim", [](const EventSim& s) { return s.engine().cells_per_dim(); });
  ev.def_property_readonly("scene_kernel", [](const EventSim& s) { return s.engine().scene_kernel(); });
  add_simulation(ev);
}
