#!/usr/bin/env python3
"""Nothing silent about a residual analysis (issue 52). Run under xvfb-run (1280x800 screen).

Drives the real `shearbench gui` (gui_journeys.py's driver: xdotool, the window title, the saved session):
  1. `gui --residual R` with no --dataset opens R's own dataset (the report's JSON names it): it opened the
     default scene and showed twin_sphere35's answer over it;
  2. `gui --dataset twin_frames --residual <twin_sphere35's report>` does not show the report (the saved session
     holds no residual section) and the window stays up; twin_frames' own report over twin_frames still loads;
  3. P writes its screenshot in the output folder (the per-user one: the session file is in a checkout here),
     not into the working folder (the repository).
"""
import functools
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from journey_runner import journey_args, run_journeys  # noqa: E402  (the shared command line and loop)
from gui_journeys import Journeys  # noqa: E402


def report(src, name):
    return os.path.join(src, "docs", "residuals", name, "residual.json")


def save(j):
    t = time.time()
    j.key("ctrl+s")
    return j.wait_saved(t)


def journey_own_dataset(j):
    j.start("--residual", report(j.src, "twin_sphere35_hydroshear"))
    j.check(j.wait_title("twin_sphere35 / ", timeout=90) is not None,
            "gui --residual <twin_sphere35's report> opens twin_sphere35, not the default scene")
    d = save(j)
    j.check(d is not None and d["open"].get("dataset", "").endswith("twin_sphere35")
            and d.get("residual", {}).get("file", "").endswith("twin_sphere35_hydroshear/residual.json"),
            "the session holds twin_sphere35 and its report")
    j.kill()


def journey_wrong_dataset(j):
    j.start("--dataset", "data:twin/twin_frames", "--residual", report(j.src, "twin_sphere35_hydroshear"))
    j.check(j.wait_title("twin_frames / ", timeout=90) is not None, "--dataset says otherwise: twin_frames opens")
    d = save(j)
    j.check(d is not None and "residual" not in d,
            "twin_sphere35's report is not shown over twin_frames (no residual in the saved session)")
    j.check(j.proc.poll() is None, "the window stays up after refusing the report")
    j.kill()
    os.remove(j.session)
    j.start("--dataset", "data:twin/twin_frames", "--residual", report(j.src, "twin_frames_hydroshear"))
    j.wait_title("twin_frames / ", timeout=90)
    d = save(j)
    j.check(d is not None and d.get("residual", {}).get("file", "").endswith("twin_frames_hydroshear/residual.json"),
            "twin_frames' own report over twin_frames loads")
    j.kill()


def journey_screenshot_folder(j):
    """P writes its screenshot beside the session file, or, as here, where the session file (the test's XDG state
    folder) is inside a checkout (the build folder), in $XDG_DATA_HOME/shearbench/output; never into the working
    folder (the repository: P twice wrote two PNGs into it)."""
    j.env["XDG_DATA_HOME"] = os.path.join(j.work, "data_home")
    beside = os.path.join(j.env["XDG_DATA_HOME"], "shearbench", "output")
    before = set(os.listdir(beside)) if os.path.isdir(beside) else set()
    j.start("--scene", "scenes/press_sphere.json")
    j.wait_title("press_sphere")
    j.xdo("mousemove", "--window", j.wid, 800, 400)   # over the 3D view, no field focused
    time.sleep(0.3)
    j.key("p")
    end = time.time() + 10
    new = []
    while time.time() < end and not new:
        new = [f for f in (os.listdir(beside) if os.path.isdir(beside) else []) if f not in before and f.endswith(".png")]
        time.sleep(0.2)
    j.check(bool(new), f"P wrote a screenshot in the user's output folder ({beside}): {new}")
    stray = os.path.join(j.src, "screenshots")
    j.check(not os.path.isdir(stray), "no screenshots/ folder in the working folder (the repository)")
    j.kill()


def main():
    a = journey_args()
    j = Journeys(a)
    run_journeys(j, [functools.partial(f, j) for f in (journey_own_dataset, journey_wrong_dataset, journey_screenshot_folder)], a.only)


if __name__ == "__main__":
    main()
