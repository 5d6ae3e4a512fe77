#!/usr/bin/env bash
# Ctrl-C (SIGINT) and SIGTERM cancel a long operation: exit code 130, progress was reported, the old
# output is untouched and no new output appears.
set -euo pipefail
exe=$1; work=$2
rm -rf "$work"; mkdir -p "$work"
data="${SHEARBENCH_DATA:?SHEARBENCH_DATA must name the data root}"
[[ -d "$data/twin/twin_sphere8" ]] || { echo "FAIL: missing dataset $data/twin/twin_sphere8"; exit 1; }

# run_and_interrupt SIGNAL PATTERN LOG CMD...: starts CMD, waits until its stderr matches PATTERN (the
# operation is under way), sends SIGNAL, and prints the exit code.
run_and_interrupt() {
  local sig=$1 pattern=$2 log=$3; shift 3
  "$@" 2>"$log" >/dev/null &
  local pid=$!
  for _ in $(seq 1 1200); do grep -q -- "$pattern" "$log" 2>/dev/null && break; sleep 0.1; done
  grep -q -- "$pattern" "$log" || { kill -9 $pid; echo "FAIL: no progress line matching '$pattern' in $log" >&2; return 1; }
  kill -s "$sig" $pid 2>/dev/null || { echo "FAIL: '$*' ended before the signal: too short to interrupt" >&2; return 1; }
  local rc=0
  wait $pid || rc=$?
  echo $rc
}

# fit: an existing parameter file stays as it was. Every model with the joint refinement (about 5 s
# after the first iteration line on a quiet 2-core machine): HydroShear alone fits twin_sphere8 in
# 0.2 s, which can end between two polls of the log.
printf '{"old": true}\n' > "$work/params.json"
cp "$work/params.json" "$work/params.expected"
rc=$(run_and_interrupt INT " iter " "$work/fit.log" "$exe" fit --dataset "$data/twin/twin_sphere8" --model all --out "$work/params.json")
[[ $rc == 130 ]] || { echo "FAIL: fit exit code $rc after SIGINT, expected 130"; cat "$work/fit.log"; exit 1; }
cmp "$work/params.json" "$work/params.expected" || { echo "FAIL: the cancelled fit changed params.json"; exit 1; }
grep -q "cancelled" "$work/fit.log" || { echo "FAIL: the fit did not say it was cancelled"; exit 1; }
echo "ok: fit cancelled by SIGINT (exit 130), params.json untouched"

# residual: SIGTERM, neither the JSON nor the report nor a plot appears.
rc=$(run_and_interrupt TERM "residual: \[" "$work/residual.log" "$exe" residual --dataset "$data/twin/twin_sphere8" \
       --model tacsl --json "$work/res.json" --report "$work/res.md")
[[ $rc == 130 ]] || { echo "FAIL: residual exit code $rc after SIGTERM, expected 130"; cat "$work/residual.log"; exit 1; }
left=$(find "$work" -name 'res.*' | wc -l)
[[ $left == 0 ]] || { echo "FAIL: the cancelled residual run left $left output files"; find "$work" -name 'res.*'; exit 1; }
echo "ok: residual cancelled by SIGTERM (exit 130), no output written"
