#!/usr/bin/env bash
# `cmake --install` into a scratch prefix, then the installed binary's checks (installed.sh) from outside
# the checkout. The checkout stays where it is (other tests run in it); what keeps the binary from it is
# that nothing in the binary names it, which this checks first: no path of the source tree in the
# executable, and installed.sh's set that only the prefix holds.
# Usage: install.sh BUILD_DIR SOURCE_DIR WORK_DIR   (SHEARBENCH_DATA set: also evaluate with --data)
set -euo pipefail
build=$1; src=$(realpath "$2"); work=$3
rm -rf "$work"; mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >"$work/install.log"
if grep -qF "$src" "$work/prefix/bin/shearbench"; then
  echo "FAIL: the installed executable names the source tree $src:"
  strings "$work/prefix/bin/shearbench" | grep -F "$src" | head -5
  exit 1
fi
echo "ok: installed $(find "$work/prefix" -type f | wc -l) files; the executable names no path under $src"
bash "$(dirname "$0")/installed.sh" "$work/prefix" "$work/run" "${SHEARBENCH_DATA:-}" "$src/examples/consumer"
