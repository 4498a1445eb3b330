// The compiled part of the Python package `hardsphere` (docs/python.md): Box, System, Stepper and
// EventEngine over the public headers. Options and refusals are the CLI's (standalone/cli/
// options.cpp); InputError becomes ValueError, a file that cannot be read or written OSError.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "arrays.hpp"
#include "hardsphere/atomic_file.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/format.hpp"
#include "hardsphere/init.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/stepper.hpp"
#include "run_loop.hpp"
#include "simulation.hpp"
#include "states.hpp"
#include "values.hpp"

namespace py = pybind11;
using namespace py::literals;
using namespace hardsphere;
using namespace hardsphere::python;

namespace {

py::dict json_dict(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

std::optional<std::int64_t> optional_whole(const py::object& v, const char* what) {
  if (v.is_none()) return std::nullopt;
  return whole_arg(v, what, INT64_MIN, INT64_MAX);
}

//! A message as Python text: bytes that are not UTF-8 (a path given as bytes) escaped, not lost.
void set_error(PyObject* type, const char* what) {
  PyObject* text = PyUnicode_DecodeUTF8(what, Py_ssize_t(std::strlen(what)), "backslashreplace");
  if (!text) return;  // the decoding error is raised instead
  PyErr_SetObject(type, text);
  Py_DECREF(text);
}

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
  c.def_property(
      "gravity", [](const Sim& s) { return s.physics().gravity; },
      [](Sim& s, const std::array<double, 3>& g) {
        s.set_gravity(g);
        // A chute that cannot settle runs, and says why (as at construction).
        const std::string flow = unbounded_flow(s.physics(), s.origin().sys.box.periodic, physics_names());
        if (!flow.empty() && PyErr_WarnEx(PyExc_UserWarning, flow.c_str(), 1) != 0) throw py::error_already_set();
      },
      "the uniform acceleration (gx, gy, gz); set it between runs to change it from then on (each step's or "
      "event's flights stay exact parabolas)");
  c.def(
      "observables",
      [](Sim& s, py::object bins) {
        return json_dict(s.observables(whole_arg(bins, "histogram_bins", INT64_MIN, INT64_MAX)));
      },
      "histogram_bins"_a = 40,
      "The CLI's JSON summary (docs/cli.md) of the measurement since construction or reset_counters(): "
      "compressibility_factor, pressure, temperature, collisions, collision_rate_per_particle, kinetic and "
      "potential energies, momentum, speed_histogram, ... as a dict.");
  c.def("reset_counters", &Sim::reset_counters,
        "Starts a new measurement: counters, energy and momentum references, loop CPU time.");
  c.def(
      "write_data",
      [](Sim& s, py::object path) {
        const std::string p = path_arg(path, "write_data");
        file_call([&] { s.write_data(p); });
      },
      "path"_a, "Writes the current state as the CLI's --write-data does (LAMMPS data file, 17 digits, atomic).");
  c.def(
      "write_dump",
      [](Sim& s, py::object path) {
        const std::string p = path_arg(path, "write_dump");
        file_call([&] { s.write_dump(p); });
      },
      "path"_a,
      "Writes the current state as one frame of the CLI's --dump (LAMMPS text dump, atomic); hs.DumpWriter "
      "writes several.");
  c.def(
      "system",
      [](Sim& s) {
        return std::make_shared<SystemData>(SystemData{*s.state(), s.origin().seed, false});
      },
      "The current state as a System (a copy).");
}

//! hs.Box: lengths, boundaries and the exact repr.
void bind_box(py::module_& m) {
  py::class_<Box>(m, "Box", "An axis-aligned box, periodic ('p') or walled ('w') per axis.")
      .def(py::init([](py::object lengths, py::object boundary, py::object lo) {
             return make_box(lengths, text_arg(boundary, "boundary"), lo);
           }),
           "lengths"_a, "boundary"_a = "p", "lo"_a = py::none(),
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
        // Shortest exact digits (std::to_string showed a length of 1e-7 as 0.000000).
        auto three = [](const std::array<double, 3>& x) {
          return "(" + format_exact(x[0]) + ", " + format_exact(x[1]) + ", " + format_exact(x[2]) + ")";
        };
        return "Box(lengths=" + three({b.length(0), b.length(1), b.length(2)}) + ", boundary='" +
               boundary_string(b.periodic) + "', lo=" + three(b.lo) + ")";
      });
}

//! hs.System: generated, read or given states, their arrays and write_data.
void bind_system(py::module_& m) {
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
      [](py::object n, std::optional<double> phi, py::object box, py::object seed, double radius, double mass,
         std::optional<double> temperature, std::optional<double> speed, py::object boundary, py::object method,
         std::optional<double> rotational_temperature, std::optional<double> inertia, py::object walls) {
        return generate(parse_init_method(text_arg(method, "method")), whole_arg(n, "n", INT64_MIN, INT64_MAX), phi,
                        box, unsigned_arg(seed, "seed"), radius, mass, temperature, speed,
                        text_arg(boundary, "boundary"), rotational_temperature, inertia, walls);
      },
      "n"_a = 1000, "phi"_a = py::none(), "box"_a = py::none(), "seed"_a = 1, "radius"_a = 0.5, "mass"_a = 1.0,
      "temperature"_a = py::none(), "speed"_a = py::none(), "boundary"_a = "p", "method"_a = "auto",
      "rotational_temperature"_a = py::none(), "inertia"_a = py::none(), "walls"_a = py::none(),
      "A generated state as the CLI's --n/--phi/--box/--init make it: n spheres at packing fraction phi "
      "(default 0.2) or in a box of these lengths, Maxwell-Boltzmann velocities at temperature (default 1) or one "
      "speed, momentum zeroed; with rotational_temperature, angular velocities for rough spheres (each component "
      "normal with variance T/I, I = inertia m r^2, inertia 0.4 by default; the CLI's default is the translational "
      "temperature, here none: zero). "
      "method: auto (random insertion up to phi 0.25, lattice up to 0.55, dense up to 0.64), "
      "random, lattice or dense (docs/initial_states.md). walls: the shaped walls (as Stepper's walls) the spheres "
      "are placed clear of (random insertion only).");
  sys.def_static(
      "dense",
      [](py::object n, std::optional<double> phi, py::object box, py::object seed, double radius, double mass,
         std::optional<double> temperature, std::optional<double> speed, py::object boundary,
         std::optional<double> rotational_temperature, std::optional<double> inertia) {
        return generate(InitMethod::Dense, whole_arg(n, "n", INT64_MIN, INT64_MAX), phi, box,
                        unsigned_arg(seed, "seed"), radius, mass, temperature, speed, text_arg(boundary, "boundary"),
                        rotational_temperature, inertia);
      },
      "n"_a = 1000, "phi"_a = py::none(), "box"_a = py::none(), "seed"_a = 1, "radius"_a = 0.5, "mass"_a = 1.0,
      "temperature"_a = py::none(), "speed"_a = py::none(), "boundary"_a = "p", "rotational_temperature"_a = py::none(),
      "inertia"_a = py::none(),
      "System.random(..., method='dense'): an amorphous quench and compression (--init dense), up to phi 0.64.");
  sys.def_static(
      "from_data",
      [](py::object path, py::object boundary, py::object precision, py::object kinematic_types) {
        return from_data(path_arg(path, "from_data"), text_arg(boundary, "boundary"), text_arg(precision, "precision"),
                         kinematic_types);
      },
      "path"_a, "boundary"_a = "p", "precision"_a = "double", "kinematic_types"_a = py::none(),
      "Reads a LAMMPS data file (atom_style sphere) as --read-data does; overlaps up to the rounding of "
      "an engine of this precision are accepted; kinematic_types=[2, ...] makes those types' spheres "
      "kinematic (--kinematic-types; Stepper only). OSError if unreadable, ValueError (file:line) if "
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
          [](const SystemData& d, py::object path_obj, py::object title_obj) {
            const std::string path = path_arg(path_obj, "write_data");
            const std::string title = text_arg(title_obj, "title", true);
            file_call([&] {
              install_cleanup_signal_handlers();
              check_output_paths({{"write_data", path}});
              write_data(path, d.sys, title);
            });
          },
          "path"_a, "title"_a = "hardsphere state", "Writes a LAMMPS data file (17 digits, atomic).");
}

//! hs.DumpWriter: a dump of several frames, committed at close().
void bind_dump_writer(py::module_& m) {
  py::class_<DumpFile>(m, "DumpWriter",
                       "A LAMMPS text dump as the CLI's --dump writes it, one frame per write(sim); the file appears "
                       "complete at close() (a with block closes it, or discards it on an exception).")
      .def(py::init([](py::object path) {
             const std::string p = path_arg(path, "DumpWriter");
             return file_call([&] { return std::make_unique<DumpFile>(p); });
           }),
           "path"_a)
      .def(
          "write",
          [](DumpFile& d, py::object sim) {
            d.check_usable();
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
          "close",
          [](DumpFile& d) {
            if (!d.closed()) d.check_usable();
            file_call([&] { d.close(); });
          },
          "Commits the file (renamed into place); closing twice does nothing.")
      .def("discard", &DumpFile::discard, "Removes the unfinished file; nothing is left.")
      .def_property_readonly("closed", &DumpFile::closed)
      .def_property_readonly("frames", &DumpFile::frames, "frames written")
      .def_property_readonly("path", &DumpFile::path)
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](DumpFile& d, py::object type, py::object, py::object) {
        if (type.is_none()) {
          if (!d.closed()) d.check_usable();
          file_call([&] { d.close(); });
        } else {
          d.discard();
        }
        return false;
      });
}

//! hs.Stepper: the time stepper, with the CLI's options as keywords.
void bind_stepper(py::module_& m) {
  py::class_<StepperSim> st(m, "Stepper", "The time stepper (the CLI's default engine).");
  st.def(py::init([](const SystemData& s, double dt, double restitution, std::optional<double> contact_time,
                     std::optional<std::array<double, 3>> gravity, std::optional<double> resting_time,
                     py::object detect, py::object precision, py::object cells, double work_limit,
                     double tangential_restitution, std::optional<double> friction, std::optional<double> inertia,
                     py::object wall_e, py::object wall_beta, py::object wall_mu, py::object walls) {
           StepperConfig cfg;
           cfg.dt = dt;
           cfg.detect = parse_detect(text_arg(detect, "detect"));
           cfg.cells = cells_of(cells);
           cfg.max_particle_steps = work_limit_of(work_limit);
           cfg.names = physics_names();
           const Physics p = physics_of(s.sys.box, restitution, contact_time, gravity, resting_time,
                                        tangential_restitution, friction, inertia, {wall_e, wall_beta, wall_mu, walls});
           return std::make_unique<StepperSim>(s, p, cfg, parse_precision(text_arg(precision, "precision")));
         }),
         "system"_a, py::kw_only(), "dt"_a = 0.01, "restitution"_a = 1.0, "contact_time"_a = py::none(),
         "gravity"_a = py::none(), "resting_time"_a = py::none(), "detect"_a = "auto", "precision"_a = "double",
         "cells"_a = "auto", "work_limit"_a = 1e15, "tangential_restitution"_a = -1.0, "friction"_a = py::none(),
         "inertia"_a = py::none(), "wall_restitution"_a = py::none(), "wall_tangential_restitution"_a = py::none(),
         "wall_friction"_a = py::none(), "walls"_a = py::none(),
         "Stepper(system, *, dt=0.01, restitution=1, contact_time=1e-4 when restitution < 1, gravity=None, "
         "resting_time=None (with gravity; 0: the sub-step), detect='auto', precision='double', cells='auto', "
         "work_limit=1e15, tangential_restitution=-1, friction=None (inf), inertia=None (0.4; both rough spheres "
         "only), wall_restitution=None (1), wall_tangential_restitution=None, wall_friction=None (the spheres'; "
         "each one number, 'zlo=0.5,...' or {'zlo': 0.5}), walls=None (shaped walls: a list of the CLI's --wall "
         "specs, e.g. ['cylinder z 10 10 8 rotate 0.5 restitution 0.5'])): the CLI's options.");
  st.def(
      "_run",
      [](py::object self, py::object steps, std::optional<double> time, py::object callback, py::object every,
         py::object progress, bool transport, std::optional<double> transport_window, py::object transport_blocks) {
        run_stepper(
            self.cast<StepperSim&>(), self, optional_whole(steps, "steps"), time, callback,
            optional_whole(every, "every"), progress,
            {transport, transport_window, whole_arg(transport_blocks, "transport_blocks", INT64_MIN, INT64_MAX)});
      },
      "steps"_a = py::none(), "time"_a = py::none(), "callback"_a = py::none(), "every"_a = py::none(),
      "progress"_a = py::none(), "transport"_a = false, "transport_window"_a = py::none(), "transport_blocks"_a = 10);
  st.def_property_readonly("dt", &StepperSim::dt);
  st.def_property_readonly("steps", &StepperSim::steps, "steps since construction or reset_counters()");
  st.def_property_readonly("skin", [](const StepperSim& s) { return s.engine().skin(); });
  st.def_property_readonly("cells_per_dim", [](const StepperSim& s) { return s.engine().cells_per_dim(); });
  st.def_property_readonly("scene_kernel", [](const StepperSim& s) { return s.engine().scene_kernel(); });
  add_simulation(st);
}

//! hs.EventEngine: the event-driven engine, with the CLI's options as keywords.
void bind_event_engine(py::module_& m) {
  py::class_<EventSim> ev(m, "EventEngine", "The exact event-driven engine (the CLI's --engine event).");
  ev.def(py::init([](const SystemData& s, double restitution, std::optional<double> contact_time,
                     std::optional<std::array<double, 3>> gravity, std::optional<double> resting_time, py::object cells,
                     double shell, double work_limit, double tangential_restitution, std::optional<double> friction,
                     std::optional<double> inertia, py::object wall_e, py::object wall_beta, py::object wall_mu,
                     py::object walls) {
           EventConfig cfg;
           cfg.cells = cells_of(cells);
           cfg.shell = shell;
           cfg.max_events = work_limit_of(work_limit);
           cfg.names = physics_names();
           const Physics p = physics_of(s.sys.box, restitution, contact_time, gravity, resting_time,
                                        tangential_restitution, friction, inertia, {wall_e, wall_beta, wall_mu, walls});
           return std::make_unique<EventSim>(s, p, cfg);
         }),
         "system"_a, py::kw_only(), "restitution"_a = 1.0, "contact_time"_a = py::none(), "gravity"_a = py::none(),
         "resting_time"_a = py::none(), "cells"_a = "auto", "shell"_a = 0.0, "work_limit"_a = 1e15,
         "tangential_restitution"_a = -1.0, "friction"_a = py::none(), "inertia"_a = py::none(),
         "wall_restitution"_a = py::none(), "wall_tangential_restitution"_a = py::none(),
         "wall_friction"_a = py::none(), "walls"_a = py::none(),
         "EventEngine(system, *, restitution=1, contact_time=1e-4 when restitution < 1, gravity=None, "
         "resting_time=None (with gravity; 0.01 sqrt(d/|g|)), cells='auto', shell=0 (auto), work_limit=1e15, "
         "tangential_restitution=-1, friction=None (inf), inertia=None (0.4; both rough spheres only), "
         "wall_restitution=None, wall_tangential_restitution=None, wall_friction=None (as Stepper's), walls=None "
         "(refused: shaped walls are the stepper's)): the CLI's "
         "options.");
  ev.def(
      "_run",
      [](py::object self, py::object steps, std::optional<double> time, py::object callback,
         std::optional<double> every, py::object progress, py::object blocks, bool transport,
         std::optional<double> transport_window, py::object transport_blocks) {
        run_event(self.cast<EventSim&>(), self, optional_whole(steps, "steps"), time, callback, every, progress,
                  whole_arg(blocks, "blocks", INT64_MIN, INT64_MAX),
                  {transport, transport_window, whole_arg(transport_blocks, "transport_blocks", INT64_MIN, INT64_MAX)});
      },
      "steps"_a = py::none(), "time"_a = py::none(), "callback"_a = py::none(), "every"_a = py::none(),
      "progress"_a = py::none(), "blocks"_a = 20, "transport"_a = false, "transport_window"_a = py::none(),
      "transport_blocks"_a = 10);
  ev.def_property_readonly("time", &EventSim::time, "simulated time since construction");
  ev.def_property_readonly("events", &EventSim::events, "events since construction or reset_counters()");
  ev.def_property_readonly("shell", [](const EventSim& s) { return s.engine().shell(); });
  ev.def_property_readonly("cells_per_dim", [](const EventSim& s) { return s.engine().cells_per_dim(); });
  ev.def_property_readonly("scene_kernel", [](const EventSim& s) { return s.engine().scene_kernel(); });
  add_simulation(ev);
}

}  // namespace

PYBIND11_MODULE(_hardsphere, m) {
  m.doc() = "hardsphere: time-stepped and event-driven hard-sphere simulation (docs/python.md)";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const FileError& e) {
      set_error(PyExc_OSError, e.what());
    } catch (const InputError& e) {
      set_error(PyExc_ValueError, e.what());
    } catch (const ReentryError& e) {
      set_error(PyExc_RuntimeError, e.what());
    }
  });

  bind_box(m);
  bind_system(m);
  bind_dump_writer(m);
  bind_stepper(m);
  bind_event_engine(m);
}
