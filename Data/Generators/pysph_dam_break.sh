#!/bin/bash
# Generate SPH particle data with Debian's PySPH: the example dam_break_3d (a
# water column collapsing in a tank with an obstacle, the SPHERIC 3D dam
# break, weakly compressible SPH) run to TFINAL, its fluid particles at several
# times converted to legacy VTK binary polydata by pysph_to_vtk.py.
#
# Usage: pysph_dam_break.sh OUTPUT_PREFIX [DX] [TFINAL]
#   DX      particle spacing in m (default 0.04: 9,360 fluid particles;
#           0.0148: 203,278)
#   TFINAL  simulated time in s (default 0.6)
# Environment:
#   PYSPH_OPENMP     1 runs on all cores with OpenMP, 0 on one thread
#                    (default: 1 if there is more than one core)
#   PYSPH_OUTPUT_DT  output interval in s (default 0.1)
#
# Writes OUTPUT_PREFIX_<iteration>.vtk at t = 0, PYSPH_OUTPUT_DT, 2
# PYSPH_OUTPUT_DT, ... and TFINAL (the fluid), OUTPUT_PREFIX-walls.vtk (the
# tank and obstacle particles at t = 0), a <file>.provenance.txt beside each
# and OUTPUT_PREFIX.provenance.txt, written last, listing them all. If that
# exists it is kept as a cache and nothing runs: delete it to regenerate.
set -euo pipefail

if [[ $# -lt 1 || $# -gt 3 ]]; then
  sed -n '2,20p' "$0" >&2
  exit 2
fi
prefix=$1
dx=${2:-0.04}
tfinal=${3:-0.6}
output_dt=${PYSPH_OUTPUT_DT:-0.1}
if [[ -z "${PYSPH_OPENMP:-}" ]]; then
  PYSPH_OPENMP=0
  [[ $(nproc) -gt 1 ]] && PYSPH_OPENMP=1
fi
here=$(cd "$(dirname "$0")" && pwd)

if [[ -e "$prefix.provenance.txt" ]]; then
  echo "$prefix.provenance.txt exists, not regenerated"
  exit 0
fi
number='^([0-9]+\.?[0-9]*|\.[0-9]+)$'
for value in "$dx" "$tfinal" "$output_dt"; do
  [[ "$value" =~ $number ]] || { echo "DX, TFINAL and PYSPH_OUTPUT_DT must be positive numbers" >&2; exit 2; }
done
[[ "$PYSPH_OPENMP" =~ ^[01]$ ]] || { echo "PYSPH_OPENMP must be 0 or 1" >&2; exit 2; }
pysph_version=$(/usr/bin/python3 -c 'import pysph; print(pysph.__version__)' 2>/dev/null) \
  || { echo "PySPH not importable by /usr/bin/python3 (Debian package 'python3-pysph')" >&2; exit 1; }
mkdir -p "$(dirname "$prefix")"

work=$(mktemp -d)
trap 'rm -rf "$work"; rm -f "$prefix"_*.vtk.part "$prefix"-walls.vtk.part' EXIT

# The output times: multiples of PYSPH_OUTPUT_DT below TFINAL (PySPH shortens
# a time step to land on each); t = 0 and TFINAL are always written.
times=$(/usr/bin/python3 -c 'import sys; dt, tf = map(float, sys.argv[1:])
print(",".join(f"{k * dt:.6g}" for k in range(1, int(tf / dt + 1e-6) + 1) if k * dt < tf - 1e-9))' \
  "$output_dt" "$tfinal")

# The example as Debian ships it, through Application.setup() and solve():
# its run() would do the same, but its __main__ also post-processes (pressure
# probes compared with the experiment, plots), which is of no use here.
# --pfreq is set so high that only t = 0, the times above and TFINAL are
# written. PySPH compiles the generated Cython code into ~/.pysph the first
# time (about 10 s; serial and OpenMP code are separate modules).
driver='import sys
from pysph.examples.dam_break_3d import DamBreak3D
app = DamBreak3D(fname="dam_break_3d")
app.setup(sys.argv[2:])
app.solver.set_output_at_times([float(t) for t in sys.argv[1].split(",") if t])
app.solve()'
sim_args=(--dx "$dx" --tf "$tfinal" --pfreq 1000000000 -d "$work/out")
if [[ "$PYSPH_OPENMP" == 1 ]]; then sim_args+=(--openmp); else sim_args+=(--no-openmp); fi
cmd=(/usr/bin/python3 -c "<driver>" "$times" "${sim_args[@]}")

start=$(date +%s)
/usr/bin/python3 -c "$driver" "$times" "${sim_args[@]}" > "$work/pysph.out" 2>&1 \
  || { tail -n 20 "$work/pysph.out" >&2; exit 1; }
sim_seconds=$(( $(date +%s) - start ))

# Particle counts, e.g. "3D dam break with 9360 fluid, 15152 boundary, 160
# obstacle particles", and the kernel from PySPH's log.
counts=$(sed -n 's/^3D dam break with \(.*\) particles$/\1/p' "$work/pysph.out")
kernel=$(sed -n '/Using kernel:/,/^---*$/{n;n;p;q}' "$work/out/dam_break_3d.log" | tr -d ' ')
kernel_radius=$(/usr/bin/python3 -c 'import sys, pysph.base.kernels as k
print(getattr(k, sys.argv[1].split("(")[0])(dim=3).radius_scale)' "$kernel")
hdx=$(/usr/bin/python3 -c 'from pysph.examples import dam_break_3d; print(dam_break_3d.hdx)')

# Write to temporary names first so an interrupted run never leaves
# half-written files; the summary provenance, which the cache check above
# looks for, is written after all of them.
declare -a files summaries
outputs=$(find "$work/out" -maxdepth 1 \( -name 'dam_break_3d_*.hdf5' -o -name 'dam_break_3d_*.npz' \) | sort)
[[ -n "$outputs" ]] || { echo "PySPH wrote no output" >&2; exit 1; }
first=
for out in $outputs; do
  base=$(basename "$out")
  step=${base#dam_break_3d_}
  step=${step%.*}
  file="${prefix}_$step.vtk"
  summary=$(/usr/bin/python3 "$here/pysph_to_vtk.py" \
    --title "PySPH dam_break_3d fluid, {n} particles, dx = $dx m, t = {t:.4f} s (iteration {count})" \
    "$out" "$file.part")
  files+=("$file")
  summaries+=("$summary")
  [[ -n "$first" ]] || first=$out
done
walls_summary=$(/usr/bin/python3 "$here/pysph_to_vtk.py" --array boundary,obstacle \
  --title "PySPH dam_break_3d tank walls and obstacle, {n} particles, dx = $dx m" \
  "$first" "$prefix-walls.vtk.part")
for file in "${files[@]}" "$prefix-walls.vtk"; do
  mv "$file.part" "$file"
done
seconds=$(( $(date +%s) - start ))

common() {
  echo "generator: Data/Generators/pysph_dam_break.sh (PySPH example dam_break_3d, converter pysph_to_vtk.py)"
  echo "pysph: $pysph_version"
  echo "debian package: python3-pysph $(dpkg-query -W -f='${Version}' python3-pysph 2>/dev/null || echo unknown)"
  echo "command: ${cmd[*]}" | sed "s#$work/##g"
  echo "driver (<driver> above): $(echo "$driver" | tr '\n' ';' | sed 's/;/; /g')"
  echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "host cores: $(nproc), OpenMP: $PYSPH_OPENMP"
  echo "particles: $counts (dx = $dx m)"
  echo "kernel: $kernel, support radius $kernel_radius h; h = hdx dx = $hdx * $dx m, constant (no h update)"
  echo "output times: 0,$times,$tfinal s"
  echo "wall time: ${seconds} s (simulation ${sim_seconds} s, rest conversion)"
}
for i in "${!files[@]}"; do
  {
    echo "file: $(basename "${files[$i]}")"
    common
    echo "converted: ${summaries[$i]}"
  } > "${files[$i]}.provenance.txt"
done
{
  echo "file: $(basename "$prefix")-walls.vtk"
  common
  echo "converted: $walls_summary"
} > "$prefix-walls.vtk.provenance.txt"
{
  echo "files: $(for f in "${files[@]}" "$prefix-walls.vtk"; do basename "$f"; done | tr '\n' ' ')"
  common
  for i in "${!files[@]}"; do
    echo "$(basename "${files[$i]}"): ${summaries[$i]}"
  done
  echo "$(basename "$prefix")-walls.vtk: $walls_summary"
} > "$prefix.provenance.txt.part"
mv "$prefix.provenance.txt.part" "$prefix.provenance.txt"
echo "wrote ${#files[@]} fluid files ${prefix}_*.vtk and $prefix-walls.vtk ($counts particles, ${seconds} s)"
