// The `hardsphere run` options. Every value is taken as text and converted here, not by CLI11:
// its integer conversion reads "010" as octal, "0x10" as hex and saturates on overflow, and its
// errors carry no option context. Here each refusal is an InputError naming option and value.
#include "options.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "hardsphere/atomic_file.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/format.hpp"
#include "hardsphere/limits.hpp"
#include "hardsphere/stepper.hpp"

namespace hardsphere::cli {

namespace {

constexpr std::int64_t kMaxBins = 1000000;  // speed histogram bins: more is a JSON of megabytes

//! A whole number written in decimal ("-?[0-9]+") within [lo, hi].
std::int64_t whole(const std::string& option, const std::string& s, std::int64_t lo, std::int64_t hi,
                   const std::string& why_hi = "") {
  bool digits = !s.empty();
  for (std::size_t i = 0; i < s.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(s[i])) && !(i == 0 && s[i] == '-' && s.size() > 1)) digits = false;
  if (!digits) throw InputError(option + " '" + s + "' is not a whole number");
  errno = 0;
  const long long v = std::strtoll(s.c_str(), nullptr, 10);
  if (errno == ERANGE)
    throw InputError(option + " '" + s + "' is out of range (" + std::to_string(lo) + " to " + std::to_string(hi) +
                     ")");
  if (v < lo) throw InputError(option + " " + s + " must be >= " + std::to_string(lo));
  if (v > hi)
    throw InputError(option + " " + s + " is more than " + std::to_string(hi) +
                     (why_hi.empty() ? "" : " (" + why_hi + ")"));
  return v;
}

//! A finite real number (strtod syntax, the whole text).
double real(const std::string& option, const std::string& s) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size()) throw InputError(option + " '" + s + "' is not a number");
  if (!std::isfinite(v)) {
    if (errno == ERANGE) throw InputError(option + " " + s + " is too large for a double");
    throw InputError(option + " " + s + " must be finite");
  }
  return v;
}

std::vector<double> parse_list(const std::string& s, const char* what) {
  std::vector<double> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size())
      throw InputError(std::string(what) + " '" + s + "': '" + item + "' is not a number");
    if (!std::isfinite(v)) throw InputError(std::string(what) + " '" + s + "': '" + item + "' is not a finite number");
    out.push_back(v);
  }
  if ((out.size() != 1 && out.size() != 3) || s.back() == ',')
    throw InputError(std::string(what) + " '" + s + "' needs one value or three (x,y,z)");
  if (out.size() == 1) out = {out[0], out[0], out[0]};
  return out;
}

//! A seed is any whole number 0 .. 2^64-1; strtoull alone would wrap "-1" to 2^64-1.
std::uint64_t parse_seed(const std::string& s) {
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(s.c_str(), &end, 10);
  if (s.empty() || !std::isdigit(static_cast<unsigned char>(s[0])) || end != s.c_str() + s.size() || errno == ERANGE)
    throw InputError("--seed '" + s + "' must be a whole number from 0 to 18446744073709551615");
  return v;
}

std::array<int, 3> parse_cells(const std::string& s) {
  if (s == "auto") return {0, 0, 0};
  const auto v = parse_list(s, "--cells");
  std::array<int, 3> k{};
  for (int d = 0; d < 3; ++d) {
    if (!(v[d] >= 1) || v[d] != std::floor(v[d]) || v[d] > 1e6)
      throw InputError("--cells '" + s + "': cell counts must be whole numbers from 1 to 1000000 (or auto)");
    k[d] = int(v[d]);
  }
  return k;
}

//! CLI11's message, reworded where it reads like an internal check ("--n: 1 required INT missing").
std::string parse_error_text(const CLI::ParseError& e) {
  const std::string m = e.what();
  const auto colon = m.find(": ");
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) && colon != std::string::npos && m.rfind("--", 0) == 0) {
    const std::string option = m.substr(0, colon);
    if (m.find("missing") != std::string::npos) return option + " needs a value";
    if (m.find("At Most") != std::string::npos) return option + " is given more than once";
  }
  return m;
}

//! The first argument must be the command; CLI11 would report "A subcommand is required" for
//! anything else, which names neither what was given nor what is expected.
void check_command(int argc, const char* const* argv) {
  if (argc < 2) throw InputError("no command given: use 'hardsphere run [options]' (hardsphere --help lists them)");
  const std::string first = argv[1];
  if (first != "run" && first != "--help" && first != "-h")
    throw InputError("unknown command '" + first + "': the command is 'run', e.g. 'hardsphere run --n 1000'");
}

//! The command line's names of the physics settings, for the library's messages.
const PhysicsNames& physics_names() {
  static const PhysicsNames names{"--restitution",      "--contact-time",
                                  "--gravity",          "walls on that axis (--boundary ...,w)",
                                  "--resting-time",     "--tangential-restitution",
                                  "--friction",         "--inertia",
                                  "--wall-restitution", "--wall-tangential-restitution",
                                  "--wall-friction"};
  return names;
}

//! The run command's options: each value as given (converted after parsing, see the file's
//! head) and CLI11's record of whether it was given.
struct RunOptions {
  std::string n_s = "1000", phi_s = "0.2", box_s, radius_s, mass_s, t_s, speed_s, dt_s, steps_s, equil_s;
  std::string boundary_s = "p", cells_s = "auto", precision_s = "double", init_s = "auto", json_s, detect_s = "auto";
  std::string read_data_s, write_data_s, dump_s, seed_s = "1", engine_s = "stepper", time_s, etime_s, blocks_s;
  std::string dump_every_s, bins_s, restitution_s, contact_time_s, resting_time_s, gravity_s, track_s, track_every_s,
      track_file_s, beta_s, friction_s, inertia_s, t_rot_s, wall_e_s, wall_beta_s, wall_mu_s, kinematic_s;
  std::string tr_window_s, tr_blocks_s;
  bool transport = false;
  std::vector<std::string> walls_s;
  CLI::Option *o_beta, *o_bins, *o_blocks, *o_box, *o_contact_time, *o_detect, *o_dt, *o_dump, *o_dump_every, *o_equil,
      *o_etime, *o_friction, *o_gravity, *o_inertia, *o_init, *o_json, *o_mass, *o_n, *o_phi, *o_radius, *o_read,
      *o_resting_time, *o_restitution, *o_seed, *o_speed, *o_steps, *o_t, *o_t_rot, *o_time, *o_track, *o_track_every,
      *o_track_file, *o_write, *o_wall_e, *o_wall_beta, *o_wall_mu, *o_kinematic, *o_walls, *o_transport, *o_tr_window,
      *o_tr_blocks;
};

// The options, declared in the order the help lists them: the initial state, the stepping, the
// physics, then run length, inputs and outputs.
void add_state_options(CLI::App* app, RunOptions& o) {
  o.o_n = app->add_option("--n", o.n_s, "number of spheres (default 1000)")->type_name("INT");
  o.o_phi = app->add_option("--phi", o.phi_s, "packing fraction: sets the cubic box from n (default 0.2)")
                ->type_name("FLOAT");
  o.o_box = app->add_option("--box", o.box_s, "box length L or Lx,Ly,Lz (box from 0 to L)");
  o.o_radius = app->add_option("--radius", o.radius_s, "sphere radius (default 0.5)")->type_name("FLOAT");
  o.o_mass = app->add_option("--mass", o.mass_s, "sphere mass (default 1)")->type_name("FLOAT");
  app->add_option("--boundary", o.boundary_s, "p (periodic) or w (wall) per axis, e.g. p,p,w (default p)");
  o.o_t = app->add_option("--temperature", o.t_s, "initial temperature, k_B = 1 (default 1)")->type_name("FLOAT");
  o.o_speed = app->add_option("--init-speed", o.speed_s, "give every sphere this speed, isotropic directions")
                  ->type_name("FLOAT");
  o.o_init =
      app->add_option("--init", o.init_s,
                      "initial positions: auto (random up to phi 0.25, lattice up to 0.55, dense up to 0.64), random "
                      "(insertion), lattice (FCC melted and compressed, up to 0.55) or dense (amorphous quench and "
                      "compression, up to 0.64; tries denser)");
  o.o_seed = app->add_option("--seed", o.seed_s, "random seed, 0 .. 2^64-1 (default 1)")->type_name("INT");
}

void add_stepping_options(CLI::App* app, RunOptions& o) {
  o.o_dt = app->add_option("--dt", o.dt_s, "time step (default 0.01)")->type_name("FLOAT");
  o.o_steps = app->add_option("--steps", o.steps_s, "measured steps (default 1000)")->type_name("INT");
  o.o_equil =
      app->add_option("--equilibrate", o.equil_s, "steps run first and not measured (default 0)")->type_name("INT");
  app->add_option("--cells", o.cells_s, "cells per axis: auto, K or Kx,Ky,Kz (1 = one box, O(N^2))");
  app->add_option("--precision", o.precision_s, "double or float (default double)");
  o.o_detect = app->add_option("--detect", o.detect_s,
                               "contact detection: auto (default: sweep for steps with v_rms dt > 0.1 diameters, "
                               "else overlap), overlap (a posteriori) or sweep (whole step)");
  app->add_option("--engine", o.engine_s, "stepper (time-stepped, default) or event (exact event-driven)");
}

void add_physics_options(CLI::App* app, RunOptions& o) {
  o.o_gravity = app->add_option("--gravity", o.gravity_s,
                                "uniform acceleration gx,gy,gz along wall axes only, e.g. 0,0,-1 with "
                                "--boundary p,p,w (default none)");
  o.o_restitution = app->add_option("--restitution", o.restitution_s,
                                    "normal restitution e of sphere collisions, 0 < e <= 1 (default 1: elastic; the "
                                    "walls: --wall-restitution)")
                        ->type_name("FLOAT");
  o.o_contact_time =
      app->add_option("--contact-time", o.contact_time_s,
                      "TC model: a collision within this time of a sphere's previous one is elastic (default 1e-4; "
                      "> 0 when --restitution is below 1)")
          ->type_name("FLOAT");
  o.o_resting_time =
      app->add_option("--resting-time", o.resting_time_s,
                      "a wall contact slower than |g| times this rests on the wall for this time instead of bouncing "
                      "(default: the stepper's sub-step; the event engine's 0.01 sqrt(d/|g|), d the smallest diameter)")
          ->type_name("FLOAT");
  o.o_beta = app->add_option("--tangential-restitution", o.beta_s,
                             "rough spheres: tangential restitution beta of the contact points' relative velocity, "
                             "-1 <= beta <= 1 (default -1: smooth; 1: perfectly rough)")
                 ->type_name("FLOAT");
  o.o_friction = app->add_option("--friction", o.friction_s,
                                 "Walton's Coulomb friction mu >= 0: the tangential impulse slides at mu times the "
                                 "normal one (--tangential-restitution is then the sticking limit beta0)")
                     ->type_name("FLOAT");
  o.o_inertia =
      app->add_option("--inertia", o.inertia_s, "rough spheres: I = q m r^2, 0 < q <= 2/3 (default 0.4: solid sphere)")
          ->type_name("FLOAT");
  o.o_t_rot = app->add_option("--rotational-temperature", o.t_rot_s,
                              "rough spheres: initial angular velocities at this temperature, each component "
                              "normal with variance T/I (default: the translational temperature)")
                  ->type_name("FLOAT")
                  ->needs(o.o_beta);
  // The walls' own laws: one value for every wall, or face=value items (docs/cli.md).
  o.o_wall_e = app->add_option("--wall-restitution", o.wall_e_s,
                               "normal restitution of the walls, 0 < e_w <= 1: one value, or face=value items of "
                               "xlo xhi ylo yhi zlo zhi, e.g. zlo=0.5 (default 1: elastic)")
                   ->type_name("E|FACE=E,...");
  o.o_wall_beta = app->add_option("--wall-tangential-restitution", o.wall_beta_s,
                                  "rough spheres: the walls' tangential restitution, -1 <= beta_w <= 1, one value or "
                                  "face=value items (default: --tangential-restitution)")
                      ->type_name("B|FACE=B,...");
  o.o_walls = app->add_option("--wall", o.walls_s,
                              "a shaped wall (repeatable, stepper only), e.g. \"cylinder z 10 10 8 inside rotate 0.5 "
                              "restitution 0.5\": plane, cylinder, sphere or cone; see docs/cli.md")
                  ->type_name("SPEC")
                  ->allow_extra_args(false);
  o.o_wall_mu = app->add_option("--wall-friction", o.wall_mu_s,
                                "rough spheres: the walls' Coulomb friction mu_w >= 0, one value or face=value items "
                                "(default: --friction)")
                    ->type_name("MU|FACE=MU,...");
}

void add_output_options(CLI::App* app, RunOptions& o, bool& quiet) {
  o.o_time = app->add_option("--time", o.time_s, "simulated time measured (event engine; stepper: steps = time/dt)")
                 ->type_name("FLOAT");
  o.o_etime =
      app->add_option("--equilibrate-time", o.etime_s, "simulated time run first and not measured")->type_name("FLOAT");
  o.o_blocks = app->add_option("--blocks", o.blocks_s, "event engine: block averages for the error bars (default 20)")
                   ->type_name("INT");
  o.o_read = app->add_option("--read-data", o.read_data_s, "start from a LAMMPS data file (atom_style sphere)");
  o.o_kinematic = app->add_option("--kinematic-types", o.kinematic_s,
                                  "atom types of the data file whose spheres are kinematic: infinite mass, moving "
                                  "on at their own constant velocity (0: frozen), no gravity (stepper only)")
                      ->type_name("TYPE,...")
                      ->needs(o.o_read);
  o.o_write = app->add_option("--write-data", o.write_data_s, "write the final state as a LAMMPS data file");
  o.o_dump = app->add_option("--dump", o.dump_s, "write a LAMMPS text dump");
  o.o_dump_every = app->add_option("--dump-every", o.dump_every_s, "steps between dump frames (default 100)")
                       ->type_name("INT")
                       ->needs(o.o_dump);
  o.o_track = app->add_option("--track", o.track_s, "follow the sphere with this id (with --track-every, --track-file)")
                  ->type_name("ID");
  o.o_track_every = app->add_option("--track-every", o.track_every_s,
                                    "simulated time between tracker rows (stepper: a whole number of steps)")
                        ->type_name("FLOAT");
  o.o_track_file = app->add_option("--track-file", o.track_file_s,
                                   "tracker table: time, unwrapped x y z, vx vy vz, pair collisions so far");
  o.o_transport = app->add_flag("--transport", o.transport,
                                "self-diffusion, shear viscosity and thermal conductivity (Einstein/Helfand)");
  o.o_tr_window = app->add_option("--transport-window", o.tr_window_s,
                                  "longest correlation time of --transport (default 100 mean free times)")
                      ->type_name("FLOAT")
                      ->needs(o.o_transport);
  o.o_tr_blocks = app->add_option("--transport-blocks", o.tr_blocks_s,
                                  "independent blocks of --transport's error bars (default 10)")
                      ->type_name("INT")
                      ->needs(o.o_transport);
  o.o_json = app->add_option("--json", o.json_s, "write the JSON summary to FILE (- for stdout)");
  o.o_bins = app->add_option("--histogram-bins", o.bins_s, "bins of the speed histogram in the JSON (default 40)")
                 ->type_name("INT");
  app->add_flag("--quiet", quiet, "no progress line on stderr (it is shown only on a terminal anyway)");
  for (auto* opt : {o.o_n, o.o_phi, o.o_box, o.o_radius, o.o_mass, o.o_t, o.o_speed, o.o_init, o.o_seed, o.o_t_rot})
    o.o_read->excludes(opt);
  o.o_t->excludes(o.o_speed);
}

//! The settings that are one value each: boundaries, cells, seed, precision, detection, engine,
//! step and run counts.
void take_settings(const RunOptions& o, RunSpec& spec) {
  spec.periodic = parse_boundary(o.boundary_s);
  spec.stepper.cells = parse_cells(o.cells_s);
  spec.init.seed = parse_seed(o.seed_s);
  spec.precision = parse_precision(o.precision_s);
  spec.stepper.detect = parse_detect(o.detect_s);
  spec.engine = parse_engine(o.engine_s);
  if (o.o_dt->count()) spec.stepper.dt = real("--dt", o.dt_s);
  if (o.o_steps->count()) spec.steps = whole("--steps", o.steps_s, 0, LLONG_MAX);
  if (o.o_equil->count()) spec.equilibrate = whole("--equilibrate", o.equil_s, 0, LLONG_MAX);
  if (o.o_blocks->count()) spec.blocks = int(whole("--blocks", o.blocks_s, 1, kMaxBlocks));
  if (o.o_dump_every->count()) spec.dump_every = whole("--dump-every", o.dump_every_s, 1, LLONG_MAX);
  if (o.o_bins->count()) spec.histogram_bins = int(whole("--histogram-bins", o.bins_s, 1, kMaxBins));
  spec.transport = o.transport;
  if (o.o_tr_window->count()) {
    spec.transport_window = real("--transport-window", o.tr_window_s);
    if (!(spec.transport_window > 0))
      throw InputError("--transport-window " + o.tr_window_s + " must be positive and finite");
  }
  if (o.o_tr_blocks->count()) spec.transport_blocks = int(whole("--transport-blocks", o.tr_blocks_s, 2, 100000));
}

//! The walls' laws; inelastic walls take the TC model's default contact time, as --restitution.
void take_wall_laws(const RunOptions& o, RunSpec& spec, PhysicsGiven& given) {
  const struct {
    CLI::Option* option;
    WallSetting setting;
    const std::string& text;
  } settings[] = {{o.o_wall_e, WallSetting::Restitution, o.wall_e_s},
                  {o.o_wall_beta, WallSetting::TangentialRestitution, o.wall_beta_s},
                  {o.o_wall_mu, WallSetting::Friction, o.wall_mu_s}};
  for (const auto& s : settings)
    if (s.option->count()) parse_wall_setting(spec.physics, given, s.setting, s.text, s.option->get_name());
  if (spec.physics.inelastic_walls() && !o.o_contact_time->count() && spec.physics.contact_time == 0)
    spec.physics.contact_time = kDefaultContactTime;
}

//! The physics, checked by the library's rules under the command line's names.
void take_physics(const RunOptions& o, RunSpec& spec) {
  if (o.o_restitution->count()) {
    spec.physics.restitution = real("--restitution", o.restitution_s);
    spec.physics.contact_time = kDefaultContactTime;
  }
  if (o.o_contact_time->count()) spec.physics.contact_time = real("--contact-time", o.contact_time_s);
  if (o.o_gravity->count()) {
    if (std::count(o.gravity_s.begin(), o.gravity_s.end(), ',') != 2)
      throw InputError("--gravity '" + o.gravity_s + "' needs three values gx,gy,gz");
    const auto g = parse_list(o.gravity_s, "--gravity");
    spec.physics.gravity = {g[0], g[1], g[2]};
  }
  if (o.o_resting_time->count()) spec.physics.resting_time = real("--resting-time", o.resting_time_s);
  if (o.o_beta->count()) spec.physics.tangential_restitution = real("--tangential-restitution", o.beta_s);
  if (o.o_friction->count()) spec.physics.friction = real("--friction", o.friction_s);
  if (o.o_inertia->count()) spec.physics.inertia = real("--inertia", o.inertia_s);
  // The option rules (a setting given where it has no effect) are the library's, as for every face.
  PhysicsGiven given;
  for (const std::string& w : o.walls_s) spec.physics.shapes.push_back(parse_wall_shape(w, "--wall '" + w + "'"));
  take_wall_laws(o, spec, given);
  given.contact_time = o.o_contact_time->count(), given.resting_time = o.o_resting_time->count();
  given.friction = o.o_friction->count(), given.inertia = o.o_inertia->count();
  spec.physics = validated(spec.physics, spec.periodic, physics_names(), given);
  spec.stepper.names = spec.event.names = physics_names();
  // Initial rotation is the command line's own (no other face makes states and physics together).
  if (o.o_t_rot->count() && !spec.physics.rough())
    throw InputError("--rotational-temperature " + o.t_rot_s + ": smooth spheres (" +
                     physics_names().tangential_restitution + " -1) do not rotate; give a " +
                     physics_names().tangential_restitution + " above -1");
}

//! The run's length: simulated time for the event engine, steps (or time / dt) for the stepper.
void take_run_length(const RunOptions& o, RunSpec& spec) {
  const double time = o.o_time->count() ? real("--time", o.time_s) : 0.0;
  const double etime = o.o_etime->count() ? real("--equilibrate-time", o.etime_s) : 0.0;

  if (spec.engine == Engine::Event) {
    if (!o.walls_s.empty())
      throw InputError("--wall '" + o.walls_s.front() +
                       "': shaped walls run in the stepper only (the event engine predicts contacts with the box "
                       "faces alone): leave out --engine event");
    for (auto* opt : {o.o_dt, o.o_steps, o.o_equil, o.o_detect, o.o_dump_every})
      if (opt->count())
        throw InputError(opt->get_name() + " is a stepper option; the event engine runs for --time (simulated time)");
    if (spec.precision != Precision::Double)
      throw InputError("--precision " + o.precision_s + ": the event engine runs in double only");
    if (!o.o_time->count()) throw InputError("--engine event needs --time T (simulated time to run)");
    spec.time = time;
    spec.equilibrate_time = etime;
    spec.event.cells = spec.stepper.cells;
  } else {
    if (o.o_blocks->count()) throw InputError("--blocks is an event-engine option (use with --engine event)");
    // A bad --dt is reported by the stepper itself; only a valid one converts times to steps.
    const double dt = spec.stepper.dt;
    const bool dt_ok = dt > 0;
    if (o.o_time->count() && dt_ok) {
      if (o.o_steps->count()) throw InputError("--steps and --time both set the run length; give one");
      if (!(time >= 0)) throw InputError("--time " + o.time_s + " must be >= 0");
      if (time / dt > 1e15) throw InputError("--time " + o.time_s + " / --dt is more than 1e15 steps");
      spec.steps = std::llround(time / dt);
    }
    if (o.o_etime->count() && dt_ok) {
      if (o.o_equil->count())
        throw InputError("--equilibrate and --equilibrate-time both set the equilibration; give one");
      if (!(etime >= 0)) throw InputError("--equilibrate-time " + o.etime_s + " must be >= 0");
      if (etime / dt > 1e15) throw InputError("--equilibrate-time " + o.etime_s + " / --dt is more than 1e15 steps");
      spec.equilibrate = std::llround(etime / dt);
    }
  }
}

//! The output files (and the tracker), checked before anything is read, run or created.
//! --kinematic-types: atom types separated by commas, each once.
std::vector<int> kinematic_types(const std::string& list) {
  std::vector<int> types;
  std::size_t at = 0;
  while (true) {
    const std::size_t comma = list.find(',', at);
    const std::string item = list.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
    const int t = int(whole("--kinematic-types", item, 1, INT_MAX));
    if (std::find(types.begin(), types.end(), t) != types.end())
      throw InputError("--kinematic-types: type " + item + " is given twice");
    types.push_back(t);
    if (comma == std::string::npos) return types;
    at = comma + 1;
  }
}

void take_outputs(const RunOptions& o, RunSpec& spec) {
  // Outputs: an empty name is refused (not silently "no output"), and two outputs may not be
  // the same file under any spelling; checked before anything is read, run or created.
  std::vector<std::pair<std::string, std::string>> outputs;
  if (o.o_write->count()) outputs.emplace_back("--write-data", o.write_data_s);
  if (o.o_dump->count()) outputs.emplace_back("--dump", o.dump_s);
  if (o.o_json->count() && o.json_s != "-") outputs.emplace_back("--json", o.json_s);
  if (o.o_track_file->count()) outputs.emplace_back("--track-file", o.track_file_s);
  if (o.o_track->count() || o.o_track_every->count() || o.o_track_file->count()) {
    if (!(o.o_track->count() && o.o_track_every->count() && o.o_track_file->count()))
      throw InputError("--track, --track-every and --track-file go together: give all three");
    if (o.track_file_s.empty()) throw InputError("--track-file: empty file name");
    spec.track_id = whole("--track", o.track_s, LLONG_MIN, LLONG_MAX);
    spec.track_every = real("--track-every", o.track_every_s);
    if (!(spec.track_every > 0)) throw InputError("--track-every " + o.track_every_s + " must be positive");
    spec.track_file = o.track_file_s;
  }
  if (o.o_json->count() && o.json_s.empty()) throw InputError("--json: empty file name (use - for standard output)");
  check_output_paths(outputs);
  if (o.o_write->count()) spec.write_data = o.write_data_s;
  if (o.o_dump->count()) spec.dump = o.dump_s;
  if (o.o_json->count()) spec.json = o.json_s;
}

//! A generated initial state: the number of spheres, their size, mass and speeds, and the box.
void take_initial_state(const RunOptions& o, RunSpec& spec) {
  const std::int64_t n = whole("--n", o.n_s, 1, kMaxSpheres, "the largest system hardsphere simulates");
  spec.init.n = n;
  spec.init.method = parse_init_method(o.init_s);
  if (o.o_radius->count()) spec.init.radius = real("--radius", o.radius_s);
  if (o.o_mass->count()) spec.init.mass = real("--mass", o.mass_s);
  if (o.o_t->count()) spec.init.temperature = real("--temperature", o.t_s);
  if (o.o_speed->count()) spec.init.speed = real("--init-speed", o.speed_s);
  if (o.o_t_rot->count()) {
    spec.init.rotational_temperature = real("--rotational-temperature", o.t_rot_s);
    if (!(*spec.init.rotational_temperature >= 0))
      throw InputError("--rotational-temperature " + o.t_rot_s + " must be >= 0");
  }
  const double r = spec.init.radius;
  if (!(r > 0)) throw InputError("--radius " + o.radius_s + " must be positive and finite");
  std::array<double, 3> len{};
  if (o.o_box->count()) {
    if (o.o_phi->count()) throw InputError("--phi and --box both set the box size; give one");
    const auto v = parse_list(o.box_s, "--box");
    for (int d = 0; d < 3; ++d) len[d] = v[d];
  } else {
    const double phi = real("--phi", o.phi_s);
    if (!(phi > 0)) throw InputError("--phi " + o.phi_s + " must be positive");
    const double l = std::cbrt(double(n) * 4.0 / 3.0 * M_PI * r * r * r / phi);
    if (!(std::isfinite(l) && l > 0))
      throw InputError("--phi " + o.phi_s + " with --radius " + format_number(r) + " and --n " + o.n_s +
                       " gives a box length " + format_number(l) + " that is not a positive finite number");
    len = {l, l, l};
  }
  spec.init.box = Box::from_lengths(len, spec.periodic);
}

}  // namespace

CommandLine parse_command_line(int argc, const char* const* argv) {
  if (argc >= 2 && std::string(argv[1]) == "--version") {
    if (argc > 2) throw InputError("--version takes nothing after it (found '" + std::string(argv[2]) + "')");
    return {true, std::string("hardsphere ") + HS_VERSION + "\n", {}};
  }
  check_command(argc, argv);
  CLI::App app{"hardsphere: time-stepped hard-sphere molecular dynamics with cell lists", "hardsphere"};
  app.require_subcommand(1);
  auto* run = app.add_subcommand("run", "run a simulation and report a summary");

  CommandLine cmd;
  RunSpec& spec = cmd.spec;
  RunOptions o;
  add_state_options(run, o);
  add_stepping_options(run, o);
  add_physics_options(run, o);
  add_output_options(run, o, cmd.quiet);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    return {true, app.help(), {}};
  } catch (const CLI::CallForAllHelp&) {
    return {true, app.help("", CLI::AppFormatMode::All), {}};
  } catch (const CLI::ParseError& e) {
    throw InputError(parse_error_text(e));
  }

  take_settings(o, spec);
  take_physics(o, spec);
  take_run_length(o, spec);
  take_outputs(o, spec);
  if (spec.transport) check_transport(spec.periodic, spec.physics, "--transport");  // before any warning
  if (o.o_read->count()) {
    if (o.read_data_s.empty()) throw InputError("--read-data: empty file name");
    spec.read_data = o.read_data_s;
    if (o.o_kinematic->count()) spec.kinematic_types = kinematic_types(o.kinematic_s);
    return cmd;
  }
  take_initial_state(o, spec);
  return cmd;
}

}  // namespace hardsphere::cli
