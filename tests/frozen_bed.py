"""The kinematic spheres' test scene, written as a data file for the CLI, Python and LAMMPS tests:
type 2 a 6 x 6 base of touching unit spheres at z = 0.5 (moving at base_velocity), type 1 30
spheres of diameter 0.9 above it (with free_overlap the first one overlaps the base), box 6 x 6 x 12."""
import math

BOX = (6.0, 6.0, 12.0)


def write_bed(path, base_velocity=(0.0, 0.0, 0.0), free_overlap=False):
    atoms, vels, n = [], [], 0
    for i in range(6):
        for j in range(6):
            n += 1
            atoms.append(f"{n} 2 1.0 1.909859317102744 {0.5 + i} {0.5 + j} 0.5")
            vels.append(f"{n} {base_velocity[0]} {base_velocity[1]} {base_velocity[2]} 0 0 0")
    for k in range(30):
        n += 1
        z = 0.5 + 0.9 if (free_overlap and k == 0) else 2.5 + 1.5 * (k // 25)
        atoms.append(f"{n} 1 0.9 1.5 {0.6 + (k % 5) * 1.2} {0.6 + (k // 5) % 5 * 1.2} {z}")
        vels.append(f"{n} {0.3 * math.sin(k)} {0.3 * math.cos(k)} 0 0 0 0")
    path.write_text(f"bed\n\n{n} atoms\n2 atom types\n\n0 {BOX[0]} xlo xhi\n0 {BOX[1]} ylo yhi\n0 {BOX[2]} zlo zhi\n\n"
                    "Atoms # sphere\n\n" + "\n".join(atoms) + "\n\nVelocities\n\n" + "\n".join(vels) + "\n")
    return path
