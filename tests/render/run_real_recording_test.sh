#!/bin/sh
# A real recording in the workbench: imports one gsrobotics video (the vendor's GelSight Mini recording,
# with its frames) from the data root into the build folder at test time (data is never committed),
# then renders a contact frame and compares it with its baseline like the scene tests.
# Usage: run_real_recording_test.sh SHEARBENCH IMAGE_COMPARE OUT_DIR BASELINE_DIR MIN_SSIM
set -eu
exe=$1; compare=$2; out=$3; baselines=$4; min_ssim=$5
video="${SHEARBENCH_DATA:?SHEARBENCH_DATA must name the data root}/raw/gsrobotics_tracking/video_1.avi"
[ -f "$video" ] || { echo "render test: missing $video" >&2; exit 1; }
work="$out/real_recording"
rm -rf "$work"; mkdir -p "$work/raw"
ln -s "$video" "$work/raw/video_1.avi"
"$exe" -q import --source gsrobotics --frames --in "$work/raw" --out "$work/imported" >/dev/null
exec "$(dirname "$0")/run_render_test.sh" "$exe" "$compare" real_recording "$out" "$baselines" "$min_ssim" \
  --dataset "$work/imported/video_1" --frame 9
