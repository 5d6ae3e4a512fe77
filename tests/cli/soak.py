#!/usr/bin/env python3
"""An afternoon in the workbench, scripted. Run under xvfb-run (1280x800 screen).

Drives the real `shearbench gui` only through its input path (xdotool keys, clicks and drags) with a
reproducible random walk (--seed) over what a user does: nudge and drag the indenter, scrub, play and pause,
move the camera, switch the FOTS / TacSL variants, type a parameter, take screenshots, export fields, save
(Ctrl+S), quit and reopen the session, open other scenes and datasets (a restart with --scene / --dataset,
sometimes with --residual), run fits in the Fit section and cancel them, and SIGKILL the workbench at random
moments to restart it from its autosave (every other restart through the Restore dialog, answered with Enter).

What it checks:
  * after every save, the saved session holds what the user had: the script keeps its own model of the
    session (open.*, params, the indenter's last pose in path_X_EI, residual file) from what the previous
    save held plus what it did since, and compares;
  * after every SIGKILL, the autosave holds every edit made up to --autosave-interval + --margin seconds
    before the kill (it must equal the script's model at some moment of that window), or, when there is no
    autosave, nothing older than that window was unsaved;
  * after a restart through the Restore dialog, the next save holds what the autosave held;
  * a fit started and cancelled changes nothing the user had (its result is not applied);
  * no crash (the workbench never exits on its own), screenshots and exports appear.
What it records (from `gui --stats`, lines every --stats-interval s): per minute the frame-time p50/p95,
resident memory, open fds and live GL objects -> <work>/soak_minutes.csv; totals -> <work>/soak_summary.json.
Exit status 1 on a lost edit, a crash or a failed check; with --check-growth also on memory growth > 5 %
after minute 5 (within one process life; read at each minute's quiet point, --quiet-s without input, so
that what stays is what the workbench keeps) or a p95 frame time over 1.5x its first-minute value.
"""
import argparse
import csv
import json
import math
import os
import random
import shutil
import signal
import subprocess
import sys
import time

KEY_NUDGE = {  # key -> (dx, dy, dz) in m, or twist in rad (widgets/workbench.cpp: kNudgeM, kPushM, kTwistRad)
    "Right": (1e-4, 0, 0), "Left": (-1e-4, 0, 0), "Up": (0, 1e-4, 0), "Down": (0, -1e-4, 0),
    "Next": (0, 0, -5e-5), "Prior": (0, 0, 5e-5),   # PgDn pushes in, PgUp pulls out
}
KEY_TWIST = {"e": math.radians(2), "q": -math.radians(2)}
POSE_TOL_M = 1e-9
QUAT_TOL = 1e-6
PARAM_REL_TOL = 1e-6
# Positions in a 1280x800 window with a scene open and no residual (the layout is fixed at that size).
# (the Parameters section: HydroShear variant at y 479, FOTS 504, TacSL 529, beside HydroShear 554)
POS_FOTS_COMBO = (95, 504)
POS_TACSL_COMBO = (95, 529)
COMBO_ITEM_DY = (24, 45)          # the popup's two entries below the combo
POS_EXPORT = (240, 429)
POS_HS_MU = (115, 723)            # HydroShear mu slider (Ctrl+click: type a value)
POS_INDENTER = (483, 115)         # the indenter in the iso view at the scene's start (the grid's first cell)
# The Fit section, reached by collapsing Parameters (its header at y 454; Fit's header then at 479).
POS_PARAMETERS_HEADER = (60, 454)
POS_FIT_HEADER = (60, 479)
POS_FIT_DATASET = (120, 504)
POS_FIT_RUN = (80, 604)           # "Run fit"; while it runs, the progress bar with Cancel beside it
POS_FIT_CANCEL = (275, 604)
# Typed into the Fit section's dataset field. Letters that are shortcuts (E and Q twist, H help, P screenshot)
# are avoided: if a slow frame kept the field from taking the click, the typing would edit the session.
FIT_DATASETS = ("data:twin/twin_torus",)
FIT_SETTLE_S = 1.5                # a header click's layout change needs a frame; frames slow down while fits run
FOTS_IDS, TACSL_IDS = ("fots", "fots-reimpl"), ("tacsl", "tacsl-normalized")


def quat_mul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return (w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2)


def pose_close(a, b):
    if a is None or b is None:
        return a is b
    if any(abs(a[i] - b[i]) > POSE_TOL_M for i in range(3)):
        return False
    dot = abs(sum(a[3 + i] * b[3 + i] for i in range(4)))   # q and -q are one rotation
    return dot > 1 - QUAT_TOL


class Model:
    """What the user has, as the script knows it. tail: the indenter's last pose [x y z qw qx qy qz], or
    'unknown' after a drag in the viewport (where the mouse puts it is the viewport's business)."""

    def __init__(self, d=None):
        self.open = {}
        self.params = {}
        self.tail = "unknown"
        self.residual = ""
        if d:
            self.adopt(d)

    def adopt(self, d):
        self.open = {k: d["open"].get(k, "") for k in ("scene", "dataset", "sample", "fots", "tacsl", "param_set")}
        self.params = json.loads(json.dumps(d["params"]))
        self.tail = list(d["path_X_EI"][-1]) if d["path_X_EI"] else None
        self.residual = d.get("residual", {}).get("file", "") if isinstance(d.get("residual"), dict) else ""

    def copy(self):
        m = Model()
        m.open, m.params, m.tail, m.residual = dict(self.open), json.loads(json.dumps(self.params)), \
            (list(self.tail) if isinstance(self.tail, list) else self.tail), self.residual
        return m

    def differences(self, d):
        """What the saved document `d` lacks of this model (empty: nothing lost)."""
        out = []
        for k, v in self.open.items():
            if d["open"].get(k, "") != v:
                out.append(f"open.{k}: saved {d['open'].get(k)!r}, expected {v!r}")
        for mid, p in self.params.items():
            if mid not in d["params"]:
                # A variant switched away is not in the session any more (only the open variants are).
                if mid in (self.open.get("fots"), self.open.get("tacsl"), "hydroshear"):
                    out.append(f"params.{mid}: missing")
                continue
            for k, v in p.items():
                s = d["params"][mid].get(k)
                # Sliders hold floats: a typed 2.44 is saved as 2.440000057220459.
                if s is None or abs(s - v) > PARAM_REL_TOL * max(1.0, abs(v)):
                    out.append(f"params.{mid}.{k}: saved {s}, expected {v}")
        saved_res = d.get("residual", {}).get("file", "") if isinstance(d.get("residual"), dict) else ""
        if self.residual and saved_res != self.residual:
            out.append(f"residual.file: saved {saved_res!r}, expected {self.residual!r}")
        saved_tail = d["path_X_EI"][-1] if d["path_X_EI"] else None
        if self.tail != "unknown" and not pose_close(self.tail, saved_tail):
            out.append(f"path_X_EI tail: saved {saved_tail}, expected {self.tail}")
        return out


class Soak:
    def __init__(self, a):
        self.a = a
        self.rng = random.Random(a.seed)
        self.work = os.path.abspath(a.work)
        self.src = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
        self.data = os.environ.get("SHEARBENCH_DATA", os.path.join(self.src, "..", "shared", "data"))
        # Ctrl+S saves to the default session path, in the XDG state folder, here the test's own.
        self.state = os.path.join(self.work, "state")
        self.session = os.path.join(self.state, "shearbench", "session.json")
        self.autosave = os.path.join(self.work, "autosave.json")
        self.stats = os.path.join(self.work, "stats.jsonl")
        os.makedirs(self.work, exist_ok=True)
        self.log = open(os.path.join(self.work, "soak.log"), "a")
        self.proc = None
        self.wid = None
        self.t0 = time.monotonic()
        self.failures = []
        self.counts = {k: 0 for k in ("actions", "saves", "save_checks", "edits_checked", "edits_lost", "reopens",
                                      "scene_opens", "dataset_opens", "residual_loads", "kills", "kill_checks",
                                      "restores_from_autosave", "restores_from_save", "screenshots", "exports",
                                      "variant_switches", "param_edits", "quick_saves", "nudges", "drags", "drags_moved",
                                      "scrubs", "play_toggles", "camera", "crashes", "fits_started", "fits_cancelled",
                                      "restores_from_dialog")}
        self.model = Model()
        self.saved = None            # the last saved document
        self.saved_t = 0.0           # when it was saved
        self.history = []            # (t, Model) after every action that changed the model
        self.edits_since_save = 0
        self.fresh = True            # no nudge/drag yet in this process (its nudges start from the shown step)
        self.layout_ok = True        # scene open, no residual: the fixed positions hold
        self.stats_pos = 0
        self.minute_rows = []
        self.pending_stats = []
        self.env = dict(os.environ)
        self.env["SHEARBENCH_AUTOSAVE"] = self.autosave
        self.env["XDG_STATE_HOME"] = self.state
        self.env["ASAN_OPTIONS"] = (self.env.get("ASAN_OPTIONS", "") + ":detect_leaks=0").lstrip(":")
        scenes = sorted(f for f in os.listdir(os.path.join(self.src, "scenes")) if f.endswith(".json"))
        self.scenes = [os.path.join(self.src, "scenes", f) for f in scenes if not f.startswith("replay")]
        self.datasets = [os.path.join(self.data, "twin", d) for d in ("twin_sphere35", "twin_sphere8", "twin_torus")
                         if os.path.isdir(os.path.join(self.data, "twin", d))]
        rdir = os.path.join(self.src, "docs", "residuals")
        self.residuals = sorted(os.path.join(rdir, d, "residual.json") for d in os.listdir(rdir)
                                if os.path.isfile(os.path.join(rdir, d, "residual.json")))

    # ------------------------------------------------------------------ plumbing
    def now(self):
        return time.monotonic() - self.t0

    def say(self, msg):
        line = f"[{self.now():7.1f}s] {msg}"
        print(line, flush=True)
        self.log.write(line + "\n")
        self.log.flush()

    def fail(self, msg):
        self.say("FAIL: " + msg)
        self.failures.append(f"{self.now():.1f}s: {msg}")

    def xdo(self, *args, check=False):
        r = subprocess.run(["xdotool", *map(str, args)], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise RuntimeError(f"xdotool {' '.join(map(str, args))}: {r.stderr.strip()}")
        return r.stdout.strip()

    def key(self, k):
        self.xdo("key", "--window", self.wid, k)

    def chord(self, mod, k):
        # The modifier held over several frames, as a person types it (tests/cli/gui_keep_work.sh).
        self.xdo("keydown", "--window", self.wid, mod)
        time.sleep(0.25)
        self.xdo("key", "--window", self.wid, k)
        time.sleep(0.25)
        self.xdo("keyup", "--window", self.wid, mod)

    def click(self, x, y, settle=0.4):
        self.xdo("mousemove", "--window", self.wid, x, y)
        time.sleep(0.15)
        self.xdo("click", 1)
        time.sleep(settle)

    def alive(self):
        return self.proc is not None and self.proc.poll() is None

    def start(self, args, why):
        self.record_model()
        os.makedirs(os.path.dirname(self.session), exist_ok=True)
        cmd = [self.a.exe, "gui", "--size", "1280x800", "--stats", self.stats, "--stats-interval",
               str(self.a.stats_interval), "--autosave-interval", str(self.a.autosave_interval),
               "--output-folder", os.path.join(self.work, "out"), *args]   # P's screenshots and the export go there
        self.say(f"start ({why}): {' '.join(cmd[1:])}")
        self.gui_log = open(os.path.join(self.work, "gui.log"), "a")
        self.proc = subprocess.Popen(cmd, cwd=self.work, env=self.env, stdout=self.gui_log, stderr=subprocess.STDOUT)
        t = time.monotonic()
        while time.monotonic() - t < self.a.window_wait:
            if self.proc.poll() is not None:
                raise RuntimeError(f"the workbench exited ({self.proc.returncode}) before its window appeared; see {self.work}/gui.log")
            w = self.xdo("search", "--pid", self.proc.pid, "--name", "shearbench").split()
            if w:
                self.wid = w[0]
                break
            time.sleep(0.2)
        else:
            raise RuntimeError(f"waited {self.a.window_wait} s for a window named 'shearbench' of pid {self.proc.pid}, none appeared")
        time.sleep(3)   # first frames, models built
        self.wait_opened()
        self.fresh = True

    def wait_opened(self, timeout=120):
        """A session opens on a worker and input waits meanwhile: until the title stops saying
        'opening', keys would be dropped."""
        t = time.monotonic()
        while time.monotonic() - t < timeout and " - opening " in self.xdo("getwindowname", self.wid):
            time.sleep(0.2)

    def stop_clean(self):
        """Shift+Esc after a save: an unchanged session closes at once."""
        self.chord("shift", "Escape")
        t = time.monotonic()
        while self.alive() and time.monotonic() - t < 60:
            time.sleep(0.2)
        if self.alive():
            self.fail("the workbench did not close within 60 s of Shift+Esc after a save (something unsaved?)")
            self.proc.kill()
            self.proc.wait()
        elif self.proc.returncode != 0:
            self.fail(f"the workbench exited with {self.proc.returncode} on a clean quit")
        self.proc = None

    def check_alive(self):
        if self.proc is not None and self.proc.poll() is not None:
            self.counts["crashes"] += 1
            self.fail(f"the workbench exited by itself with {self.proc.returncode} (see {self.work}/gui.log)")
            return False
        return True

    def record_model(self):
        self.history.append((self.now(), self.model.copy()))
        # Only the last promise window matters for a kill.
        cut = self.now() - self.a.autosave_interval - self.a.margin - 60
        while len(self.history) > 2 and self.history[1][0] < cut:
            self.history.pop(0)

    # ------------------------------------------------------------------ saves
    def wait_file_newer(self, path, after_mtime, timeout=20):
        t = time.monotonic()
        while time.monotonic() - t < timeout:
            try:
                if os.path.getmtime(path) > after_mtime:
                    time.sleep(0.2)
                    return True
            except OSError:
                pass
            time.sleep(0.1)
        return False

    def save(self, adopt=False):
        """Ctrl+S, then compare the saved session with the model (or adopt it: a fresh scene's defaults)."""
        time.sleep(self.a.settle)   # the physics applies queued drags before the path is read
        before = os.path.getmtime(self.session) if os.path.exists(self.session) else 0
        self.chord("ctrl", "s")
        if not self.wait_file_newer(self.session, before):
            if self.check_alive():
                self.fail("Ctrl+S wrote no session file within 20 s")
            return None
        self.counts["saves"] += 1
        self.log.write(f"[{self.now():7.1f}s] saved\n")
        d = json.load(open(self.session))
        if adopt or self.model.open == {}:
            self.model = Model(d)
        else:
            self.compare(d, "save")
        self.saved, self.saved_t = d, self.now()
        self.edits_since_save = 0
        self.record_model()
        return d

    def compare(self, d, what):
        self.counts["save_checks" if what == "save" else "kill_checks"] += 1
        self.counts["edits_checked"] += self.edits_since_save
        diffs = self.model.differences(d)
        if diffs:
            self.counts["edits_lost"] += 1
            self.fail(f"{what}: the session lost what the user did: " + "; ".join(diffs[:6]))
        if self.model.tail == "unknown" and self.saved is not None and d["path_X_EI"]:
            prev = self.saved["path_X_EI"][-1] if self.saved["path_X_EI"] else None
            if not pose_close(prev, d["path_X_EI"][-1]):
                self.counts["drags_moved"] += 1
        self.model = Model(d) if not diffs else self.model
        if diffs:   # go on from what the file holds, so one loss is reported once
            self.model = Model(d)

    # ------------------------------------------------------------------ actions
    def edited(self):
        self.edits_since_save += 1
        self.record_model()

    def act_nudge(self):
        if self.fresh:
            # A fresh process nudges from the shown step: go to the last one first, so the model's tail holds.
            self.key("End")
            time.sleep(1.5)
            self.fresh = False
        for _ in range(self.rng.randint(1, 5)):
            k = self.rng.choice(list(KEY_NUDGE) + list(KEY_TWIST))
            self.key(k)
            self.counts["nudges"] += 1
            if isinstance(self.model.tail, list):
                t = self.model.tail
                if k in KEY_NUDGE:
                    for i in range(3):
                        t[i] += KEY_NUDGE[k][i]
                else:
                    h = KEY_TWIST[k] / 2
                    t[3:7] = quat_mul((math.cos(h), 0, 0, math.sin(h)), t[3:7])
            time.sleep(0.15)
            self.edited()

    def act_drag(self):
        x, y = POS_INDENTER
        self.key("r")   # camera reset: the indenter is where the iso view puts it
        time.sleep(0.5)
        self.xdo("mousemove", "--window", self.wid, x + self.rng.randint(-15, 15), y + self.rng.randint(-15, 15))
        time.sleep(0.2)
        self.xdo("mousedown", 1)
        for _ in range(self.rng.randint(3, 8)):
            x += self.rng.randint(-25, 25)
            y += self.rng.randint(-20, 20)
            self.xdo("mousemove", "--window", self.wid, x, y)
            time.sleep(0.12)
        self.xdo("mouseup", 1)
        self.counts["drags"] += 1
        self.fresh = False
        self.model.tail = "unknown"
        self.edited()

    def act_scrub(self):
        for _ in range(self.rng.randint(1, 6)):
            self.key(self.rng.choice(["Home", "End", "period", "comma", "period", "period"]))
            time.sleep(0.2)
        self.counts["scrubs"] += 1

    def act_play(self):
        self.key("space")
        time.sleep(self.rng.uniform(0.5, 4))
        self.key("space")
        self.counts["play_toggles"] += 1

    def act_camera(self):
        self.key(self.rng.choice(["1", "2", "3", "r", "equal", "minus", "m"]))
        self.counts["camera"] += 1

    def act_variant(self):
        if not self.layout_ok:
            return self.act_nudge()
        fam, pos, ids = self.rng.choice([("fots", POS_FOTS_COMBO, FOTS_IDS), ("tacsl", POS_TACSL_COMBO, TACSL_IDS)])
        want = self.rng.randrange(2)
        self.click(*pos, settle=0.6)
        self.click(pos[0], pos[1] + COMBO_ITEM_DY[want], settle=1.0)
        self.model.open[fam] = ids[want]
        self.model.params.setdefault(ids[want], {})   # its values come from the parameter set: learnt at the next save
        self.counts["variant_switches"] += 1
        self.edited()

    def act_param(self):
        if not self.layout_ok:
            return self.act_scrub()
        value = round(self.rng.uniform(0.5, 3.0), 3)
        x, y = POS_HS_MU
        self.xdo("mousemove", "--window", self.wid, x, y)
        time.sleep(0.15)
        self.xdo("keydown", "--window", self.wid, "ctrl")
        time.sleep(0.2)
        self.xdo("click", 1)
        time.sleep(0.2)
        self.xdo("keyup", "--window", self.wid, "ctrl")
        time.sleep(0.4)
        self.chord("ctrl", "a")
        self.xdo("type", "--window", self.wid, "--delay", "60", str(value))
        self.key("Return")
        time.sleep(0.5)
        # A click on the status bar ends the text edit as a person would (a Return alone did not always reach
        # ImGui 1.86's temporary input, and while it is active the shortcuts, Ctrl+S too, are off).
        self.click(640, 792, settle=0.5)
        # ImGui applies a typed value at every character: "1.986" sets 1, 1.9, 1.98 on its way, and an autosave
        # in between holds one of them. Each is a state the user's session passed through.
        typed = str(value)
        for k in range(1, len(typed)):
            try:
                partial = float(typed[:k])
            except ValueError:
                continue
            m = self.model.copy()
            m.params.setdefault("hydroshear", {})["mu"] = partial
            self.history.append((self.now(), m))
        self.model.params.setdefault("hydroshear", {})["mu"] = value
        self.log.write(f"[{self.now():7.1f}s] typed mu {value}\n")
        self.log.flush()
        self.counts["param_edits"] += 1
        self.edited()

    def act_fit(self):
        """Open the Fit section, start a fit on a twin set, cancel it after a moment, and put the layout back."""
        if not self.layout_ok:
            return self.act_scrub()
        self.click(*POS_PARAMETERS_HEADER, settle=FIT_SETTLE_S)   # collapse Parameters: Fit moves up under it
        self.click(*POS_FIT_HEADER, settle=FIT_SETTLE_S)
        self.click(*POS_FIT_DATASET, settle=0.5)
        self.chord("ctrl", "a")
        self.xdo("type", "--window", self.wid, "--delay", "40", self.rng.choice(FIT_DATASETS))
        self.key("Return")
        time.sleep(0.3)
        self.click(*POS_FIT_RUN, settle=self.rng.uniform(0.5, 4.0))
        self.counts["fits_started"] += 1
        self.click(*POS_FIT_CANCEL, settle=FIT_SETTLE_S)   # the progress bar's Cancel (a finished fit stays unapplied)
        self.counts["fits_cancelled"] += 1
        self.click(*POS_FIT_HEADER, settle=FIT_SETTLE_S)      # collapse Fit, open Parameters again
        self.click(*POS_PARAMETERS_HEADER, settle=FIT_SETTLE_S)
        # Nothing the user had changes: the next save is compared with the unchanged model.

    def act_screenshot(self):
        d = os.path.join(self.work, "out")   # --output-folder
        pngs = lambda: len([f for f in os.listdir(d) if f.endswith(".png")]) if os.path.isdir(d) else 0  # noqa: E731
        n = pngs()
        time.sleep(1.05)   # the file name has a one-second stamp
        self.key("p")
        t = time.monotonic()
        while time.monotonic() - t < 20:
            if pngs() > n:
                self.counts["screenshots"] += 1
                break
            time.sleep(0.2)
        else:
            if self.check_alive():
                self.fail("P wrote no screenshot within 20 s")
        # Keep the folder small over an hour.
        if os.path.isdir(d) and len(os.listdir(d)) > 20:
            for f in sorted(os.listdir(d))[:-5]:
                os.remove(os.path.join(d, f))

    def act_export(self):
        if not self.layout_ok:
            return self.act_camera()
        out = os.path.join(self.work, "out", "fields_export")   # the Export row's relative folder, in --output-folder

        def newest():   # a re-export replaces the models' folders inside; the top folder's mtime stays
            try:
                return max([os.path.getmtime(out)] + [os.path.getmtime(os.path.join(out, f)) for f in os.listdir(out)])
            except OSError:
                return 0
        before = newest()
        self.click(*POS_EXPORT, settle=0.5)
        t = time.monotonic()
        while time.monotonic() - t < 60:
            if newest() > before:
                self.counts["exports"] += 1
                return
            time.sleep(0.3)
        if self.check_alive():
            self.say("note: no new fields_export within 60 s (export of a long path still running?)")

    def act_quick_save(self):
        """A nudge and Ctrl+S typed at once (one xdotool call: often one frame): the save must hold the nudge."""
        if self.fresh:
            self.key("End")
            time.sleep(1.5)
            self.fresh = False
        k = self.rng.choice(list(KEY_NUDGE))
        before = os.path.getmtime(self.session) if os.path.exists(self.session) else 0
        self.xdo("key", "--window", self.wid, k, "ctrl+s")
        if isinstance(self.model.tail, list):
            for i in range(3):
                self.model.tail[i] += KEY_NUDGE[k][i]
        self.counts["nudges"] += 1
        self.counts["quick_saves"] += 1
        self.edited()
        if not self.wait_file_newer(self.session, before):
            if self.check_alive():
                self.fail("a nudge + Ctrl+S wrote no session file within 20 s")
            return
        self.counts["saves"] += 1
        d = json.load(open(self.session))
        self.compare(d, "save")
        self.saved, self.saved_t = d, self.now()
        self.edits_since_save = 0
        self.record_model()

    def act_save(self):
        self.save()

    def act_reopen(self):
        if self.save() is None:
            return
        self.stop_clean()
        self.counts["reopens"] += 1
        self.start(["--session", self.session], "reopen the saved session")
        self.layout_ok = self.layout_ok and not self.model.residual
        self.save()   # reopened and saved again: nothing the file held may be lost

    def act_open(self):
        if self.save() is None:
            return
        self.stop_clean()
        if os.path.exists(self.session):
            os.replace(self.session, self.session + ".prev")
        kind = self.rng.choice(["scene", "scene", "dataset", "residual"])
        if kind == "dataset" and self.datasets:
            args = ["--dataset", self.rng.choice(self.datasets)]
            self.counts["dataset_opens"] += 1
            self.layout_ok = False
        else:
            args = ["--scene", self.rng.choice(self.scenes)]
            self.counts["scene_opens"] += 1
            self.layout_ok = True
            if kind == "residual" and self.residuals:
                args += ["--residual", self.rng.choice(self.residuals)]
                self.counts["residual_loads"] += 1
                self.layout_ok = False
        self.start(args, "open " + kind)
        self.model = Model()
        self.saved = None
        self.save(adopt=True)

    def act_kill(self):
        if self.rng.random() < 0.5:
            # Half the kills come after a stretch of unsaved work longer than the autosave interval, as a user
            # who never presses Ctrl+S: then only the autosave can bring the edits back.
            until = self.now() + self.a.autosave_interval + self.rng.uniform(3, 10)
            while self.now() < until:
                self.rng.choice([self.act_nudge, self.act_nudge, self.act_param, self.act_scrub])()
                time.sleep(self.rng.uniform(0.5, 2.0))
        kill_t = self.now()
        os.kill(self.proc.pid, signal.SIGKILL)
        self.proc.wait()
        self.proc = None
        self.counts["kills"] += 1
        promise = kill_t - self.a.autosave_interval - self.a.margin
        # The models the autosave may hold: the one in effect at `promise` and every later one.
        window = [m for (t, m) in self.history if t >= promise]
        before = [m for (t, m) in self.history if t < promise]
        if before:
            window.insert(0, before[-1])
        if os.path.exists(self.autosave):
            d = json.load(open(self.autosave))
            self.counts["kill_checks"] += 1
            self.counts["edits_checked"] += self.edits_since_save
            if not any(not m.differences(d) for m in window):
                self.counts["edits_lost"] += 1
                best = min(window, key=lambda m: len(m.differences(d)))
                self.fail(f"kill at {kill_t:.1f}s: the autosave lacks edits made before {promise:.1f}s: "
                          + "; ".join(best.differences(d)[:6]))
            self.model = Model(d)
            self.counts["restores_from_autosave"] += 1
            if self.counts["kills"] % 2 == 1:   # as a user would: start plainly, answer Restore (Enter)
                self.start([], "restart after SIGKILL: the Restore dialog, answered with Enter")
                self.key("Return")
                time.sleep(0.5)
                self.wait_opened()
                time.sleep(1.5)
                self.counts["restores_from_dialog"] += 1
            else:
                shutil.copyfile(self.autosave, self.session)
                self.start(["--session", self.session], "restart after SIGKILL, from the autosave")
        else:
            # No autosave: fine only when nothing unsaved is older than the promise window.
            self.counts["kill_checks"] += 1
            # (A save after `promise` holds every earlier edit: it was checked against the model when made.)
            if self.saved is not None and self.saved_t < promise and before and before[-1].differences(self.saved):
                self.counts["edits_lost"] += 1
                self.fail(f"kill at {kill_t:.1f}s: no autosave, but edits from before {promise:.1f}s were unsaved: "
                          + "; ".join(before[-1].differences(self.saved)[:6]))
            self.model = Model(self.saved) if self.saved else Model()
            self.counts["restores_from_save"] += 1
            self.start(["--session", self.session], "restart after SIGKILL, no autosave: from the last save")
        self.layout_ok = self.layout_ok and not self.model.residual
        self.edits_since_save = 0
        self.save()   # what was restored is what the file holds now

    # ------------------------------------------------------------------ stats
    def read_stats(self):
        if not os.path.exists(self.stats):
            return
        with open(self.stats) as f:
            f.seek(self.stats_pos)
            for line in f:
                if not line.endswith("\n"):
                    break
                self.stats_pos += len(line)
                try:
                    self.pending_stats.append(json.loads(line))
                except json.JSONDecodeError:
                    pass   # a line cut by SIGKILL

    def quiet_sample(self):
        """Resident memory after --quiet-s seconds without input: the idle workbench trims its heap every 10 s
        (app/frontend.cpp), so what a fit, a drag or an export freed has gone back and what is left is what
        the workbench keeps: a leak or an accumulation stays, a working set does not."""
        if self.a.quiet_s <= 0 or not self.alive():
            return {}
        time.sleep(self.a.quiet_s)
        out = {}
        try:
            with open(f"/proc/{self.proc.pid}/status") as f:
                for line in f:
                    k, _, v = line.partition(":")
                    if k in ("VmRSS", "RssAnon"):
                        out["rss_quiet_mb" if k == "VmRSS" else "rss_anon_quiet_mb"] = round(int(v.split()[0]) / 1024, 1)
        except OSError:
            pass
        return out

    def close_minute(self, minute, life_start):
        quiet = self.quiet_sample()
        self.read_stats()
        rows, self.pending_stats = self.pending_stats, []
        ms = sorted(x for r in rows for x in r.get("frame_ms", []))
        pct = lambda q: ms[min(len(ms) - 1, max(0, math.ceil(q * len(ms)) - 1))] if ms else float("nan")
        last = rows[-1] if rows else {}
        row = {"minute": minute, "t_s": round(self.now(), 1), "process_minute": round((self.now() - life_start) / 60, 2),
               "frames": len(ms), "frame_ms_p50": round(pct(0.5), 2), "frame_ms_p95": round(pct(0.95), 2),
               "rss_mb": round(last.get("rss_kb", float("nan")) / 1024, 1),
               "rss_anon_mb": round(last.get("rss_anon_kb", float("nan")) / 1024, 1),   # heap (file: code, mapped data)
               "rss_file_mb": round(last.get("rss_file_kb", float("nan")) / 1024, 1), "fds": last.get("fds", ""),
               "loadavg_1min": float(open("/proc/loadavg").read().split()[0]),   # a shared machine's frame-time noise
               **quiet, **{f"gl_{k}": v for k, v in last.get("gl", {}).items()}, "pid": self.proc.pid if self.proc else "",
               **{k: self.counts[k] for k in ("saves", "kills", "reopens", "edits_checked", "edits_lost")}}
        self.minute_rows.append(row)
        self.say(f"minute {minute}: p50 {row['frame_ms_p50']} ms, p95 {row['frame_ms_p95']} ms, rss {row['rss_mb']} MB "
                 f"(quiet {row.get('rss_quiet_mb', '-')} MB), "
                 f"gl {last.get('gl')}, frames {len(ms)}")

    # ------------------------------------------------------------------ the walk
    def run(self):
        os.makedirs(self.work, exist_ok=True)
        self.say(f"soak: seed {self.a.seed}, {self.a.minutes} min, work {self.work}")
        actions = [(self.act_nudge, 20), (self.act_drag, 8), (self.act_scrub, 10), (self.act_play, 6),
                   (self.act_camera, 6), (self.act_variant, 5), (self.act_param, 5), (self.act_screenshot, 3),
                   (self.act_export, 2), (self.act_fit, 1.5), (self.act_save, 8), (self.act_quick_save, 3), (self.act_reopen, 1.2), (self.act_open, 1.2),
                   (self.act_kill, self.a.kill_weight)]
        if self.a.actions:   # a narrowed walk, to find which action grows memory (docs/reliability.md)
            keep = set(self.a.actions.split(","))
            unknown = keep - {f.__name__[4:] for f, _ in actions}
            if unknown:
                raise SystemExit(f"--actions: unknown action(s) {sorted(unknown)}")
            actions = [(f, w) for f, w in actions if f.__name__[4:] in keep]
        funcs, weights = zip(*actions)
        names = {f.__name__[4:] for f in funcs}
        first = self.rng.choice(self.scenes)
        self.start(["--scene", first], "first scene")
        life_start = self.now()
        self.save(adopt=True)
        end = self.a.minutes * 60
        next_minute, minute = 60, 0
        done = set()   # the action kinds run so far
        try:
            while self.now() < end:
                f = self.rng.choices(funcs, weights)[0]
                if f == self.act_fit and self.now() < 60:
                    f = self.act_save   # the first minute is the frame-time reference: no fit in it
                if f in (self.act_kill, self.act_reopen, self.act_open) and self.now() < self.a.restarts_after * 60:
                    f = self.act_save   # one long process life first: memory growth needs minutes in one process
                # The first five minutes are the memory reference: two fits in them, so the heap's high-water
                # mark of a fit is in the reference rather than counted as growth (docs/reliability.md).
                if self.a.minutes >= 10 and "fit" in names:
                    for t_fit, n in ((90, 1), (200, 2)):
                        if self.now() > t_fit and self.counts["fits_started"] < n:
                            f = self.act_fit
                # Every other action the first life can take once in minutes 2-4 too: a first use (the
                # first export's buffers, the first variant's model) is part of the reference.
                if self.a.minutes >= 10 and 60 < self.now() < 240:
                    missing = [g for g in funcs if g not in done and g not in
                               (self.act_kill, self.act_reopen, self.act_open)]
                    if missing and f not in missing and self.rng.random() < 0.5:
                        f = missing[0]
                if self.a.ensure_restarts:   # a short run still kills, reopens and opens once each
                    for frac, g, c in ((0.15, self.act_quick_save, "quick_saves"), (0.2, self.act_fit, "fits_started"),
                                       (0.3, self.act_kill, "kills"), (0.5, self.act_reopen, "reopens"),
                                       (0.7, self.act_open, "scene_opens")):
                        if self.now() > frac * end and self.counts[c] == 0 and (c != "scene_opens" or self.counts["dataset_opens"] == 0):
                            f = g
                            break
                pid = self.proc.pid
                self.log.write(f"[{self.now():7.1f}s] {f.__name__[4:]}\n")   # every action, for a failure's context
                self.log.flush()
                f()
                done.add(f)
                self.counts["actions"] += 1
                if not self.check_alive():
                    self.proc = None
                    self.start(["--session", self.session], "restart after a crash")
                if self.proc.pid != pid:
                    life_start = self.now()
                time.sleep(self.rng.uniform(0.2, 1.5))
                if self.now() >= next_minute:
                    minute += 1
                    self.close_minute(minute, life_start)
                    next_minute += 60
                    self.write_outputs()
        except Exception as e:   # a driver error is a failure too, reported with what was done so far
            self.fail(f"driver error: {type(e).__name__}: {e}")
        finally:
            if self.alive():
                try:
                    self.save()
                    self.stop_clean()
                except Exception as e:
                    self.fail(f"final save/quit: {e}")
                    self.proc.kill()
        return self.write_outputs(final=True)

    def write_outputs(self, final=False):
        rows = self.minute_rows
        if rows:
            keys = list(dict.fromkeys(k for r in rows for k in r))
            with open(os.path.join(self.work, "soak_minutes.csv"), "w", newline="") as f:
                w = csv.DictWriter(f, keys)
                w.writeheader()
                w.writerows(rows)
        s = {"seed": self.a.seed, "minutes_planned": self.a.minutes, "minutes_run": round(self.now() / 60, 2),
             "counts": self.counts, "failures": self.failures}
        s.update(growth_summary(rows))
        crit = []
        if self.counts["edits_lost"]:
            crit.append("lost edits")
        if self.counts["crashes"]:
            crit.append("crashes")
        if self.a.check_growth:
            if s.get("rss_growth_after_min5_pct", 0) > 5:
                crit.append(f"memory growth {s['rss_growth_after_min5_pct']} % > 5 %")
            if s.get("p95_ratio_max", 0) > 1.5:
                crit.append(f"p95 frame time {s['p95_ratio_max']}x its first minute > 1.5x")
        if self.a.max_rss_mb and s.get("rss_max_mb", 0) > self.a.max_rss_mb:
            crit.append(f"resident memory {s['rss_max_mb']} MB > --max-rss-mb {self.a.max_rss_mb}")
        if self.a.max_gl_growth is not None and s.get("gl_growth_max", 0) > self.a.max_gl_growth:
            crit.append(f"live GL objects grew by {s['gl_growth_max']} within one process life ({s['gl_growth_kind']}) "
                        f"> --max-gl-growth {self.a.max_gl_growth}")
        s["failed_criteria"] = crit
        s["ok"] = not crit and not self.failures
        with open(os.path.join(self.work, "soak_summary.json"), "w") as f:
            json.dump(s, f, indent=1)
        if final:
            self.say("summary: " + json.dumps({k: v for k, v in s.items() if k != "failures"}))
        return s


def worst_growth(lives, key):
    """The largest rise of rows[key] over its value at a life's fifth minute, in per cent, with where."""
    worst = None
    for pid, rs in lives.items():
        base = [r for r in rs if r["process_minute"] >= 5 and isinstance(r.get(key), (int, float))
                and not math.isnan(r[key])]
        if len(base) < 2:
            continue
        g = 100 * (max(r[key] for r in base[1:]) - base[0][key]) / base[0][key]
        if worst is None or g > worst[0]:
            worst = (round(g, 2), pid, base[0]["minute"], len(base))
    return worst


def growth_summary(rows):
    """Memory growth within each process life after its first five minutes (a restart frees everything,
    so growth across lives says nothing), and the p95 frame time against the first minute.

    Two readings of memory: at each minute's quiet point (--quiet-s without input, after the idle trim: what
    the workbench keeps; the criterion when recorded) and the minute's last stats line (whatever was running
    then: a fit's working set, a drag, an export; reported beside it)."""
    out = {}
    if not rows:
        return out
    lives = {}
    for r in rows:
        lives.setdefault(r["pid"], []).append(r)
    end = worst_growth(lives, "rss_mb")
    quiet = worst_growth(lives, "rss_quiet_mb")
    if end:
        out["rss_growth_minute_end_after_min5_pct"] = end[0]
    worst = quiet or end
    if worst:
        out["rss_growth_after_min5_pct"] = worst[0]
        out["rss_growth_measure"] = "quiet" if quiet else "minute_end"
        out["rss_growth_life"] = {"pid": worst[1], "from_minute": worst[2], "minutes": worst[3]}
    # Live GL objects of each kind: the largest rise from a life's first minute to any later one.
    gmax, gkind = 0, ""
    for rs in lives.values():
        for k in [k for k in rs[0] if k.startswith("gl_")]:
            vals = [r[k] for r in rs if isinstance(r.get(k), int)]
            if len(vals) >= 2 and max(vals[1:]) - vals[0] > gmax:
                gmax, gkind = max(vals[1:]) - vals[0], k[3:]
    out["gl_growth_max"], out["gl_growth_kind"] = gmax, gkind
    out["process_lives"] = len(lives)
    out["longest_life_min"] = max(len(v) for v in lives.values())
    p95 = [r["frame_ms_p95"] for r in rows if not math.isnan(r["frame_ms_p95"])]
    if p95:
        out["p95_first_minute_ms"] = p95[0]
        out["p95_max_ms"] = max(p95)
        out["p95_median_ms"] = sorted(p95)[len(p95) // 2]
        out["p95_ratio_max"] = round(max(p95) / p95[0], 2)
        out["p95_ratio_median"] = round(sorted(p95)[len(p95) // 2] / p95[0], 2)
    rss = [r["rss_mb"] for r in rows if not math.isnan(r["rss_mb"])]
    if rss:
        out["rss_min_mb"], out["rss_max_mb"] = min(rss), max(rss)
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--exe", required=True)
    p.add_argument("--work", required=True)
    p.add_argument("--seed", type=int, default=19)
    p.add_argument("--minutes", type=float, default=2)
    p.add_argument("--check-growth", action="store_true")
    p.add_argument("--autosave-interval", type=float, default=30, help="the GUI's --autosave-interval (its promise)")
    p.add_argument("--margin", type=float, default=5, help="seconds allowed beyond the autosave promise (a loaded machine)")
    p.add_argument("--settle", type=float, default=1.0, help="seconds before Ctrl+S for the physics to take queued edits")
    p.add_argument("--stats-interval", type=float, default=5)
    p.add_argument("--quiet-s", type=float, default=None,
                   help="seconds without input before each minute's memory reading (default: 12 for runs of "
                        "10 minutes or more, above the workbench's 10 s idle trim; 0 for shorter runs)")
    p.add_argument("--kill-weight", type=float, default=1.0, help="relative weight of SIGKILL among the actions")
    p.add_argument("--restarts-after", type=float, default=0,
                   help="minutes of one process life before kills, reopens and opens join the walk")
    p.add_argument("--ensure-restarts", action="store_true",
                   help="kill, reopen and open at least once each (by 30, 50, 70 %% of the run): for short runs")
    p.add_argument("--max-rss-mb", type=float, default=0, help="fail when resident memory exceeds this (0: no bound)")
    p.add_argument("--max-gl-growth", type=int, default=None,
                   help="fail when live GL objects of one kind grow by more than this within one process life")
    p.add_argument("--window-wait", type=float, default=120)
    p.add_argument("--actions", default="", help="comma-separated actions to walk over (e.g. fit,save; default: all)")
    a = p.parse_args()
    if a.quiet_s is None:
        a.quiet_s = 12.0 if a.minutes >= 10 else 0.0
    for tool in ("xdotool",):
        if shutil.which(tool) is None:
            sys.exit(f"FAIL: {tool} is not installed (apt-get install {tool})")
    if not os.environ.get("DISPLAY"):
        sys.exit("FAIL: no DISPLAY (run under xvfb-run -s '-screen 0 1280x800x24')")
    if os.path.exists(a.work):
        shutil.rmtree(a.work)
    s = Soak(a).run()
    print("ok" if s["ok"] else "FAIL: " + "; ".join(s["failed_criteria"] + s["failures"][:5]))
    sys.exit(0 if s["ok"] else 1)


if __name__ == "__main__":
    main()
