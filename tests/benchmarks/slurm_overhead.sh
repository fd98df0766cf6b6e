#!/usr/bin/env bash
# Scheduling overhead per Slurm array task of `crackflow batch --backend slurm` on a one-node
# cluster on loopback (docs/performance.md). Runs N short rows (the batch tests' box in tension,
# ~0.2 s each) one task at a time (--max-parallel 1), first one row per task, then R rows per
# task, and prints JSON: overhead per task = (wall time from submission to summary - the rows'
# own seconds) / tasks, and the fit wall - rows = fixed + tasks x per_task through both runs. Needs root and slurmctld, slurmd, slurm-client.
# Usage: tests/benchmarks/slurm_overhead.sh build/runtime/crackflow [N=20] [R=10]
set -uo pipefail
EXE=$(realpath "$1")
N=${2:-20}
R=${3:-10}
SRC=$(cd "$(dirname "$0")/../.." && pwd)
[ "$(id -u)" -eq 0 ] || { echo "needs root (the cluster's daemons)"; exit 1; }
MAX_ARRAY_SIZE=1001
source "$SRC/tests/runtime/slurm/one_node_cluster.sh"

W=$T/work
mkdir -p "$W"
cp "$SRC/tests/runtime/data/batch/box.off" "$W/"
{
  echo "id,pipeline,operators.E"
  for i in $(seq 1 "$N"); do echo "r$i,$SRC/tests/runtime/data/batch/tension.yaml,${i}e9"; done
} > "$W/m.csv"
cd "$W" || exit 1

measure() {  # rows_per_task out_dir -> "wall row_seconds tasks"
  local r=$1 out=$2
  local t0 t1
  t0=$(date +%s.%N)
  "$EXE" batch m.csv --out "$out" --backend slurm --wait --rows-per-task "$r" --max-parallel 1 --cpus-per-task 1 \
    > "$out.log" 2>&1 || { cat "$out.log"; exit 1; }
  t1=$(date +%s.%N)
  local rows
  rows=$(awk -F, 'NR > 1 {s += $7} END {print s}' "$out/summary.csv")
  echo "$(awk "BEGIN {print $t1 - $t0}") $rows $(( (N + r - 1) / r ))"
}
read -r wall1 rows1 tasks1 < <(measure 1 "$T/one")
read -r wallR rowsR tasksR < <(measure "$R" "$T/many")
awk -v n="$N" -v r="$R" -v w1="$wall1" -v s1="$rows1" -v t1="$tasks1" -v wr="$wallR" -v sr="$rowsR" -v tr="$tasksR" 'BEGIN {
  printf "{\"rows\": %d, \"one_row_per_task\": {\"tasks\": %d, \"wall_s\": %.2f, \"row_s\": %.2f, \"overhead_per_task_s\": %.3f},", n, t1, w1, s1, (w1 - s1) / t1
  printf " \"rows_per_task\": %d, \"packed\": {\"tasks\": %d, \"wall_s\": %.2f, \"row_s\": %.2f, \"overhead_per_task_s\": %.3f},", r, tr, wr, sr, (wr - sr) / tr
  # wall - rows = fixed + tasks * per_task, from the two runs: the fixed part is the submission,
  # the first scheduling pass and the last squeue poll.
  p = ((w1 - s1) - (wr - sr)) / (t1 - tr)
  printf " \"fit\": {\"per_task_s\": %.3f, \"fixed_per_batch_s\": %.3f}}\n", p, (w1 - s1) - t1 * p
}'
