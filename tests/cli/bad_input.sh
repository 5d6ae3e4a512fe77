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
# Models by name (a form with effects): a typo in either part names the part.
expect "\-\-model.*unknown effect 'wobble'" "$exe" simulate --scene "$work/broken_scene.json" --model hydroshear+wobble --out "$work/out"
expect "\-\-model.*unknown model id 'hydroshear-nope'" "$exe" evaluate --dataset "$work/nope" --model hydroshear-nope+lens_distortion --json "$work/e.json"
expect "\-\-predictions.*one --model" "$exe" evaluate --dataset "$work/nope" --model all --predictions "$work/p.csv" --json "$work/e.json"
# residual: the greedy rounds' count outside 1..10, refused before any dataset is read.
expect "\-\-max-effects.*0" "$exe" residual --dataset "$work/nope" --model hydroshear --max-effects 0 --json "$work/r.json" \
  --report "$work/r.md"
[[ ! -e "$work/r.json" ]] || { echo "FAIL: the refused residual run wrote $work/r.json"; fail=1; }
# inject: an unknown effect, a value outside its range, and never into a folder that holds a dataset.
expect "\-\-effect.*unknown effect 'wobble'" "$exe" inject --dataset data:twin/twin_sphere8 --effect wobble --out "$work/inj"
expect "\-\-set.*tau_s.*range" "$exe" inject --dataset data:twin/twin_sphere8 --effect viscoelastic_creep --set tau_s=99 --out "$work/inj"
mkdir -p "$work/taken" && echo '{}' > "$work/taken/dataset.json"
expect "taken.*already holds a dataset" "$exe" inject --dataset data:twin/twin_sphere8 --effect lens_distortion --out "$work/taken"
[[ $(cat "$work/taken/dataset.json") == '{}' ]] || { echo "FAIL: inject overwrote $work/taken/dataset.json"; fail=1; }
# Too few calibration samples for the TacTip pin prior: refused before any work, naming the flag that avoids it
# (--max-samples 40 wrote samples with 0 of 327 pins tracked and only said "kept fraction min 0.0000").
expect "\-\-max-samples 66 or more" "$exe" import --source tactip_shear --in "$work/nope" --out "$work/imp" --max-samples 40
[[ ! -e "$work/imp" ]] || { echo "FAIL: the refused import wrote $work/imp"; fail=1; }
# The global options after the subcommand (`gui --data DIR` was refused as unexpected).
"$exe" check --data "$work" --dataset data:nope >/dev/null 2>"$work/err"
grep -q "$work/nope" "$work/err" && echo "ok: check --data DIR resolves data: through DIR" \
  || { echo "FAIL: check --data DIR (after the subcommand): $(cat "$work/err")"; fail=1; }
exit $fail
