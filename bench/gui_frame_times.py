#!/usr/bin/env python3
"""Frame times of the workbench while the indenter is dragged, as a user drags it (issue 52's goal: at 1280 x 800
with every panel on, p90 <= 40 ms and p99 <= 80 ms on 2 cores). A measurement, not a test: run it on a quiet
machine under Xvfb and read the numbers; docs/workbench.md quotes its output.

    xvfb-run -n 85 -s "-screen 0 1280x800x24" python3 bench/gui_frame_times.py --exe build/shearbench \
        --seconds 60 --out /tmp/frame_times.json

What it does: opens `gui --size 1280x800 --stats` on a scene (default: the first view), waits for the first
frames, then drags the indenter in the 3D view for --seconds in loops of slides in the pad plane, Shift+drags
(press in / pull out) and Ctrl+drags (twist), with a mouse event every --move-ms like a hand on a mouse; every
frame time the workbench reports from the first to the last second of the drag is pooled (`--stats` writes each
one) and its percentiles printed. Nothing is written into the checkout: the stats and any output go to a temporary
folder.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time

POS_INDENTER = (483, 115)  # the indenter in the iso view at the first view's start (tests/cli/soak.py)


def xdo(*args):
    return subprocess.run(["xdotool", *map(str, args)], capture_output=True, text=True).stdout.strip()


def percentile(sorted_ms, q):
    """Nearest rank, as widgets/frame_stats.cpp computes its own."""
    rank = max(1, math.ceil(q * len(sorted_ms)))
    return sorted_ms[min(len(sorted_ms), rank) - 1]


def start_gui(exe, scene, work, stats):
    cmd = [exe, "gui", "--size", "1280x800", "--stats", stats, "--stats-interval", "1",
           "--output-folder", work]
    if scene:
        cmd += ["--scene", scene]
    log = open(os.path.join(work, "gui.log"), "w")
    env = dict(os.environ, XDG_STATE_HOME=work)  # the session Ctrl+S writes goes to the temporary folder
    proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env)
    end = time.time() + 120
    while time.time() < end and proc.poll() is None:
        w = xdo("search", "--pid", proc.pid, "--name", "shearbench").split()
        if w:
            return proc, w[0], time.time()
        time.sleep(0.2)
    sys.exit(f"no workbench window from: {' '.join(cmd)} (log: {log.name})")


def drag(wid, seconds, move_ms):
    """Slides, presses and twists in turn, each a circle of mouse moves around the indenter."""
    x0, y0 = POS_INDENTER
    gestures = [None, "shift", "ctrl"]
    end = time.time() + seconds
    g = 0
    while time.time() < end:
        mod = gestures[g % len(gestures)]
        g += 1
        xdo("mousemove", "--window", wid, x0, y0)
        if mod:
            xdo("keydown", mod)
        xdo("mousedown", 1)
        for k in range(60):
            a = 2 * math.pi * k / 60
            xdo("mousemove", "--window", wid, int(x0 + 30 * math.sin(a)), int(y0 + 20 * (1 - math.cos(a))))
            time.sleep(move_ms / 1000)
            if time.time() >= end:
                break
        xdo("mouseup", 1)
        if mod:
            xdo("keyup", mod)


def pooled_frame_ms(stats, t_from_s, t_to_s):
    """Every frame time of the --stats lines whose window lies inside [t_from_s, t_to_s] (the GUI's clock)."""
    ms = []
    with open(stats) as f:
        for line in f:
            d = json.loads(line)
            if d["t_s"] - d["window_s"] >= t_from_s and d["t_s"] <= t_to_s:
                ms += d["frame_ms"]
    return sorted(ms)


def saved_path_poses(work):
    """How many poses the session saved after the drag holds (the first view's own path is short: a drag that
    moved the indenter adds one per physics step of the drag); -1 when no session was saved."""
    for root, _, files in os.walk(work):
        if "session.json" in files:
            with open(os.path.join(root, "session.json")) as f:
                return len(json.load(f).get("path_X_EI", []))
    return -1


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--exe", required=True)
    p.add_argument("--scene", default="", help="a scene file (default: the workbench's first view)")
    p.add_argument("--seconds", type=float, default=60)
    p.add_argument("--move-ms", type=float, default=16, help="time between two mouse moves of the drag")
    p.add_argument("--settle", type=float, default=8, help="seconds after the window opens before the drag")
    p.add_argument("--out", help="write the figures as JSON here")
    a = p.parse_args()
    work = tempfile.mkdtemp(prefix="shearbench_frame_times_")
    stats = os.path.join(work, "stats.jsonl")
    proc, wid, window_t = start_gui(os.path.abspath(a.exe), a.scene, work, stats)
    time.sleep(a.settle)
    xdo("key", "--window", wid, "r")  # camera reset: the indenter where POS_INDENTER expects it
    time.sleep(0.5)
    t_from = time.time() - window_t
    drag(wid, a.seconds, a.move_ms)
    t_to = time.time() - window_t
    time.sleep(2.5)  # the stats line that covers the drag's end
    xdo("key", "--window", wid, "ctrl+s")  # the saved path says whether the drag moved the indenter
    time.sleep(2.0)
    proc.kill()
    proc.wait()
    ms = pooled_frame_ms(stats, t_from + 1, t_to)
    if not ms:
        sys.exit(f"no frame times in {stats} between {t_from:.1f} s and {t_to:.1f} s")
    figures = {"path_poses_saved": saved_path_poses(work), "frames": len(ms), "seconds": round(t_to - t_from, 1), "p50_ms": percentile(ms, 0.5),
               "p90_ms": percentile(ms, 0.9), "p99_ms": percentile(ms, 0.99), "max_ms": ms[-1],
               "load_average_1min": os.getloadavg()[0], "window": "1280x800", "scene": a.scene or "first view"}
    print(json.dumps(figures))
    if a.out:
        with open(a.out, "w") as f:
            json.dump(figures, f, indent=1)


if __name__ == "__main__":
    main()
