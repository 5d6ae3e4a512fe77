# Sourced by the tests that drive the real workbench under Xvfb (gui_keep_work.sh, gui_fields.sh).
# Prints the window id of the shearbench window of process $1. Waits up to WINDOW_WAIT_S (120 s: an ASan
# build starting VTK and llvmpipe on a machine whose two cores are busy with other tests has taken over
# 20 s), stops early when the process has exited, and on failure says on stderr what it waited for and how long.
WINDOW_WAIT_S=${WINDOW_WAIT_S:-120}
wait_window() {
  local start=$SECONDS
  while (( SECONDS - start < WINDOW_WAIT_S )); do
    if ! kill -0 "$1" 2>/dev/null; then
      echo "the workbench (pid $1) exited after $((SECONDS - start)) s before its window appeared" >&2; return 1
    fi
    local w; w=$(xdotool search --pid "$1" --name shearbench 2>/dev/null | head -1 || true)
    [[ -n "$w" ]] && { echo "$w"; return 0; }
    sleep 0.2
  done
  echo "waited ${WINDOW_WAIT_S} s for a window named 'shearbench' of pid $1 (xdotool search --pid), none appeared" >&2
  return 1
}
