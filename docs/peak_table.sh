#!/usr/bin/env bash
# Peak |d| (px) at the last step of every scene in scenes/ for HydroShear, FOTS (re-impl.) and TacSL with
# the default parameter set (docs/workbench.md, "Do the models agree"). Run from the repository root:
#   bash docs/peak_table.sh [build/shearbench]
set -uo pipefail
exe=${1:-build/shearbench}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
echo "scene hydroshear fots-reimpl tacsl"
for s in scenes/*.json; do n=$(basename $s .json); line="$n"; for m in hydroshear fots-reimpl tacsl; do "$exe" -q simulate --scene $s --model $m --out $tmp/$n/$m >/dev/null 2>&1 || { line="$line fail"; continue; }; p=$(python3 -c "
import csv,glob,math
f=glob.glob('$tmp/$n/$m/*/markers.csv')[0]
rows=list(csv.DictReader(open(f)))
last=max(int(r['frame']) for r in rows)
print(round(max((math.hypot(float(r['du_px']),float(r['dv_px'])) for r in rows if int(r['frame'])==last and r['du_px']!='nan'),default=0),3))"); line="$line $p"; done; echo "$line"; done
