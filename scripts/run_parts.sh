# Sourced by the table scripts: run_parts TABLE CMD... -- INPUT...
# Runs CMD INPUT once per input, JOBS at a time (default 2; a run's own threads aside),
# each into TABLE.part-N (stderr into TABLE.part-N.log), then joins the parts in the
# inputs' order into TABLE under the first part's two header lines (their stderr, in the
# same order, to stderr), and prints it.
# Fails (stopping the other runs) if any run fails.
run_parts() {
  local table=$1
  shift
  local cmd=()
  while [[ $1 != -- ]]; do
    cmd+=("$1")
    shift
  done
  shift
  local inputs=("$@") pids=() i
  for i in "${!inputs[@]}"; do
    while (($(jobs -rp | wc -l) >= ${JOBS:-2})); do wait -n || true; done
    "${cmd[@]}" "${inputs[$i]}" >"$table.part-$i" 2>"$table.part-$i.log" &
    pids+=($!)
  done
  for i in "${!pids[@]}"; do
    wait "${pids[$i]}" || {
      echo "run_parts: ${cmd[*]} ${inputs[$i]} failed:" >&2
      cat "$table.part-$i.log" >&2
      kill "${pids[@]}" 2>/dev/null || true
      return 1
    }
  done
  for i in "${!inputs[@]}"; do
    if ((i == 0)); then cat "$table.part-$i"; else tail -n +3 "$table.part-$i"; fi
    cat "$table.part-$i.log" >&2  # each run's progress and set-up times, in order
  done >"$table"
  rm -f "$table".part-*
  cat "$table"
}
