"""hardsphere: hard-sphere simulation from Python (docs/python.md).

    import hardsphere as hs
    s = hs.System.random(n=8000, phi=0.45, seed=1)
    sim = hs.Stepper(s, dt=0.01)
    sim.run(time=10.0)
    sim.observables()["compressibility_factor"]
"""
import numpy as _np

from ._hardsphere import Box, DumpWriter, EventEngine, Stepper, System
from .progress import progress_bar
from .render import render

__all__ = ["Box", "System", "Stepper", "EventEngine", "DumpWriter", "render", "progress_bar", "unwrapped_positions",
           "freud_box"]


def _run(self, steps=None, time=None, *, callback=None, every=None, progress=None, **engine_options):
    """Runs `steps` steps or simulated `time` (Stepper: steps = round(time / dt); EventEngine: time only).

    A run over the engine's work_limit is refused before it starts (ValueError, the CLI's message).
    EventEngine.run(..., blocks=20): the run is measured in that many blocks, as the CLI's --blocks,
    for the error bars in observables().

    The loop runs in C++ with the GIL released, in chunks; between chunks Ctrl-C raises
    KeyboardInterrupt and leaves the engine at the end of the last chunk, ready to run again.
    callback(sim) is called every `every` steps (Stepper) or every `every` of simulated time
    (EventEngine); returning False stops the run. progress: a callable(fraction, sim_time), or
    True for a tqdm bar (a line on stderr without tqdm).
    """
    bar = None
    if progress is True:
        bar = progress_bar()
        progress = bar.update
    try:
        self._run(steps=steps, time=time, callback=callback, every=every, progress=progress, **engine_options)
    finally:
        if bar is not None:
            bar.close()
    return self


def unwrapped_positions(obj):
    """(N, 3) float64 copy: positions + images * box lengths, continuous in time (for an MSD)."""
    lengths = _np.asarray(obj.box.lengths)
    return obj.positions + obj.images * lengths


def freud_box(obj):
    """freud's (box, points): ([Lx, Ly, Lz, 0, 0, 0], positions relative to the box centre).

    freud boxes are centred on the origin, so the points are shifted by the box centre (a copy).
    Works without freud installed: pass the tuple to freud.locality or freud.box.Box.from_box.
    """
    box = obj.box
    centre = (_np.asarray(box.lo) + _np.asarray(box.hi)) / 2
    lx, ly, lz = box.lengths
    return [lx, ly, lz, 0.0, 0.0, 0.0], obj.positions - centre


for _cls in (Stepper, EventEngine):
    _cls.run = _run
for _cls in (System, Stepper, EventEngine):
    _cls.freud_box = freud_box
    _cls.unwrapped_positions = property(unwrapped_positions, doc=unwrapped_positions.__doc__)
del _cls
