#include "io/tracker.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "hardsphere/errors.hpp"

namespace hardsphere {

std::size_t Tracker::find_index(const ParticleSystem& sys, std::int64_t id) {
  for (std::size_t i = 0; i < sys.size(); ++i)
    if (sys.id[i] == id) return i;
  throw InputError("--track " + std::to_string(id) + ": no sphere has this id");
}

Tracker::Tracker(const std::string& path, const ParticleSystem& sys, std::int64_t id, double every, double run_time,
                 const std::string& engine)
    : id_(id), path_(path), index_(find_index(sys, id)), every_(every) {
  if (!(every > 0) || !std::isfinite(every)) {
    std::ostringstream m;
    m << "--track-every " << every << " must be positive and finite";
    throw InputError(m.str());
  }
  if (run_time / every + 1 > kMaxTrackSamples) {
    std::ostringstream m;
    m << "--track-every " << every << " over time " << run_time << " would write " << run_time / every + 1
      << " rows, more than the limit of " << kMaxTrackSamples << "; use a longer interval";
    throw InputError(m.str());
  }
  file_ = std::make_unique<AtomicFile>(path);
  std::ostream& o = file_->stream();
  const std::size_t i = index_;
  o << std::setprecision(17) << "# hardsphere track: sphere id " << id << ", radius " << sys.radius[i] << ", mass "
    << sys.mass[i] << ", engine " << engine << ", every " << every << ", box lengths " << sys.box.length(0) << ' '
    << sys.box.length(1) << ' ' << sys.box.length(2) << '\n'
    << "# x y z are unwrapped (position + image * box length); pair_collisions counts from time 0\n"
    << "# time x y z vx vy vz pair_collisions\n";
}

void Tracker::write(double time, const SphereSample& s) {
  std::ostream& o = file_->stream();
  o << time << ' ' << s.unwrapped.x << ' ' << s.unwrapped.y << ' ' << s.unwrapped.z << ' ' << s.velocity.x << ' '
    << s.velocity.y << ' ' << s.velocity.z << ' ' << s.pair_collisions << '\n';
  ++samples_;
}

nlohmann::json Tracker::summary() const {
  return {{"id", id_}, {"every", every_}, {"samples", samples_}, {"file", path_}};
}

}  // namespace hardsphere
