"""Bad inputs end with a LAMMPS error naming what to change: the offending command or value and
the fix's advice, exactly. The cases, their decks and messages are in errors.yaml; under --np 2
the cases marked mpi run (error->all must stop every rank the same way). Each case prints its
name with the first ERROR line."""
from tests.lammps.lammps_runner import Cases, main

cases = Cases(__file__)


def joined(text):
    return "".join(text) if isinstance(text, list) else text


for name, entry in cases.spec["cases"].items():
    entry["function"] = "refused"
    if not entry["mpi"]:
        entry["only"] = "serial"
    entry["quantities"] = {"exit status": {"above": 0}, "error": {"contains": joined(entry["error"])}}


@cases.case
def refused(ctx, case):
    ctx.state("init.data", "--n", 100, "--phi", 0.2)
    out = ctx.lammps(case.get("deck", "errors/gas.lmp"), vars=dict(data="init.data", **case.get("vars", {})),
                     commands=joined(case["commands"]), expect_ok=False)
    return {"exit status": abs(out.returncode), "error": (out.errors or ["(no ERROR line)"])[0]}, {}


if __name__ == "__main__":
    raise SystemExit(main(cases))
