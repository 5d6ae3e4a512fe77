#!/usr/bin/env bash
# The MuJoCo example end to end: MuJoCo steps the peg grasp headless, both pads' fields come from the API
# each step, the log passes `shearbench check`, and `simulate` on each written scene reproduces that pad's
# logged field (within 1e-9 px: the poses pass through poses.csv).
# Usage: mujoco_grasp.sh MUJOCO_GRASP SHEARBENCH MJCF WORK_DIR
set -euo pipefail
example=$1; exe=$2; mjcf=$3; work=$4
rm -rf "$work"; mkdir -p "$work"
"$example" --mjcf "$mjcf" --out "$work/run" | tee "$work/run.log"
"$exe" -q check --dataset "$work/run/log" >"$work/check.log" || { cat "$work/check.log"; exit 1; }
for pad in left_pad right_pad; do
  "$exe" -q simulate --scene "$work/run/$pad.json" --model hydroshear --out "$work/sim_$pad"
  /usr/bin/python3 - "$work/run/log/$pad/markers.csv" "$work/sim_$pad/$pad/markers.csv" "$pad" <<'PY'
import csv, sys
logged, simulated, pad = sys.argv[1:]
def field(path):
    with open(path) as f:
        return {(r["frame"], r["marker"]): (float(r["du_px"]), float(r["dv_px"])) for r in csv.DictReader(f)}
a, b = field(logged), field(simulated)
assert a.keys() == b.keys(), f"{pad}: the simulated field has other frames or markers than the log"
worst = max(max(abs(p - q) for p, q in zip(a[k], b[k])) for k in a)
peak = max(max(abs(v) for v in a[k]) for k in a)
assert peak > 0.5, f"{pad}: the logged field peaks at {peak:.3f} px: the grasp did not press"
assert worst <= 1e-9, f"{pad}: simulate differs from the log by {worst:.3g} px"
print(f"ok: {pad}: simulate on the scene reproduces the log ({len(a)} values, peak {peak:.2f} px, worst {worst:.2g} px)")
PY
done
