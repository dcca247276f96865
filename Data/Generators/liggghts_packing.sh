#!/bin/bash
# Generate a polydisperse granular packing with Debian's LIGGGHTS: spheres of
# three radii (by default 2, 3 and 5 mm) dropped into a square box settle under gravity
# into a dense bed (liggghts_packing.in), converted to legacy VTK binary
# polydata by lammps_dump_to_vtk.py, with each sphere's radius as a point array.
#
# Usage: liggghts_packing.sh OUTPUT.vtk [N]
#   N  number of spheres (default 80000)
# Environment:
#   LIGGGHTS_NP     MPI ranks (default: number of cores; 1 runs liggghts without mpirun)
#   LIGGGHTS_RADII  the three radii in m, smallest first (default "0.002 0.003 0.005")
#   LIGGGHTS_FILL   solid fraction at which they are inserted (default 0.35; random
#                   insertion of radii far apart places all of them only at a lower one)
#   LIGGGHTS_STEPS  settling steps (default: 0.4 s of them)
#   LIGGGHTS_MAY_LOSE  spheres that may leave the box, the file then holds fewer (default 0)
#   The time step is 5e-5 s, scaled down with the smallest radius below 2 mm (a
#   sphere's Rayleigh time, which the step must stay a fifth of, grows with its radius).
#
# Writes OUTPUT.vtk and OUTPUT.vtk.provenance.txt. If OUTPUT.vtk exists it is
# kept as a cache and nothing runs: delete it to regenerate.
set -euo pipefail

if [[ $# -lt 1 || $# -gt 2 ]]; then
  sed -n '2,14p' "$0" >&2
  exit 2
fi
output=$1
n=${2:-80000}
read -r r1 r2 r3 <<< "${LIGGGHTS_RADII:-0.002 0.003 0.005}"
dt=$(awk -v r="$r1" 'BEGIN { printf "%.6g", 5e-5 * (r < 0.002 ? r / 0.002 : 1) }')
steps=${LIGGGHTS_STEPS:-$(awk -v dt="$dt" 'BEGIN { printf "%d", 0.4 / dt + 0.5 }')}
np=${LIGGGHTS_NP:-$(nproc)}
here=$(cd "$(dirname "$0")" && pwd)

if [[ -e "$output" ]]; then
  echo "$output exists, not regenerated"
  exit 0
fi
[[ "$n" =~ ^[1-9][0-9]*$ && "$n" -ge 100 ]] || { echo "N must be an integer >= 100" >&2; exit 2; }
command -v liggghts >/dev/null || { echo "liggghts not found (Debian package 'liggghts')" >&2; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work" "$output.part"' EXIT

# Run the simulator as an MPI job of its own: a caller that is itself an MPI process
# (pvpython and pvbatch start one) hands down its Open MPI and PMIx variables, with which
# mpirun and the simulator fail before they start.
for v in $(compgen -e); do
  case "$v" in OMPI_* | PMIX_* | OPAL_* | PRTE_*) unset "$v" ;; esac
done

liggghts_cmd=(liggghts)
if [[ "$np" -gt 1 ]] && command -v mpirun >/dev/null; then
  liggghts_cmd=(mpirun --allow-run-as-root -np "$np" "${liggghts_cmd[@]}")
fi
# No '-screen none': LIGGGHTS 3.8 then crashes when fix insert/pack prints
# to the (missing) screen, so the screen output goes to a file instead.
liggghts_cmd+=(-in "$here/liggghts_packing.in" -log "$work/log.liggghts"
               -var n "$n" -var steps "$steps" -var dump "$work/packing.dump"
               -var r1 "$r1" -var r2 "$r2" -var r3 "$r3" -var dt "$dt"
               -var fill "${LIGGGHTS_FILL:-0.35}")

start=$(date +%s)
"${liggghts_cmd[@]}" > "$work/screen.txt" 2>&1 || { tail -n 20 "$work/screen.txt" >&2; exit 1; }
inserted=$(sed -n 's/^ - a total of \([0-9]*\) particle templates.*/\1/p' "$work/log.liggghts" | tail -n 1)
if [[ "$inserted" != "$n" ]]; then
  echo "LIGGGHTS inserted ${inserted:-no} spheres instead of $n" >&2
  exit 1
fi
convert_cmd=(/usr/bin/python3 "$here/lammps_dump_to_vtk.py"
             --title "LIGGGHTS polydisperse packing, {n} spheres, box {box}, SI units (m)")
# Write to a temporary name first so an interrupted run never leaves a
# half-written file that the cache check above would accept.
summary=$("${convert_cmd[@]}" "$work/packing.dump" "$output.part")
atoms=${summary%% *}
lost=$(( n - atoms ))
if [[ "$lost" -lt 0 || "$lost" -gt "${LIGGGHTS_MAY_LOSE:-0}" ]]; then
  echo "the dump holds $atoms spheres instead of $n (spheres lost from the box?)" >&2
  exit 1
fi
mv "$output.part" "$output"
seconds=$(( $(date +%s) - start ))

# Last thermo line of the settling run: step atoms ke rotational-ke max-speed cpu.
final=$(awk '/^ *Step +Atoms/ {n++} n == 1 && $1 ~ /^[0-9]+$/ && NF == 6 {last=$0} END {print last}' "$work/log.liggghts")
{
  echo "file: $(basename "$output")"
  echo "generator: Data/Generators/liggghts_packing.sh (input liggghts_packing.in, converter lammps_dump_to_vtk.py)"
  echo "liggghts: $(head -n 1 "$work/log.liggghts")"
  echo "debian package: liggghts $(dpkg-query -W -f='${Version}' liggghts 2>/dev/null || echo unknown)"
  echo "command: ${liggghts_cmd[*]}" | sed "s#$work/##g"
  echo "converter: ${convert_cmd[*]} packing.dump $(basename "$output")" | sed "s#$here/##g"
  echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "host cores: $(nproc), MPI ranks: $np"
  echo "spheres: $atoms ($lost lost from the box), radii $r1 $r2 $r3 m inserted at solid fraction ${LIGGGHTS_FILL:-0.35} (settling steps: $steps of $dt s)"
  echo "final thermo (step, spheres, kinetic and rotational energy in J, max speed in m/s, cpu s): $(echo $final)"
  echo "converted: $summary"
  echo "wall time: ${seconds} s (simulation + conversion)"
} > "$output.provenance.txt"
echo "wrote $output ($atoms spheres, ${seconds} s)"
