"""Benchmarks, run from the repository root as `python3 -m bench.NAME ...` (docs/dev/performance.md,
docs/lammps.md, docs/initial_states.md): big_spheres, event_big_spheres, bench_table (tables from
hs_bench_stepper's JSON), lammps_speed and lammps_scaling (lmp_hs against the standalone, serial
and on 2 ranks), initial_states (time and structure of the generated initial states),
python_overhead (the Python module's loop against the CLI's).
Speeds are reported, never asserted."""
