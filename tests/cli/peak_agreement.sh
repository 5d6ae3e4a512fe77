#!/usr/bin/env bash
# The first view's models agree within a factor 3 on every scene: docs/peak_table.sh's table, run
# from the repository root with the default parameter set, and its last column (the spread of HydroShear
# (contact), FOTS (re-impl.) and TacSL peaks at the last step) at most 3 on every scene. The authors' three
# are printed beside it (they exceed 3 on the 4 mm sphere: docs/workbench.md says why).
# Usage: peak_agreement.sh SHEARBENCH SOURCE_DIR WORK_DIR
set -uo pipefail
exe=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
cd "$src" || exit 1
bash docs/peak_table.sh "$exe" > "$work/table.md" || { echo "FAIL: docs/peak_table.sh"; exit 1; }
cat "$work/table.md"
python3 - "$work/table.md" <<'PY'
import sys
rows = [l.strip().strip('|').split('|') for l in open(sys.argv[1]) if l.startswith('| ') and not l.startswith('| scene')]
bad, n = [], 0
for r in rows:
    r = [c.strip() for c in r]
    if 'fail' in r:
        bad.append(f"{r[0]}: a model failed to simulate"); continue
    if r[-1] == '–':
        continue   # every model at 0 (the replay ends after the unload)
    n += 1
    if float(r[-1]) > 3.0:
        bad.append(f"{r[0]}: spread {r[-1]} > 3")
if n < 18:
    bad.append(f"only {n} scenes with a field")
print("\n".join("FAIL: " + b for b in bad) if bad else f"ok: {n} scenes within a factor 3")
sys.exit(1 if bad else 0)
PY
