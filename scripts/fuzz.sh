#!/usr/bin/env bash
# hardsphere fuzzing: builds the libFuzzer targets (tests/fuzz) with clang, ASan and UBSan in their
# own build directory and runs each for a bounded time from the committed seed corpus. Inputs that
# crash, hang, break an invariant or exhaust memory are saved as findings; libFuzzer keeps going
# after each (fork mode), so one run reports all it finds.
#   bash scripts/fuzz.sh [seconds-per-target] [target...]   default: 60 s each, targets read_data cli
# Environment: HS_FUZZ_BUILD_DIR (build-fuzz), HS_FUZZ_OUT_DIR (<build>/fuzz-out),
# HS_FUZZ_TIMEOUT (10 s per input), HS_FUZZ_JOBS (1 fuzzing process per target).
# A finding is replayed with the target and the file: build-fuzz/tests/fuzz/hs_fuzz_cli FILE.
# Keep it as tests/fuzz/regressions/<target>/NAME once fixed (ctest replays those), or under
# tests/fuzz/regressions/pending/<target>/ while the fix belongs elsewhere.
set -euo pipefail
secs=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(read_data cli)
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${HS_FUZZ_BUILD_DIR:-$root/build-fuzz}
out=${HS_FUZZ_OUT_DIR:-$build/fuzz-out}

bash "$root/scripts/apt_install_missing.sh" fuzz clang-14 libclang-rt-14-dev

cmake -S "$root" -B "$build" -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DHS_BUILD_FUZZ=ON -DHS_BUILD_TESTS=OFF -DHS_BUILD_BENCH=OFF -DHS_BUILD_PLUGIN=OFF >/dev/null
cmake --build "$build" -j"$(nproc)" --target "${targets[@]/#/hs_fuzz_}"

# Stack traces for UBSan findings too (ASan prints them by default).
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
status=0
summary=()
for t in "${targets[@]}"; do
  work=$out/corpus/$t
  findings=$out/findings/$t
  mkdir -p "$work" "$findings"
  log=$out/$t.log
  echo "fuzz: $t for ${secs} s (log $log)"
  # The working corpus grows in $work; the committed seeds are only read.
  "$build/tests/fuzz/hs_fuzz_$t" -max_total_time="$secs" -timeout="${HS_FUZZ_TIMEOUT:-10}" -rss_limit_mb=2048 \
    -max_len=8192 -dict="$root/tests/fuzz/$t.dict" -artifact_prefix="$findings/" \
    -fork="${HS_FUZZ_JOBS:-1}" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
    "$work" "$root/tests/fuzz/corpus/$t" >"$log" 2>&1 || true
  execs=$(grep -oE '^#[0-9]+' "$log" | tail -1 | tr -d '#')
  n=$(find "$findings" -type f | wc -l)
  summary+=("$t: ${execs:-0} executions in ${secs} s, $n findings in $findings")
  [ "$n" = 0 ] || status=1
done
printf 'fuzz: %s\n' "${summary[@]}"
exit $status
