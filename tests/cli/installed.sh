#!/usr/bin/env bash
# An installed shearbench (a `cmake --install` prefix or an unpacked .deb), run from a folder outside any
# checkout with no SHEARBENCH_HOME and no SHEARBENCH_DATA: it must find its scenes and parameter sets in
# PREFIX/share/shearbench (never the checkout it was built from), read data only through the root it is
# given, and say how to fix what is missing. Used by the cli_install test and by .ci/package (which also
# hides the checkout while this runs).
# Usage: installed.sh PREFIX WORK_DIR [DATA_ROOT]   (DATA_ROOT given: also `--data DATA_ROOT evaluate`)
# The render runs under xvfb-run.
set -euo pipefail
prefix=$(realpath "$1"); work=$2; data=${3:-}
exe=$prefix/bin/shearbench
share=$prefix/share/shearbench
unset SHEARBENCH_HOME SHEARBENCH_DATA
rm -rf "$work"; mkdir -p "$work"; cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
# Runs "$@" expecting exit code 2 (bad input) and stderr matching every further -e pattern.
expect_error() {
  local log=$1; shift
  local rc=0; "$@" >/dev/null 2>"$log" || rc=$?
  [[ $rc == 2 ]] || fail "$* exited $rc, not 2: $(cat "$log")"
}
xvfb=(xvfb-run -a -s "-screen 0 1280x800x24")
# GL processes: no leak checking under the sanitizer build (see tests/render/run_render_test.sh).
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"

for f in bin/shearbench share/shearbench/scenes/default.json share/shearbench/assets/params/twin_sphere35.json \
         share/shearbench/assets/sphere_r4.obj share/shearbench/docs/models.md share/shearbench/LICENSE \
         share/shearbench/NOTICE share/shearbench/CHANGELOG.md; do
  [[ -e $prefix/$f ]] || fail "not installed: $prefix/$f"
done

"$exe" --version >version.txt
grep -Eq '^shearbench [0-9]+\.[0-9]+\.[0-9]+ \(commit [^)]+\)$' version.txt || fail "--version: $(cat version.txt)"
echo "ok: $(cat version.txt)"

# A set only the installed folder holds: `params` listing it shows the sets are read from there.
cp "$share/assets/params/twin_sphere8.json" "$share/assets/params/only_installed.json"
"$exe" params >params.txt
rm "$share/assets/params/only_installed.json"
grep -q '^twin_sphere35 (default)' params.txt || fail "params: no default set: $(head -3 params.txt)"
grep -q '^only_installed$' params.txt || fail "params does not read $share/assets/params"
echo "ok: params lists $(grep -c '^parameter set' params.txt) sets from $share/assets/params"

"$exe" -q simulate --scene "$share/scenes/shear_sphere.json" --model hydroshear --out sim >sim.log
[[ -s sim/dataset.json && -s sim/shear_sphere/markers.csv ]] || fail "simulate wrote no sim/dataset.json, sim/shear_sphere/markers.csv"
echo "ok: simulate --scene $share/scenes/shear_sphere.json ($(wc -l <sim/shear_sphere/markers.csv) lines of markers.csv)"

# No --scene: the installed default scene.
"${xvfb[@]}" "$exe" render --size 800x500 --no-timings --out default.png >render.log 2>&1 ||
  fail "render: $(tail -n 3 render.log)"
[[ $(head -c 8 default.png | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] || fail "render wrote no PNG"
echo "ok: render of the default scene: $work/default.png ($(stat -c %s default.png) bytes)"

# What is missing is named, with the ways to set it: the data root ...
expect_error nodata.err "$exe" evaluate --dataset data:twin/twin_sphere8 --model fots --json nodata.json
grep -q -- '--data' nodata.err && grep -q SHEARBENCH_DATA nodata.err || fail "no data root: $(cat nodata.err)"
echo "ok: without a data root: $(cat nodata.err)"
# ... and the home, for a copy of the executable with nothing beside it; --home gives it back.
cp "$exe" lone
expect_error lone.err ./lone params
grep -q SHEARBENCH_HOME lone.err && grep -q -- '--home' lone.err || fail "no home: $(cat lone.err)"
echo "ok: a lone copy says: $(cat lone.err)"
./lone --home "$share" params | grep -q '^twin_sphere35 (default)' || fail "--home $share: no parameter sets"
SHEARBENCH_HOME=$share ./lone params | grep -q '^twin_sphere35 (default)' || fail "SHEARBENCH_HOME: no parameter sets"
rm lone
echo "ok: --home and SHEARBENCH_HOME override"

if [[ -n $data ]]; then
  "$exe" --data "$data" evaluate --dataset data:twin/twin_sphere8 --model all --json eval.json >eval.txt
  [[ -s eval.json ]] || fail "evaluate wrote no eval.json"
  echo "ok: --data $data evaluate --dataset data:twin/twin_sphere8 --model all:"; grep '^| [a-z]' eval.txt
fi
echo "installed shearbench in $prefix: all checks passed"
