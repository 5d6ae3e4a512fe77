#!/usr/bin/env python3
"""The first hour in the workbench, scripted. Run under xvfb-run (1280x800 screen).

Drives the real `shearbench gui` through its input path only (xdotool keys, clicks, typing) and reads what
it shows through its window title ("shearbench - <what is open> - new session, not saved | unsaved changes |
saved | opening ..."), the files it writes and `gui --stats` (frame times). Journeys, each checking a point
of the issue:
  1. a fresh session does not say "saved"; switching the parameter set is a change (2);
  2. a scene typed into the Session field: Ctrl+S there (a text field has the focus) refuses to overwrite
     it, Open opens it as a scene without adopting its path, Shift+Esc asks, Enter saves to the default
     session path (the XDG state folder), and the scene file is byte-identical afterwards (1, 2, 4, 6);
  2b. a path typed into the Session field and saved with Ctrl+S stays the session file after an Esc: the next
     Ctrl+S saves it again, not the default session (Esc once put the old path back in the field);
  3. Ctrl+S while a text field has the focus saves; the camera (key 1: top) is saved; a dataset typed
     relative to the data root ("twin/twin_sphere35") opens on a worker while frames keep coming, and the
     residual analysis of another dataset is not shown over the scene (3, 5, 6); the Enter that opens it is tapped
     while the window is busy (press and release in one event poll: CI lost it under load, 2026-11-28);
  4. the saved session reopens (on the worker: frames keep coming) with its camera (5, "the view is saved");
  5. a sample with no marker tracked says so (7);
  6. at 1280x800 a field panel is at least 300 px wide (8);
  7. the RMSE timeline (issue 52): a click in its one plot seeks the replay to the step under the pointer, a drag
     seeks to where it ends, and its CSV button writes step, time_s and one column per model beside the session;
and that no file was written anywhere but the session path, the autosave beside it and this test's folder.
"""
import argparse
import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import time

# Positions in the 1280x800 window (left column), for scenes/press_sphere.json as opened below.
POS_PARAMETERS_HEADER = (60, 454)   # collapsing it brings Fit and Session up under it
POS_PARAM_SET_COMBO = (200, 604)    # its popup: published, real_fots_pair, ... (the second: +45)
POS_SESSION_FIELD = (100, 529)
POS_SESSION_OPEN = (230, 529)   # Parameters collapsed: no scrollbar, the column is 320 px
POS_OPEN_FIELD = (100, 66)
# The RMSE timeline for data:twin/twin_frames shr_00 (59 steps, 4 models: the plot is 4 x 38 - 4 = 148 px high
# under its header at y 181). Its plot area spans x 38..294 (the column's content less the 30 px RMSE axis), so
# step k's column is 38 + k * 256 / 59 .. (k + 1) * 256 / 59: the x below are mid-column.
TIMELINE_X0, TIMELINE_W, TIMELINE_STEPS, TIMELINE_Y = 38, 256, 59, 250
POS_TIMELINE_CSV = (18, 334)


class Journeys:
    def __init__(self, a):
        self.a = a
        self.exe = a.exe
        self.work = a.work
        self.src = a.src
        self.root = a.data
        self.state = os.path.join(self.work, "state")
        self.session = os.path.join(self.state, "shearbench", "session.json")
        self.env = dict(os.environ, XDG_STATE_HOME=self.state)
        self.env.pop("SHEARBENCH_AUTOSAVE", None)
        self.proc = None
        self.wid = None
        self.failures = []
        self.t0 = time.time()

    # ------------------------------------------------------------------------------------------- driving
    def say(self, msg):
        print(f"[{time.time() - self.t0:6.1f}s] {msg}", flush=True)

    def check(self, ok, msg):
        self.say(("ok: " if ok else "FAIL: ") + msg)
        if not ok:
            self.failures.append(msg)
        return ok

    def xdo(self, *args):
        return subprocess.run(["xdotool", *map(str, args)], capture_output=True, text=True).stdout.strip()

    def key(self, *keys):
        self.xdo("key", "--window", self.wid, *keys)
        time.sleep(0.3)

    def tap(self, key):
        """A tap made while the window is busy (a slow frame: here the process is stopped), so its press and its
        release reach the window in one event poll. ImGui 1.86 reads a key only as down or up at a frame's
        start and never sees such a tap; the workbench must still act on it (widgets/keys.cpp records it)."""
        os.kill(self.proc.pid, signal.SIGSTOP)
        try:
            self.xdo("keydown", "--window", self.wid, key, "keyup", "--window", self.wid, key)
            time.sleep(0.2)
        finally:
            os.kill(self.proc.pid, signal.SIGCONT)
        time.sleep(0.3)

    def click(self, x, y, settle=0.5):
        self.xdo("mousemove", "--window", self.wid, x, y)
        time.sleep(0.15)
        self.xdo("click", 1)
        time.sleep(settle)

    def type_into(self, pos, text):
        self.click(*pos, settle=0.4)
        self.key("ctrl+a")
        self.xdo("type", "--window", self.wid, "--delay", "20", text)
        time.sleep(0.4)

    def shift_escape(self):
        self.xdo("keydown", "--window", self.wid, "shift")
        time.sleep(0.3)
        self.xdo("key", "--window", self.wid, "Escape")
        time.sleep(0.3)
        self.xdo("keyup", "--window", self.wid, "shift")

    def title(self):
        return self.xdo("getwindowname", self.wid)

    def wait_title(self, *parts, timeout=60):
        end = time.time() + timeout
        t = ""
        while time.time() < end:
            t = self.title()
            if all(p in t for p in parts):
                return t
            if self.proc.poll() is not None:
                break
            time.sleep(0.1)
        self.check(False, f"window title never showed {parts} (last: '{t}')")
        return None

    def start(self, *args, stats=None):
        cmd = [self.exe, "gui", "--data", self.root, *args]   # --data after the subcommand
        if stats:
            cmd += ["--stats", stats, "--stats-interval", "0.5"]
        self.log = open(os.path.join(self.work, f"gui_{int(time.time() * 1000)}.log"), "w")
        self.proc = subprocess.Popen(cmd, cwd=self.src, env=self.env, stdout=self.log, stderr=subprocess.STDOUT)
        end = time.time() + 120
        while time.time() < end and self.proc.poll() is None:
            w = self.xdo("search", "--pid", self.proc.pid, "--name", "shearbench").split()
            if w:
                self.wid = w[0]
                self.window_t = time.time()   # about when --stats starts its clock
                time.sleep(1.0)   # first frames
                return True
            time.sleep(0.2)
        self.check(False, f"no window for {' '.join(cmd)}")
        return False

    def wait_exit(self, timeout=30):
        try:
            return self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            return None

    def kill(self):
        if self.proc and self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()

    def saved_session(self):
        with open(self.session) as f:
            return json.load(f)

    def wait_saved(self, after, timeout=15):
        end = time.time() + timeout
        while time.time() < end:
            if os.path.exists(self.session) and os.path.getmtime(self.session) > after:
                time.sleep(0.2)
                return self.saved_session()
            time.sleep(0.1)
        return None

    def frames_while(self, stats, t_from, t_to):
        """(frames drawn, longest frame in ms) over the --stats lines inside [t_from, t_to] (time.time())."""
        a, b = t_from - self.window_t, t_to - self.window_t
        frames, worst = 0, 0.0
        with open(stats) as f:
            for line in f:
                d = json.loads(line)
                if d["t_s"] - d["window_s"] >= a - 0.1 and d["t_s"] <= b + 0.1:
                    frames += d["frames"]
                    worst = max(worst, d["frame_ms_max"])
        return frames, worst

    def check_live(self, stats, t_from, t_to, what):
        """A load that froze the window draws no frame while it runs and one frame as long as the load; the
        window stays live when it draws at least 2 frames a second and no frame takes half the load."""
        time.sleep(1.2)   # the stats line covering the end
        frames, worst = self.frames_while(stats, t_from, t_to)
        span = t_to - t_from
        self.check(frames >= 2 * span and worst < 500 * span,
                   f"the window stayed live while {what} ({span:.1f} s): {frames} frames, longest {worst:.0f} ms")

    # ------------------------------------------------------------------------------------------ journeys
    def journey_overwrite(self):
        scene = os.path.join(self.work, "my_scene.json")
        shutil.copy(os.path.join(self.src, "scenes", "press_cow.json"), scene)
        digest = sha(scene)
        self.start("--scene", "scenes/press_sphere.json")
        self.check(self.wait_title("press_sphere", "new session, not saved") is not None,
                   "a fresh, never-saved session says 'new session, not saved', not 'saved'")
        # The parameter set: another set is a change (it said "saved" before).
        self.click(*POS_PARAM_SET_COMBO, settle=0.6)
        self.click(POS_PARAM_SET_COMBO[0], POS_PARAM_SET_COMBO[1] + 45, settle=0.6)
        self.check(self.wait_title("unsaved changes", timeout=30) is not None,
                   "switching the parameter set marks the session unsaved")
        self.click(*POS_PARAMETERS_HEADER, settle=1.0)   # collapse Parameters: Session comes up
        self.type_into(POS_SESSION_FIELD, scene)
        t = time.time()
        self.key("ctrl+s")   # the field still has the focus
        time.sleep(1.5)
        self.check(sha(scene) == digest and not os.path.exists(self.session) and "unsaved changes" in self.title(),
                   "Ctrl+S with a scene file in the Session field refuses to overwrite it (still unsaved)")
        self.click(*POS_SESSION_OPEN, settle=0.5)
        self.check(self.wait_title("press_cow", "unsaved changes") is not None,
                   "Session -> Open on a scene opens the scene (not as the session file)")
        self.shift_escape()
        time.sleep(2.0)
        self.check(self.proc.poll() is None, "Shift+Esc with unsaved changes asks first (the window stays)")
        self.key("Return")   # the dialog's first button: Save (to the session path, never the scene)
        rc = self.wait_exit()
        self.check(rc == 0, f"Save in the quit dialog saved and closed (exit {rc})")
        self.check(sha(scene) == digest, "the scene file is byte-identical after the quit dialog's Save")
        ok = os.path.exists(self.session) and self.saved_session().get("format") == "shearbench-session"
        self.check(ok, f"the session was saved to the default path {self.session} (XDG state folder)")
        if ok:
            self.check(os.path.samefile(self.saved_session()["open"]["scene"], scene),
                       "the saved session opens the scene that was opened")
        self.kill()

    def journey_session_escape(self):
        """A path typed into the Session field and saved with Ctrl+S is the session file: an Esc afterwards does
        not put the old path back in the field (the next Ctrl+S wrote the default session)."""
        mine = os.path.join(self.work, "mine.json")
        self.start("--scene", "scenes/press_sphere.json")
        if self.wait_title("press_sphere") is None:
            return self.kill()
        self.click(*POS_PARAMETERS_HEADER, settle=1.0)   # collapse Parameters: Session comes up
        self.type_into(POS_SESSION_FIELD, mine)
        t = time.time()
        self.key("ctrl+s")   # the field still has the focus
        time.sleep(1.5)
        self.check(os.path.exists(mine) and os.path.getmtime(mine) > t, f"Ctrl+S in the Session field saved {mine}")
        self.key("Escape")
        time.sleep(0.5)
        self.key("Right")    # an edit ...
        time.sleep(1.5)
        t = time.time()
        self.key("ctrl+s")   # ... saved where the session is
        time.sleep(2.0)
        default_untouched = not os.path.exists(self.session) or os.path.getmtime(self.session) <= t
        self.check(os.path.getmtime(mine) > t and default_untouched,
                   f"after Esc the next Ctrl+S saves {os.path.basename(mine)} again, not the default session")
        self.kill()

    def journey_open_dataset(self):
        residual = os.path.join(self.src, "docs", "residuals", "twin_frames_hydroshear", "residual.json")
        stats = os.path.join(self.work, "stats_open.jsonl")
        self.start("--scene", "scenes/press_sphere.json", "--residual", residual, stats=stats)
        self.wait_title("press_sphere")
        t = time.time()
        self.type_into(POS_OPEN_FIELD, "twin/twin_sphere35")   # no such folder here: the data root's
        self.key("ctrl+s")   # Ctrl+S while the Open field has the focus
        d = self.wait_saved(t)
        self.check(d is not None, "Ctrl+S saves while a text field has the focus")
        # twin_frames' report over a scene is refused (a report is shown only over its own dataset: gui_reports.py).
        self.check(d is not None and "residual" not in d, "a residual analysis of twin_frames is not shown over a scene")
        load_from = time.time()
        self.tap("Return")
        opening = self.wait_title("opening", timeout=10)
        self.check(opening is not None, "the dataset opens on a worker ('opening ...' in the title)")
        self.wait_title("twin_sphere35 / ", timeout=90)   # the new session's title (not "opening ...")
        self.check_live(stats, load_from, time.time(), "twin_sphere35 opened")
        self.check(self.wait_title("twin_sphere35 / ", "unsaved changes", timeout=5) is not None,
                   "opening another dataset is a change (unsaved)")
        self.key("1")   # camera: top
        time.sleep(0.5)
        t = time.time()
        self.key("ctrl+s")
        d = self.wait_saved(t)
        ok = d is not None
        self.check(ok and d["open"]["dataset"] == "data:twin/twin_sphere35",
                   "'twin/twin_sphere35' opened the data root's dataset (saved as data:twin/twin_sphere35)")
        self.check(ok and "residual" not in d, "the residual analysis was dropped with its dataset")
        cam = d.get("display", {}).get("camera") if ok else None
        self.check(cam is not None and abs(cam["position_mm"][0]) < 1e-6 and abs(cam["position_mm"][1]) < 1e-6,
                   f"the camera (top view) is in the session: {cam}")
        self.camera = cam
        self.shift_escape()
        self.check(self.wait_exit() == 0, "a saved session closes at once with Shift+Esc")
        self.kill()

    def journey_reopen(self):
        stats = os.path.join(self.work, "stats_reopen.jsonl")
        self.start("--session", self.session, stats=stats)
        self.check(self.wait_title("twin_sphere35 / ", " - saved", timeout=90) is not None, "the session reopens, saved")
        self.check_live(stats, self.window_t + 0.5, time.time(), "the session reopened")
        t = time.time()
        self.key("ctrl+s")
        d = self.wait_saved(t)
        cam = d.get("display", {}).get("camera") if d else None
        same = cam is not None and self.camera is not None and all(
            abs(a - b) < 1e-6 for k in cam for a, b in zip(cam[k], self.camera[k]))
        self.check(same, "the camera orbit came back from the session")
        self.shift_escape()
        self.wait_exit()
        self.kill()

    def journey_empty_sample(self):
        src = os.path.join(self.root, "twin", "twin_torus")
        dst = os.path.join(self.work, "empty_set")
        meta = json.load(open(os.path.join(src, "dataset.json")))
        sample = meta["samples"][0]["id"]
        meta["samples"] = meta["samples"][:1]
        shutil.copytree(os.path.join(src, sample), os.path.join(dst, sample),
                        ignore=shutil.ignore_patterns("frames"))
        if os.path.isdir(os.path.join(src, "meshes")):
            shutil.copytree(os.path.join(src, "meshes"), os.path.join(dst, "meshes"))
        meta["samples"][0]["has_frames"] = False
        json.dump(meta, open(os.path.join(dst, "dataset.json"), "w"), indent=1)
        markers = os.path.join(dst, sample, "markers.csv")
        rows = open(markers).read().splitlines()
        with open(markers, "w") as f:
            f.write(rows[0] + "\n")
            for r in rows[1:]:
                frame, marker = r.split(",")[:2]
                f.write(f"{frame},{marker},nan,nan\n")
        self.start("--dataset", dst)
        self.check(self.wait_title("no marker tracked", timeout=60) is not None,
                   "a sample with no marker tracked says so")
        self.shift_escape()
        self.wait_exit()
        self.kill()

    def timeline_x(self, step):
        return int(TIMELINE_X0 + (step + 0.5) * TIMELINE_W / TIMELINE_STEPS)

    def saved_step(self):
        t = time.time()
        self.key("ctrl+s")
        d = self.wait_saved(t)
        return d.get("step") if d else None

    def journey_timeline(self):
        self.start("--dataset", os.path.join(self.root, "twin", "twin_frames"), "--sample", "shr_00")
        self.wait_title("twin_frames / ", timeout=90)
        time.sleep(4.0)   # the RMSE series (a worker) is done
        self.click(self.timeline_x(14), TIMELINE_Y, settle=0.8)
        step = self.saved_step()
        self.check(step == 14, f"a click in the RMSE timeline at step 14's x seeks there (step {step})")
        self.xdo("mousemove", "--window", self.wid, self.timeline_x(20), TIMELINE_Y)
        time.sleep(0.2)
        self.xdo("mousedown", 1)
        for k in (25, 32, 40, 47):
            time.sleep(0.15)
            self.xdo("mousemove", "--window", self.wid, self.timeline_x(k), TIMELINE_Y + 3)
        time.sleep(0.3)
        self.xdo("mouseup", 1)
        time.sleep(0.8)
        step = self.saved_step()
        self.check(step == 47, f"a drag in the RMSE timeline seeks to where it ends, step 47 (step {step})")
        csv = os.path.join(self.state, "shearbench", "rmse_twin_frames_shr_00.csv")
        self.click(*POS_TIMELINE_CSV, settle=1.0)
        rows = open(csv).read().splitlines() if os.path.exists(csv) else []
        head = rows[0].split(",") if rows else []
        self.check(head[:2] == ["step", "time_s"] and len(head) == 6 and len(rows) == 1 + TIMELINE_STEPS,
                   f"the timeline's CSV beside the session has step, time_s, 4 models and 59 rows: {head}, "
                   f"{len(rows)} lines")
        self.check(len(rows) > 11 and rows[11].startswith("10,0.2,"), "its row for step 10 is at t = 0.2 s")
        self.shift_escape()
        self.wait_exit()
        self.kill()

    def panel_width(self):
        out = os.path.join(self.work, "hydroshear_panel.png")
        r = subprocess.run([self.exe, "--data", self.root, "render", "--size", "1280x800", "--no-timings", "--scene",
                            "scenes/press_sphere.json", "--panel", "HydroShear", "--out", out],
                           cwd=self.src, env=self.env, capture_output=True, text=True)
        width = 0
        if r.returncode == 0:
            with open(out, "rb") as f:
                head = f.read(24)
            width = int.from_bytes(head[16:20], "big")
        self.check(width >= 300, f"at 1280x800 the HydroShear panel is {width} px wide (>= 300)")


def sha(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


def files_written_since(marker, roots, allowed):
    """Files under `roots` newer than `marker`, outside `allowed` folders."""
    out = subprocess.run(["find", *roots, "-newer", marker, "-type", "f"], capture_output=True, text=True).stdout.split()
    return [p for p in out if not any(p.startswith(a + os.sep) for a in allowed)]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--exe", required=True)
    p.add_argument("--work", required=True)
    p.add_argument("--src", required=True)
    p.add_argument("--build", required=True, help="the build folder (tests write there; not checked)")
    p.add_argument("--data", default=os.environ.get("SHEARBENCH_DATA", ""))
    a = p.parse_args()
    a.data = os.path.abspath(a.data)
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    marker = os.path.join(a.work, "marker")
    open(marker, "w").close()
    time.sleep(1.1)   # mtime granularity
    j = Journeys(a)
    try:
        for journey in (j.journey_overwrite, j.journey_session_escape, j.journey_open_dataset, j.journey_reopen,
                        j.journey_empty_sample, j.panel_width, j.journey_timeline):
            j.say(f"--- {journey.__name__}")
            journey()
    finally:
        j.kill()
    stray = files_written_since(marker, [a.src, a.data], [os.path.abspath(a.build), os.path.abspath(a.work),
                                                          os.path.join(a.src, ".git")])
    # A path typed wrong (the field's old text kept) once made a folder beside the repository: new entries
    # there, and in the user's own state folder (the test sets XDG_STATE_HOME), are stray too.
    parent = os.path.dirname(os.path.abspath(a.src))
    stray += subprocess.run(["find", parent, "-mindepth", "1", "-maxdepth", "1", "-newer", marker],
                            capture_output=True, text=True).stdout.split()
    home_state = os.path.join(os.path.expanduser("~"), ".local", "state", "shearbench")
    if os.path.isdir(home_state):
        stray += files_written_since(marker, [home_state], [])
    j.check(not stray, "no file written outside the session path and the test's folder" +
            ("" if not stray else ": " + ", ".join(stray[:10])))
    j.say(f"{len(j.failures)} failures in {time.time() - j.t0:.0f} s")
    sys.exit(1 if j.failures else 0)


if __name__ == "__main__":
    main()
