"""fix python/invoke: shifts every atom of this rank by 0.05 along x."""
from lammps import lammps


def move(ptr):
    lmp = lammps(ptr=ptr)
    x = lmp.numpy.extract_atom("x")
    n = lmp.extract_global("nlocal")
    x[:n, 0] += 0.05
