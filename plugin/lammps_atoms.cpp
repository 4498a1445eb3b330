#include "lammps_atoms.h"

#include "atom.h"
#include "domain.h"

using namespace LAMMPS_NS;
using hardsphere::Vec3d;

hardsphere::Box LAMMPS_NS::lammps_box(const Domain *domain) {
  hardsphere::Box box;
  for (int d = 0; d < 3; d++) {
    box.lo[d] = domain->boxlo[d], box.hi[d] = domain->boxhi[d];
    box.periodic[d] = domain->periodicity[d] != 0;
  }
  return box;
}

hardsphere::ParticleSystem LAMMPS_NS::atoms_to_system(const Atom *atom, const hardsphere::Box &box,
                                                      const AtomRows &rows) {
  hardsphere::ParticleSystem sys;
  sys.box = box;
  const int n = atom->nlocal + (rows.ghosts ? atom->nghost : 0);
  sys.reserve(std::size_t(n));
  double **x = atom->x, **v = atom->v;
  for (int i = 0; i < n; i++) {
    Vec3d p{x[i][0], x[i][1], x[i][2]};
    std::int64_t id = std::int64_t(atom->tag[i]);
    if (rows.place && !rows.place(i, sys, p, id)) continue;
    const Vec3d w = rows.rough ? Vec3d{atom->omega[i][0], atom->omega[i][1], atom->omega[i][2]} : Vec3d{0, 0, 0};
    sys.push_back(id, atom->type[i], atom->radius[i], atom->rmass[i], p, {v[i][0], v[i][1], v[i][2]}, {0, 0, 0}, w);
    if (rows.kinematic_bits) {
      sys.kinematic.resize(sys.size());
      sys.kinematic.back() = (atom->mask[i] & rows.kinematic_bits) != 0;
    }
  }
  return sys;
}

int LAMMPS_NS::atom_record_size(bool rough) { return rough ? 13 : 10; }

std::vector<double> LAMMPS_NS::owned_atom_records(const Atom *atom, bool rough) {
  const int nlocal = atom->nlocal, fields = atom_record_size(rough);
  std::vector<double> out(std::size_t(nlocal) * std::size_t(fields));
  for (int i = 0; i < nlocal; i++) {
    double *o = &out[std::size_t(i) * std::size_t(fields)];
    const double *p = atom->x[i], *u = atom->v[i];
    o[0] = double(atom->tag[i]), o[1] = atom->type[i], o[2] = atom->radius[i], o[3] = atom->rmass[i];
    o[4] = p[0], o[5] = p[1], o[6] = p[2], o[7] = u[0], o[8] = u[1], o[9] = u[2];
    if (rough) o[10] = atom->omega[i][0], o[11] = atom->omega[i][1], o[12] = atom->omega[i][2];
  }
  return out;
}

hardsphere::ParticleSystem LAMMPS_NS::records_to_system(const std::vector<double> &records, const hardsphere::Box &box,
                                                        bool rough) {
  hardsphere::ParticleSystem sys;
  sys.box = box;
  const std::size_t fields = std::size_t(atom_record_size(rough));
  for (std::size_t k = 0; k < records.size(); k += fields) {
    const double *o = &records[k];
    sys.push_back(std::int64_t(o[0]), int(o[1]), o[2], o[3], {o[4], o[5], o[6]}, {o[7], o[8], o[9]}, {0, 0, 0},
                  rough ? Vec3d{o[10], o[11], o[12]} : Vec3d{0, 0, 0});
  }
  return sys;
}
