#!/usr/bin/env python3
"""Taps faster than a frame, scripted. Run under xvfb-run (1600x900 screen).

At 10 fps (a fit or an import running) a human click or key tap is shorter than a frame: its press and release
reach the window in one event poll. ImGui 1.86 reads a key or button only as down or up at a frame's start, so
such taps were lost by ImGui's own widgets (the workbench's shortcuts record their presses themselves). Here the
process is stopped (SIGSTOP) while xdotool makes the taps, then continued, so that every tap is polled at once,
and each journey checks that every tap landed, reading what the window shows (its title) and the session file
that Ctrl+S writes:
  1. ten clicks on the replay's ">" advance exactly ten steps;
  2. two clicks on Play after opening the cow are a play and a pause (the replay stays where it was), a third
     plays it;
  3. in the Open field, Ctrl+A, End and 60 BackSpaces empty it: what is typed next opens alone;
  4. a Ctrl+click on a parameter's slider, a value typed and Enter set that value.
"""
import os
import signal
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from journey_runner import journey_args, run_journeys  # noqa: E402  (the shared command line and loop)
from gui_journeys import Journeys  # noqa: E402  (the driving: start, keys, clicks, titles, the session file)

# Positions in the 1600x900 window, for scenes/press_cow.json as opened below (the layout of the headless PNG).
SIZE = "1600x900"
POS_OPEN_FIELD = (148, 66)
POS_OPEN_BUTTON = (346, 66)
POS_PLAY = (36, 91)
POS_REWIND = (87, 91)   # "|<": step -1, before the first step
POS_STEP = (143, 91)    # ">"
POS_SPEED = (286, 91)
POS_SLIDER_K = (143, 798)   # HydroShear's K (1 in the scene's parameter set)


class Taps(Journeys):
    def stopped(self, *xdotool_runs):
        """Each argument list run by xdotool while the process is stopped: all its events are polled at once."""
        os.kill(self.proc.pid, signal.SIGSTOP)
        try:
            for args in xdotool_runs:
                self.xdo(*args)
            time.sleep(0.2)
        finally:
            os.kill(self.proc.pid, signal.SIGCONT)

    def hover(self, pos):
        self.xdo("mousemove", "--window", self.wid, *pos)
        time.sleep(0.4)   # the move polled and drawn before the taps

    def saved_step(self):
        t = time.time()
        self.key("ctrl+s")
        d = self.wait_saved(t)
        return None if d is None else d.get("step")

    def open_cow(self):
        for attempt in range(2):
            failures = len(self.failures)
            if self.start("--scene", "scenes/press_cow.json", "--size", SIZE):
                return self.wait_title("press_cow") is not None
            # Seen once: glfwInit failed just after the previous window closed ("no X display"). One retry.
            if attempt == 0:
                self.say("the window did not open; once more")
                del self.failures[failures:]
                time.sleep(2.0)
        return False

    def wait_frames(self, seconds):
        """Every tap in its own frame: twenty clicks' events take 40 frames, well under a second here."""
        time.sleep(seconds)

    def journey_step_clicks(self):
        if not self.open_cow():
            return
        self.click(*POS_REWIND, settle=1.0)
        start = self.saved_step()
        self.check(start == -1, f"|< goes before the first step (step {start})")
        self.hover(POS_STEP)
        self.stopped(["click", "--repeat", "10", "--delay", "5", "1"])
        self.wait_frames(3.0)
        step = self.saved_step()
        self.check(step == 9, f"ten clicks on '>' polled at once advance ten steps: from -1 to {step} (expected 9)")
        self.kill()

    def set_slider(self, pos, text):
        """Ctrl+click on a slider makes it a text field: the value typed and Enter set it (made slowly)."""
        self.hover(pos)
        self.xdo("keydown", "--window", self.wid, "ctrl")
        time.sleep(0.3)
        self.xdo("click", "1")
        time.sleep(0.3)
        self.xdo("keyup", "--window", self.wid, "ctrl")
        time.sleep(0.3)
        self.key("ctrl+a")
        self.xdo("type", "--window", self.wid, "--delay", "20", text)
        self.key("Return")

    def journey_play_clicks(self):
        if not self.open_cow():
            return
        # At 0.05x a step takes 0.4 s: the replay between the two clicks' frames moves a step or two at most, and
        # a replay left playing is seen moving.
        self.set_slider(POS_SPEED, "0.05")
        self.click(*POS_REWIND, settle=1.0)
        self.hover(POS_PLAY)
        self.stopped(["click", "--repeat", "2", "--delay", "5", "1"])
        self.wait_frames(2.0)
        step = self.saved_step()
        time.sleep(2.0)
        again = self.saved_step()
        self.check(step is not None and step == again and step < 25,
                   f"two clicks on Play polled at once play and pause: the replay stays at {step} (2 s later: {again})")
        self.stopped(["click", "1"])
        self.wait_frames(3.0)
        later = self.saved_step()
        self.check(later is not None and again is not None and later > again,
                   f"a third click plays it: step {again} -> {later}")
        self.kill()

    def journey_text_field(self):
        if not self.open_cow():
            return
        self.type_into(POS_OPEN_FIELD, "data:twin/twin_frames")
        self.stopped(["key", "--window", self.wid, "--delay", "5", "ctrl+a", "End", *["BackSpace"] * 60])
        self.wait_frames(3.0)
        self.xdo("type", "--window", self.wid, "--delay", "20", "scenes/press_sphere.json")
        time.sleep(0.4)
        self.click(*POS_OPEN_BUTTON, settle=0.5)
        self.check(self.wait_title("press_sphere", timeout=30) is not None,
                   "Ctrl+A, End and 60 BackSpaces polled at once empty the Open field: the scene typed next opens")
        self.kill()

    def journey_slider(self):
        if not self.open_cow():
            return
        self.hover(POS_SLIDER_K)
        self.stopped(["keydown", "--window", self.wid, "ctrl"], ["click", "1"],
                     ["keyup", "--window", self.wid, "ctrl"],
                     ["key", "--window", self.wid, "--delay", "5", "ctrl+a", "2", "period", "5", "Return"])
        self.wait_frames(3.0)
        t = time.time()
        self.key("ctrl+s")
        d = self.wait_saved(t)
        k = None if d is None else d.get("params", {}).get("hydroshear", {}).get("K")
        self.check(k == 2.5, f"a Ctrl+click on K's slider, '2.5' and Enter polled at once set K to 2.5 (K = {k})")
        self.kill()


def main():
    a = journey_args()
    j = Taps(a)
    run_journeys(j, [j.journey_step_clicks, j.journey_play_clicks, j.journey_text_field, j.journey_slider], a.only)


if __name__ == "__main__":
    main()
