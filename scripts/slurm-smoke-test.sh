#!/usr/bin/env bash
# End-to-end check of a sweep's Slurm pattern on a throw-away one-node cluster
# (scripts/slurm-cluster.sh): a 4-task job array whose task 2 fails on its first attempt, merge
# jobs that depend on the array (--dependency=afterok), then the failed task alone resubmitted
# with a new merge job. Checks the states Slurm reports at each step and the files the tasks
# write; prints the job ids and states it saw. Exits non-zero on any failure; the cluster is
# stopped on every exit (also on failure and Ctrl-C). Needs root (see slurm-cluster.sh).
#
#   bash scripts/slurm-smoke-test.sh
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
timeout_s=${SLURM_SMOKE_TIMEOUT:-120}
work=$(mktemp -d /tmp/slurm-smoke.XXXXXX)
chmod a+x "$work"  # munged's socket must be reachable by all (slurm-cluster.sh)
cluster=$work/cluster
out=$work/out
passed=0

cleanup() {
  local t0=$SECONDS
  bash "$here/slurm-cluster.sh" stop "$cluster" || echo "smoke: stopping the cluster failed" >&2
  echo "smoke: cluster stopped in $((SECONDS - t0))s"
  if [ $passed -eq 1 ]; then
    rm -rf "$work"
  else
    echo "smoke: FAILED; logs and outputs kept in $work" >&2
  fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

fail() {
  echo "smoke: FAIL: $*" >&2
  exit 1
}

# "TASK STATE" for each task of array job $1 ("TASK" may be a range while tasks are pending),
# or "- STATE" for a job that is not an array.
job_states() {
  scontrol -o show job "$1" | awk '{
    task = "-"; state = "?"
    for (i = 1; i <= NF; i++) {
      if ($i ~ /^ArrayTaskId=/) task = substr($i, 13)
      if ($i ~ /^JobState=/) state = substr($i, 10)
    }
    print task, state
  }' | sort
}

job_field() {
  scontrol -o show job "$1" | tr ' ' '\n' | sed -n "s/^$2=//p"
}

finished() {
  ! job_states "$1" | grep -qE ' (PENDING|CONFIGURING|RUNNING|COMPLETING|SUSPENDED|REQUEUED|RESIZING|SIGNALING|STAGE_OUT)$'
}

# Polls the shell command $2 until it succeeds; fails with description $1 after the timeout.
wait_until() {
  local what=$1 deadline=$((SECONDS + timeout_s))
  until eval "$2"; do
    [ $SECONDS -ge $deadline ] && fail "timed out after ${timeout_s}s waiting for $what"
    sleep 0.5
  done
}

# Each record of job $1 (one per array task) with its job id, state and reason.
report() {
  echo "smoke: job $1 ($2):"
  scontrol -o show job "$1" | tr ' ' '\n' |
    grep -E '^(JobId|ArrayJobId|ArrayTaskId|JobState|Reason|Dependency|ExitCode)=' |
    awk '/^JobId=/ && NR > 1 { print line; line = "" } { line = line " " $0 } END { print line }' |
    sort -t= -k4,4n | sed 's/^/   /'
}

expect_states() {
  local id=$1 expected=$2 actual
  actual=$(job_states "$id" | tr '\n' ';')
  [ "$actual" = "$expected" ] || fail "job $id: expected states '$expected', got '$actual'"
}

t0=$SECONDS
client_env=$(bash "$here/slurm-cluster.sh" start "$cluster")
eval "$client_env"
echo "smoke: cluster up in $((SECONDS - t0))s, SLURM_CONF=$SLURM_CONF"

mkdir -p "$out" "$work/log"
cat > "$work/task.sh" <<'EOF'
#!/bin/bash
# One shard: writes task-ID; task 2 fails on its first attempt.
set -euo pipefail
out=$1
id=$SLURM_ARRAY_TASK_ID
if [ "$id" = 2 ] && [ ! -e "$out/task-2.failed-once" ]; then
  touch "$out/task-2.failed-once"
  echo "task 2 fails on purpose" >&2
  exit 1
fi
echo "array job $SLURM_ARRAY_JOB_ID task $id (job $SLURM_JOB_ID)" > "$out/task-$id"
EOF
cat > "$work/merge.sh" <<'EOF'
#!/bin/bash
# Joins the four shards' files; fails when one is missing.
set -euo pipefail
out=$1
cat "$out"/task-0 "$out"/task-1 "$out"/task-2 "$out"/task-3 > "$out/merged"
EOF

submit() { sbatch --parsable --output="$work/log/%x-%j.out" "$@" | cut -d';' -f1; }

# 1. The sweep: array (at most 2 tasks at a time) and two merge jobs, one left at Slurm's default
#    for an unsatisfiable dependency, one asking to be cancelled then.
array=$(submit --job-name=shard --array=0-3%2 "$work/task.sh" "$out")
merge_default=$(submit --job-name=merge --dependency=afterok:"$array" "$work/merge.sh" "$out")
merge_kill=$(submit --job-name=merge --dependency=afterok:"$array" --kill-on-invalid-dep=yes \
  "$work/merge.sh" "$out")
echo "smoke: submitted array $array, merge $merge_default (default), merge $merge_kill" \
  "(--kill-on-invalid-dep=yes)"

wait_until "array $array to finish" "finished $array"
wait_until "merge $merge_kill to end" "finished $merge_kill"
wait_until "merge $merge_default to end or show DependencyNeverSatisfied" \
  "finished $merge_default || [ \"\$(job_field $merge_default Reason)\" = DependencyNeverSatisfied ]"
report "$array" "array 0-3%2"
report "$merge_default" "afterok:$array"
report "$merge_kill" "afterok:$array, --kill-on-invalid-dep=yes"

expect_states "$array" "0 COMPLETED;1 COMPLETED;2 FAILED;3 COMPLETED;"
[ "$(job_field "$array" ExitCode | sort | tr '\n' ' ')" = "0:0 0:0 0:0 1:0 " ] ||
  fail "array $array: unexpected exit codes $(job_field "$array" ExitCode | tr '\n' ' ')"
expect_states "$merge_default" "- PENDING;"
expect_states "$merge_kill" "- CANCELLED;"
[ "$(job_field "$merge_kill" Reason)" = DependencyNeverSatisfied ] ||
  fail "merge $merge_kill: reason $(job_field "$merge_kill" Reason)"
for i in 0 1 3; do [ -s "$out/task-$i" ] || fail "task $i wrote no task-$i"; done
[ ! -e "$out/task-2" ] || fail "the failed task 2 wrote task-2"
[ ! -e "$out/merged" ] || fail "a merge job ran although the array failed"

# A merge job left pending forever would keep the sweep's queue busy: cancel it.
scancel "$merge_default"
wait_until "merge $merge_default to be cancelled" \
  "[ \"\$(job_field $merge_default JobState)\" = CANCELLED ]"
report "$merge_default" "afterok:$array, after scancel"

# 2. The failed task alone, under its own index, and a new merge job depending on it.
retry=$(submit --job-name=shard --array=2 "$work/task.sh" "$out")
merge_retry=$(submit --job-name=merge --dependency=afterok:"$retry" --kill-on-invalid-dep=yes \
  "$work/merge.sh" "$out")
echo "smoke: resubmitted task 2 as array $retry, merge $merge_retry"
wait_until "merge $merge_retry to finish" "finished $merge_retry"
report "$retry" "array 2"
report "$merge_retry" "afterok:$retry"

expect_states "$retry" "2 COMPLETED;"
expect_states "$merge_retry" "- COMPLETED;"
grep -qx "array job $retry task 2 (job $retry)" "$out/task-2" ||
  fail "task-2 is not from the resubmitted task: $(cat "$out/task-2")"
[ "$(wc -l < "$out/merged")" -eq 4 ] || fail "merged has $(wc -l < "$out/merged") lines, not 4"
echo "smoke: merged:"
sed 's/^/    /' "$out/merged"

passed=1
echo "smoke: PASS in $((SECONDS - t0))s"
