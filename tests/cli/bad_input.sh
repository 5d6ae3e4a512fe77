#!/usr/bin/env bash
# Bad input from the command line: exit code 2 and a message naming the file (or flag) and the place,
# never a crash (exit codes >= 128 are signals) and never an unexplained exit 1.
set -uo pipefail
exe=$1; work=$2
rm -rf "$work"; mkdir -p "$work"
fail=0
expect() {   # expect PATTERN CMD...: exit 2 and stderr matching PATTERN
  local pattern=$1; shift
  "$@" >/dev/null 2>"$work/err"; local rc=$?
  if [[ $rc != 2 ]] || ! grep -q -- "$pattern" "$work/err"; then
    echo "FAIL: '$*' exited $rc, stderr: $(cat "$work/err")"; fail=1
  else
    echo "ok: $* -> $(head -c 160 "$work/err")"
  fi
}
expect "unknown model 'nonsense'" "$exe" bench --model nonsense
expect "$work/nope" "$exe" check --dataset "$work/nope"
printf '{\n  "name": "x",\n  oops\n}\n' > "$work/broken_scene.json"
expect "broken_scene.json:3" "$exe" simulate --scene "$work/broken_scene.json" --model tacsl --out "$work/out"
expect "\-\-hold.*lambda_x: no stage of hydroshear fits it" "$exe" fit --dataset "$work/nope" --model hydroshear \
  --hold lambda_d,lambda_x --out "$work/fit.json"
exit $fail
