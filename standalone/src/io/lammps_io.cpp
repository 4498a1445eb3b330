// LAMMPS files out: data files (atom_style sphere) and text dumps. Reading is data_reader.cpp.
#include "hardsphere/lammps_io.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "hardsphere/errors.hpp"

namespace hardsphere {

void write_data(std::ostream& o, const ParticleSystem& sys, const std::string& title) {
  const auto old_precision = o.precision(17);
  int ntypes = 1;
  for (int t : sys.type) ntypes = std::max(ntypes, t);
  o << title << "\n\n" << sys.size() << " atoms\n" << ntypes << " atom types\n\n";
  const char* ax[3] = {"x", "y", "z"};
  for (int d = 0; d < 3; ++d) o << sys.box.lo[d] << ' ' << sys.box.hi[d] << ' ' << ax[d] << "lo " << ax[d] << "hi\n";
  o << "\nAtoms # sphere\n\n";
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const double r = sys.radius[i];
    const double density = sys.mass[i] / (4.0 * M_PI / 3.0 * r * r * r);
    const auto img = i < sys.image.size() ? sys.image[i] : std::array<std::int32_t, 3>{0, 0, 0};
    o << sys.id[i] << ' ' << sys.type[i] << ' ' << 2 * r << ' ' << density << ' ' << sys.pos[i].x << ' ' << sys.pos[i].y
      << ' ' << sys.pos[i].z << ' ' << img[0] << ' ' << img[1] << ' ' << img[2] << '\n';
  }
  o << "\nVelocities\n\n";
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const Vec3d w = i < sys.omega.size() ? sys.omega[i] : Vec3d{};
    o << sys.id[i] << ' ' << sys.vel[i].x << ' ' << sys.vel[i].y << ' ' << sys.vel[i].z << ' ' << w.x << ' ' << w.y
      << ' ' << w.z << '\n';
  }
  o.precision(old_precision);
}

void write_data(const std::string& path, const ParticleSystem& sys, const std::string& title) {
  AtomicFile f(path);
  write_data(f.stream(), sys, title);
  f.commit();
}

void DumpWriter::write_frame(std::int64_t timestep, const ParticleSystem& sys) {
  // Spins given to smooth spheres (which keep them) are dumped too: the first frame decides.
  if (frames_++ == 0 && !omega_)
    omega_ = std::any_of(sys.omega.begin(), sys.omega.end(), [](const Vec3d& w) {
      return w.x != 0 || w.y != 0 || w.z != 0 || std::signbit(w.x) || std::signbit(w.y) || std::signbit(w.z);
    });
  auto& o = file_.stream();
  o << "ITEM: TIMESTEP\n" << timestep << "\nITEM: NUMBER OF ATOMS\n" << sys.size() << "\nITEM: BOX BOUNDS";
  for (int d = 0; d < 3; ++d) o << (sys.box.periodic[d] ? " pp" : " ff");
  o << '\n';
  for (int d = 0; d < 3; ++d) o << sys.box.lo[d] << ' ' << sys.box.hi[d] << '\n';
  // Image flags make the unwrapped position x + ix L continuous in time (mean-squared
  // displacements from dumps).
  o << (omega_ ? "ITEM: ATOMS id type radius x y z vx vy vz ix iy iz wx wy wz\n"
               : "ITEM: ATOMS id type radius x y z vx vy vz ix iy iz\n");
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const auto img = i < sys.image.size() ? sys.image[i] : std::array<std::int32_t, 3>{0, 0, 0};
    o << sys.id[i] << ' ' << sys.type[i] << ' ' << sys.radius[i] << ' ' << sys.pos[i].x << ' ' << sys.pos[i].y << ' '
      << sys.pos[i].z << ' ' << sys.vel[i].x << ' ' << sys.vel[i].y << ' ' << sys.vel[i].z << ' ' << img[0] << ' '
      << img[1] << ' ' << img[2];
    if (omega_) {
      const Vec3d w = i < sys.omega.size() ? sys.omega[i] : Vec3d{};
      o << ' ' << w.x << ' ' << w.y << ' ' << w.z;
    }
    o << '\n';
  }
  // A full disk or a file size limit shows here, at the frame, not only after the whole run.
  if (!o)
    throw InputError("error while writing '" + file_.path() + "'" +
                     (errno ? std::string(": ") + std::strerror(errno) : ""));
}

}  // namespace hardsphere
