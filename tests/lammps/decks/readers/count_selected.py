"""fix python/invoke: appends 'step count' of this rank's atoms the selection holds (the variable
sel, evaluated by LAMMPS from the rows this function also reads) and its own count from x, v
and omega, to py_count.RANK.txt."""
from lammps import lammps


def count(ptr):
    lmp = lammps(ptr=ptr)
    n = lmp.extract_global("nlocal")
    sel = lmp.numpy.extract_variable("sel", "all", 1)[:n]  # atom-style: LAMMPS's own reading
    rank = lmp.extract_setting("world_rank")
    with open(f"py_count.{rank}.txt", "a") as f:
        f.write(f"{lmp.extract_global('ntimestep')} {int(round(sel.sum()))}\n")
