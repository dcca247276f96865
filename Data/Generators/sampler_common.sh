# What the Python samplers galpy_halo.sh and plummer_sphere.sh share: the cache
# check, the checks of N and the seed, the run through OUTPUT.part and the
# provenance file. Sourced, not run; the caller has set -euo pipefail and $here.
#
#   sampler_start OUTPUT N SEED SEED_VARIABLE
#                 exit 0 if OUTPUT exists (it is the cache); exit 2 unless N is a
#                 positive integer and SEED a non-negative one (SEED_VARIABLE names
#                 it in the message)
#   sampler_run COMMAND...
#                 run COMMAND OUTPUT.part, then move it to OUTPUT (an interrupted
#                 run never leaves a half-written file that the cache check would
#                 accept); sets $summary (its output) and $seconds (wall time)
#   sampler_provenance GENERATOR LINE...
#                 write OUTPUT.provenance.txt: the file, the generator, the LINEs,
#                 the command, the date, the cores and the wall time

sampler_start() {
  output=$1
  local n=$2 seed=$3 seed_variable=$4
  if [[ -e "$output" ]]; then
    echo "$output exists, not regenerated"
    exit 0
  fi
  [[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "N must be a positive integer" >&2; exit 2; }
  [[ "$seed" =~ ^[0-9]+$ ]] || { echo "$seed_variable must be a non-negative integer" >&2; exit 2; }
  trap 'rm -f "$output.part"' EXIT
}

sampler_run() {
  sampler_cmd=("$@")
  local start
  start=$(date +%s)
  summary=$("${sampler_cmd[@]}" "$output.part")
  mv "$output.part" "$output"
  seconds=$(( $(date +%s) - start ))
}

sampler_provenance() {
  local generator=$1
  shift
  {
    echo "file: $(basename "$output")"
    echo "generator: $generator"
    printf '%s\n' "$@"
    echo "command: ${sampler_cmd[*]} $(basename "$output")" | sed "s#$here/##g"
    echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "host cores: $(nproc)"
    echo "wall time: ${seconds} s"
  } > "$output.provenance.txt"
}
