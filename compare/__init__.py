"""hardsphere's Python side: validation against theory and other engines, the figures of the
documentation, and the readers of LAMMPS files that every Python program of the project uses.

Run an entry point from the repository root as `python3 -m compare.NAME ...` (--help for each).
Every one goes through compare.harness: the same options (--build DIR, --hardsphere PATH,
--lmp-hs PATH, --out DIR, --work DIR), the same log and the same exit status (0 passed, 1 a check
failed, 2 refused input, 3 a program or the script failed). The reports go to --out as NAME.md and
NAME.json (docs/reports/, indexed with their headlines by compare.headlines).

Validations (each writes a report and exits 1 when a check fails):
  accuracy            run time against error, the event engine as reference; eos, speed
                      (docs/reports/event_engine/)
  brownian            a heavy sphere's diffusion against Enskog (docs/reports/validation/brownian.md)
  cooling             a granular gas against Haff's law in every engine (docs/reports/validation/cooling.md)
  cross_validate      the same states through every engine (docs/reports/validation/cross_validation.md)
  granular_figures    gravity, walls and inelastic collisions (docs/reports/validation/granular.md)
  dem_scenes          LAMMPS's granular examples, soft and converted to hard spheres
                      (docs/reports/validation/dem_scenes.md)
  hcs                 the homogeneous cooling state's a2 (docs/reports/validation/hcs.md)
  rough_hcs           rough spheres' homogeneous cooling against kinetic theory (.../rough_hcs.md)
  rough_cooling_soft  a rough gas against LAMMPS and LIGGGHTS frictional soft spheres
                      (.../rough_cooling_soft.md)
  seed_figures        the seed paper's figures (docs/reports/validation/seed_figures.json)
  transport           D, eta and lambda against Enskog and DynamO (docs/reports/validation/transport.md)
Reports and figures from committed data (no simulation):
  docs_figures        the README's figures (docs/reports/figures/)
  headlines           docs/reports/README.md: every report with its headline result
Tools:
  big_sphere_scene    a data file of a gas with a few big spheres
  packing_structure   bond order and g(r) of a packing in a data file (docs/initial_states.md)
  plot_speeds         a data file's speed distribution against Maxwell-Boltzmann

Theory (formulas only, no runs):
  hard_sphere_theory  equations of state, contact values, Enskog rates and transport, the heavy
                      tracer, Haff's law, the cooling state's a2, the barometric height
  rough_theory        rough inelastic spheres: two-temperature cooling, Walton's friction
  soft_spheres        the soft-sphere force laws of the granular styles, Barker-Henderson shifts,
                      contact times, the damping for a restitution, the sticking limit beta0
Shared modules:
  harness             options, programs, log, reports, exit status of every entry point
  lammps_files        LAMMPS data files, text dumps and log lines: read and write
  machine_info        the machine and versions a report was made on
  crossval            the cross-validation's parts (plan, states, engines, observables, analysis,
                      report), used by cross_validate and cooling
  NAME_runs, NAME_report, NAME_figures   the runs, report text and figures of the entry point NAME
"""
