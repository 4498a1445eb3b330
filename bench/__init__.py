"""Benchmarks, run from the repository root as `python3 -m bench.NAME ...` (--help for each), through
compare.harness like compare/'s programs (--build, --hardsphere, --lmp-hs, --mpirun, --out, --work;
exit status 2 for refused input, 3 when a program fails). Each writes its report into --out as
NAME.md and NAME.json (docs/reports/performance/ and docs/reports/lammps/); speeds are reported,
never asserted.

  bench_table         the kernel tables from hs_bench_stepper's JSON (performance/kernel.md)
  big_spheres         what big spheres and size spread cost the stepper
  event_big_spheres   the same for the event engine
  auto_cells          the automatic cell grid against manual grids
  initial_states      time and structure of the generated initial states
  python_overhead     the Python module's loop against the CLI's
  lammps_speed        lmp_hs against the standalone, serial variants and 2 ranks
  lammps_scaling      serial against 2 ranks, weak scaling and the uncoupled-runs ceiling
  lammps_work_counts  instructions (callgrind) and MPI traffic per rank
  mpi_model           a model of the owned + ghost path on many ranks (no run)
"""
