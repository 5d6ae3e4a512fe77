#!/usr/bin/env bash
# Regenerates the residual analyses in this folder: every twin dataset with FOTS (re-impl.) and TacSL,
# and HydroShear on the smaller sets (its fits take longest). Each run fits the base model on the
# calibration split, then every catalogued effect (core/effects.hpp) with the base refitted jointly, and
# scores them on the validation split (shearbench residual; docs/effects.md has the selection rule).
#   usage: docs/residuals/run.sh [build/shearbench]      (data root: $SHEARBENCH_DATA or ../shared/data)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
exe=${1:-$here/../../build/shearbench}
runs=(
  "twin_frames fots-reimpl" "twin_frames tacsl" "twin_frames hydroshear"
  "twin_sphere8 fots-reimpl" "twin_sphere8 tacsl" "twin_sphere8 hydroshear"
  "twin_torus fots-reimpl" "twin_torus tacsl"
  "twin_punch fots-reimpl" "twin_punch tacsl"
  "twin_sphere35 fots-reimpl" "twin_sphere35 tacsl"
)
for run in "${runs[@]}"; do
  read -r set model <<<"$run"
  name="${set}_${model}"
  mkdir -p "$here/$name"
  echo "== $name"
  "$exe" --reproducible residual --dataset "data:twin/$set" --model "$model" \
    --json "$here/$name/residual.json" --report "$here/$name/report.md"
done
