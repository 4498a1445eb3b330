# shellcheck shell=bash
# Private apt configuration for Debian *source* packages, shared by fetch_lammps_source.sh and
# build_lammps.sh (source this file; it defines functions only and runs nothing).
#
# The configuration lives in a directory of its own (sources list with deb-src lines, package
# lists, download cache), so /etc/apt and the system's package lists are never touched.
#
#   hs_private_apt DIR SUITE OWNER   # writes DIR/sources.list (deb-src for SUITE, plus
#                                    # SUITE-updates where Debian has one) and fills the array
#                                    # HS_APT_OPTS with the -o options that point apt there;
#                                    # OWNER names the calling script in the list's comment
#   apt-get "${HS_APT_OPTS[@]}" update
#   apt-cache "${HS_APT_OPTS[@]}" showsrc PACKAGE
#
# HS_DEBIAN_MIRROR overrides the mirror (default http://deb.debian.org/debian).

hs_private_apt() {
  local dir=$1 suite=$2 owner=$3
  local mirror=${HS_DEBIAN_MIRROR:-http://deb.debian.org/debian}
  mkdir -p "$dir/lists/partial" "$dir/archives/partial" "$dir/sources.list.d"
  {
    echo "# private to hardsphere/scripts/$owner; not used by the system's apt"
    echo "deb-src $mirror $suite main"
    # The development suites have no -updates suite (apt-get update would fail on it).
    case $suite in
      sid | unstable | experimental | rc-buggy) ;;
      *) echo "deb-src $mirror $suite-updates main" ;;
    esac
  } >"$dir/sources.list"
  # shellcheck disable=SC2034  # used by the scripts that source this file
  HS_APT_OPTS=(
    -o "Dir::Etc::SourceList=$dir/sources.list"
    -o "Dir::Etc::SourceParts=$dir/sources.list.d"
    -o "Dir::State::Lists=$dir/lists"
    -o "Dir::Cache=$dir"
    -o "Dir::Cache::archives=$dir/archives"
    -o "Dir::Cache::pkgcache="
    -o "Dir::Cache::srcpkgcache="
    -o "APT::Sandbox::User=$(id -un)"
    -o "Acquire::Languages=none"
    -q
  )
}
