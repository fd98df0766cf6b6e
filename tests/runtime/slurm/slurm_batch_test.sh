#!/usr/bin/env bash
# `crackflow batch --backend slurm` on a real one-node Slurm cluster (issue 15): slurmctld and
# slurmd on 127.0.0.1 only, inside a temporary directory, AuthType=auth/none (a test cluster: no
# munge key needed). A 10-row manifest in which row 'flaky' reads a mesh that does not exist yet:
# the first pass must report exactly that row failed, the retry must resubmit only its task and
# complete it, the summary must show 10 of 10 ok, and every row's outputs must equal those of a
# local-backend run of the same manifest. MaxArraySize=4 makes the 5 tasks two array jobs.
# The daemons are stopped by their process ids; nothing is left running.
# Usage: slurm_batch_test.sh CRACKFLOW_EXE SOURCE_DIR     (needs root and slurmctld, slurmd, slurm-client)
set -uo pipefail
EXE=$1
SRC=$2

if [ "$(id -u)" -ne 0 ]; then
  echo "SKIP: the one-node Slurm cluster runs its daemons as root (run the tests as root, as CI does)"
  exit 77
fi
for b in slurmctld slurmd sbatch squeue scontrol; do
  command -v "$b" >/dev/null || { echo "FAIL: $b not installed (./setup.sh test installs slurmctld slurmd slurm-client)"; exit 1; }
done

source "$(dirname "$0")/one_node_cluster.sh"
echo "cluster up: $(sinfo -h -o '%P %T %c CPUs')"
check "daemons listen on 127.0.0.1 only" bash -c "! grep -q ' 00000000:$(printf %04X "$port") ' /proc/net/tcp"

# The rows: a box pulled by a traction, 10 loads and stiffnesses; 'flaky' reads flaky.off, which
# appears only after the first pass.
W=$T/work
mkdir -p "$W"
cp "$SRC/tests/runtime/data/batch/box.off" "$W/box.off"
PIPE=$SRC/tests/runtime/data/batch/tension.yaml
{
  echo "id,pipeline,box.path,operators.E,solution.boundary_conditions"
  for i in 0 1 2 3 4 5 6 7 8 9; do
    mesh=box.off
    [ $i -eq 3 ] && mesh=flaky.off
    id=row$i
    [ $i -eq 3 ] && id=flaky
    echo "$id,$PIPE,$mesh,$((i + 1))e9,\"bottom: displacement 0 0 0; top: traction 0 0 ${i}.5e5; *: traction 0 0 0\""
  done
} > "$W/manifest.csv"

cd "$W" || exit 1
printf 'partition: debug\ntime: "5:00"\nmem: 500M\ncpus-per-task: 4\n' > "$T/cluster.yaml"
SLURM_ARGS=(--backend slurm --wait --rows-per-task 2 --max-parallel 2 --cpus-per-task 1 --slurm-config "$T/cluster.yaml")
t0=$(date +%s.%N)
"$EXE" batch manifest.csv --out "$T/slurm" "${SLURM_ARGS[@]}" > "$T/pass1.log" 2>&1
code1=$?
t1=$(date +%s.%N)
cat "$T/pass1.log"
# The missing mesh makes 'flaky' an invalid row (exit 2 when its pipeline loads): the batch exits 2,
# as the local backend does for the same manifest (docs/batch.md: exit codes).
check "first pass exits 2 (a row was invalid)" test "$code1" -eq 2
check "the summary calls row 'flaky' invalid" grep -q "^flaky,invalid," "$T/slurm/summary.csv"
check "first pass: 5 tasks in 2 array jobs at MaxArraySize 4" grep -q "10 of 10 rows to run, 2 per task: 5 tasks in 2 array jobs (MaxArraySize 4)" "$T/pass1.log"
failed1=$(awk -F, 'NR > 1 && $2 != "ok" {print $1}' "$T/slurm/summary.csv")
check "first pass reports exactly row 'flaky' failed (got: $failed1)" test "$failed1" = flaky
check "the failed row's log names the missing mesh" grep -q "flaky.off" "$T/slurm/flaky/batch_row.log"
check "job script: the configuration's partition, time and memory, the command line's CPUs" \
  bash -c "grep -q -- '--partition=debug' $T/slurm/.batch/slurm/*/job.sh && grep -q -- '--time=5:00' $T/slurm/.batch/slurm/*/job.sh && grep -q -- '--mem=500M' $T/slurm/.batch/slurm/*/job.sh && grep -q -- '--cpus-per-task=1' $T/slurm/.batch/slurm/*/job.sh"
check "per-task logs exist" bash -c "ls '$T'/slurm/.batch/slurm/*/task_*_*.log >/dev/null"

cp box.off flaky.off
"$EXE" batch manifest.csv --out "$T/slurm" "${SLURM_ARGS[@]}" > "$T/pass2.log" 2>&1
code2=$?
t2=$(date +%s.%N)
cat "$T/pass2.log"
check "retry exits 0" test "$code2" -eq 0
check "retry resubmits only the failed row's task (array index 1)" grep -q "1 of 10 rows to run, 2 per task: 1 task in 1 array job" "$T/pass2.log"
check "retry: task 1 as array index 1" grep -q "tasks 1 (array indices 1%2, offset 0)" "$T/pass2.log"
check "summary: 10 of 10 ok" test "$(awk -F, 'NR > 1 && $2 == "ok"' "$T/slurm/summary.csv" | wc -l)" -eq 10
check "summary: every row has its array job and task ids and host" \
  test "$(awk -F, 'NR > 1 && $10 != "" && $11 != "" && $9 != ""' "$T/slurm/summary.csv" | wc -l)" -eq 10
check "summary.json says 10 ok" grep -q '"rows":10,"ok":10,"failed":0' "$T/slurm/summary.json"
check "row0 ran once, flaky twice" bash -c "grep -q '\"attempt\":1' '$T/slurm/row0/batch_row.json' && grep -q '\"attempt\":2' '$T/slurm/flaky/batch_row.json'"

# The same manifest on the local backend: identical outputs, row by row.
"$EXE" batch manifest.csv --out "$T/local" --jobs 2 > "$T/local.log" 2>&1
check "local run of the same manifest: all ok" test $? -eq 0
check "outputs identical to the local run (all but timing reports and logs)" \
  diff -r -x report.json -x batch_row.json -x batch_row.log -x .batch -x 'summary.*' "$T/slurm" "$T/local"
check "the rows differ from each other (the loads were applied)" \
  bash -c "test -s '$T/slurm/row1/tension.vtp' && test -s '$T/slurm/row2/tension.vtp' && ! cmp -s '$T/slurm/row1/tension.vtp' '$T/slurm/row2/tension.vtp'"

echo "timing: first pass $(awk "BEGIN {print $t1 - $t0}") s, retry $(awk "BEGIN {print $t2 - $t1}") s"
stop_cluster
left=$(pgrep -f "$T/slurm.conf" || true)
check "no Slurm daemon left running" test -z "$left"
check "no crackflow process left running" test -z "$(pgrep -f "[c]rackflow (run|batch) .*$T")"
[ "$failures" -eq 0 ] && echo "PASS" || echo "$failures check(s) failed"
exit $(( failures > 0 ))
