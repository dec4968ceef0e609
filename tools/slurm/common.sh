# Shared by the submit-* launchers: find the penumbra binary and sbatch, fail in one line.
# Sourced, not run.

die() { echo "${0##*/}: $*" >&2; exit 2; }

# The penumbra executable as an absolute path: $PENUMBRA if set, else the repository's
# build/penumbra next to this script, else penumbra on PATH. Job scripts get it as an
# argument, since sbatch runs a copy of the script from its spool directory.
find_penumbra() {
  local here candidate
  here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
  if [ -n "${PENUMBRA:-}" ]; then
    candidate=$PENUMBRA
  elif [ -x "$here/../../build/penumbra" ]; then
    candidate=$here/../../build/penumbra
  else
    candidate=$(command -v penumbra || true)
  fi
  [ -n "$candidate" ] && [ -x "$candidate" ] ||
    die "cannot find the penumbra executable: set PENUMBRA=/path/to/penumbra or build it (tools/setup)"
  case $candidate in
    /*) ;;
    */*) candidate=$(cd "$(dirname "$candidate")" && pwd)/$(basename "$candidate") ;;
    *) candidate=$(command -v "$candidate") ;;
  esac
  echo "$candidate"
}

command -v sbatch >/dev/null || die "sbatch not found: run this on a Slurm login node"

absolute() { case $1 in /*) echo "$1" ;; *) echo "$PWD/$1" ;; esac; }
