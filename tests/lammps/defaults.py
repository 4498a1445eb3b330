"""Settings the fix makes itself: an input without 'neigh_modify every 1 delay 0 check yes' runs,
the fix sets those itself and says so once; the collisions are those with the explicit setting
and the standalone stepper's. With newton on the fix skips LAMMPS's reverse communication of
ghost forces during runs, says so once and restores the setting. Allowed fixes change nothing;
per-atom diameters work for mixed pairs, also after a restart.
Groups: neighbour, newton, allowed, mixture."""
import re

from tests.lammps.lammps_runner import Cases, main, thermo_rows

cases = Cases(__file__)


def reference(ctx):
    ctx.state("init.data", "--n", 500, "--phi", 0.3)
    return ctx.standalone("--read-data", "init.data", "--steps", 200, "--dt", 0.01)


@cases.case
def neighbour_lists(ctx, case):
    """Two runs with the neighbour settings of the case: the fix's note appears once over both
    (serial: LAMMPS checks its lists every step; the owned + ghost path on 2 ranks decides
    re-neighbouring itself and says so whatever the settings were)."""
    ref = reference(ctx)
    deck, neigh = case["deck"], case.get("neigh")
    out = ctx.lammps(deck, vars=dict(data="init.data", **({"neigh": neigh} if neigh else {})))
    notes = out.lines(case["note"]["mpi" if ctx.mpi else "serial"])
    default = lammps_neighbour_defaults(ctx)
    # Serial runs need 'every 1 delay 0 check yes': a LAMMPS whose default it is gets no note.
    default_notes = 1 if ctx.mpi or default != "every 1 delay 0 check yes" else 0
    note = notes[0] if notes else ""
    return {"collisions": out.last["f_hs[1]"], "notes": len(notes), "note": note,
            "note names LAMMPS's defaults": f"(were '{default}')" in note if default_notes else not note}, \
        dict(standalone=ref, default_notes=default_notes)


_NEIGHBOUR_DEFAULTS = {}  # per LAMMPS program: its defaults, asked once per process


def lammps_neighbour_defaults(ctx):
    """LAMMPS's own neighbour settings as the fix's note spells them ('every 1 delay 10 check yes'
    before LAMMPS 2022, 'every 1 delay 0 check yes' since), from the settings a run without the
    fix prints."""
    if ctx.lmp not in _NEIGHBOUR_DEFAULTS:
        text = ctx.lammps("defaults/lammps_neighbour_defaults.lmp", np=1).text
        m = re.search(r"update:? every =? ?(\d+) steps, delay =? ?(\d+) steps, check =? ?(\w+)", text)
        if not m:
            raise ValueError("no neighbour settings in LAMMPS's output")
        _NEIGHBOUR_DEFAULTS[ctx.lmp] = "every {} delay {} check {}".format(*m.groups())
    return _NEIGHBOUR_DEFAULTS[ctx.lmp]


@cases.case
def newton(ctx, case):
    ref = reference(ctx)
    out = ctx.lammps("defaults/newton.lmp", vars=dict(data="init.data"))
    before_after = out.text.split("after: newton")[0]  # the two runs with setup
    rows = thermo_rows(before_after)
    return {"notes": len(out.lines("ghost forces are not communicated back")),
            "newton during the runs": sorted({r["v_nw"] for r in rows}),
            "before the runs (write_data's init)": out.text, "after the runs": out.text,
            "after run pre no": out.text, "collisions": rows[-1]["f_hs[1]"]}, dict(standalone=ref)


@cases.case
def allowed_fixes(ctx, case):
    ref = reference(ctx)
    out = ctx.lammps("defaults/allowed_fixes.lmp", vars=dict(data="init.data"))
    return {"collisions": out.last["f_hs[1]"]}, dict(standalone=ref)


@cases.case
def heat_flow(ctx, case):
    """fix heat/flow with fix add/heat (LAMMPS 2025 on): per-atom temperatures grow by the added
    heat, 2 x 200 steps of 0.01 over specific heat 1 and mass 1, and the collisions are the
    standalone's (neither fix touches the motion)."""
    ref = reference(ctx)
    last = ctx.lammps("defaults/heat_flow.lmp", vars=dict(data="init.data", rate=2.0)).last
    return {"collisions": last["f_hs[1]"], "mean temperature": last["c_tmean"],
            "lowest temperature": last["c_tmin"]}, dict(standalone=ref)


@cases.case
def mixture_restart(ctx, case):
    """A mixture with per-atom diameters for type 1 ('pair_coeff 1 1') and 0.6 for type 2: the 1-2
    pair takes the per-atom diameters too (not a mix of the resolved 1 1 value), also after
    write_restart/read_restart."""
    first = ctx.lammps("defaults/mixture.lmp", expect_ok=False)
    second = ctx.lammps("defaults/mixture_restarted.lmp", expect_ok=False)
    got = {"exit status": first.returncode, "exit status after read_restart": second.returncode,
           "error": "\n".join(first.errors + second.errors)}
    got["collisions"] = first.last["f_hs[1]"] if first.rows else 0
    got["collisions after read_restart"] = second.last["f_hs[1]"] if second.rows else 0
    return got, {}


if __name__ == "__main__":
    raise SystemExit(main(cases))
