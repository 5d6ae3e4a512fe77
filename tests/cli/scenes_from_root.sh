#!/usr/bin/env bash
# Every scene in scenes/ simulates and renders from the repository root with no flags and no
# SHEARBENCH_DATA: the default data root (../shared/data beside the repository) must be found, and a
# scene's data: paths must resolve against it once (a relative root used to be joined to the scene's
# folder: "scenes/../shared/data/meshes/cow.obj: indenter mesh not found").
# Usage: scenes_from_root.sh SHEARBENCH SOURCE_DIR WORK_DIR   (run under xvfb-run for the renders)
set -uo pipefail
exe=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
unset SHEARBENCH_DATA
# GL processes: no leak checking under the sanitizer build (see tests/render/run_render_test.sh).
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
cd "$src" || exit 1
if [[ ! -d ../shared/data ]]; then
  echo "FAIL: $src/../shared/data is missing: the test needs the data beside the repository"; exit 1
fi
fail=0; n=0
for scene in scenes/*.json; do
  name=$(basename "$scene" .json); n=$((n + 1))
  if ! "$exe" simulate --scene "$scene" --model hydroshear --out "$work/sim_$name" >"$work/$name.sim.log" 2>&1; then
    echo "FAIL: simulate $scene: $(tail -n 3 "$work/$name.sim.log")"; fail=1; continue
  fi
  if ! "$exe" render --scene "$scene" --size 640x400 --no-timings --out "$work/$name.png" >"$work/$name.render.log" 2>&1; then
    echo "FAIL: render $scene: $(tail -n 3 "$work/$name.render.log")"; fail=1; continue
  fi
  echo "ok: $scene"
done
# The first view's extra panel: auto (the default) and none are both accepted ("none" once failed its own check).
for beside in auto none; do
  if ! "$exe" render --beside-hydroshear "$beside" --size 640x400 --no-timings --out "$work/beside_$beside.png" \
      >"$work/beside_$beside.log" 2>&1; then
    echo "FAIL: render --beside-hydroshear $beside: $(tail -n 3 "$work/beside_$beside.log")"; fail=1
  fi
done
[[ $fail == 0 ]] && echo "all $n scenes simulate and render from the repository root without SHEARBENCH_DATA"
exit $fail
