#!/usr/bin/env bash
# SIGKILL while an output is being written must leave the user's old file byte-identical.
# The write hook SHEARBENCH_TEST_WRITE_DELAY_MS holds the process between "temporary complete" and
# "rename", the one moment where a non-atomic writer would have truncated the target already.
set -euo pipefail
exe=$1; work=$2
rm -rf "$work"; mkdir -p "$work"
out="$work/bench.json"
printf 'the user'"'"'s old file\n' > "$out"
cp "$out" "$work/expected"

SHEARBENCH_TEST_WRITE_DELAY_MS=60000 "$exe" bench --model tacsl --envs 4 --steps 4 --json "$out" >/dev/null 2>&1 &
pid=$!
tmp="$work/.bench.json.tmp.$pid"
for _ in $(seq 1 600); do [[ -s "$tmp" ]] && break; sleep 0.1; done
if [[ ! -s "$tmp" ]]; then kill -9 $pid 2>/dev/null || true; echo "FAIL: the temporary $tmp never appeared"; exit 1; fi
kill -9 $pid
wait $pid 2>/dev/null || true
cmp "$out" "$work/expected" || { echo "FAIL: $out changed although the writer was killed before the rename"; exit 1; }
echo "ok: killed during the write; $out intact; the complete temporary $(basename "$tmp") is hidden"

# The same command, not killed, replaces the file with a complete JSON document.
SHEARBENCH_TEST_WRITE_DELAY_MS=0 "$exe" bench --model tacsl --envs 4 --steps 4 --json "$out" >/dev/null
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d, "empty"' "$out" \
  || { echo "FAIL: $out is not a complete JSON document after an uninterrupted run"; exit 1; }
echo "ok: an uninterrupted run replaced $out"
