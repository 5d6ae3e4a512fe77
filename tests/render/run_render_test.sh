#!/bin/sh
# One render test: draw a scene headless under Xvfb exactly as the GUI draws it, then compare with its
# baseline. Usage: run_render_test.sh SHEARBENCH IMAGE_COMPARE NAME OUT_DIR BASELINE_DIR MIN_SSIM [render args]
set -eu
exe=$1; compare=$2; name=$3; out=$4; baselines=$5; min_ssim=$6
shift 6
command -v xvfb-run >/dev/null || { echo "render test: xvfb-run is not installed (apt-get install xvfb xauth)" >&2; exit 1; }
mkdir -p "$out"
# Under the sanitizer build: Mesa's GL driver is dlclose'd before LeakSanitizer reports, so its one-time
# allocations show up as leaks from "<unknown module>" that no suppression can name; leak checking is
# off for processes that open a GL window (ASan and UBSan stay on). See docs/reliability.md.
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
xvfb-run -a -s "-screen 0 1600x900x24" "$exe" -q render --size 1280x800 --no-timings --out "$out/$name.png" "$@"
exec "$compare" "$baselines/$name.png" "$out/$name.png" "$out/${name}_diff.png" "$min_ssim"
