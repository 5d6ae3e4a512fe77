#!/usr/bin/env bash
# The "Under degradation" tables of docs/tracking.md: every real GelSight recording tracked clean and
# under three strengths of each degradation (blur, noise, brightness drift, JPEG, dropped frames, a
# sliding occluder), scored against its own clean track. Run from the repository root:
#   bash docs/degrade_table.sh [build/shearbench] [out_dir]
# Writes out_dir/{gsrobotics,incipient_slip}.{md,json} (pooled table, then one table per clip).
# About 1 + 5 minutes on this machine (all frames of every clip; no subsampling).
set -euo pipefail
exe=${1:-build/shearbench}
out=${2:-degrade_study}
data="${SHEARBENCH_DATA:-../shared/data}"
gs="$data/raw/gsrobotics_tracking"
slip="$data/raw/incipient_slip"
for d in "$gs" "$slip"; do [[ -d "$d" ]] || { echo "FAIL: data missing: $d (set SHEARBENCH_DATA)" >&2; exit 1; }; done
mkdir -p "$out"
# video_4.avi is left out: OpenCV decodes no frame from it (docs/tracking.md).
"$exe" track-degrade --per-clip --video "$gs"/video_{0,1,2,3,5}.avi "$gs/mini_example.avi" \
  --json "$out/gsrobotics.json" --markdown "$out/gsrobotics.md" >/dev/null
"$exe" track-degrade --per-clip --video "$slip"/*/camera_*.avi \
  --json "$out/incipient_slip.json" --markdown "$out/incipient_slip.md" >/dev/null
echo "wrote $out/gsrobotics.md and $out/incipient_slip.md"
