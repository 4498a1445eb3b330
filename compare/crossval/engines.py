"""Runs one state through one engine and setting, returning what the cross-validation measures.

Every engine starts from the same LAMMPS data file and writes trajectory frames, block-averaged
pressure and its CPU time; compare.cross_validate turns these into the compared figures.
A run is a dict: engine, setting, kind ('hard'/'soft'), ranks, dt, sim_time, steps, frames,
z_blocks, collision_rate (+ _err), cpu_seconds (CPU time of the stepping loop, all ranks),
plus engine-specific keys.
"""
import json
import math
import re
import time
from pathlib import Path

import numpy as np

from compare import lammps_files
from compare.harness import ProgramError, run_program
from compare import soft_spheres as soft
from compare.crossval import states as xv_states
from compare.crossval.observables import iter_frames, read_frames

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ROOT / "reference_inputs"


def run_logged(cmd, cwd, log):
    """Runs cmd in cwd with its output in the file log; (CompletedProcess, wall seconds), or
    harness.ProgramError with the output's last lines."""
    t0 = time.time()
    p = run_program(cmd, cwd=cwd, log=log)
    return p, time.time() - t0


def z_from_blocks(p_virial, temperature, n, volume):
    """Z per block from the virial pressure and the kinetic temperature of each block."""
    return [1 + pv * volume / (n * t) for pv, t in zip(p_virial, temperature)]


def mean_err(values):
    v = np.asarray(values, dtype=float)
    return float(v.mean()), float(v.std(ddof=1) / math.sqrt(len(v))) if len(v) > 1 else float("nan")


class Engines:
    def __init__(self, hardsphere, lmp_hs=None, lmp=None, liggghts=None, mpirun=None):
        self.hs, self.lmp_hs, self.lmp, self.liggghts, self.mpirun = hardsphere, lmp_hs, lmp, liggghts, mpirun

    # --- the standalone program ----------------------------------------------------------------

    def stepper(self, state, work, dt, steps, precision="double", blocks=8, frames_per_block=4):
        """The stepper in `blocks` chained runs (data file to data file): Z per block."""
        work.mkdir(parents=True, exist_ok=True)
        per = steps // blocks
        every = max(1, per // frames_per_block)
        frames, zs, coll, cpu, ke0, ke1, summaries = [], [], [], 0.0, None, None, []
        current = state
        for b in range(blocks):
            tag = work / f"block{b}"
            run_logged([self.hs, "run", "--read-data", current, "--dt", dt, "--steps", per, "--precision", precision,
                  "--dump", f"{tag}.dump", "--dump-every", every, "--json", f"{tag}.json",
                  "--write-data", f"{tag}.data"], work, f"{tag}.log")
            j = json.loads(Path(f"{tag}.json").read_text())
            summaries.append(j)
            t0 = b * per * dt
            fr = read_frames(f"{tag}.dump", dt=dt)
            for f in fr:
                f["t"] += t0
            frames += fr if b == 0 else fr[1:]
            zs.append(j["compressibility_factor"])
            coll.append(j["collisions"])
            cpu += j["loop_cpu_seconds"]
            ke0 = ke0 if ke0 is not None else j["kinetic_energy_initial"]
            ke1 = j["kinetic_energy_final"]
            if b > 0:
                Path(current).unlink()
            current = f"{tag}.data"
        n, sim_time = summaries[0]["n"], blocks * per * dt
        rate, rate_err = mean_err([2 * c / (n * per * dt) for c in coll])
        return dict(kind="hard", ranks=1, dt=dt, sim_time=sim_time, steps=blocks * per, n=n, frames=frames,
                    z_blocks=zs, collision_rate=rate, collision_rate_err=rate_err, cpu_seconds=cpu,
                    energy_drift=abs(ke1 - ke0) / ke0, max_overlap=max(s["max_overlap"] for s in summaries),
                    warnings=sum((s["warnings"] for s in summaries), []))

    def event(self, state, work, sim_time, blocks=32):
        work.mkdir(parents=True, exist_ok=True)
        run_logged([self.hs, "run", "--engine", "event", "--read-data", state, "--time", sim_time, "--blocks", blocks,
              "--dump", work / "run.dump", "--json", work / "run.json"], work, work / "run.log")
        j = json.loads((work / "run.json").read_text())
        frames = read_frames(work / "run.dump", times=[k * sim_time / blocks for k in range(blocks + 1)])
        return dict(kind="hard", ranks=1, dt=None, sim_time=sim_time, steps=None, n=j["n"], frames=frames,
                    z=j["compressibility_factor"], z_err=j["compressibility_factor_error"],
                    collision_rate=j["collision_rate_per_particle"], collision_rate_err=j["collision_rate_error"],
                    cpu_seconds=j["loop_cpu_seconds"], energy_drift=abs(j["energy_rel_drift"]),
                    max_overlap=j["max_overlap"], warnings=j["warnings"], events=j["events"])

    # --- LAMMPS and LIGGGHTS -------------------------------------------------------------------

    def lammps_family(self, exe, script, state, work, ranks, dt, nrun, nequil, dumpevery, blocksteps,
                       contactsteps=0, extra=()):
        work.mkdir(parents=True, exist_ok=True)
        variables = dict(data=Path(state).resolve(), dt=dt, nrun=nrun, nequil=nequil,
                         dumpfile="run.dump", dumpevery=dumpevery, virialfile="virial.txt",
                         blocksteps=blocksteps, contactfile="contact.dump", contactsteps=max(1, contactsteps))
        variables.update(extra)
        cmd = [exe, "-in", script, "-log", "log.lammps", "-screen", "none"]
        for k, v in variables.items():
            cmd += ["-var", k, v]
        if ranks > 1:
            cmd = [self.mpirun, "--allow-run-as-root", "--oversubscribe", "-np", ranks] + cmd
        _, wall = run_logged(cmd, work, work / "run.out")
        log = (work / "log.lammps").read_text()
        loops = lammps_files.loop_times(log)
        if not loops:
            raise ProgramError(f"no 'Loop time' line in {work / 'log.lammps'}")
        seconds, procs, steps = loops[-1]
        # Writing dumps is not simulating (the standalone's loop time leaves it out too).
        tail = log[log.rfind("Loop time of"):]
        output = re.search(r"^Output\s*\|\s*\S+\s*\|\s*([0-9.eE+-]+)", tail, re.M) or \
            re.search(r"^Outpt time \(%\) = ([0-9.eE+-]+)", tail, re.M)  # LIGGGHTS 3.8
        output_seconds = float(output.group(1)) if output else 0.0
        blocks = soft.read_blocks(work / "virial.txt")
        frames = read_frames(work / "run.dump", dt=dt)
        n = len(frames[0]["ids"])
        volume = float(np.prod(frames[0]["hi"] - frames[0]["lo"]))
        # compute temp divides by 3N - 3 degrees of freedom; Z uses T = sum m v^2 / 3N
        temps = blocks[:, 2] * (n - 1) / n
        return dict(ranks=procs, dt=dt, sim_time=steps * dt, steps=steps, n=n, frames=frames, blocks=blocks,
                    z_blocks=z_from_blocks(blocks[:, 1], temps, n, volume),
                    cpu_seconds=(seconds - output_seconds) * procs, output_seconds=output_seconds * procs,
                    wall_seconds=wall, work=work)

    def lmp_hardsphere(self, state, work, dt, nrun, ranks=1, dumpevery=None, blocksteps=None, skin=None):
        script = INPUTS / "lammps" / "in.hardsphere_state"
        r = self.lammps_family(self.lmp_hs, script, state, work, ranks, dt, nrun, 0, dumpevery, blocksteps,
                                extra=dict(skin=skin))
        r["kind"] = "hard"
        per_step = r["blocks"][:, 3]  # collisions per step, block means
        rate = 2 * per_step / (r["n"] * dt)
        r["collision_rate"], r["collision_rate_err"] = mean_err(rate)
        return r

    def soft(self, engine, state, work, dt, nrun, nequil, dumpevery, blocksteps, contactsteps, stiffness,
             ranks=1):
        """engine: 'lammps hooke', 'lammps hertz' (stiffness = kn) or 'liggghts hertz' (= Young's modulus)."""
        if engine == "liggghts hertz":
            exe, script = self.liggghts, INPUTS / "liggghts" / "in.granular_hertz"
            extra = dict(ymod=stiffness, ntypes=xv_states.type_count(state))
        else:
            exe = self.lmp
            script = INPUTS / "lammps" / ("in.granular_hooke" if engine == "lammps hooke" else "in.granular_hertz")
            extra = dict(kn=stiffness)
        r = self.lammps_family(exe, script, state, work, ranks, dt, nrun, nequil, dumpevery, blocksteps,
                                contactsteps, extra)
        r["kind"] = "soft"
        r["contact_frames"] = iter_frames(work / "contact.dump", dt=dt)  # one pass, frame by frame
        return r
