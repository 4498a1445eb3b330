//! The fixed-step engine's construction and validation, in named steps, and make_stepper.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "hardsphere/scene_limits.hpp"
#include "stepper/grid_choice.hpp"
#include "stepper/stepper_engine.hpp"

namespace hardsphere {

Precision parse_precision(const std::string& s) {
  if (s == "double") return Precision::Double;
  if (s == "float") return Precision::Float;
  throw InputError("unknown precision '" + s + "' (expected double or float)");
}

Detect parse_detect(const std::string& s) {
  if (s == "overlap") return Detect::Overlap;
  if (s == "sweep") return Detect::Sweep;
  if (s == "auto") return Detect::Auto;
  throw InputError("unknown detection mode '" + s + "' (expected auto, overlap or sweep)");
}

namespace {
double rms_speed(const ParticleSystem& sys) {
  double v2 = 0;
  for (const auto& v : sys.vel) v2 += dot(v, v);
  return sys.size() ? std::sqrt(v2 / double(sys.size())) : 0.0;
}
}  // namespace

bool detects_by_sweep(Detect d, const ParticleSystem& sys, double dt) {
  if (d != Detect::Auto) return d == Detect::Sweep;
  // Overlap detection misses grazes (pairs that touch and part within one step), which matter only for
  // long steps; sweeping costs more, so it is chosen only beyond kOverlapDetectionLimit (see docs/dev/performance.md).
  double smallest = std::numeric_limits<double>::infinity();
  for (const double r : sys.radius) smallest = std::min(smallest, 2 * r);
  return rms_speed(sys) * dt > kOverlapDetectionLimit * smallest;
}

namespace detail {

template <class Real, bool Mono>
Stepper<Real, Mono>::Stepper(const ParticleSystem& sys, const Physics& physics, const StepperConfig& cfg)
    : box_(relative_box(sys.box)),
      user_box_(sys.box),
      origin_(sys.box.lo),
      // Kinematic spheres and shaped walls take the general kernel: under gravity (along any axis)
      // kinematic pairs need consider_kinematic(), and the all-periodic kernel has no walls.
      all_periodic_(cfg.specialise && sys.box.all_periodic() && !sys.kinematic_count() && physics.shapes.empty()),
      sweep_(detects_by_sweep(cfg.detect, sys, cfg.dt)),
      dt_(Real(cfg.dt)) {
  check_config(sys, physics, cfg);
  set_detection(sys, cfg);
  const double phi_gas = cfg.packing_fraction > 0 ? cfg.packing_fraction : sys.packing_fraction();
  const SizeSplit split = split_by_size(sys);
  const GridChoice choice = choose_cells(sys, physics, cfg, phi_gas, split);
  set_lengths(choice.skin, cfg);
  load_spheres(sys, physics, cfg);
  max_radius_ = Real(sys.max_radius());
  cell_radius_ = Real(choice.diameter / 2);
  mark_big(split, choice.big_pass);
  configure_resolver(physics, cfg);
  configure_lists(cfg, phi_gas);
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::check_config(const ParticleSystem& sys, const Physics& physics, const StepperConfig& cfg) {
  if (!(std::isfinite(cfg.dt) && cfg.dt > 0)) {
    std::ostringstream m;
    m << "time step dt = " << cfg.dt << " must be positive and finite";
    throw InputError(m.str());
  }
  if (cfg.max_events_per_step < 1) throw InputError("max events per step must be >= 1");
  check_scene_numbers(sys, "stepper");
  check_clear_of_shapes(sys, physics.shapes);
  // A moving kinematic sphere passes through a shaped wall unseen (only the box faces are checked
  // for its reach): refused until the shapes check it too.
  if (!physics.shapes.empty())
    for (std::size_t i = 0; i < sys.size(); ++i)
      if (sys.is_kinematic(i) && (sys.vel[i].x != 0 || sys.vel[i].y != 0 || sys.vel[i].z != 0))
        throw InputError(atom_origin(sys, i, "initial state", nullptr) +
                         " is kinematic and moving, with shaped walls, which do not stop it or check its path: "
                         "give moving kinematic spheres no shaped walls, or make them frozen (velocity 0)");
  const double g_norm = std::sqrt(physics.gravity[0] * physics.gravity[0] + physics.gravity[1] * physics.gravity[1] +
                                  physics.gravity[2] * physics.gravity[2]);
  check_engine_numbers<Real>(sys, cfg.dt, sizeof(Real) == sizeof(float) ? "stepper in single precision" : "stepper",
                             g_norm, physics.rough());
  const std::size_t n = sys.size();
  if (n > std::size_t(kMaxAdjIndex) + 1)
    throw InputError("too many particles for one stepper: " + std::to_string(n) + " (at most " +
                     std::to_string(std::size_t(kMaxAdjIndex) + 1) + ")");
  const bool auto_cells = cfg.cells[0] == 0 && cfg.cells[1] == 0 && cfg.cells[2] == 0;
  if (!auto_cells)
    for (int d = 0; d < 3; ++d)
      if (cfg.cells[d] < 1) throw InputError("cells per axis must be >= 1, got " + std::to_string(cfg.cells[d]));
  if (!(cfg.packing_fraction >= 0 && cfg.packing_fraction < 1))
    throw InputError("packing fraction hint " + std::to_string(cfg.packing_fraction) + " must be in [0, 1)");
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::set_detection(const ParticleSystem& sys, const StepperConfig& cfg) {
  detect_auto_ = cfg.detect == Detect::Auto;
  if (detect_auto_) {
    double smallest = std::numeric_limits<double>::infinity();
    for (const double r : sys.radius) smallest = std::min(smallest, 2 * r);
    sweep_above_ = kOverlapDetectionLimit * smallest;
  }
}

template <class Real, bool Mono>
GridChoice Stepper<Real, Mono>::choose_cells(const ParticleSystem& sys, const Physics& physics,
                                             const StepperConfig& cfg, double phi_gas, const SizeSplit& split) {
  const GridChoice choice = choose_grid(sys, box_, cfg.cells, cfg.dt, phi_gas, split, physics.gravity);
  grid_ = choice.grid;
  const bool auto_cells = cfg.cells[0] == 0 && cfg.cells[1] == 0 && cfg.cells[2] == 0;
  if (!(choice.skin > 0)) throw InputError(grid_refusal(sys, choice, auto_cells, split));
  return choice;
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::set_lengths(double skin, const StepperConfig& cfg) {
  skin_ = Real(skin);
  half_skin_ = Real(0.4995) * skin_;
  h_ = dt_;
  max_particle_steps_ = cfg.max_particle_steps;
  for (int d = 0; d < 3; ++d) length_[d] = Real(box_.length(d));
  for (int kx = -1; kx <= 1; ++kx)
    for (int ky = -1; ky <= 1; ++ky)
      for (int kz = -1; kz <= 1; ++kz)
        image_shift_[image_code(kx, ky, kz)] = {Real(kx) * length_[0], Real(ky) * length_[1], Real(kz) * length_[2]};
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::load_spheres(const ParticleSystem& sys, const Physics& physics, const StepperConfig& cfg) {
  const std::size_t n = sys.size();
  pos_.resize(n);
  vel_.resize(n);
  r_.resize(n);
  m_.resize(n);
  slot_.resize(n);
  id_.resize(n);
  type_.resize(n);
  image_.assign(n, {0, 0, 0});
  image0_.assign(n, {0, 0, 0});
  if (cfg.count_per_sphere) pair_collisions_.assign(n, 0);
  // Internal order starts from the ids, not the input order: the cell sorts are stable, so the
  // same spheres give the same run bit for bit in whatever order an adapter hands them over.
  const std::vector<std::size_t> by_id = order_by_id(sys.id);
  input_of_rank_.assign(by_id.begin(), by_id.end());
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t s = by_id[i];
    slot_[i] = std::uint32_t(i);
    id_[i] = sys.id[s];
    type_[i] = sys.type[s];
    if (s < sys.image.size()) image0_[i] = sys.image[s];
    pos_[i] = {Real(sys.pos[s].x - origin_[0]), Real(sys.pos[s].y - origin_[1]), Real(sys.pos[s].z - origin_[2])};
    vel_[i] = {Real(sys.vel[s].x), Real(sys.vel[s].y), Real(sys.vel[s].z)};
    r_[i] = Real(sys.radius[s]);
    m_[i] = Real(sys.mass[s]);
  }
  if (physics.rough()) {
    omega_.assign(n, V3<Real>{});
    for (std::size_t i = 0; i < n && sys.omega.size() == n; ++i) {
      const Vec3d& w = sys.omega[by_id[i]];
      omega_[i] = {Real(w.x), Real(w.y), Real(w.z)};
    }
    inertia_ = physics.inertia;
    resolver_.set_roughness({Real(physics.tangential_restitution), Real(physics.friction), Real(physics.inertia)});
  } else {
    spins_.take(sys.omega, by_id);
  }
  if (n) sigma_ = Real(2) * r_[0];
  if (sys.kinematic_count()) {
    kin_rank_.resize(n), kin_vel_.resize(n);
    for (std::size_t i = 0; i < n; ++i) kin_rank_[i] = sys.kinematic[by_id[i]] != 0, kin_vel_[i] = vel_[i];
  }
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::mark_big(const SizeSplit& split, bool big_pass) {
  const std::size_t n = pos_.size();
  if (big_pass) {
    big_.assign(n, 0);
    std::vector<std::uint32_t> rank_of_input(n);
    for (std::size_t r = 0; r < n; ++r) rank_of_input[input_of_rank_[r]] = std::uint32_t(r);
    for (const std::uint32_t b : split.big) big_[rank_of_input[b]] = 1;
    big_begin_ = std::uint32_t(n - split.big.size());
  }
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::configure_resolver(const Physics& physics, const StepperConfig& cfg) {
  const std::size_t n = pos_.size();
  resolver_.reset(n, dt_);
  resolver_.set_uniform(sigma_, n ? m_[0] : Real(0));
  resolver_.set_event_limit(cfg.max_events_per_step);
  collapse_advice_ = collapse_advice(physics, cfg.names);
  if (!physics.elastic()) {
    last_collision_.assign(n, -std::numeric_limits<double>::infinity());
    resolver_.set_restitution(Real(physics.restitution), physics.contact_time, last_collision_.data());
  }
  resolver_.set_wall_laws(kernel::wall_laws<Real>(physics));
  std::array<Real, 3> wall_lo{}, wall_hi{};
  for (std::size_t d = 0; d < 3; ++d) wall_lo[d] = Real(box_.lo[d]), wall_hi[d] = Real(box_.hi[d]);
  unreached_walls_ = cfg.unreached_walls;
  std::array<bool, 3> no_tests = box_.periodic;
  for (std::size_t d = 0; d < 3; ++d) no_tests[d] = no_tests[d] || unreached_walls_[d];
  resolver_.set_walls(no_tests, wall_lo, wall_hi);
  names_ = cfg.names;
  gravity_in_ = physics.gravity;
  gravity_ = {Real(physics.gravity[0]), Real(physics.gravity[1]), Real(physics.gravity[2])};
  has_gravity_ = physics.has_gravity();
  if (sizeof(Real) == sizeof(float) && has_gravity_) kick_residual_.assign(n, V3<Real>{});
  resolver_.set_gravity(gravity_);
  resolver_.set_resting_time(Real(physics.resting_time));
  const double extent = std::max({box_.length(0), box_.length(1), box_.length(2)});
  if (!physics.shapes.empty()) resolver_.set_shapes(physics, origin_, extent);
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::set_gravity(const std::array<double, 3>& g) {
  gravity_in_ = validated_gravity(g, names_);
  gravity_ = {Real(gravity_in_[0]), Real(gravity_in_[1]), Real(gravity_in_[2])};
  has_gravity_ = gravity_in_ != std::array<double, 3>{0, 0, 0};
  if (sizeof(Real) == sizeof(float) && has_gravity_ && kick_residual_.empty())
    kick_residual_.assign(pos_.size(), V3<Real>{});
  resolver_.set_gravity(gravity_);
  if (has_gravity_ && speeds_) {  // speeds change during a step under gravity (configure_lists)
    speeds_ = false;
    bind_resolver();
  }
  refresh_speed_bound();
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::configure_lists(const StepperConfig& cfg, double phi_gas) {
  const std::size_t n = pos_.size();
  pairs_.configure({&grid_, &box_, length_, image_shift_, skin_, sigma_, cell_radius_, max_radius_});
  // Threats are enumerated from the cells within two of a sphere's: every periodic axis needs
  // 3 cells (so a cell is at least sigma + skin wide).
  guard_.configure(skin_, cfg.pairwise_list_check && grid_.half_stencil_ok(), std::max<std::size_t>(n / 32, 16));
  // Speeds pay where the sweeps' extra loads hit the cache: positions and speeds within ~1 MiB
  // (the L2 of this machine's cores); beyond it each speed is one more miss (see docs/dev/performance.md).
  // Under gravity speeds change during the step, so the per-sphere bounds are not used.
  speeds_ = !has_gravity_ && phi_gas >= 0.3 && double(n) * double(sizeof(V3<Real>) + sizeof(Real)) <= 1048576.0;
  rebuild();
  counters_.rebuilds = 0;
  refresh_speed_bound();
}

template <class Real>
std::unique_ptr<StepperBase> make_stepper_for(const ParticleSystem& sys, const Physics& physics,
                                              const StepperConfig& cfg) {
  if (cfg.specialise && sys.monodisperse()) return std::make_unique<Stepper<Real, true>>(sys, physics, cfg);
  return std::make_unique<Stepper<Real, false>>(sys, physics, cfg);
}

}  // namespace detail

std::unique_ptr<StepperBase> make_stepper(const ParticleSystem& sys, const Physics& physics, const StepperConfig& cfg,
                                          Precision precision) {
  const Physics checked = validated(physics, sys.box.periodic);
  if (precision == Precision::Float) return detail::make_stepper_for<float>(sys, checked, cfg);
  return detail::make_stepper_for<double>(sys, checked, cfg);
}

StateExchange& state_exchange(StepperBase& stepper) {
  // Every engine make_stepper builds implements both interfaces.
  return dynamic_cast<StateExchange&>(stepper);
}

}  // namespace hardsphere
