#!/usr/bin/env bash
# An installed shearbench (a `cmake --install` prefix or an unpacked .deb), run from a folder outside any
# checkout with no SHEARBENCH_HOME and no SHEARBENCH_DATA: it must find its scenes and parameter sets in
# PREFIX/share/shearbench (never the checkout it was built from), read data only through the root it is
# given, and say how to fix what is missing. Used by the cli_install test and by .ci/package (which also
# hides the checkout while this runs).
# The library from the same prefix: its CMake package builds CONSUMER_SRC (examples/consumer, copied out of
# the checkout), and Debian's python3 imports the module from PREFIX/lib/python3/dist-packages and computes
# the benchmark workload's field equal to `shearbench bench --field-out`'s.
# Usage: installed.sh PREFIX WORK_DIR [DATA_ROOT [CONSUMER_SRC]]   (DATA_ROOT given and not empty: also
# `--data DATA_ROOT evaluate`)
# The render runs under xvfb-run.
set -euo pipefail
prefix=$(realpath "$1"); work=$2; data=${3:-}; consumer=${4:-}
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

# The library, its header and its CMake package.
lib=$(ls "$prefix"/lib*/libshearbench.so.0 2>/dev/null | head -1 || true)
[[ -n $lib ]] || fail "not installed: $prefix/lib/libshearbench.so.0"
[[ -e $prefix/include/shearbench/sensor_model.hpp ]] || fail "not installed: $prefix/include/shearbench/sensor_model.hpp"
ls "$prefix"/lib*/cmake/shearbench/shearbenchConfig.cmake >/dev/null || fail "not installed: the CMake package"
if [[ -n $consumer ]]; then
  cmake -S "$consumer" -B consumer -G Ninja -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=$prefix" >consumer.log 2>&1 ||
    fail "configuring $consumer against $prefix: $(tail -n 5 consumer.log)"
  cmake --build consumer >>consumer.log 2>&1 || fail "building the consumer: $(tail -n 5 consumer.log)"
  ./consumer/consumer >consumer.txt || fail "the consumer: $(cat consumer.txt)"
  echo "ok: examples/consumer built with find_package(shearbench CONFIG) from $prefix: $(cat consumer.txt)"
fi

# The Python module, for Debian's python3: the benchmark workload's field equals `shearbench bench`'s.
pydir=$prefix/lib/python3/dist-packages
if compgen -G "$pydir/shearbench*.so" >/dev/null; then
  "$exe" bench --model hydroshear --envs 8 --field-out bench_field.json >/dev/null
  PYTHONPATH=$pydir /usr/bin/python3 - "$pydir" bench_field.json >python.txt <<'PY' || fail "python3: $(cat python.txt)"
import json, sys
import numpy as np
import shearbench
pydir, field_json = sys.argv[1:]
assert shearbench.__file__.startswith(pydir), f"imported {shearbench.__file__}, not the installed module"
want = json.load(open(field_json))
model = shearbench.SensorModel(want["model"], param_set="published", indenter="bench_peg", envs=2 * want["envs"])
for X in shearbench.bench_poses(want["envs"], want["steps"]):
    field = model.step(X, shearbench.bench_dt)
diff = np.abs(field.ravel() - np.array(want["field_px"])).max()
assert np.abs(field).max() > 0.1 and diff == 0, f"the module's field differs from shearbench bench's by {diff} px"
print(f"shearbench {shearbench.__version__} from {shearbench.__file__}: the bench field of {want['envs']} envs x 2 pads "
      f"equals shearbench bench's (max |disp| {np.abs(field).max():.3f} px)")
PY
  echo "ok: python3 -c 'import shearbench': $(cat python.txt)"
else
  fail "not installed: $pydir/shearbench*.so (the Python module)"
fi

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
