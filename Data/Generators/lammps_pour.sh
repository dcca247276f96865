#!/bin/bash
# Generate a polydisperse granular bed with Debian's LAMMPS: spheres of
# diameters 0.5 to 1.2 poured under gravity into a cylindrical bucket with
# fix pour, settled (lammps_pour.in), converted to legacy VTK binary polydata
# by lammps_dump_to_vtk.py, with each grain's radius as LAMMPS dumps it.
#
# Usage: lammps_pour.sh OUTPUT.vtk [N]
#   N  number of grains (default 8000)
# Environment:
#   LAMMPS_NP     MPI ranks (default: number of cores; 1 runs lmp without mpirun)
#   LAMMPS_STEPS  settling steps of 0.001 after the last grain is in (default 8000)
#
# Writes OUTPUT.vtk and OUTPUT.vtk.provenance.txt. If OUTPUT.vtk exists it is
# kept as a cache and nothing runs: delete it to regenerate.
set -euo pipefail

if [[ $# -lt 1 || $# -gt 2 ]]; then
  sed -n '2,14p' "$0" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lammps_common.sh"
n=${2:-8000}
steps=${LAMMPS_STEPS:-8000}

lammps_start "$1"
[[ "$n" =~ ^[1-9][0-9]*$ && "$n" -ge 100 ]] || { echo "N must be an integer >= 100" >&2; exit 2; }

lammps_run lammps_pour.in -var n "$n" -var steps "$steps" -var dump "$work/pour.dump"
convert_cmd=(/usr/bin/python3 "$here/lammps_dump_to_vtk.py"
             --title "LAMMPS granular pour, {n} grains, box {box}, reduced units")
lammps_convert pour.dump "$n"

# Last thermo line: step, grains, kinetic and rotational energy, fastest grain.
final=$(awk 'NF == 5 && $1 ~ /^[0-9]+$/ && $2 ~ /^[0-9]+$/ {last=$0} END {print last}' "$work/log.lammps")
lammps_provenance lammps_pour.sh lammps_pour.in \
  "grains: $atoms (settling steps after the last insertion: $steps)" \
  "final thermo (step, grains, kinetic and rotational energy, max speed): $(echo $final)" \
  "converted: $summary"
echo "wrote $output ($atoms grains, ${seconds} s)"
