"""What the cross-validation runs: states, engines, settings, run lengths, tolerances.

Stiffness is chosen by the Barker-Henderson shift it gives (sigma - d for a pair of unit
spheres), so every soft engine is swept over the same softness; the time step is the head-on
contact time at a relative speed of 6 (beyond 4 standard deviations) over steps_per_contact.
"""
import math
from dataclasses import dataclass, field

from scipy.optimize import brentq

from compare import soft_spheres as soft
from compare.crossval import states as xv_states

SOFT_ENGINES = ("lammps hooke", "lammps hertz", "liggghts hertz")
FAST_PAIR_SPEED = 6.0
DEFAULT_DT = 0.01  # the CLI's default time step


@dataclass
class State:
    n: int
    phi: float
    composition: str
    equilibrate: float
    path: object = None

    @property
    def msd_window(self):
        """Lags over which D is fitted: past a few mean free times (at 0.1 ~0.6 tau)."""
        return (1.0, 2.0) if self.phi < 0.2 else (0.5, 1.0)

    @property
    def label(self):
        return xv_states.name(self.n, self.phi, self.composition)

    @property
    def species(self):
        return xv_states.species(self.composition)


MODEL = {"lammps hooke": "hooke", "lammps hertz": "hertz_lammps", "liggghts hertz": "hertz_liggghts"}


def poisson(engine):
    return soft.POISSON_LIGGGHTS if engine == "liggghts hertz" else None


def bh_shift(engine, stiffness, reff=0.25):
    """Barker-Henderson shift of a pair (unit spheres: reff = 1/4) for the engine's stiffness parameter."""
    if engine == "lammps hooke":
        return soft.bh_shift_hooke(stiffness)
    if engine == "lammps hertz":
        return soft.bh_shift_hertz_lammps(stiffness, reff)
    return soft.bh_shift_hertz_liggghts(stiffness, soft.POISSON_LIGGGHTS, reff)


def stiffness_for_shift(engine, shift):
    """The stiffness parameter whose unit-pair Barker-Henderson shift is `shift`."""
    return math.exp(brentq(lambda lk: math.log(bh_shift(engine, math.exp(lk)) / shift), math.log(1e-3),
                           math.log(1e16)))


def contact_time(engine, stiffness, meff=0.5, reff=0.25):
    """Head-on contact time of a unit pair (Hertz: at the relative speed FAST_PAIR_SPEED)."""
    if engine == "lammps hooke":
        return soft.contact_time_hooke(stiffness, meff)
    k = soft.hertz_stiffness(MODEL[engine], stiffness, reff, poisson(engine))
    return soft.contact_time_hertz(k, meff, FAST_PAIR_SPEED)


def _steps(sim_time, dt, every):
    """Steps covering sim_time, rounded up to a multiple of `every`."""
    return max(every, int(math.ceil(sim_time / dt / every)) * every)


@dataclass
class Task:
    state: State
    engine: str  # 'event', 'stepper', 'lmp_hs', or one of SOFT_ENGINES
    sim_time: float
    dt: float = None
    precision: str = "double"
    ranks: int = 1
    shift: float = None  # soft: Barker-Henderson shift of a unit pair
    steps_per_contact: int = None
    reference: bool = False  # event engine's long run: the precise hard-sphere value
    cost: float = 1.0  # estimated seconds
    stiffness: float = None
    extra: dict = field(default_factory=dict)

    def __post_init__(self):
        if self.engine in SOFT_ENGINES:
            self.stiffness = stiffness_for_shift(self.engine, self.shift)
            self.dt = contact_time(self.engine, self.stiffness) / self.steps_per_contact
        self.cost = self.estimate()

    @property
    def kind(self):
        return "soft" if self.engine in SOFT_ENGINES else "hard"

    @property
    def label(self):
        if self.engine == "event":
            return "event engine" + (" (reference)" if self.reference else "")
        if self.engine == "stepper":
            return f"stepper {self.precision} dt={self.dt:g}"
        if self.engine == "lmp_hs":
            return f"lmp_hs fix hardsphere dt={self.dt:g} np={self.ranks}"
        return f"{self.engine} shift={self.shift:g} dt=tc/{self.steps_per_contact} np={self.ranks}"

    def steps(self, every=1):
        return _steps(self.sim_time, self.dt, every)

    def estimate(self):
        """Seconds, from rough speeds on this class of machine (only for the progress line)."""
        n = self.state.n
        if self.engine == "event":
            return n * self.sim_time * 10 / 1.5e6
        if self.engine == "stepper":
            return 8 * 0.05 + n * self.steps() / 2.5e7
        if self.engine == "lmp_hs":
            return 1 + n * self.steps() / 1e7
        speed = 1.0e7 if self.engine.startswith("lammps") else 4e6  # atom-steps per second, with output
        analysis = n * (65 + self.extra.get("contact_steps", 200)) / 2e6
        return 1 + analysis + n * self.steps() * (1.5 if self.state.composition == "binary" else 1.0) / speed

    def execute(self, engines, work):
        s = self.state.path
        if self.engine == "event":
            return engines.event(s, work, self.sim_time, blocks=32 if self.reference else 64)
        if self.engine == "stepper":
            return engines.stepper(s, work, self.dt, self.steps(64), self.precision, blocks=8, frames_per_block=8)
        if self.engine == "lmp_hs":
            nrun = self.steps(64)
            return engines.lmp_hardsphere(s, work, self.dt, nrun, self.ranks, dumpevery=nrun // 64,
                                          blocksteps=nrun // 8, skin=max(0.3, 6 * FAST_PAIR_SPEED / 2 * self.dt))
        nrun = self.steps(64)
        nequil = _steps(self.extra.get("equilibrate", 0.2), self.dt, 1)
        contact = min(nrun, self.extra.get("contact_steps", 200))
        return engines.soft(self.engine, s, work, self.dt, nrun, nequil, nrun // 64, nrun // 8, contact,
                            self.stiffness, self.ranks)


@dataclass
class Plan:
    states: list
    tasks: list
    tolerances: dict
    seed_figure_cost: float
    mode: str

    def describe(self):
        return dict(mode=self.mode, states=[s.label for s in self.states], runs=len(self.tasks))


TOLERANCES = dict(
    hard_z_sigmas=4.0,  # hard engines' Z: |Z_a - Z_b| <= 4 sqrt(err_a^2 + err_b^2) (exact-limit settings)
    soft_mapped_z=0.02,  # mapped soft Z within 2% of the hard-sphere value at the stiffest setting
    ks_p=6e-5,  # speeds against Maxwell-Boltzmann: KS p-value at least this (the two-sided 4-sigma tail)
    within=0.01,  # 'within_1pct': |Z / Z_ref - 1| <= 1%
)


def _hard_tasks(st, t_hard, t_ref, dts, lmp_ranks=(1, 2)):
    tasks = [Task(st, "event", t_ref, reference=True), Task(st, "event", t_hard)]
    for precision in ("double", "float"):
        tasks += [Task(st, "stepper", t_hard, dt=dt, precision=precision) for dt in dts]
    tasks += [Task(st, "lmp_hs", t_hard, dt=DEFAULT_DT, ranks=r) for r in lmp_ranks]
    return tasks


def _soft_tasks(st, shifts, t_soft, engines=SOFT_ENGINES, ranks=1, dt_check=None, contact_steps=200):
    tasks = []
    for e in engines:
        for sh in shifts:
            tasks.append(Task(st, e, t_soft, shift=sh, steps_per_contact=20, ranks=ranks,
                              extra=dict(contact_steps=contact_steps)))
        if dt_check is not None:
            tasks.append(Task(st, e, t_soft, shift=dt_check, steps_per_contact=40, ranks=ranks,
                              extra=dict(contact_steps=contact_steps)))
    return tasks


def quick_plan():
    st = State(1000, 0.3, "mono", equilibrate=2.0)
    tasks = _hard_tasks(st, t_hard=2.0, t_ref=20.0, dts=(0.02, DEFAULT_DT, 0.005))
    tasks += _soft_tasks(st, (0.02, 0.01), t_soft=1.0, contact_steps=100)
    return Plan([st], tasks, TOLERANCES, seed_figure_cost=8, mode="quick")


def full_plan():
    """N = 8000: every engine, stiffness sweeps on the one-species states; N = 64000: every engine,
    the soft ones at one stiffness."""
    states, tasks = [], []
    for composition in ("mono", "binary"):
        for phi in (0.1, 0.3, 0.45):
            st = State(8000, phi, composition, equilibrate=5.0)
            states.append(st)
            t_soft = 2 * st.msd_window[1]
            tasks += _hard_tasks(st, t_hard=4.0, t_ref=40.0, dts=(0.04, 0.02, DEFAULT_DT, 0.005, 0.0025))
            if composition == "mono":
                tasks += _soft_tasks(st, (0.04, 0.02, 0.01, 0.005, 0.0025, 0.00125), t_soft=t_soft,
                                    dt_check=0.01 if phi == 0.3 else None)
            else:
                tasks += _soft_tasks(st, (0.01,), t_soft=t_soft)
            if composition == "mono" and phi == 0.3:
                tasks += _soft_tasks(st, (0.01,), t_soft=t_soft, ranks=2)
    for composition in ("mono", "binary"):
        for phi in (0.1, 0.3, 0.45):
            st = State(64000, phi, composition, equilibrate=2.0)
            states.append(st)
            tasks += _hard_tasks(st, t_hard=4.0, t_ref=8.0, dts=(0.02, DEFAULT_DT))
            tasks += _soft_tasks(st, (0.01,), t_soft=2 * st.msd_window[1], contact_steps=50)
            if composition == "mono" and phi == 0.3:
                tasks += _soft_tasks(st, (0.01,), t_soft=2 * st.msd_window[1], ranks=2, contact_steps=50)
    return Plan(states, tasks, TOLERANCES, seed_figure_cost=180, mode="full")
