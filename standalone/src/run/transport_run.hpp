#pragma once
//! Transport coefficients in a run (RunSpec::transport): the tally both engines feed, the samples
//! at whole intervals of the measured run and the blocks of the error bars (transport.hpp).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>

#include "hardsphere/simulation.hpp"
#include "hardsphere/transport.hpp"

namespace hardsphere {

class TransportRun {
 public:
  //! Checks the scene and the window against the measured run (InputError, naming the options);
  //! `quantum` is the time the samples must be whole multiples of (the stepper's dt; 0: any).
  TransportRun(const RunSpec& spec, const ParticleSystem& initial, double measured_time, double quantum);
  //! The measured run starts from `state`: the tally's clock and the first sample.
  void begin(const ParticleSystem& state);
  TransportTally& tally() { return tally_; }
  double interval() const { return interval_; }
  std::int64_t samples() const { return samples_; }  //!< sample intervals in the measured run
  //! Sample `index` (1 .. samples()) of `state`, at index * interval() into the measured run.
  void sample(std::int64_t index, const ParticleSystem& state);
  void add_summary(nlohmann::json& j) const;

 private:
  TransportTally tally_;
  std::optional<TransportEstimator> estimator_;
  double interval_ = 0;
  std::int64_t samples_ = 0;
  int lags_ = 0, blocks_ = 0;
};

}  // namespace hardsphere
