"""The cross-validation's parts (compare.cross_validate runs them; compare.cooling reuses them):

  plan         states, engines, settings, run lengths and tolerances
  states       the equilibrated initial states (data files), cached by name
  engines      one state through one engine: runs and what they measured
  observables  observables of trajectory frames, the same code for every engine
  analysis     from one run to one result row; the agreement checks
  report       cross_validation.md and its figures
"""
