# What the LAMMPS generators lammps_crack.sh and lammps_pour.sh share: the
# cache check, the MPI job, the run, the conversion and the provenance file.
# Sourced, not run; the caller has set -euo pipefail and $here (this folder).
#
#   lammps_start OUTPUT   exit 0 if OUTPUT exists (it is the cache); else check for
#                         lmp, make $work (removed on exit, with OUTPUT.part), and
#                         set $np (LAMMPS_NP, default: the cores) and $start
#   lammps_run INPUT ARGS...
#                         run lmp -sf opt on $here/INPUT with ARGS (-var ...),
#                         under mpirun when np > 1; the log is $work/log.lammps;
#                         sets $lmp_cmd; on failure prints the log's tail, exits 1
#   lammps_convert DUMP_NAME [COUNT]
#                         convert $work/DUMP_NAME with $convert_cmd into OUTPUT (through
#                         OUTPUT.part, so an interrupted run never leaves a half-written
#                         file that the cache check would accept); sets $summary (the
#                         converter's line) and $atoms; fails if COUNT is given and the
#                         dump holds another number of atoms
#   lammps_provenance GENERATOR INPUT LINE...
#                         write OUTPUT.provenance.txt: the file, generator, LAMMPS
#                         and Debian versions, command, converter ($convert_cmd on
#                         DUMP_NAME), date, cores and ranks, the LINEs, and
#                         the wall time since lammps_start (also set as $seconds)

lammps_start() {
  output=$1
  if [[ -e "$output" ]]; then
    echo "$output exists, not regenerated"
    exit 0
  fi
  command -v lmp >/dev/null || { echo "lmp not found (Debian package 'lammps')" >&2; exit 1; }
  np=${LAMMPS_NP:-$(nproc)}
  work=$(mktemp -d)
  trap 'rm -rf "$work" "$output.part"' EXIT
  # Run the simulator as an MPI job of its own: a caller that is itself an MPI process
  # (pvpython and pvbatch start one) hands down its Open MPI and PMIx variables, with
  # which mpirun and the simulator fail before they start.
  for v in $(compgen -e); do
    case "$v" in OMPI_* | PMIX_* | OPAL_* | PRTE_*) unset "$v" ;; esac
  done
  start=$(date +%s)
}

lammps_run() {
  local input=$1
  shift
  # MPI ranks split the box (measured, 1M atoms on 2 cores: 2 ranks run 1.9x as
  # fast as 1); -sf opt selects the OPT package's lj/cut, about 10 % faster (styles
  # without an OPT version, such as the granular ones, run as they are).
  lmp_cmd=(lmp -sf opt)
  if [[ "$np" -gt 1 ]] && command -v mpirun >/dev/null; then
    lmp_cmd=(mpirun --allow-run-as-root -np "$np" "${lmp_cmd[@]}")
  fi
  lmp_cmd+=(-nocite -in "$here/$input" -log "$work/log.lammps" -screen none "$@")
  "${lmp_cmd[@]}" || { tail -n 20 "$work/log.lammps" >&2; exit 1; }
}

lammps_convert() {
  dump_name=$1
  summary=$("${convert_cmd[@]}" "$work/$dump_name" "$output.part")
  atoms=${summary%% *}
  if [[ -n "${2:-}" && "$atoms" != "$2" ]]; then
    echo "the dump holds $atoms atoms instead of $2" >&2
    exit 1
  fi
  mv "$output.part" "$output"
}

lammps_provenance() {
  local generator=$1 input=$2 line
  shift 2
  seconds=$(( $(date +%s) - start ))
  {
    echo "file: $(basename "$output")"
    echo "generator: Data/Generators/$generator (input $input, converter lammps_dump_to_vtk.py)"
    echo "lammps: $(head -n 1 "$work/log.lammps")"
    echo "debian package: lammps $(dpkg-query -W -f='${Version}' lammps 2>/dev/null || echo unknown)"
    echo "command: ${lmp_cmd[*]}" | sed "s#$work/##g"
    echo "converter: ${convert_cmd[*]} $dump_name $(basename "$output")" | sed "s#$here/##g"
    echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "host cores: $(nproc), MPI ranks: $np"
    for line in "$@"; do
      echo "$line"
    done
    echo "wall time: ${seconds} s (simulation + conversion)"
  } > "$output.provenance.txt"
}
