#!/usr/bin/env bash
# The same inputs give bit-identical outputs on the same machine (with --reproducible, which leaves
# wall-clock times out): evaluate, fit, residual, simulate; and render when the GUI is built.
set -euo pipefail
exe=$1; work=$2
rm -rf "$work"; mkdir -p "$work/a" "$work/b"
data="${SHEARBENCH_DATA:?SHEARBENCH_DATA must name the data root}"
ds="$data/twin/twin_sphere8"
[[ -d "$ds" ]] || { echo "FAIL: missing dataset $ds"; exit 1; }
src=$(cd "$(dirname "$0")/../.." && pwd)

for run in a b; do
  d="$work/$run"
  "$exe" -q --reproducible evaluate --dataset "$ds" --model all --json "$d/eval.json" >/dev/null
  "$exe" -q --reproducible fit --dataset "$ds" --model tacsl --max-iterations 8 --out "$d/fit.json"
  # The base parameters as given (the fit above): only the effect's parameters are fitted, which keeps
  # this test short; the joint path runs the same deterministic code.
  "$exe" -q --reproducible residual --dataset "$ds" --model tacsl --params "$d/fit.json" --effects lens_distortion \
    --resamples 200 --json "$d/res.json" --report "$d/res.md"
  "$exe" -q --reproducible simulate --scene "$src/scenes/shear_sphere.json" --model hydroshear --out "$d/sim" >/dev/null
done
diff -r "$work/a" "$work/b" >/dev/null || { echo "FAIL: two runs differ:"; diff -rq "$work/a" "$work/b"; exit 1; }
echo "ok: evaluate, fit, residual (with plots) and simulate outputs are bit-identical across runs"

if "$exe" --help | grep -q "^ *render"; then
  for run in a b; do
    ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" xvfb-run -a -s "-screen 0 1280x800x24" "$exe" --reproducible render --scene "$src/scenes/press_sphere.json" --size 800x500 \
      --out "$work/$run/render.png" >/dev/null 2>&1
  done
  cmp "$work/a/render.png" "$work/b/render.png" || { echo "FAIL: two renders of the same scene differ"; exit 1; }
  echo "ok: two headless renders are pixel-identical"
fi
