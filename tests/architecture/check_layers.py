#!/usr/bin/env python3
"""Fails when an #include runs up a layer (docs/dev/architecture.md, "Source tree and layers").

Private headers live in standalone/src/<layer>/ and are included by their owner's name
("stepper/list_guard.hpp"); public headers in standalone/include/hardsphere/ belong to a layer
each (PUBLIC below). A file may include its own layer and the layers below it only. The CLI, the
LAMMPS styles and the Python module (python/src/) are adapters: they see public headers only.
"""
import argparse
import re
import sys
from pathlib import Path

# Each layer and the layers it may use (besides itself).
BELOW = {
    "common": set(),
    "scene": {"common"},
    "kernel": {"common"},
    "stepper": {"common", "scene", "kernel"},
    "event": {"common", "scene", "kernel"},
    "init": {"common", "scene", "kernel", "stepper", "event"},
    "io": {"common", "scene"},
    "run": {"common", "scene", "kernel", "stepper", "event", "init", "io"},
}
PUBLIC = {
    "vec3.hpp": "common", "precision.hpp": "common", "errors.hpp": "common", "limits.hpp": "common", "rng.hpp": "common",
    "format.hpp": "common", "collision_totals.hpp": "common",
    "box.hpp": "scene", "particles.hpp": "scene", "scene_limits.hpp": "scene", "observables.hpp": "scene",
    "physics.hpp": "scene", "wall_shapes.hpp": "scene", "transport.hpp": "scene",
    "collision.hpp": "kernel", "contact_law.hpp": "kernel",
    "stepper.hpp": "stepper", "state_exchange.hpp": "stepper",
    "event_engine.hpp": "event",
    "init.hpp": "init",
    "atomic_file.hpp": "io", "lammps_io.hpp": "io", "run_summary.hpp": "io",
    "simulation.hpp": "run",
}
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)


def layer_of(include):
    """The layer an include names, or None for a header outside the library."""
    if include.startswith("hardsphere/"):
        return PUBLIC.get(include[len("hardsphere/"):], "?public")
    head = include.split("/")[0]
    return head if "/" in include and head in BELOW else None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", required=True, help="repository root")
    root = Path(ap.parse_args().root)
    src, pub = root / "standalone/src", root / "standalone/include/hardsphere"
    problems = []
    files = []  # (path, layer of the file or "adapter")
    for p in sorted(src.rglob("*.[ch]pp")):
        layer = p.relative_to(src).parts[0]
        if layer not in BELOW or len(p.relative_to(src).parts) != 2:
            problems.append(f"{p}: not in a layer folder standalone/src/<{'|'.join(BELOW)}>/")
            continue
        files.append((p, layer))
    for p in sorted(pub.glob("*.hpp")):
        if p.name not in PUBLIC:
            problems.append(f"{p}: public header without a layer (add it to PUBLIC in {__file__})")
            continue
        files.append((p, PUBLIC[p.name]))
    for d in ("standalone/cli", "plugin", "python/src"):
        files += [(p, "adapter") for p in sorted((root / d).glob("*.[ch]*")) if p.suffix in (".cpp", ".hpp", ".h")]
    for path, layer in files:
        for inc in INCLUDE.findall(path.read_text()):
            target = layer_of(inc)
            if layer == "adapter":
                if target is not None and not inc.startswith("hardsphere/"):
                    problems.append(f"{path}: includes the private header \"{inc}\"; adapters see public headers only")
                elif target == "?public":
                    problems.append(f"{path}: includes \"{inc}\", which is not a public header")
                continue
            if target is None:
                if (path.parent / inc).exists() or any((src / l / inc).exists() for l in BELOW):
                    problems.append(f"{path}: includes \"{inc}\" without its layer (write \"<layer>/{inc}\")")
                continue
            if target == "?public":
                problems.append(f"{path}: includes \"{inc}\", which is not a public header")
            elif target != layer and target not in BELOW[layer]:
                problems.append(f"{path}: layer '{layer}' includes \"{inc}\" of layer '{target}', which is above it")
    for m in problems:
        print(m)
    print(f"{len(files)} files checked, {len(problems)} layer violations")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
