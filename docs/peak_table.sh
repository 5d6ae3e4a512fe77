#!/usr/bin/env bash
# Peak |d| (px) at the last step of every scene in scenes/ for HydroShear, HydroShear (contact), FOTS (re-impl.)
# and TacSL with the default parameter set, as the Markdown table of docs/workbench.md ("Do the models agree"):
# the spread max/min of the authors' three, and of the three with the corrected HydroShear in HydroShear's place.
# Run from the repository root:
#   bash docs/peak_table.sh [build/shearbench]
set -uo pipefail
exe=${1:-build/shearbench}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
models="hydroshear hydroshear-contact fots-reimpl tacsl"
echo "| scene | HydroShear | HydroShear (contact) | FOTS (re-impl.) | TacSL | max / min, authors' three | max / min, with HydroShear (contact) |"
echo "|---|---:|---:|---:|---:|---:|---:|"
for s in scenes/*.json; do
  n=$(basename "$s" .json)
  peaks=()
  for m in $models; do
    if ! "$exe" -q simulate --scene "$s" --model "$m" --out "$tmp/$n/$m" >/dev/null 2>&1; then peaks+=(fail); continue; fi
    peaks+=("$(python3 -c "
import csv, glob, math
rows = list(csv.DictReader(open(glob.glob('$tmp/$n/$m/*/markers.csv')[0])))
last = max(int(r['frame']) for r in rows)
print(max((math.hypot(float(r['du_px']), float(r['dv_px'])) for r in rows
           if int(r['frame']) == last and r['du_px'] != 'nan'), default=0))")")
  done
  python3 -c "
import sys
n, p = sys.argv[1], sys.argv[2:]
if 'fail' in p:
    print(f'| {n} | ' + ' | '.join(p) + ' | fail | fail |'); sys.exit()
v = [float(x) for x in p]
spread = lambda a: f'{max(a) / min(a):.1f}' if min(a) > 0 else '–'
print(f'| {n} | ' + ' | '.join(f'{x:.2f}' for x in v) + f' | {spread([v[0], v[2], v[3]])} | {spread(v[1:])} |')
" "$n" "${peaks[@]}"
done
