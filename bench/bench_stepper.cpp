// Stepper throughput (particle-steps per CPU second), as in the seed paper's figures 1-3:
//   Scaling        N = 1e3..1e6 at phi = 0.1, 0.3, 0.45, auto cells
//   OneBox         the seed's K = 1 baseline (O(N^2)), small N only
//   CellsSweep     time per step against cells per axis at fixed N (the "ideal number of boxes")
//   Kernel         scene-specialised against general kernel on the same scene
//   Target         the reference point: N = 1e5, phi = 0.2, dt = 0.01
// Initial states are generated once per (N, phi) and cached; only stepping is timed.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>

#include "hardsphere/init.hpp"
#include "hardsphere/stepper.hpp"

using namespace hardsphere;

namespace {

const ParticleSystem& state(std::int64_t n, double phi) {
  static std::map<std::pair<std::int64_t, double>, ParticleSystem> cache;
  auto it = cache.find({n, phi});
  if (it == cache.end()) {
    InitSpec spec;
    spec.n = n;
    const double l = std::cbrt(double(n) * M_PI / 6.0 / phi);
    spec.box = Box::from_lengths({l, l, l}, {true, true, true});
    spec.seed = 2024;
    it = cache.emplace(std::make_pair(n, phi), make_initial_state(spec)).first;
  }
  return it->second;
}

void time_steps(benchmark::State& st, const ParticleSystem& sys, StepperConfig cfg, Precision p = Precision::Double) {
  auto stepper = make_stepper(sys, Physics{}, cfg, p);
  // ~1e6 particle-steps per iteration keeps the timer resolution irrelevant.
  const std::int64_t steps = std::max<std::int64_t>(1, 1000000 / std::int64_t(sys.size()));
  stepper->run(steps);  // warm caches and the pair list
  for (auto _ : st) stepper->run(steps);
  const double total = double(st.iterations()) * double(steps) * double(sys.size());
  st.counters["particle_steps_per_s"] = benchmark::Counter(total, benchmark::Counter::kIsRate);
  st.counters["collisions_per_particle_step"] =
      double(stepper->counters().collisions) / double(stepper->counters().steps) / double(sys.size());
  st.counters["cells_per_axis"] = stepper->cells_per_dim()[0];
}

void Scaling(benchmark::State& st) {
  StepperConfig cfg;
  cfg.dt = 0.01;
  time_steps(st, state(st.range(0), double(st.range(1)) / 100.0), cfg);
}
BENCHMARK(Scaling)
    ->ArgNames({"N", "phi%"})
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {10, 30, 45}})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(1.0);

void OneBox(benchmark::State& st) {
  StepperConfig cfg;
  cfg.dt = 0.01;
  cfg.cells = {1, 1, 1};
  time_steps(st, state(st.range(0), double(st.range(1)) / 100.0), cfg);
}
BENCHMARK(OneBox)->ArgNames({"N", "phi%"})->ArgsProduct({{1000, 4000}, {10, 30, 45}})->Unit(benchmark::kMillisecond);

void CellsSweep(benchmark::State& st) {
  // N = 1e4 at phi = 0.1: box 37.4 diameters, so up to 34 cells per axis stay wider than one.
  StepperConfig cfg;
  cfg.dt = 0.01;
  const int k = int(st.range(0));
  cfg.cells = {k, k, k};
  time_steps(st, state(10000, 0.1), cfg);
}
BENCHMARK(CellsSweep)->ArgName("K")->DenseRange(1, 5, 1)->DenseRange(8, 32, 4)->Arg(34)->Unit(benchmark::kMillisecond);

void Kernel(benchmark::State& st) {
  StepperConfig cfg;
  cfg.dt = 0.01;
  cfg.specialise = st.range(1) != 0;
  time_steps(st, state(st.range(0), 0.2), cfg);
}
BENCHMARK(Kernel)
    ->ArgNames({"N", "specialised"})
    ->ArgsProduct({{10000, 100000}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

void Target(benchmark::State& st) {
  StepperConfig cfg;
  cfg.dt = 0.01;
  time_steps(st, state(100000, 0.2), cfg, st.range(0) ? Precision::Float : Precision::Double);
}
BENCHMARK(Target)->ArgName("float")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
