#!/usr/bin/env bash
# The residual analyses of the real recordings in ../shared/data/raw (docs/residuals/README.md):
#  - the FOTS press/shear pair (sphere pose estimated from the image at import): the residual loop with
#    the press calibrating and the shear validating, for each model;
#  - the gsrobotics and incipient-slip recordings (pose unknown): the release phase, where every model
#    predicts zero (shearbench release).
#   usage: docs/residuals/run_real.sh [build/shearbench]      (data root: $SHEARBENCH_DATA or ../shared/data)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
exe=${1:-$here/../../build/shearbench}
data=${SHEARBENCH_DATA:-$here/../../../shared/data}
imp=$(mktemp -d)
trap 'rm -rf "$imp"' EXIT
"$exe" import --source fots --in "$data/raw/fots_marker_calib" --out "$imp/fots" >/dev/null
"$exe" import --source gsrobotics --in "$data/raw/gsrobotics_tracking" --out "$imp/gsrobotics" >/dev/null
"$exe" import --source incipient_slip --in "$data/raw/incipient_slip" --out "$imp/incipient_slip" >/dev/null
for model in fots-reimpl hydroshear tacsl; do
  mkdir -p "$here/real_fots_pair_$model"
  "$exe" --reproducible residual --dataset "$imp/fots" --model "$model" --calibration press \
    --json "$here/real_fots_pair_$model/residual.json" --report "$here/real_fots_pair_$model/report.md"
done
# The real TacTip set: the shipped parameter set's subset (the first 20 calibration samples fit, every 5th
# validation sample scores; params --rebuild --set tactip_shear). HydroShear without its model-form round:
# a variant's fit through the dome's output stage takes 15-20 min (issue 32).
"$exe" import --source tactip_shear --in "$data/raw/tactip_shear" --out "$imp/tactip" >/dev/null
read -r cal val < <(python3 - "$imp/tactip/dataset.json" <<'PY'
import json, sys
samples = json.load(open(sys.argv[1]))["samples"]
cal = [s["id"] for s in samples if s["split"] == "calibration"][:20]
val = [s["id"] for s in samples if s["split"] == "validation"][::5]
print(",".join(cal), ",".join(val))
PY
)
for model in fots-reimpl hydroshear tacsl; do
  mkdir -p "$here/real_tactip_$model"
  forms=(); [[ $model == hydroshear ]] && forms=(--no-model-forms)
  "$exe" --reproducible residual --dataset "$imp/tactip" --model "$model" --calibration "$cal" --validation "$val" \
    "${forms[@]}" --max-iterations 10 \
    --json "$here/real_tactip_$model/residual.json" --report "$here/real_tactip_$model/report.md"
done
mkdir -p "$here/real_release"
args=()
for d in "$imp"/gsrobotics/* "$imp"/incipient_slip/*; do args+=(--dataset "$d"); done
"$exe" release "${args[@]}" --json "$here/real_release/release.json" --report "$here/real_release/report.md"
