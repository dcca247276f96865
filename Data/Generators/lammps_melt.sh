#!/bin/bash
# Generate a large particle dataset with Debian's LAMMPS: a binary
# Lennard-Jones fcc crystal whose core has melted (lammps_melt.in), converted
# to legacy VTK binary polydata by lammps_dump_to_vtk.py.
#
# Usage: lammps_melt.sh OUTPUT.vtk [NCELLS]
#        lammps_melt.sh OUTPUT.dump [NCELLS]   (a time series: the whole run as a text
#        dump of every LAMMPS_DUMP_EVERY steps, for the plugin's LAMMPS reader)
#   NCELLS  fcc unit cells per box edge, 4*NCELLS^3 atoms (default 63: 1,000,188)
# Environment:
#   LAMMPS_NP     MPI ranks (default: number of cores; 1 runs lmp without mpirun)
#   LAMMPS_STEPS  NVE steps (default 150)
#   LAMMPS_DUMP_EVERY  steps between the snapshots of a .dump series (default 10)
#
# Writes OUTPUT and OUTPUT.provenance.txt. If OUTPUT exists it is
# kept as a cache and nothing runs: delete it to regenerate.
set -euo pipefail

if [[ $# -lt 1 || $# -gt 2 ]]; then
  sed -n '2,16p' "$0" >&2
  exit 2
fi
output=$1
ncells=${2:-63}
steps=${LAMMPS_STEPS:-150}
np=${LAMMPS_NP:-$(nproc)}
here=$(cd "$(dirname "$0")" && pwd)
every=0
[[ "$output" == *.dump ]] && every=${LAMMPS_DUMP_EVERY:-10}

if [[ -e "$output" ]]; then
  echo "$output exists, not regenerated"
  exit 0
fi
[[ "$ncells" =~ ^[1-9][0-9]*$ ]] || { echo "NCELLS must be a positive integer" >&2; exit 2; }
command -v lmp >/dev/null || { echo "lmp not found (Debian package 'lammps')" >&2; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work" "$output.part"' EXIT

# Run the simulator as an MPI job of its own: a caller that is itself an MPI process
# (pvpython and pvbatch start one) hands down its Open MPI and PMIx variables, with which
# mpirun and the simulator fail before they start.
for v in $(compgen -e); do
  case "$v" in OMPI_* | PMIX_* | OPAL_* | PRTE_*) unset "$v" ;; esac
done

# MPI ranks split the box (measured, 1M atoms on 2 cores: 2 ranks run 1.9x as
# fast as 1); -sf opt selects the OPT package's lj/cut, about 10 % faster.
lmp_cmd=(lmp -sf opt)
if [[ "$np" -gt 1 ]] && command -v mpirun >/dev/null; then
  lmp_cmd=(mpirun --allow-run-as-root -np "$np" "${lmp_cmd[@]}")
fi
lmp_cmd+=(-nocite -in "$here/lammps_melt.in" -log "$work/log.lammps" -screen none
          -var ncells "$ncells" -var steps "$steps" -var dump "$work/melt.dump"
          -var every "$every" -var series "$output.part")

start=$(date +%s)
"${lmp_cmd[@]}" || { tail -n 20 "$work/log.lammps" >&2; exit 1; }
# Write to a temporary name first so an interrupted run never leaves a
# half-written file that the cache check above would accept.
if [[ "$every" -gt 0 ]]; then
  summary="text dump series, $(grep -c '^ITEM: TIMESTEP' "$output.part") snapshots every $every steps"
else
  summary=$(/usr/bin/python3 "$here/lammps_dump_to_vtk.py" "$work/melt.dump" "$output.part")
fi
mv "$output.part" "$output"
seconds=$(( $(date +%s) - start ))

atoms=$(sed -n 's/^Created \([0-9]*\) atoms.*/\1/p' "$work/log.lammps")
{
  echo "file: $(basename "$output")"
  echo "generator: Data/Generators/lammps_melt.sh (input lammps_melt.in, converter lammps_dump_to_vtk.py)"
  echo "lammps: $(head -n 1 "$work/log.lammps")"
  echo "debian package: lammps $(dpkg-query -W -f='${Version}' lammps 2>/dev/null || echo unknown)"
  echo "command: ${lmp_cmd[*]}" | sed "s#$work/##g"
  echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "host cores: $(nproc), MPI ranks: $np"
  echo "atoms: $atoms (fcc cells per edge: $ncells, NVE steps: $steps)"
  echo "converted: $summary"
  echo "wall time: ${seconds} s (simulation + conversion)"
} > "$output.provenance.txt"
echo "wrote $output ($atoms atoms, ${seconds} s)"
