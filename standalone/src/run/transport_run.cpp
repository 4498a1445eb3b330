// Transport coefficients in a run: the window and the sampling chosen (or checked) before the run,
// the samples and blocks during it, the summary keys after it.
#include <cmath>
#include <sstream>

#include "hardsphere/errors.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/simulation.hpp"

namespace hardsphere {

namespace {

//! Enskog's mean free time with the Carnahan-Starling contact value: 1 / (4 n sigma^2 g sqrt(pi T / m)).
double mean_free_time(const ParticleSystem& sys) {
  const double phi = sys.packing_fraction(), sigma = 2 * sys.radius[0], m = sys.mass[0];
  const double n = double(sys.size()) / sys.box.volume(), g = (1 - phi / 2) / std::pow(1 - phi, 3);
  const double t = std::max(temperature(sys), 1e-300);
  return 1 / (4 * n * sigma * sigma * g * std::sqrt(3.14159265358979323846 * t / m));
}

}  // namespace

TransportRun::TransportRun(const RunSpec& spec, const ParticleSystem& initial, double measured_time, double quantum,
                           const TransportNames& names)
    : lags_(kTransportLags), blocks_(spec.transport_blocks) {
  check_transport(initial, spec.physics, names.option);
  if (spec.transport_blocks < 2)
    throw InputError(names.blocks + " " + std::to_string(spec.transport_blocks) +
                     " must be >= 2 (the error bars are the spread of the blocks)");
  const double window =
      spec.transport_window > 0 ? spec.transport_window : kTransportWindowFreeTimes * mean_free_time(initial);
  if (!(std::isfinite(window) && window > 0)) {
    std::ostringstream m;
    m << names.window << " " << window << " must be positive and finite";
    throw InputError(m.str());
  }
  interval_ = window / lags_;
  if (quantum > 0) interval_ = std::max(1.0, std::round(interval_ / quantum)) * quantum;
  samples_ = std::int64_t(std::floor(measured_time / interval_ * (1 + 1e-12)));
  // Each block must hold at least two windows, or its slope is no better than noise.
  if (samples_ < std::int64_t(2) * lags_ * blocks_) {
    std::ostringstream m;
    m << names.option << ": the measured run of time " << measured_time << " is too short for " << blocks_
      << " blocks of two correlation windows of " << interval_ * lags_
      << (spec.transport_window > 0 ? " (" + names.window + ")" : std::string(" (100 mean free times)"))
      << ": run at least " << 2.0 * blocks_ * lags_ * interval_ << ", or give a shorter " << names.window
      << " or fewer " << names.blocks;
    throw InputError(m.str());
  }
}

void TransportRun::begin(const ParticleSystem& state) {
  tally_.start(state);
  estimator_.emplace(state, interval_, lags_, blocks_);
  estimator_->sample(tally_.moments(), state);
}

void TransportRun::sample(std::int64_t index, const ParticleSystem& state) {
  estimator_->sample(tally_.moments(), state);
  // Sample `index` ends a block when it is the last of one of `blocks_` equal shares; it also starts the next.
  const auto block_of = [&](std::int64_t s) { return s * blocks_ / samples_; };
  if (index < samples_ && block_of(index) != block_of(index - 1)) {
    estimator_->end_block();
    estimator_->sample(tally_.moments(), state);
  }
}

void TransportRun::add_summary(nlohmann::json& j) const {
  const TransportResult r = estimator_->result();
  j["diffusion"] = r.diffusion;
  j["diffusion_error"] = r.diffusion_error;
  j["diffusion_raw"] = r.diffusion_raw;
  j["diffusion_raw_error"] = r.diffusion_raw_error;
  j["shear_viscosity"] = r.shear_viscosity;
  j["shear_viscosity_error"] = r.shear_viscosity_error;
  j["thermal_conductivity"] = r.thermal_conductivity;
  j["thermal_conductivity_error"] = r.thermal_conductivity_error;
  j["transport_blocks"] = r.blocks;
  j["transport_window"] = r.window;
  j["transport_sample_interval"] = r.sample_interval;
  j["transport_temperature"] = r.temperature;
}

}  // namespace hardsphere
