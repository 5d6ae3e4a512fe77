#!/usr/bin/env bash
# Regenerates the residual analyses in this folder: every twin dataset with every model (FOTS re-impl.,
# TacSL, HydroShear). Each run fits the base model on the calibration split, then every catalogued effect
# (core/effects/effects.hpp), first alone over the recorded base field and, when that shows promise, with the
# base refitted jointly, and scores them on the validation split (shearbench residual; docs/effects.md
# has the selection rule, the bound verdict and the fingerprints).
#   usage: docs/residuals/run.sh [build/shearbench]      (data root: $SHEARBENCH_DATA or ../shared/data)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
exe=${1:-$here/../../build/shearbench}
runs=()
for set in twin_frames twin_sphere8 twin_torus twin_punch twin_sphere35; do
  for model in fots-reimpl tacsl hydroshear; do runs+=("$set $model"); done
done
for run in "${runs[@]}"; do
  read -r set model <<<"$run"
  name="${set}_${model}"
  mkdir -p "$here/$name"
  echo "== $name"
  "$exe" --reproducible residual --dataset "data:twin/$set" --model "$model" \
    --json "$here/$name/residual.json" --report "$here/$name/report.md"
done
