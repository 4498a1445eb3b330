"""Benchmarks, run from the repository root as `python3 -m bench.NAME ...` (docs/performance.md,
docs/lammps.md): big_spheres, event_big_spheres, bench_table (tables from hs_bench_stepper's
JSON), lammps_speed and lammps_scaling (lmp_hs against the standalone, serial and on 2 ranks).
Speeds are reported, never asserted."""
