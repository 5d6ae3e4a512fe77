#!/bin/sh
# The TacTip shear set in the workbench: imports the first sample of each split from the data root into
# the build folder at test time (data is never committed), then renders validation image_14 (a 1.45 mm
# press with 2.1 mm of slide) with the flat surface as the indenter, the tracked pins in Measured and the
# real thresholded image (--frames) behind every panel.
# Usage: run_tactip_test.sh SHEARBENCH IMAGE_COMPARE OUT_DIR BASELINE_DIR MIN_SSIM
set -eu
exe=$1; compare=$2; out=$3; baselines=$4; min_ssim=$5
raw="${SHEARBENCH_DATA:?SHEARBENCH_DATA must name the data root}/raw/tactip_shear"
[ -d "$raw" ] || { echo "render test: missing $raw" >&2; exit 1; }
work="$out/tactip"
rm -rf "$work"; mkdir -p "$work"
# One sample per split is too few to identify the image-from-tool rotation: it is given, as the whole set's import
# identifies it (docs/sensors.md, "The TacTip import").
printf '{"image_from_tool_deg": -161.39}\n' >"$work/sensor.json"
"$exe" -q import --source tactip_shear --max-samples 1 --no-pin-prior --frames --sensor "$work/sensor.json" \
  --in "$raw" --out "$work/imported" >/dev/null
# The loop's answer for this sensor (docs/residuals/real_tactip_full_hydroshear) beside HydroShear by default, at the
# loop's fitted parameters: a panel the first view shows (not the contact variant the twin sets select).
report=$(xvfb-run -a -s "-screen 0 1600x900x24" "$exe" render --dataset "$work/imported" --sample val_0014 --report --out "$work/report.png")
echo "$report" | grep -q "HydroShear + dome_sway + tool_frame + skin_indentation" ||
  { echo "render test: the loop's answer is not beside HydroShear on the real TacTip:" >&2; echo "$report" >&2; exit 1; }
exec "$(dirname "$0")/run_render_test.sh" "$exe" "$compare" tactip "$out" "$baselines" "$min_ssim" \
  --dataset "$work/imported" --sample val_0014
