#!/usr/bin/env python3
"""Values typed where they are refused or flagged, and shortcuts only for the window (issue 52). Run under
xvfb-run with a screen larger than the window (1920x1080 for a 1600x900 window), so the pointer can leave it.

  1. z = -20 mm typed into the pose's xyz field (under the cow scene's 4.5 mm gel) is refused: the saved
     session's pose is the one before;
  2. kappa_d = -5 typed into its slider (Ctrl+click) is set to its bound 1 and a note says so (the window's log
     carries the note the field shows);
  3. with the pointer outside the window, P writes no PNG into the output folder; with it inside, P writes one.
"""
import glob
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from journey_runner import journey_args, run_journeys  # noqa: E402  (the shared command line and loop)
from gui_taps import Taps  # noqa: E402  (the driving, and taps made while the process is stopped)

# Positions in the 1600x900 window, for scenes/press_cow.json (the layout of the headless PNG at 1600x900).
SIZE = "1600x900"
POS_POSE_Z = (258, 191)          # the z of "xyz mm"
POS_SLIDER_KAPPA_D = (143, 748)  # HydroShear's kappa_d (range [1, 1e9] px/m)
POS_OUTSIDE = (1800, 1000)       # on the screen, beside the window
POS_INSIDE = (1100, 300)         # over a field panel


class Values(Taps):
    def ctrl_click_type(self, pos, keys):
        """Ctrl+click on a drag or slider field makes it a text field: `keys` typed and Enter, all polled at once
        (the process stopped meanwhile, as gui_taps.py's slider journey: the window feeds each its own frame)."""
        self.hover(pos)
        self.stopped(["keydown", "--window", self.wid, "ctrl"], ["click", "1"],
                     ["keyup", "--window", self.wid, "ctrl"],
                     ["key", "--window", self.wid, "--delay", "5", "ctrl+a", *keys, "Return"])
        time.sleep(3.0)

    def saved(self):
        t = time.time()
        self.key("ctrl+s")
        return self.wait_saved(t)

    def pose_z_mm(self, d):
        if not d or "path_X_EI" not in d:
            return None
        k = max(0, d.get("step", 0))
        return d["path_X_EI"][min(k, len(d["path_X_EI"]) - 1)][2] * 1e3

    def open_cow(self):
        self.out = os.path.join(self.work, "out")
        os.makedirs(self.out, exist_ok=True)
        for attempt in range(2):
            failures = len(self.failures)
            if self.start("--scene", "scenes/press_cow.json", "--size", SIZE, "--output-folder", self.out):
                return self.wait_title("press_cow") is not None
            # As gui_taps.py: glfwInit once failed just after the previous window closed ("no X display").
            if attempt == 0:
                self.say("the window did not open; once more")
                del self.failures[failures:]
                time.sleep(2.0)
        return False

    def journey_pose(self):
        if not self.open_cow():
            return
        before = self.pose_z_mm(self.saved())
        self.ctrl_click_type(POS_POSE_Z, ["minus", "2", "0"])
        after = self.pose_z_mm(self.saved())
        self.check(before is not None and after is not None and abs(after - before) < 1e-6,
                   f"z = -20 mm (under the 4.5 mm gel) is refused: the pose's z stays {before} mm (saved: {after})")
        self.kill()

    def journey_param(self):
        if not self.open_cow():
            return
        self.ctrl_click_type(POS_SLIDER_KAPPA_D, ["minus", "5"])
        d = self.saved()
        k = None if d is None else d.get("params", {}).get("hydroshear", {}).get("kappa_d")
        self.check(k == 1, f"kappa_d = -5 typed is set to its bound 1 (saved: {k})")
        self.log.flush()
        log = open(self.log.name).read()
        self.check("kappa_d: -5 is below its bound 1; set to 1" in log, "a note says kappa_d was set to its bound")
        self.kill()

    def pngs(self):
        return glob.glob(os.path.join(self.out, "**", "*.png"), recursive=True)

    def journey_shortcut_outside(self):
        if not self.open_cow():
            return
        self.xdo("mousemove", *POS_OUTSIDE)   # screen coordinates: beside the window
        time.sleep(0.6)
        self.key("p")
        time.sleep(2.0)
        outside = self.pngs()
        self.check(not outside, f"P with the pointer outside the window writes no PNG ({outside})")
        self.xdo("mousemove", "--window", self.wid, *POS_INSIDE)
        time.sleep(0.6)
        self.key("p")
        end = time.time() + 15
        while time.time() < end and len(self.pngs()) < 1:
            time.sleep(0.2)
        inside = self.pngs()
        self.check(len(inside) == 1, f"P with the pointer over the window writes one PNG ({inside})")
        self.kill()


def main():
    a = journey_args()
    j = Values(a)
    run_journeys(j, [j.journey_pose, j.journey_param, j.journey_shortcut_outside], a.only)


if __name__ == "__main__":
    main()
