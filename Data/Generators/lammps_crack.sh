#!/bin/bash
# Generate a flat particle dataset with Debian's LAMMPS: a two-dimensional
# Lennard-Jones crystal slab with a notch, pulled apart until a crack opens
# from the notch tip (lammps_crack.in), converted to legacy VTK binary
# polydata by lammps_dump_to_vtk.py. Every atom has z = 0.
#
# Usage: lammps_crack.sh OUTPUT.vtk [SCALE]
#   SCALE  slab height in hex lattice cells, width 3*SCALE cells,
#          about 6*SCALE^2 atoms (default 230: 317,284 atoms)
# Environment:
#   LAMMPS_NP     MPI ranks (default: number of cores; 1 runs lmp without mpirun)
#   LAMMPS_STEPS  NVE steps (default 10000)
#
# Writes OUTPUT.vtk and OUTPUT.vtk.provenance.txt. If OUTPUT.vtk exists it is
# kept as a cache and nothing runs: delete it to regenerate.
set -euo pipefail

if [[ $# -lt 1 || $# -gt 2 ]]; then
  sed -n '2,15p' "$0" >&2
  exit 2
fi
output=$1
scale=${2:-230}
steps=${LAMMPS_STEPS:-10000}
np=${LAMMPS_NP:-$(nproc)}
here=$(cd "$(dirname "$0")" && pwd)

if [[ -e "$output" ]]; then
  echo "$output exists, not regenerated"
  exit 0
fi
[[ "$scale" =~ ^[1-9][0-9]*$ && "$scale" -ge 8 ]] || { echo "SCALE must be an integer >= 8" >&2; exit 2; }
command -v lmp >/dev/null || { echo "lmp not found (Debian package 'lammps')" >&2; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work" "$output.part"' EXIT

# Run the simulator as an MPI job of its own: a caller that is itself an MPI process
# (pvpython and pvbatch start one) hands down its Open MPI and PMIx variables, with which
# mpirun and the simulator fail before they start.
for v in $(compgen -e); do
  case "$v" in OMPI_* | PMIX_* | OPAL_* | PRTE_*) unset "$v" ;; esac
done

lmp_cmd=(lmp -sf opt)
if [[ "$np" -gt 1 ]] && command -v mpirun >/dev/null; then
  lmp_cmd=(mpirun --allow-run-as-root -np "$np" "${lmp_cmd[@]}")
fi
lmp_cmd+=(-nocite -in "$here/lammps_crack.in" -log "$work/log.lammps" -screen none
          -var scale "$scale" -var steps "$steps" -var dump "$work/crack.dump")

start=$(date +%s)
"${lmp_cmd[@]}" || { tail -n 20 "$work/log.lammps" >&2; exit 1; }
# All three atom types (interior, bottom grip, top grip) are drawn as spheres
# of radius 0.5 sigma, as in lammps_melt.sh.
convert_cmd=(/usr/bin/python3 "$here/lammps_dump_to_vtk.py" --radius-by-type 1:0.5,2:0.5,3:0.5
             --title "LAMMPS 2d LJ crack, {n} atoms, box {box}, sigma units, all z = 0")
# Write to a temporary name first so an interrupted run never leaves a
# half-written file that the cache check above would accept.
summary=$("${convert_cmd[@]}" "$work/crack.dump" "$output.part")
mv "$output.part" "$output"
seconds=$(( $(date +%s) - start ))

atoms=${summary%% *}
{
  echo "file: $(basename "$output")"
  echo "generator: Data/Generators/lammps_crack.sh (input lammps_crack.in, converter lammps_dump_to_vtk.py)"
  echo "lammps: $(head -n 1 "$work/log.lammps")"
  echo "debian package: lammps $(dpkg-query -W -f='${Version}' lammps 2>/dev/null || echo unknown)"
  echo "command: ${lmp_cmd[*]}" | sed "s#$work/##g"
  echo "converter: ${convert_cmd[*]} crack.dump $(basename "$output")" | sed "s#$here/##g"
  echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "host cores: $(nproc), MPI ranks: $np"
  echo "atoms: $atoms (slab height in lattice cells: $scale, NVE steps: $steps)"
  echo "converted: $summary"
  echo "wall time: ${seconds} s (simulation + conversion)"
} > "$output.provenance.txt"
echo "wrote $output ($atoms atoms, ${seconds} s)"
