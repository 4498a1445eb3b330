// Runs a small gas through both engines with the installed headers and libraries only, and
// round-trips the state through a LAMMPS data file. Exit 0 when the physics checks hold.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "hardsphere/event_engine.hpp"
#include "hardsphere/init.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/stepper.hpp"

namespace hs = hardsphere;

static int fail(const char* what, double value) {
  std::fprintf(stderr, "consumer: %s (%.17g)\n", what, value);
  return 1;
}

int main() {
  hs::InitSpec spec;
  spec.n = 500;
  const double length = std::cbrt(spec.n * M_PI / 6 / 0.3);  // phi = 0.3 for unit diameters
  spec.box = hs::Box::from_lengths({length, length, length}, {true, true, true});
  const hs::ParticleSystem start = hs::make_initial_state(spec);
  const double e0 = hs::kinetic_energy(start);

  hs::StepperConfig cfg;
  cfg.dt = 0.01;
  auto stepper = hs::make_stepper(start, hs::Physics{}, cfg);
  stepper->run(200);
  const hs::ParticleSystem end = stepper->state();
  if (stepper->counters().collisions == 0) return fail("the stepper resolved no collision", 0);
  const double drift = std::abs(hs::kinetic_energy(end) / e0 - 1);
  if (drift > 1e-12) return fail("stepper energy drift", drift);

  hs::EventEngine event(start, hs::Physics{}, hs::EventConfig{});
  event.advance(2.0);
  const double event_drift = std::abs(hs::kinetic_energy(event.state()) / e0 - 1);
  if (event_drift > 1e-12) return fail("event engine energy drift", event_drift);

  // Same gas, same start: the two engines' collision rates agree within a few per cent.
  const double rate_ratio = double(event.counters().collisions) / double(stepper->counters().collisions);
  if (std::abs(rate_ratio - 1) > 0.1) return fail("event/stepper collision ratio", rate_ratio);

  std::stringstream file;
  hs::write_data(file, end, "consumer");
  const hs::ParticleSystem back = hs::read_data(file, "consumer.data", {true, true, true});
  if (back.size() != end.size()) return fail("data file round trip lost spheres", double(back.size()));
  std::printf("consumer: %lld collisions, energy drift %.1e\n", static_cast<long long>(stepper->counters().collisions),
              drift);
  return 0;
}
