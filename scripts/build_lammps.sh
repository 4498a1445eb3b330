#!/usr/bin/env bash
# Builds a newer LAMMPS release from a newer Debian suite's source package, for checking the
# hardsphere styles as a plugin (`plugin load hardsphereplugin.so`) in a stock `lmp`.
#
#   bash scripts/build_lammps.sh VERSION        # prints the install prefix (PREFIX/bin/lmp)
#   bash scripts/build_lammps.sh --refresh sid  # re-ask the mirror what sid provides now
#
# VERSION: a Debian suite whose `lammps` source package to build (trixie, sid; `newest` is sid)
# or the LAMMPS version date one of them provides (20250204 is trixie's). Tested: trixie, sid.
#
# The source is the orig tarball of Debian's source package, downloaded through a private apt
# configuration (scripts/private_apt.sh: its own deb-src list and package lists, so /etc/apt
# and the system's lists are never touched) and checked against the SHA-256 in the suite's
# signed Sources index. The Debian packaging (debian/ patches) is not applied: it only adds
# Debian's potentials path and documentation build, and the mirror need not carry it.
#
# Cache, outside the repository: ${HS_LAMMPS_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/hardsphere}/
#   lammps-DATE/source/     the unpacked LAMMPS tree (source/src: headers for out-of-tree styles,
#                           source/python: its Python module, for PYTHONPATH; examples, docs,
#                           benchmarks and potentials are dropped)
#   lammps-DATE/build/      the CMake build directory (kept: an interrupted build resumes)
#   lammps-DATE/prefix/     the install prefix: bin/lmp, lib/liblammps.so, include/lammps,
#                           lib/cmake/LAMMPS
#   lammps-DATE/build.log   configure, build and install output
#   lammps-DATE/stamp       written last, after the installed lmp passed its checks; a cache
#                           without it (or with another recipe in it) is rebuilt, never used
#   lammps-SUITE            symlink to lammps-DATE, so `build_lammps.sh trixie` needs no network
#                           once built (--refresh asks the mirror again)
#   apt-SUITE/              the private apt configuration and lists of that suite
# A second call with a complete cache prints the prefix and does nothing else.
#
# stdout: exactly one line, the install prefix; progress goes to stderr. Non-zero exit with a
# message on stderr on failure (the last lines of build.log for a failed build).
#
# Environment: HS_LAMMPS_CACHE (cache root), HS_DEBIAN_MIRROR (default deb.debian.org),
# HS_LAMMPS_JOBS (parallel compile jobs, default nproc), HS_LAMMPS_CCACHE=1 (compile through
# ccache, installing it; off by default: a fresh build with an empty ccache, as on CI, gains
# nothing, a repeated call is answered from this cache anyway and an interrupted build resumes in
# build/; it pays only when a lammps-DATE/ is deleted and built again on the same machine:
# ~1 min instead of 15-20 on 2 cores), HS_LAMMPS_VERBOSE=1 (the whole build output on stderr).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
log() { echo "build_lammps: $*" >&2; }
die() {
  log "error: $*"
  exit 1
}
usage() {
  sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'
}

refresh=0
while [ $# -gt 0 ]; do
  case $1 in
    --refresh) refresh=1 ;;
    -h | --help)
      usage
      exit 0
      ;;
    --) shift && break ;;
    -*) die "unknown option '$1' (see --help)" ;;
    *) break ;;
  esac
  shift
done
[ $# -eq 1 ] || {
  usage >&2
  exit 2
}
arg=$1
[ "$arg" = newest ] && arg=sid
# Suites searched for a version date, oldest first.
date_suites=(trixie sid)
if [[ $arg =~ ^[0-9]{8}$ ]]; then
  kind="date"
elif [[ $arg =~ ^[a-z][a-z-]*$ ]]; then
  kind="suite"
else
  die "VERSION '$arg' is neither a Debian suite (trixie, sid, newest) nor a date like 20250204"
fi

root=${HS_LAMMPS_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/hardsphere}
mkdir -p "$root"
root=$(cd "$root" && pwd -P)

# What a complete build is made of. Any change here (options, packages, checks) changes the
# recipe hash in the stamp and so rebuilds the caches made before it.
recipe_version=1
# Packages: GRANULAR (pair gran/*, granular, fix pour, fix wall/gran), PLUGIN (the `plugin`
# command), PYTHON (python, fix python/invoke), MOLECULE (atom_style bond, bond_style harmonic
# in the bonds check), RIGID (fix ehex). Everything else the checks use is in the core.
packages=(GRANULAR PLUGIN PYTHON MOLECULE RIGID)
# Styles the project's LAMMPS checks (tests/lammps, compare/, reference_inputs/lammps) use:
# each must be listed by `lmp -h`.
required_styles=(
  # fixes
  gravity wall/gran pour python/invoke deposit evaporate ehex efield spring spring/self
  temp/berendsen temp/rescale langevin viscous recenter momentum balance deform dt/reset
  wall/lj93 wall/reflect addforce aveforce setforce ave/time nve/sphere nve print
  # computes
  stress/atom com reduce pressure
  # pair, bond, atom, minimize, integrate and command styles
  gran/hooke gran/hertz/history granular soft lj/cut harmonic sphere bond hybrid fire cg respa
  plugin create_bonds rerun write_dump
)

cmake_options() { # $1 = lammps-DATE directory
  local d=$1
  opts=(
    -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_INSTALL_PREFIX="$d/prefix"
    -DCMAKE_INSTALL_LIBDIR=lib
    -DLAMMPS_INSTALL_RPATH=on
    -DBUILD_SHARED_LIBS=on
    -DBUILD_MPI=on
    -DBUILD_OMP=off
    -DLAMMPS_SIZES=smallbig
    -DPython_EXECUTABLE=/usr/bin/python3
    -DWITH_JPEG=off -DWITH_PNG=off -DWITH_FFMPEG=off
    -DDOWNLOAD_POTENTIALS=off
  )
  local p
  for p in "${packages[@]}"; do opts+=("-DPKG_$p=on"); done
}

recipe_hash() { # $1 = lammps-DATE directory
  cmake_options "$1"
  { echo "recipe $recipe_version"; printf '%s\n' "${opts[@]}" "${required_styles[@]}"; } |
    sha256sum | cut -c1-16
}

is_complete() { # $1 = lammps-DATE directory (or an alias symlink to one)
  local d=$1
  [ -f "$d/stamp" ] && [ -x "$d/prefix/bin/lmp" ] && [ -f "$d/source/src/lammpsplugin.h" ] || return 1
  grep -qx "recipe $(recipe_hash "$(cd "$d" && pwd -P)")" "$d/stamp"
}

print_prefix() { # $1 = lammps-DATE directory (or an alias symlink to one)
  echo "$(cd "$1" && pwd -P)/prefix"
}

# --- fast path: a complete cache needs neither the network nor a lock ---------------------------
if [ "$kind" = date ] && is_complete "$root/lammps-$arg"; then
  print_prefix "$root/lammps-$arg"
  exit 0
fi
if [ "$kind" = suite ] && [ $refresh = 0 ] && [ -L "$root/lammps-$arg" ] && is_complete "$root/lammps-$arg"; then
  print_prefix "$root/lammps-$arg"
  exit 0
fi

# --- resolve VERSION to a Debian version of the lammps source package -----------------------------
# shellcheck source=scripts/private_apt.sh
. "$here/private_apt.sh"
mirror=${HS_DEBIAN_MIRROR:-http://deb.debian.org/debian}

command -v apt-get >/dev/null || die "apt-get not found: this script needs Debian's apt"
lists_updated=()
suite_apt() { # $1 = suite: sets HS_APT_OPTS for it, updating its lists once per call of the script
  local s=$1 u
  hs_private_apt "$root/apt-$s" "$s" build_lammps.sh
  for u in "${lists_updated[@]}"; do [ "$u" = "$s" ] && return 0; done
  log "reading the $s source index from $mirror (private apt lists in $root/apt-$s)"
  if ! apt-get "${HS_APT_OPTS[@]}" update >&2; then
    die "apt-get update for suite '$s' failed (no network to $mirror, or no such suite?)"
  fi
  lists_updated+=("$s")
}
suite_versions() { # the versions of the lammps source package in the suite of the last suite_apt
  apt-cache "${HS_APT_OPTS[@]}" showsrc --only-source lammps 2>/dev/null |
    sed -n 's/^Version: //p' | sort -u
}
newest_of() { # stdin: Debian versions; stdout: the newest by dpkg's ordering
  local best="" v
  while read -r v; do
    [ -n "$v" ] || continue
    if [ -z "$best" ] || dpkg --compare-versions "$v" gt "$best"; then best=$v; fi
  done
  echo "$best"
}

suite="" deb_version=""
if [ "$kind" = suite ]; then
  suite=$arg
  suite_apt "$suite"
  deb_version=$(suite_versions | newest_of)
  [ -n "$deb_version" ] || die "suite '$suite' has no lammps source package"
else
  for s in "${date_suites[@]}"; do
    suite_apt "$s"
    deb_version=$(suite_versions | grep "^$arg" | newest_of || true)
    if [ -n "$deb_version" ]; then
      suite=$s
      break
    fi
  done
  [ -n "$deb_version" ] || die "no suite of ${date_suites[*]} has lammps $arg (see apt-cache showsrc lammps)"
fi
date=${deb_version:0:8}
[[ $date =~ ^[0-9]{8}$ ]] || die "Debian version '$deb_version' of lammps in $suite does not start with a date"
dir=$root/lammps-$date
log "LAMMPS $date: Debian lammps $deb_version from $suite"

make_alias() {
  [ "$kind" = suite ] || return 0
  ln -sfn "lammps-$date" "$root/.lammps-$suite.tmp"
  mv -Tf "$root/.lammps-$suite.tmp" "$root/lammps-$suite"
}

# One build of a version at a time; another call waits, then finds the cache complete.
mkdir -p "$dir"
exec 9>"$dir/.lock"
if ! flock -n 9; then
  log "waiting for another build of LAMMPS $date to finish ($dir)"
  flock 9
fi
if is_complete "$dir"; then
  make_alias
  print_prefix "$dir"
  exit 0
fi

# --- build dependencies -----------------------------------------------------------------------------
deps=(cmake make g++ openmpi-bin libopenmpi-dev python3-dev xz-utils)
ccache=${HS_LAMMPS_CCACHE:-0}
[ "$ccache" = 1 ] && deps+=(ccache)
bash "$here/apt_install_missing.sh" build_lammps "${deps[@]}" >&2 ||
  die "could not install the build dependencies ${deps[*]}"

# --- source -------------------------------------------------------------------------------------------
rm -f "$dir/stamp" # from here on the cache is incomplete until the stamp is written again
cleanup=()
trap 'rm -rf "${cleanup[@]}"' EXIT
if [ "$(cat "$dir/source/.hardsphere-source" 2>/dev/null || true)" != "$deb_version" ]; then
  suite_apt "$suite"
  # The orig tarball's directory, name and SHA-256 from the (signed) Sources index.
  read -r pool file sha < <(
    apt-cache "${HS_APT_OPTS[@]}" showsrc --only-source lammps | awk -v want="$deb_version" '
      BEGIN { RS = ""; FS = "\n" }
      {
        ver = ""; pool = ""; file = ""; sha = ""; sec = 0
        for (i = 1; i <= NF; i++) {
          if ($i ~ /^Version: /) ver = substr($i, 10)
          else if ($i ~ /^Directory: /) pool = substr($i, 12)
          if ($i ~ /^Checksums-Sha256:/) { sec = 1; continue }
          if (sec && $i ~ /^ /) {
            split($i, a, " ")
            if (a[3] ~ /\.orig\.tar\./) { sha = a[1]; file = a[3] }
          } else sec = 0
        }
        if (ver == want && file != "") { print pool, file, sha; exit }
      }') || true
  [ -n "${sha:-}" ] || die "no orig tarball of lammps $deb_version in the $suite Sources index"
  dl=$(mktemp -d "$dir/download.XXXXXX")
  cleanup+=("$dl")
  log "downloading $file ($mirror/$pool)"
  /usr/lib/apt/apt-helper "${HS_APT_OPTS[@]}" download-file "$mirror/$pool/$file" "$dl/$file" "SHA256:$sha" >&2 ||
    die "download of $mirror/$pool/$file failed"
  echo "$sha  $dl/$file" | sha256sum -c --quiet - >&2 || die "$file does not match the SHA-256 of the Sources index"

  log "unpacking $file"
  unpack=$(mktemp -d "$dir/unpack.XXXXXX")
  cleanup+=("$unpack")
  tar -xf "$dl/$file" -C "$unpack" || die "could not unpack $file"
  # Debian's tarballs differ: trixie's has a top directory (lammps-4Feb2025/), sid's none.
  top=$unpack
  if [ ! -f "$top/cmake/CMakeLists.txt" ]; then
    top=$(find "$unpack" -mindepth 3 -maxdepth 3 -path '*/cmake/CMakeLists.txt' -printf '%h\n' | head -n1)
    top=${top%/cmake}
  fi
  if [ -z "$top" ] || [ ! -f "$top/cmake/CMakeLists.txt" ] || [ ! -f "$top/src/version.h" ]; then
    die "$file has no cmake/CMakeLists.txt and src/version.h"
  fi
  # Not needed to build or to compile styles against (~400 MB): examples, the documentation
  # sources (the man pages stay, `cmake --install` installs them), benchmark inputs and potential
  # files (their folders stay, empty, for the install rules).
  rm -rf "$top/examples"
  find "$top/doc" -mindepth 1 -maxdepth 1 ! -name '*.1' -exec rm -rf {} +
  find "$top/bench" "$top/potentials" -mindepth 1 -maxdepth 1 -exec rm -rf {} + 2>/dev/null || true
  echo "$deb_version" >"$top/.hardsphere-source"
  rm -rf "$dir/source" "$dir/build" "$dir/prefix" # a build dir of another source is not reused
  mv "$top" "$dir/source"
  rm -rf "$unpack" "$dl"
fi
lammps_version=$(sed -n 's/^#define LAMMPS_VERSION "\(.*\)"/\1/p' "$dir/source/src/version.h")
log "LAMMPS source: version.h '$lammps_version' in $dir/source"

# --- configure, build, install ------------------------------------------------------------------------
cmake_options "$dir"
hash=$(recipe_hash "$dir")
launcher=()
if [ "$ccache" = 1 ]; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
else
  # Clear a launcher an earlier HS_LAMMPS_CCACHE=1 run left in the CMake cache.
  launcher=(-UCMAKE_CXX_COMPILER_LAUNCHER -UCMAKE_C_COMPILER_LAUNCHER)
fi
jobs=${HS_LAMMPS_JOBS:-$(nproc)}
logf=$dir/build.log
fail() {
  log "error: $1 failed; last lines of $logf:"
  tail -n 40 "$logf" >&2
  exit 1
}
# Progress on stderr: the make percentage every 10 %, and warnings and errors; all in build.log.
progress() {
  if [ "${HS_LAMMPS_VERBOSE:-0}" = 1 ]; then
    tee -a "$logf" >&2
  else
    tee -a "$logf" | awk '
      /^\[ *[0-9]+%\]/ { match($0, /[0-9]+%/); p = substr($0, RSTART, RLENGTH - 1) + 0; if (p >= next_p) { print "build_lammps: [" p "%]"; fflush(); next_p = p - p % 10 + 10 } ; next }
      /error:|Error( [0-9]+|:)|CMake Error|warning:/ { print; fflush() }' >&2
  fi
}

{
  echo "=== $(date -u '+%F %T') LAMMPS $date ($deb_version, $suite), recipe $hash"
  echo "cmake -S $dir/source/cmake -B $dir/build ${opts[*]} ${launcher[*]}"
} >>"$logf"
log "configuring (${packages[*]}; log: $logf)"
mkdir -p "$dir/build"
cmake -S "$dir/source/cmake" -B "$dir/build" "${opts[@]}" "${launcher[@]}" 2>&1 | progress || fail "cmake configure"
start=$(date +%s)
via=""
[ "$ccache" = 1 ] && via=", through ccache"
log "building with $jobs jobs$via"
cmake --build "$dir/build" -j "$jobs" 2>&1 | progress || fail "the build"
log "built in $((($(date +%s) - start + 30) / 60)) min"
rm -rf "$dir/prefix"
cmake --install "$dir/build" 2>&1 | progress || fail "cmake --install"

# --- checks: the installed lmp runs, has the packages and styles, and knows `plugin load` ----------------
lmp=$dir/prefix/bin/lmp
help=$("$lmp" -h 2>&1) || {
  echo "$help" | tail -n 20 >&2
  die "$lmp -h failed"
}
pkgs=$(echo "$help" | sed -n '/^Installed packages:/,/^List of individual style options/p')
missing=()
for p in "${packages[@]}"; do echo "$pkgs" | tr -s '[:space:]' '\n' | grep -qx "$p" || missing+=("package $p"); done
tokens=$(echo "$help" | tr -s '[:space:]' '\n')
for s in "${required_styles[@]}"; do echo "$tokens" | grep -qxF "$s" || missing+=("style $s"); done
[ ${#missing[@]} = 0 ] || die "$lmp -h lacks: ${missing[*]}"
probe=$(mktemp -d)
cleanup+=("$probe")
printf 'plugin list\nplugin load %s/none.so\n' "$probe" >"$probe/in.probe"
out=$(cd "$probe" && { "$lmp" -log none -nocite -in in.probe 2>&1 || true; })
# `plugin list` answers, and `plugin load` of a missing file gets as far as dlopen().
{ echo "$out" | grep -q "Currently loaded plugins" && echo "$out" | grep -q "Open of file $probe/none.so failed"; } ||
  die "$lmp does not run 'plugin list' and 'plugin load': $(echo "$out" | tail -n 3)"

{
  echo "lammps $date debian $deb_version suite $suite version.h '$lammps_version'"
  echo "recipe $hash"
  echo "prefix $dir/prefix"
  echo "headers $dir/prefix/include/lammps $dir/source/src"
  echo "python $dir/source/python"
} >"$dir/stamp.tmp"
mv -f "$dir/stamp.tmp" "$dir/stamp"
make_alias
log "LAMMPS $date installed in $dir/prefix"
log "  headers for plugins: $dir/source/src (prefix/include/lammps lacks e.g. lammpsplugin.h, version.h)"
log "  its Python module (for the python command, fix python/invoke): PYTHONPATH=$dir/source/python"
print_prefix "$dir"
