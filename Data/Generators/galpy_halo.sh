#!/bin/bash
# Generate a large particle dataset with Debian's galpy: a Milky-Way-like NFW
# dark-matter halo (scale radius 16 kpc, 1e12 Msun inside 20 scale radii)
# sampled from its isotropic self-consistent distribution function, written
# as legacy VTK binary polydata by galpy_halo.py.
#
# Usage: galpy_halo.sh OUTPUT.vtk [N]
#   N  number of particles (default 1000000)
# Environment:
#   GALPY_HALO_SEED  random seed (default 1)
#
# Writes OUTPUT.vtk and OUTPUT.vtk.provenance.txt. If OUTPUT.vtk exists it is
# kept as a cache and nothing runs: delete it to regenerate.
set -euo pipefail

if [[ $# -lt 1 || $# -gt 2 ]]; then
  sed -n '2,13p' "$0" >&2
  exit 2
fi
output=$1
n=${2:-1000000}
seed=${GALPY_HALO_SEED:-1}
here=$(cd "$(dirname "$0")" && pwd)
source "$here/sampler_common.sh"

sampler_start "$output" "$n" "$seed" GALPY_HALO_SEED
galpy_version=$(/usr/bin/python3 -c 'import galpy; print(galpy.__version__)' 2>/dev/null) \
  || { echo "galpy not importable by /usr/bin/python3 (Debian package 'python3-galpy')" >&2; exit 1; }

sampler_run /usr/bin/python3 "$here/galpy_halo.py" --n "$n" --seed "$seed"
sampler_provenance "Data/Generators/galpy_halo.sh (sampler galpy_halo.py)" \
  "galpy: $galpy_version" \
  "debian package: python3-galpy $(dpkg-query -W -f='${Version}' python3-galpy 2>/dev/null || echo unknown)" \
  "particles: $n, seed: $seed" \
  "sampled: $summary" \
  "wall time covers: sampling, neighbour search and writing"
echo "wrote $output ($n particles, ${seconds} s)"
