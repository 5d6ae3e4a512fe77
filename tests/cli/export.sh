#!/usr/bin/env bash
# Exports from the workbench's code path (run under xvfb-run): one panel as a PNG, and every model's
# field along the path as tsd/1 datasets that `check` accepts and `evaluate` reads back; a second export
# replaces the first; a folder that is not an export is refused (exit 2) and left as it was.
set -euo pipefail
exe=$1; work=$2
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"   # GL process (see gui_keep_work.sh)
src=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$work"; mkdir -p "$work"
scene="$src/scenes/shear_sphere.json"

"$exe" render --scene "$scene" --size 1280x800 --panel FOTS --out "$work/fots.png" >/dev/null
size=$(python3 -c "import struct,sys; d=open(sys.argv[1],'rb').read(24); print(*struct.unpack('>II', d[16:24]))" "$work/fots.png")
read -r w h <<<"$size"
# One of four panels in the right 75 % of 1280 px: about 230 px wide, a 4:3 image plus its title.
(( w > 150 && w < 320 && h > 120 && h < 280 )) || { echo "FAIL: the FOTS panel PNG is ${w}x${h}"; exit 1; }
echo "ok: --panel FOTS wrote a ${w}x${h} PNG"

for round in 1 2; do
  "$exe" render --scene "$scene" --size 800x500 --export-fields "$work/fields" --out "$work/all.png" >/dev/null
done
for m in hydroshear fots tacsl; do
  "$exe" check --dataset "$work/fields/$m" >/dev/null || { echo "FAIL: the exported $m dataset does not check"; exit 1; }
done
# The export of a model replays to itself. Not exactly: the indenter travels in the dataset as a mesh
# (meshes/*.obj), so the replay presses a tessellated sphere (measured: 0.004 px RMSE; bound 0.02 px).
# (FOTS: its field in this scene moves markers by more than the metric's 0.5 px threshold.)
"$exe" evaluate --dataset "$work/fields/fots" --model fots --json "$work/eval.json" >/dev/null
python3 - "$work/eval.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
def find(o):
    if isinstance(o, dict):
        for k, v in o.items():
            if k == "rmse_px" and v is not None: yield v
            yield from find(v)
    elif isinstance(o, list):
        for v in o: yield from find(v)
vals = list(find(d))
assert vals and max(vals) < 0.02, f"FAIL: fots against its own export: rmse {vals}"
print(f"ok: the exported fields check and replay to themselves (RMSE {max(vals):.4f} px)")
PY

mkdir -p "$work/mine/fots"; echo "my notes" > "$work/mine/fots/notes.txt"
rc=0; "$exe" render --scene "$scene" --size 800x500 --export-fields "$work/mine" --out "$work/x.png" 2>"$work/err.txt" || rc=$?
[[ $rc == 2 ]] || { echo "FAIL: exporting over a foreign folder exited $rc, expected 2"; exit 1; }
grep -q "not a shearbench field export" "$work/err.txt" || { echo "FAIL: no clear message"; cat "$work/err.txt"; exit 1; }
[[ "$(cat "$work/mine/fots/notes.txt")" == "my notes" && ! -e "$work/mine/fots/dataset.json" ]] \
  || { echo "FAIL: the foreign folder was touched"; exit 1; }
echo "ok: a folder that is not an export is refused and left alone"
