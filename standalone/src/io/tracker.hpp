#pragma once
//! The CLI's tracker (--track): one sphere's unwrapped position, velocity and pair-collision
//! count at fixed intervals of simulated time, written as a text table (an AtomicFile, committed
//! with the run's other outputs).
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "hardsphere/atomic_file.hpp"
#include "hardsphere/particles.hpp"

namespace hardsphere {

//! The most rows a tracker file may get: beyond this the file would be tens of gigabytes.
constexpr double kMaxTrackSamples = 1e8;

class Tracker {
 public:
  //! `ordered` is the state in the engine's state() order: the tracked sphere's index in it is
  //! what the engine's sphere() takes. Refuses (InputError) an id no sphere has, an interval that
  //! is not positive and finite, and more than kMaxTrackSamples rows over `run_time`; all before
  //! the file is created.
  Tracker(const std::string& path, const ParticleSystem& ordered, std::int64_t id, double every, double run_time,
          const std::string& engine);
  std::size_t index() const { return index_; }
  double every() const { return every_; }
  //! Time (since the start of the measured run) of the next row to write.
  double next_time() const { return double(samples_) * every_; }
  void write(double time, const SphereSample& s);
  AtomicFile& file() { return *file_; }
  //! The run summary's "track" key: id, every, samples, file.
  nlohmann::json summary() const;

 private:
  static std::size_t find_index(const ParticleSystem& sys, std::int64_t id);
  std::int64_t id_;
  std::string path_;
  std::size_t index_;
  double every_;
  std::int64_t samples_ = 0;
  std::unique_ptr<AtomicFile> file_;
};

}  // namespace hardsphere
