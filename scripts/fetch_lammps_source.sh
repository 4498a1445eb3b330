#!/usr/bin/env bash
# Fetches the LAMMPS source tree that exactly matches the installed Debian liblammps, so the
# hardsphere LAMMPS styles can be compiled against LAMMPS's own headers (Debian's
# /usr/include/lammps is not self-contained: it lacks the bundled fmt and e.g. neigh_request.h).
#
# Uses Debian's source package (`apt-get source lammps`) through a *private* apt configuration
# (its own sources list with a deb-src line for this system's suite, its own lists/cache dirs),
# so /etc/apt and the system's package lists are never touched. The unpacked tree is cached
# outside the repository and reused; nothing from LAMMPS is ever written into this repository.
#
#   bash scripts/fetch_lammps_source.sh          # prints the path of LAMMPS's src/ directory
#   HS_LAMMPS_CACHE=/some/dir bash scripts/...   # cache elsewhere
#
# Exit status: 0 and the path of src/ on stdout; non-zero with a message on stderr if the
# installed LAMMPS is unknown or the source cannot be fetched.
set -euo pipefail

log() { echo "fetch_lammps_source: $*" >&2; }

pkg=liblammps0
version=$(dpkg-query -W -f='${source:Version}' "$pkg" 2>/dev/null || true)
src_pkg=$(dpkg-query -W -f='${source:Package}' "$pkg" 2>/dev/null || true)
if [ -z "$version" ] || [ -z "$src_pkg" ]; then
  log "package $pkg is not installed (apt-get install liblammps-dev); nothing to match"
  exit 1
fi

cache_root=${HS_LAMMPS_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/hardsphere/lammps-src}
safe_version=${version//[:\/]/_}
tree=$cache_root/$safe_version
stamp=$tree/.hardsphere-source-version

if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$src_pkg $version" ] && [ -f "$tree/lammps/src/version.h" ]; then
  echo "$tree/lammps/src"
  exit 0
fi

# The suite of this system (e.g. bookworm): the deb-src entry must match the installed binaries.
suite=""
if [ -r /etc/os-release ]; then
  # shellcheck disable=SC1091
  suite=$(. /etc/os-release && echo "${VERSION_CODENAME:-}")
fi
if [ -z "$suite" ]; then
  log "cannot determine the Debian suite from /etc/os-release"
  exit 1
fi
# shellcheck source=scripts/private_apt.sh
. "$(dirname "${BASH_SOURCE[0]}")/private_apt.sh"
apt_dir=$cache_root/apt
mkdir -p "$tree"
hs_private_apt "$apt_dir" "$suite" fetch_lammps_source.sh
apt_opts=("${HS_APT_OPTS[@]}")
mirror=${HS_DEBIAN_MIRROR:-http://deb.debian.org/debian}

log "fetching Debian source $src_pkg $version for $suite into $tree"
if ! apt-get "${apt_opts[@]}" update >&2; then
  log "apt-get update with the private deb-src list failed (no network to $mirror?)"
  exit 1
fi

work=$(mktemp -d "$tree/fetch.XXXXXX")
trap 'rm -rf "$work"' EXIT
# apt-get source unpacks with dpkg-source; the signature check needs no keyring setup here
# because the .dsc hashes are verified against the signed Release file of the private lists.
if ! (cd "$work" && apt-get "${apt_opts[@]}" source --only-source "$src_pkg=$version" >&2); then
  log "apt-get source $src_pkg=$version failed; is that version still in $mirror $suite?"
  exit 1
fi
unpacked=$(find "$work" -mindepth 1 -maxdepth 1 -type d -name "$src_pkg-*" | head -n1)
if [ -z "$unpacked" ] || [ ! -f "$unpacked/src/version.h" ]; then
  log "the unpacked source has no src/version.h"
  exit 1
fi

# Keep what out-of-tree styles compile against (src/ with the bundled fmt, cmake/) and drop
# the rest (examples, docs, potentials, tarballs) to keep the cache small.
rm -rf "$tree/lammps"
mkdir -p "$tree/lammps"
mv "$unpacked/src" "$tree/lammps/src"
[ -d "$unpacked/cmake" ] && mv "$unpacked/cmake" "$tree/lammps/cmake"
[ -d "$unpacked/debian" ] && mv "$unpacked/debian" "$tree/lammps/debian"
echo "$src_pkg $version" >"$stamp"

# Cross-check: the headers' version string must be the installed library's.
src_date=$(sed -n 's/^#define LAMMPS_VERSION "\(.*\)"/\1/p' "$tree/lammps/src/version.h")
log "LAMMPS source version.h: '$src_date' (Debian $version)"
echo "$tree/lammps/src"
