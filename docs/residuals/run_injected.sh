#!/usr/bin/env bash
# The residual loop on finite-element twin data with one known effect put in, undeclared (`shearbench inject`):
# the loop must find that effect from its own evidence and nothing else (docs/residuals/README.md, "Injected
# effects"). HydroShear on twin_sphere35, the set the untouched answer is known for; about a minute each on two
# cores.
#   usage: docs/residuals/run_injected.sh [build/shearbench]      (data root: $SHEARBENCH_DATA or ../shared/data)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
exe=${1:-$here/../../build/shearbench}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# name | effect | its parameters | extra inject flags (creep needs a held press to show)
runs=(
  "creep_0.6s|viscoelastic_creep|tau_s=0.6,creep_fraction=0.3|--hold-frames 50"
  "lens_k1_-0.15|lens_distortion|k1=-0.15|"
  "subsurface_0.3mm|subsurface_markers|depth_m=0.0003|"
  "subsurface_1mm|subsurface_markers|depth_m=0.001|"
)
for run in "${runs[@]}"; do
  IFS='|' read -r name effect params extra <<<"$run"
  out="$here/injected_twin_sphere35_${name}_hydroshear"
  mkdir -p "$out"
  echo "== $name"
  # shellcheck disable=SC2086
  "$exe" inject --dataset data:twin/twin_sphere35 --effect "$effect" --set "$params" $extra --out "$work/$name" >/dev/null
  "$exe" --reproducible residual --dataset "$work/$name" --model hydroshear \
    --json "$out/residual.json" --report "$out/report.md"
done
