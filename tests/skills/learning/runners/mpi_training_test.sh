#!/usr/bin/env bash
# `flsd train` as an MPI job on loopback, end to end: two ranks train, one rank resumes their
# checkpoint and two resume again; a rank killed mid-run takes the job down with a message naming
# it, and the last checkpoint still resumes. `flsd train-selector` trains on two ranks and resumes
# on one.
# Usage: mpi_training_test.sh FLSD MPIRUN SOURCE_DIR
set -euo pipefail
flsd=$1 mpirun=$2 root=$3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
mpi=("$mpirun" -np 2 --oversubscribe --allow-run-as-root)
run="$dir/run"

fail() {
  echo "FAIL: $*" >&2
  [ -f "$dir/log" ] && cat "$dir/log" >&2
  exit 1
}
rows() { echo $(($(wc -l < "$run/progress.csv") - 1)); }
# env_steps (the second column) of the last progress row.
last_env_steps() { tail -1 "$run/progress.csv" | cut -d, -f2; }

# configs/smoke.yaml: 8 envs x 24 steps per iteration, a checkpoint every 2 iterations.
"${mpi[@]}" "$flsd" train --config "$root/configs/smoke.yaml" --out "$run" --iterations 4 --threads 1 \
  > "$dir/log" 2>&1 || fail "two ranks did not train"
grep -q "2 ranks, 4 envs and 1 threads each" "$dir/log" || fail "the job did not report its layout"
[ "$(rows)" -eq 4 ] || fail "two ranks: expected 4 progress rows (the leader's alone), got $(rows)"
[ "$(last_env_steps)" -eq $((4 * 8 * 24)) ] || fail "env_steps $(last_env_steps) is not the whole job's"

"$flsd" train --resume --out "$run" --iterations 6 > "$dir/log" 2>&1 || fail "one rank did not resume"
grep -q "resumed $run at iteration 4" "$dir/log" || fail "one rank did not resume at iteration 4"
[ "$(rows)" -eq 6 ] || fail "one rank: expected 6 progress rows, got $(rows)"

"${mpi[@]}" "$flsd" train --resume --out "$run" --iterations 8 --threads 1 > "$dir/log" 2>&1 ||
  fail "two ranks did not resume"
[ "$(rows)" -eq 8 ] || fail "two ranks again: expected 8 progress rows, got $(rows)"
[ "$(wc -l < "$run/commits")" -eq 3 ] || fail "expected one commits line per sitting"

# A rank killed mid-run: wait for a checkpoint past iteration 8, then kill the newest rank.
"${mpi[@]}" "$flsd" train --resume --out "$run" --iterations 100000 --threads 1 > "$dir/log" 2>&1 &
job=$!
for _ in $(seq 600); do
  [ "$(rows)" -ge 12 ] && break
  sleep 0.1
done
[ "$(rows)" -ge 12 ] || fail "the killed job never reached iteration 12"
pkill -KILL -n -f -- "flsd train --resume --out $run" || fail "no rank to kill"
status=0
wait "$job" || status=$?
[ "$status" -ne 0 ] || fail "the job exited 0 after losing a rank"
grep -qE "rank [0-9]+ .*exited on signal 9" "$dir/log" || fail "mpirun did not name the killed rank"

"$flsd" train --resume --out "$run" --iterations $(($(rows) + 1)) > "$dir/log" 2>&1 ||
  fail "the last checkpoint did not resume after the kill"
# The selector: two ranks train, one resumes.
run="$dir/selector"
"${mpi[@]}" "$flsd" train-selector --config "$root/configs/selector_smoke.yaml" --library "$root/models/a1_flsd.safetensors" \
  --out "$run" --iterations 2 --threads 1 > "$dir/log" 2>&1 || fail "two ranks did not train the selector"
grep -q "2 ranks, 4 envs and 1 threads each" "$dir/log" || fail "the selector job did not report its layout"
[ "$(rows)" -eq 2 ] || fail "selector on two ranks: expected 2 progress rows, got $(rows)"
# selector_smoke.yaml: 8 envs x 16 decisions of 1 control step per iteration.
[ "$(last_env_steps)" -eq $((2 * 8 * 16)) ] || fail "selector env_steps $(last_env_steps) is not the whole job's"
"$flsd" train-selector --resume --out "$run" --iterations 3 > "$dir/log" 2>&1 || fail "one rank did not resume the selector"
[ "$(rows)" -eq 3 ] || fail "selector on one rank: expected 3 progress rows, got $(rows)"
echo "PASS"
