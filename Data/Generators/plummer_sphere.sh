#!/bin/bash
# Generate a large clustered particle dataset: a Plummer sphere (a model star
# cluster, N-body units G = M = 1, scale length a = 1, truncated at 20 a)
# sampled with numpy by plummer_sphere.py, written in chunks as legacy VTK
# binary polydata. Up to 1e8 particles fit in a few GB of memory.
#
# Usage: plummer_sphere.sh OUTPUT.vtk [N]
#   N  number of particles (default 1000000, at most 1073741823)
# Environment:
#   PLUMMER_SEED  random seed (default 1)
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
seed=${PLUMMER_SEED:-1}
here=$(cd "$(dirname "$0")" && pwd)
source "$here/sampler_common.sh"

sampler_start "$output" "$n" "$seed" PLUMMER_SEED
numpy_version=$(/usr/bin/python3 -c 'import numpy; print(numpy.__version__)' 2>/dev/null) \
  || { echo "numpy not importable by /usr/bin/python3 (Debian package 'python3-numpy')" >&2; exit 1; }

sampler_run /usr/bin/python3 "$here/plummer_sphere.py" --n "$n" --seed "$seed"
sampler_provenance "Data/Generators/plummer_sphere.sh (sampler plummer_sphere.py)" \
  "python: $(/usr/bin/python3 -c 'import platform; print(platform.python_version())')" \
  "numpy: $numpy_version" \
  "debian package: python3-numpy $(dpkg-query -W -f='${Version}' python3-numpy 2>/dev/null || echo unknown)" \
  "particles: $n, seed: $seed" \
  "sampled: $summary" \
  "wall time covers: sampling and writing"
echo "wrote $output ($n particles, ${seconds} s)"
