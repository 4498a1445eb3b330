"""hardsphere's Python side: validation against theory and other engines, the figures of the
documentation, and the readers of LAMMPS files that every Python program of the project uses.

Run an entry point from the repository root as `python3 -m compare.NAME ...` (--help for each):

  accuracy           run time against error, the event engine as reference (docs/event_engine.md)
  big_sphere_scene   a data file of a gas with a few big spheres
  brownian           a heavy sphere's diffusion against Enskog (docs/reports/validation/brownian.md)
  cooling            a granular gas against Haff's law in every engine (docs/reports/validation/cooling.md)
  cross_validate     the same states through every engine (docs/reports/validation/cross_validation.md)
  docs_figures       the README's figures (docs/reports/figures/) from committed data
  granular_figures   gravity, walls and inelastic collisions (docs/reports/validation/granular.md)
  hcs                the homogeneous cooling state's a2 (docs/reports/validation/hcs.md)
  packing_structure  bond order and g(r) of a packing in a data file (docs/initial_states.md)
  plot_speeds        a data file's speed distribution against Maxwell-Boltzmann
  seed_figures       the seed paper's figures (docs/reports/validation/seed_figures.json)

Shared modules:

  lammps_files       LAMMPS data files, text dumps and log lines: read and write
  hard_sphere_theory equations of state, contact values, Enskog collision rates
  soft_spheres       the soft-sphere force laws of the granular styles, Barker-Henderson shifts
  machine_info       the machine a report was made on
  crossval           the cross-validation's parts (plan, states, engines, observables, analysis,
                     report), used by cross_validate and cooling
"""
