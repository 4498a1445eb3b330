// Fuzz target: the LAMMPS data-file reader. Each input is a data file, read with periodic and
// with wall boundaries. A refusal (InputError) is the expected outcome for most inputs; a file
// that is accepted must give a consistent state that write_data writes and read_data reads
// back unchanged. Anything else (another exception, a broken invariant) aborts: a finding.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>
#include <unordered_set>

#include "fuzz_check.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/limits.hpp"

using namespace hardsphere;
using hardsphere::fuzz::require;

namespace {

void check_state(const ParticleSystem& s) {
  require(s.size() >= 1 && std::int64_t(s.size()) <= kMaxSpheres, "atom count within 1..kMaxSpheres");
  std::unordered_set<std::int64_t> ids;
  for (std::size_t i = 0; i < s.size(); ++i) {
    require(s.id[i] >= 1 && ids.insert(s.id[i]).second, "ids positive and distinct");
    require(s.type[i] >= 1, "types >= 1");
    require(std::isfinite(s.radius[i]) && s.radius[i] > 0, "radius positive and finite");
    require(std::isfinite(s.mass[i]) && s.mass[i] > 0, "mass positive and finite");
    for (int d = 0; d < 3; ++d) {
      const double p = s.pos[i][d];
      require(std::isfinite(p) && std::isfinite(s.vel[i][d]), "position and velocity finite");
      if (s.box.periodic[d])
        require(p >= s.box.lo[d] && p < s.box.hi[d], "periodic coordinate wrapped into [lo, hi)");
      else
        require(p - s.radius[i] >= s.box.lo[d] && p + s.radius[i] <= s.box.hi[d], "sphere inside the walls");
    }
  }
}

// write_data then read_data gives the same state: ids, types, radii, positions and velocities bit
// for bit; masses to rounding (they pass through density = m / (4/3 pi r^3) and back).
void check_round_trip(const ParticleSystem& s) {
  std::ostringstream out;
  write_data(out, s, "fuzz round trip");
  std::istringstream in(out.str());
  ParticleSystem b;
  try {
    b = read_data(in, "round-trip.data", s.box.periodic);
  } catch (const InputError& e) {
    fuzz::fail(std::string("write_data output refused: ") + e.what());
  }
  require(b.size() == s.size(), "round trip keeps the atom count");
  for (std::size_t i = 0; i < s.size(); ++i) {
    require(b.id[i] == s.id[i] && b.type[i] == s.type[i] && b.radius[i] == s.radius[i], "round trip: id, type, radius");
    for (int d = 0; d < 3; ++d) {
      require(b.pos[i][d] == s.pos[i][d], "round trip: position bit for bit");
      require(b.vel[i][d] == s.vel[i][d], "round trip: velocity bit for bit");
    }
    require(std::abs(b.mass[i] - s.mass[i]) <= 8 * std::numeric_limits<double>::epsilon() * s.mass[i],
            "round trip: mass to rounding");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (const std::array<bool, 3> periodic : {std::array<bool, 3>{true, true, true}, {false, false, true}}) {
    ParticleSystem s;
    try {
      std::istringstream in(text);
      s = read_data(in, "fuzz.data", periodic);
    } catch (const InputError&) {
      continue;  // refused: the expected outcome for malformed files
    } catch (const std::exception& e) {
      fuzz::fail(std::string("read_data threw a non-InputError: ") + e.what());
    }
    check_state(s);
    check_round_trip(s);
  }
  return 0;
}
