#!/usr/bin/env bash
# `rigsim sweep --slurm` on a real one-node Slurm cluster (Debian's slurm-wlm, started in a
# temporary folder by scripts/slurm-cluster.sh and stopped on every exit, leaving nothing running):
#
#   1. a 4-cell sweep submitted as a job array of 4 shards (at most 2 at a time) and a merge job;
#      the merged results must equal a single-machine run of the same config byte for byte where
#      the content is deterministic (results.jsonl without timings, the plots);
#   2. the same sweep with shard 2 made to fail: the array reports the task FAILED, the merge job is
#      cancelled and writes nothing; the failed task resubmitted alone with a new merge job
#      completes the sweep, again equal to the single-machine run;
#   3. a 6-frame render submitted with `rigsim render --slurm` as 3 array tasks and a render-merge
#      job: the merged dataset equals a one-machine render byte for byte.
# Prints the job ids and the states Slurm reports (scontrol show job). Needs root (slurmd runs the
# jobs as root here), the built binary (scripts/build.sh) and jq. Exits non-zero on any failure.
#
#   bash scripts/slurm-test.sh            # about a minute
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
rigsim=$(cd "$here/.." && pwd)/${RIGSIM_BUILD_DIR:-build}/apps/rigsim/rigsim
[ -x "$rigsim" ] || { echo "slurm-test: build rigsim first (bash scripts/build.sh)" >&2; exit 1; }
command -v jq > /dev/null || { echo "slurm-test: needs jq (apt-get install jq)" >&2; exit 1; }
timeout_s=${SLURM_TEST_TIMEOUT:-300}
work=$(mktemp -d /tmp/rigsim-slurm-test.XXXXXX)
chmod a+x "$work"  # munged's socket must be reachable by all (slurm-cluster.sh)
cluster=$work/cluster
passed=0

cleanup() {
  bash "$here/slurm-cluster.sh" stop "$cluster" || echo "slurm-test: stopping the cluster failed" >&2
  if [ $passed -eq 1 ]; then rm -rf "$work"; else echo "slurm-test: FAILED; everything kept in $work" >&2; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

fail() { echo "slurm-test: FAIL: $*" >&2; exit 1; }
say() { echo "slurm-test: $*"; }

# "TASK STATE" per record of job $1 (sorted), "- STATE" for a job that is not an array.
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
finished() { ! job_states "$1" | grep -qE ' (PENDING|CONFIGURING|RUNNING|COMPLETING|SUSPENDED|REQUEUED)$'; }
wait_finished() {
  local deadline=$((SECONDS + timeout_s))
  until finished "$1"; do
    [ $SECONDS -ge $deadline ] && fail "timed out after ${timeout_s}s waiting for job $1"
    sleep 1
  done
}
show() {
  echo "  job $1:"
  scontrol -o show job "$1" | tr ' ' '\n' | grep -E '^(JobId|ArrayJobId|ArrayTaskId|JobState|Reason|ExitCode)=' |
    awk '/^JobId=/ && NR > 1 { print line; line = "" } { line = line " " $0 } END { print line }' | sed 's/^/   /'
}
expect_states() {
  local actual
  actual=$(job_states "$1" | tr '\n' ';')
  [ "$actual" = "$2" ] || fail "job $1: expected states '$2', got '$actual'"
}
# The job ids `rigsim sweep --slurm` printed.
array_id() { sed -n 's/^submitted job array \([0-9]*\) .*/\1/p' "$1"; }
merge_id() { sed -n 's/.* and the merge as job \([0-9]*\) .*/\1/p' "$1"; }
# The job array's and the merge job's ids from a submission's output LOG, into $array and $merge.
read_ids() {
  array=$(array_id "$1")
  merge=$(merge_id "$1")
  [ -n "$array" ] && [ -n "$merge" ] || fail "no job ids in the submission's output $1"
}
# Waits for the job (array) $1 and the merge job $2, prints them and checks their states: $3 for
# $1's tasks, $4 for the merge (expect_states' form).
expect_finished() {
  wait_finished "$1"
  wait_finished "$2"
  show "$1"
  show "$2"
  expect_states "$1" "$3"
  expect_states "$2" "$4"
}

# The deterministic content of a sweep's results: rows without timings, and the plots.
same_results() {
  local strip='with_entries(select((.key | test("^time_|time_s$")) | not))'
  diff <(jq -c "$strip" "$1/results.jsonl") <(jq -c "$strip" "$2/results.jsonl") > /dev/null ||
    fail "$2/results.jsonl differs from the single-machine run's (timings aside)"
  for f in "$1"/plots/*.png "$1"/plots/*.svg; do
    cmp -s "$f" "$2/plots/$(basename "$f")" || fail "$2/plots/$(basename "$f") differs from the single-machine run's"
  done
}

cat > "$work/tiny.yaml" <<'EOF'
name: slurm-tiny
base: {rig: ring, cameras: 2, spacing: 40, width: 200, height: 120, frames: 2, spp: 1}
methods: {semantics: [none]}
grid:
  radius: [0.3, 0.4, 0.5, 0.6]
EOF

t0=$SECONDS
eval "$(bash "$here/slurm-cluster.sh" start "$cluster")"
say "cluster up, SLURM_CONF=$SLURM_CONF"

"$rigsim" sweep "$work/tiny.yaml" --out "$work/single" > "$work/single.log" 2>&1 || fail "single-machine run: $(tail -3 "$work/single.log")"
say "single-machine run done ($((SECONDS - t0)) s)"

# 1. The whole sweep on the cluster.
"$rigsim" sweep "$work/tiny.yaml" --slurm --shards 4 --max-parallel 2 --cpus-per-task 1 --out "$work/on-slurm" \
  > "$work/submit.log" 2>&1 || fail "submission: $(cat "$work/submit.log")"
cat "$work/submit.log"
read_ids "$work/submit.log"
expect_finished "$array" "$merge" "0 COMPLETED;1 COMPLETED;2 COMPLETED;3 COMPLETED;" "- COMPLETED;"
same_results "$work/single" "$work/on-slurm"
say "1. job array $array and merge $merge completed; the merged results equal the single-machine run's"

# 2. Shard 2 fails: a file where its folder goes. The partition is held down until it is there.
scontrol update PartitionName=debug State=DOWN
"$rigsim" sweep "$work/tiny.yaml" --slurm --shards 4 --max-parallel 2 --cpus-per-task 1 --out "$work/failing" \
  > "$work/submit2.log" 2>&1 || fail "submission: $(cat "$work/submit2.log")"
mkdir -p "$work/failing/shards"
echo "not a folder" > "$work/failing/shards/2"
scontrol update PartitionName=debug State=UP
read_ids "$work/submit2.log"
expect_finished "$array" "$merge" "0 COMPLETED;1 COMPLETED;2 FAILED;3 COMPLETED;" "- CANCELLED;"
[ ! -e "$work/failing/results.csv" ] || fail "the merge wrote results although a task failed"
grep -q "is a file, not a folder" "$work/failing/slurm/logs/shard-2.log" || fail "task 2's log does not say why it failed"
say "2. task 2 of job array $array FAILED, merge $merge CANCELLED, no results written"

rm "$work/failing/shards/2"
retry=$(sbatch --parsable --array=2 "$work/failing/slurm/sweep.sbatch" | cut -d';' -f1)
merge=$(sbatch --parsable --dependency=afterok:"$retry" --kill-on-invalid-dep=yes "$work/failing/slurm/merge.sbatch" | cut -d';' -f1)
expect_finished "$retry" "$merge" "2 COMPLETED;" "- COMPLETED;"
same_results "$work/single" "$work/failing"
say "   task 2 resubmitted as job $retry and merge $merge: completed, equal to the single-machine run"

# 3. A render in shards on the cluster.
"$rigsim" make-rig ring --cameras 2 --width 200 --height 120 --frames 6 --out "$work/rig" > /dev/null
render=("$rigsim" render --scene "$here/../assets/scenes/street.glb" --rig "$work/rig/rig.json" --frames "$work/rig/frames.json" --spp 2 --coco)
"${render[@]}" --out "$work/render-single" > "$work/render-single.log" 2>&1 || fail "one-machine render: $(tail -3 "$work/render-single.log")"
"${render[@]}" --out "$work/render-slurm" --slurm --shards 3 --cpus-per-task 1 > "$work/submit3.log" 2>&1 ||
  fail "render submission: $(cat "$work/submit3.log")"
cat "$work/submit3.log"
read_ids "$work/submit3.log"
expect_finished "$array" "$merge" "0 COMPLETED;1 COMPLETED;2 COMPLETED;" "- COMPLETED;"
diff -r "$work/render-single" "$work/render-slurm" > /dev/null || fail "the merged render differs from the one-machine render"
say "3. render job array $array and render-merge $merge completed; the dataset equals the one-machine render byte for byte"

passed=1
say "PASS in $((SECONDS - t0)) s"
