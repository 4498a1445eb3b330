#!/usr/bin/env bash
# hardsphere set-up: installs what is missing (Debian 12, apt), builds, then either runs the
# default simulation ("run") or the whole test suite ("test").
#   bash scripts/setup.sh run     # build + default simulation + speed-distribution plot
#   bash scripts/setup.sh test    # build + all tests (ctest)
set -euo pipefail
mode=${1:-run}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${HS_BUILD_DIR:-$root/build}

packages=(cmake g++ make libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev
          python3-numpy python3-scipy python3-matplotlib python3-pytest python3-yaml
          python3-pybind11 python3-dev python3-mdanalysis python3-tqdm)
# The test run checks that every C++ file is formatted (.clang-format).
[ "$mode" = test ] && packages+=(clang-format)
if [ "${HS_WITH_LAMMPS:-1}" = 1 ]; then
  packages+=(lammps liblammps-dev lammps-examples openmpi-bin libopenmpi-dev liggghts python3-lammps dpkg-dev)
fi
bash "$root/scripts/apt_install_missing.sh" setup "${packages[@]}"

# LAMMPS styles: compiled against the Debian LAMMPS source matching the installed liblammps
# (fetched once into a cache outside the repository); skipped if that is not possible.
lammps_args=()
if [ "${HS_WITH_LAMMPS:-1}" = 1 ] && dpkg-query -W -f='${Status}' liblammps-dev 2>/dev/null | grep -q "install ok installed"; then
  if lammps_src=$(bash "$root/scripts/fetch_lammps_source.sh"); then
    lammps_args=(-DLAMMPS_SOURCE_DIR="$lammps_src")
  else
    echo "setup: LAMMPS source not available; building without the LAMMPS styles" >&2
  fi
fi
# The test run also checks the styles as a plugin in the newest LAMMPS Debian's source packages
# offer (label lammps_versions): built once into a cache outside the repository (~20-30 min on 2
# cores the first time, then reused). HS_LAMMPS_VERSIONS: others to build as well (e.g.
# "trixie newest"), or "none".
if [ "$mode" = test ] && [ "${HS_WITH_LAMMPS:-1}" = 1 ]; then
  roots=()
  for v in ${HS_LAMMPS_VERSIONS:-newest}; do
    [ "$v" = none ] && continue
    if prefix=$(bash "$root/scripts/build_lammps.sh" "$v"); then
      roots+=("$prefix")
    else
      echo "setup: LAMMPS '$v' could not be built (above); its lammps_versions checks are skipped" >&2
    fi
  done
  lammps_args+=("-DHS_LAMMPS_ROOT=$(IFS=';'; echo "${roots[*]}")")
fi
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DHS_NATIVE=${HS_NATIVE:-ON} -DPython3_EXECUTABLE=/usr/bin/python3 "${lammps_args[@]}" >/dev/null
cmake --build "$build" -j"$(nproc)"

case "$mode" in
  run)
    out=${HS_OUT_DIR:-$root/results}
    mkdir -p "$out"
    "$build/standalone/hardsphere" run --n 4000 --phi 0.3 --init-speed 1.7320508075688772 --steps 2000 --dt 0.01 \
      --json "$out/summary.json" --write-data "$out/final.data" --dump "$out/trajectory.dump" --dump-every 500
    PYTHONPATH="$root" /usr/bin/python3 -m compare.plot_speeds "$out/final.data" "$out/speed_distribution.png"
    # The final state drawn by the Python module from the build tree (docs/python.md).
    if [ -f "$build/python/hardsphere/__init__.py" ] && ls "$build"/python/hardsphere/_hardsphere*.so >/dev/null 2>&1; then
      PYTHONPATH="$build/python" /usr/bin/python3 -c 'import sys, hardsphere as hs
hs.render(hs.System.from_data(sys.argv[1]), sys.argv[2], color="speed")' "$out/final.data" "$out/snapshot.png"
      snapshot=", snapshot.png"
    else
      echo "setup: the Python module was not built (python3-pybind11 missing?): no snapshot.png" >&2
      snapshot=""
    fi
    echo "setup: results in $out (summary.json, final.data, trajectory.dump, speed_distribution.png$snapshot)"
    ;;
  test)
    cd "$build" && ctest --output-on-failure -j"$(nproc)" ${HS_CTEST_ARGS:-}
    ;;
  *)
    echo "usage: $0 run|test" >&2
    exit 2
    ;;
esac
