#!/usr/bin/env bash
# The workbench keeps the user's work (run under xvfb-run; keys sent with xdotool):
#  1. an edit (keyboard nudges of the indenter) is autosaved within the autosave interval;
#  2. closing with unsaved changes asks instead of closing (the process is still there);
#  3. after a crash (SIGKILL) the autosave is still there and restores (render --session uses the GUI's
#     restore path and must show the nudged pose);
#  4. a session without changes closes at once and leaves no autosave behind.
set -euo pipefail
exe=$1; work=$2
# GL processes: no leak checking under the sanitizer build (see tests/render/run_render_test.sh).
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
src=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$work"; mkdir -p "$work"
command -v xdotool >/dev/null || { echo "FAIL: xdotool is not installed (apt-get install xdotool)"; exit 1; }
[[ -n "${DISPLAY:-}" ]] || { echo "FAIL: no DISPLAY (run under xvfb-run)"; exit 1; }

# Shift+Esc (quit), held the way a person types it: the modifier down over several frames.
press_quit() {
  xdotool keydown --window "$1" shift; sleep 0.3
  xdotool key --window "$1" Escape; sleep 0.3
  xdotool keyup --window "$1" shift 2>/dev/null || true   # the window may be gone already
}

source "$(dirname "${BASH_SOURCE[0]}")/wait_window.sh"

export SHEARBENCH_AUTOSAVE="$work/autosave.json"
"$exe" gui --scene "$src/scenes/press_sphere.json" --autosave-interval 1 >"$work/gui1.log" 2>&1 &
pid=$!
wid=$(wait_window $pid) || { kill -9 $pid 2>/dev/null; echo "FAIL: the workbench window never appeared"; cat "$work/gui1.log"; exit 1; }
sleep 2   # first frames, models built
for _ in 1 2 3; do xdotool key --window "$wid" Right; sleep 0.3; done
for _ in $(seq 1 100); do [[ -s "$SHEARBENCH_AUTOSAVE" ]] && break; sleep 0.1; done
[[ -s "$SHEARBENCH_AUTOSAVE" ]] || { kill -9 $pid; echo "FAIL: no autosave within 10 s of an edit"; exit 1; }
grep -q '"format": "shearbench-session"' "$SHEARBENCH_AUTOSAVE" || { kill -9 $pid; echo "FAIL: the autosave is not a session file"; exit 1; }
echo "ok: the edit was autosaved to $SHEARBENCH_AUTOSAVE"

press_quit "$wid"
sleep 2
kill -0 $pid 2>/dev/null || { echo "FAIL: the workbench closed with unsaved changes without asking"; exit 1; }
echo "ok: closing with unsaved changes asked first (the window stayed open)"

kill -9 $pid; wait $pid 2>/dev/null || true
[[ -s "$SHEARBENCH_AUTOSAVE" ]] || { echo "FAIL: the autosave vanished with the crash"; exit 1; }
"$exe" render --session "$SHEARBENCH_AUTOSAVE" --size 800x500 --report --out "$work/restored.png" >"$work/restore.log" 2>&1 \
  || { echo "FAIL: the autosaved session does not restore"; cat "$work/restore.log"; exit 1; }
python3 - "$SHEARBENCH_AUTOSAVE" <<'PY' || exit 1
import json, sys
d = json.load(open(sys.argv[1]))
x = d["path_X_EI"][-1][0]
# press_sphere starts at x = 0; each Right nudge moves +0.1 mm.
assert x >= 0.1e-3 - 1e-12, f"FAIL: the autosaved pose x = {x} m does not hold the nudges"
print(f"ok: after a crash the autosave restores (indenter x = {x * 1e3:.1f} mm)")
PY

export SHEARBENCH_AUTOSAVE="$work/autosave_clean.json"
"$exe" gui --scene "$src/scenes/press_sphere.json" --autosave-interval 1 >"$work/gui2.log" 2>&1 &
pid=$!
wid=$(wait_window $pid) || { kill -9 $pid 2>/dev/null; echo "FAIL: the workbench window never appeared (second run)"; cat "$work/gui2.log"; exit 1; }
sleep 2
press_quit "$wid"
# "At once" for a person; the bound is generous because a sanitizer build on a loaded CI machine draws
# a frame in up to a second and tears VTK down slowly.
for _ in $(seq 1 300); do kill -0 $pid 2>/dev/null || break; sleep 0.1; done
if kill -0 $pid 2>/dev/null; then
  xdotool getwindowname "$wid" 2>/dev/null | sed 's/^/window title: /' || true
  kill -9 $pid; echo "FAIL: an unchanged session did not close within 30 s"; cat "$work/gui2.log"; exit 1
fi
rc=0; wait $pid || rc=$?
[[ $rc == 0 ]] || { echo "FAIL: the workbench exited with $rc"; cat "$work/gui2.log"; exit 1; }
[[ ! -e "$SHEARBENCH_AUTOSAVE" ]] || { echo "FAIL: a clean exit left an autosave"; exit 1; }
echo "ok: an unchanged session closed at once, no autosave left"
