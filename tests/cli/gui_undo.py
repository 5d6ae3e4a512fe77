#!/usr/bin/env python3
"""Nothing in the workbench changes for good without a word (issue 52), scripted. Run under xvfb-run (1600x900).

Each journey reads what the workbench writes: the session file Ctrl+S saves, and the window's title.
  1. at step 0 one nudge (Up) replaces the scene's path by a short one; Ctrl+Z brings the whole path back, at
     step 0, and Ctrl+Shift+Z the nudged one again;
  2. a parameter set by its slider (Ctrl+click, a value, Enter) goes back to what it was with Ctrl+Z;
  3. opening another scene over unsaved work (a nudge) keeps that work: Ctrl+Z in the new scene, with nothing of
     its own to undo, brings back the cow with its nudged path, unsaved.
"""
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from journey_runner import journey_args, run_journeys  # noqa: E402  (the shared command line and loop)
from gui_taps import POS_OPEN_BUTTON, POS_OPEN_FIELD, POS_SLIDER_K, SIZE, Taps  # noqa: E402  (positions, driving)

# The keeper looks at the work every 0.5 s: an edit is "unsaved" for an open after this long.
KEEPER_SETTLE_S = 1.5


class Undo(Taps):
    def save(self):
        t = time.time()
        self.key("ctrl+s")
        return self.wait_saved(t)

    def path_and_step(self):
        d = self.save()
        return (None, None) if d is None else (len(d.get("path_X_EI", [])), d.get("step"))

    def at_step_zero(self):
        self.key("Home")
        self.key("period")
        time.sleep(1.0)

    def journey_nudge(self):
        if not self.open_cow():
            return
        self.at_step_zero()
        steps, step = self.path_and_step()
        self.check(step == 0 and steps is not None and steps > 10, f"the scene at step 0: {steps} steps, step {step}")
        self.key("Up")
        time.sleep(1.5)   # the nudge's segment stepped
        nudged, _ = self.path_and_step()
        self.check(nudged is not None and steps is not None and nudged < steps,
                   f"one nudge at step 0 replaces the path: {steps} -> {nudged} steps")
        self.key("ctrl+z")
        time.sleep(1.5)
        back, back_step = self.path_and_step()
        self.check(back == steps and back_step == 0,
                   f"Ctrl+Z brings the scene's path back: {back} steps (expected {steps}), at step {back_step}")
        self.key("ctrl+shift+z")
        time.sleep(1.5)
        again, _ = self.path_and_step()
        self.check(again == nudged, f"Ctrl+Shift+Z redoes the nudge: {again} steps (expected {nudged})")
        self.kill()

    def saved_k(self):
        d = self.save()
        return None if d is None else d.get("params", {}).get("hydroshear", {}).get("K")

    def journey_slider(self):
        if not self.open_cow():
            return
        before = self.saved_k()
        # As gui_taps.py's slider journey: a Ctrl+click on K's slider, "2.5" and Enter.
        self.hover(POS_SLIDER_K)
        self.stopped(["keydown", "--window", self.wid, "ctrl"], ["click", "1"],
                     ["keyup", "--window", self.wid, "ctrl"],
                     ["key", "--window", self.wid, "--delay", "5", "ctrl+a", "2", "period", "5", "Return"])
        time.sleep(3.0)
        edited = self.saved_k()
        self.check(edited == 2.5, f"K set to 2.5 by its slider (K = {edited})")
        self.click(*POS_OPEN_FIELD[:1], 40, settle=0.5)   # away from the slider: it lets go
        self.key("ctrl+z")
        time.sleep(2.0)
        undone = self.saved_k()
        self.check(undone is not None and undone == before, f"Ctrl+Z sets K back: {undone} (expected {before})")
        self.kill()


    def tail_x(self):
        """The indenter's last x on the saved path (m), or None."""
        d = self.save()
        return d["path_X_EI"][-1][0] if d and d.get("path_X_EI") else None

    def journey_open(self):
        if not self.open_cow():
            return
        self.key("Right")
        time.sleep(1.5)    # the nudge stepped
        saved = self.tail_x()   # saved: the first nudge is in the file
        self.key("Right")  # ... the second is not
        time.sleep(KEEPER_SETTLE_S)
        self.type_into(POS_OPEN_FIELD, "scenes/press_sphere.json")
        self.click(*POS_OPEN_BUTTON, settle=0.5)
        if self.wait_title("press_sphere", timeout=30) is None:
            return self.kill()
        time.sleep(1.0)
        self.key("ctrl+z")
        self.check(self.wait_title("press_cow", timeout=30) is not None,
                   "Ctrl+Z after opening another scene over unsaved work brings the cow back")
        time.sleep(1.5)
        back = self.tail_x()
        self.check(back is not None and saved is not None and abs(back - (saved + 1e-4)) < 1e-9,
                   f"... with its unsaved nudge: x = {back} m (saved {saved} m, one more nudge of 0.1 mm)")
        self.kill()


def main():
    a = journey_args()
    j = Undo(a)
    run_journeys(j, [j.journey_nudge, j.journey_slider, j.journey_open], a.only)


if __name__ == "__main__":
    main()
