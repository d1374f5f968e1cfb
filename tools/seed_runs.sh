# Shared by tools/eval_explore_seeds.sh and tools/eval_explore_long.sh (sourced, not run): the
# arguments SQUINT OUT_DIR FIRST_SEED LAST_SEED [extra options...] and the runs two at a time.

# seed_args USAGE "$@": sets squint, out, first, last and the array extra (the options after the
# four), or prints the usage or what is wrong and exits 2.
seed_args() {
  local usage=$1
  shift
  if [ $# -lt 4 ]; then
    echo "usage: $0 $usage" >&2
    exit 2
  fi
  squint=$1 out=$2 first=$3 last=$4
  shift 4
  extra=("$@")
  [ -x "$squint" ] || { echo "$0: $squint is not an executable" >&2; exit 2; }
  [[ "$first" =~ ^[0-9]+$ && "$last" =~ ^[0-9]+$ && "$first" -le "$last" ]] ||
    { echo "$0: seeds must be whole numbers, FIRST <= LAST (got $first, $last)" >&2; exit 2; }
  mkdir -p "$out"
}

# seed_runs FN: FN S for each seed from first to last, two at a time in the background; exits 1
# naming the logs if one fails.
seed_runs() {
  local fn=$1 s p
  local pids=()
  for s in $(seq "$first" "$last"); do
    "$fn" "$s" &
    pids+=($!)
    if [ ${#pids[@]} -ge 2 ]; then
      wait "${pids[0]}" || { echo "$0: a seed's run failed, see $out/*.log" >&2; exit 1; }
      pids=("${pids[@]:1}")
    fi
  done
  for p in "${pids[@]}"; do wait "$p" || { echo "$0: a seed's run failed, see $out/*.log" >&2; exit 1; }; done
}
