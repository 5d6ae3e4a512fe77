#!/usr/bin/env bash
# The command line as a user mistypes it: a misspelt command or model gets "did you mean", evaluate prints its
# table with no output file named, and simulate never writes over a folder that holds files unless told --force.
set -uo pipefail
exe=$1; work=$2
src=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$work"; mkdir -p "$work"
fail=0
check() {   # check WHAT CONDITION...: prints ok or FAIL
  local what=$1; shift
  if "$@"; then echo "ok: $what"; else echo "FAIL: $what"; fail=1; fi
}
run() {     # run CMD...: stdout to $work/out, stderr to $work/err, exit code in $rc
  "$@" >"$work/out" 2>"$work/err"; rc=$?
}

run "$exe" evalute --dataset data:twin/twin_sphere8 --model all
check "a misspelt command exits 2 naming the nearest ($(head -c 120 "$work/err"))" \
  grep -q "unknown command 'evalute' (did you mean 'evaluate'?)" "$work/err"
[[ $rc == 2 ]] || { echo "FAIL: 'evalute' exited $rc"; fail=1; }
run "$exe" simulate --scene "$src/scenes/shear_sphere.json" --model hydroshaer --out "$work/never"
check "a misspelt model names the nearest ($(head -c 120 "$work/err"))" \
  grep -q "unknown model id 'hydroshaer' (did you mean 'hydroshear'?)" "$work/err"
run "$exe" simulate --scene "$src/scenes/shear_sphere.json" --model hydroshear+lens_distorton --out "$work/never"
check "a misspelt effect names the nearest" grep -q "did you mean 'lens_distortion'" "$work/err"
[[ ! -e $work/never ]] || { echo "FAIL: a refused simulate wrote $work/never"; fail=1; }

run "$exe" evaluate --dataset data:twin/twin_sphere8 --model tacsl --split validation
check "evaluate without --json prints its table (rc $rc)" grep -q "^| .*tacsl" "$work/out"

# simulate into a new folder, then again into the same one: refused, the first dataset untouched; --force
# replaces it whole (no file of the old run left behind).
run "$exe" -q simulate --scene "$src/scenes/shear_sphere.json" --model tacsl --out "$work/sim"
check "simulate writes a new folder (rc $rc)" test -s "$work/sim/dataset.json"
touch "$work/sim/my_notes.txt"
before=$(md5sum "$work/sim/dataset.json")
run "$exe" -q simulate --scene "$src/scenes/shear_sphere.json" --model hydroshear --out "$work/sim"
check "simulate refuses a folder that holds files, exit 2 ($(head -c 160 "$work/err"))" \
  bash -c "[[ $rc == 2 ]] && grep -q 'already holds files.*--force' '$work/err'"
check "the refused run left the old dataset as it was" test "$(md5sum "$work/sim/dataset.json")" == "$before"
run "$exe" -q simulate --scene "$src/scenes/shear_sphere.json" --model hydroshear --out "$work/sim" --force
check "--force replaces the folder (rc $rc)" grep -q '"model": "hydroshear"' "$work/sim/dataset.json"
check "--force leaves none of the old folder's files" test ! -e "$work/sim/my_notes.txt"
check "--force leaves no hidden temporary beside it" bash -c "! ls -a '$work' | grep -q '^\.sim\.'"
mkdir -p "$work/empty"
run "$exe" -q simulate --scene "$src/scenes/shear_sphere.json" --model tacsl --out "$work/empty"
check "an empty folder is taken as new (rc $rc)" test -s "$work/empty/dataset.json"
exit $fail
