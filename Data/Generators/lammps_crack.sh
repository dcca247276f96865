#!/bin/bash
# Generate a cracked crystal with Debian's LAMMPS: a Lennard-Jones crystal slab
# with a notch, pulled apart until a crack opens from the notch tip, converted
# to legacy VTK binary polydata by lammps_dump_to_vtk.py. By default the slab
# is two-dimensional (lammps_crack.in, every atom at z = 0); with --3d it is an
# fcc slab of finite thickness (lammps_crack3d.in, periodic in z).
#
# Usage: lammps_crack.sh [--3d] OUTPUT.vtk [SCALE]
#   SCALE  slab height in lattice cells, width 3*SCALE cells;
#          2d: about 6*SCALE^2 atoms (default 230: 317,284 atoms)
#          3d: thickness SCALE/4 cells, about 6*SCALE^3 atoms
#              (default 22: 69,840 atoms)
# Environment:
#   LAMMPS_NP     MPI ranks (default: number of cores; 1 runs lmp without mpirun)
#   LAMMPS_STEPS  NVE steps (default 10000 in 2d, 2500 in 3d)
#
# Writes OUTPUT.vtk and OUTPUT.vtk.provenance.txt. If OUTPUT.vtk exists it is
# kept as a cache and nothing runs: delete it to regenerate.
set -euo pipefail

dim=2
if [[ "${1:-}" == --3d ]]; then
  dim=3
  shift
fi
if [[ $# -lt 1 || $# -gt 2 ]]; then
  sed -n '2,18p' "$0" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lammps_common.sh"
if [[ $dim == 3 ]]; then
  input=lammps_crack3d.in default_scale=22 default_steps=2500
  title="LAMMPS 3d fcc LJ crack, {n} atoms, box {box}, sigma units"
else
  input=lammps_crack.in default_scale=230 default_steps=10000
  title="LAMMPS 2d LJ crack, {n} atoms, box {box}, sigma units, all z = 0"
fi
scale=${2:-$default_scale}
steps=${LAMMPS_STEPS:-$default_steps}

lammps_start "$1"
[[ "$scale" =~ ^[1-9][0-9]*$ && "$scale" -ge 8 ]] || { echo "SCALE must be an integer >= 8" >&2; exit 2; }

lammps_run "$input" -var scale "$scale" -var steps "$steps" -var dump "$work/crack.dump"
# All three atom types (interior, bottom grip, top grip) are drawn as spheres
# of radius 0.5 sigma, as in lammps_melt.sh.
convert_cmd=(/usr/bin/python3 "$here/lammps_dump_to_vtk.py" --radius-by-type 1:0.5,2:0.5,3:0.5
             --title "$title")
lammps_convert crack.dump
lammps_provenance lammps_crack.sh "$input" \
  "atoms: $atoms (${dim}d, slab height in lattice cells: $scale, NVE steps: $steps)" \
  "converted: $summary"
echo "wrote $output ($atoms atoms, ${seconds} s)"
