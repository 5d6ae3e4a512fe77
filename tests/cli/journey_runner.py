"""The command line and the loop shared by the GUI journey scripts (gui_taps, gui_reports, gui_undo, gui_values):
each script drives the workbench through a driver (a class with say, check, kill, failures and t0, as gui_taps.Taps)
and lists its journeys; this runs the ones --only names, each with a window of its own, and exits 1 on a failure."""
import argparse
import os
import shutil
import sys
import time


def journey_args():
    """--exe, --work (emptied), --src, --data and --only, as tests/cli/CMakeLists.txt passes them."""
    p = argparse.ArgumentParser()
    p.add_argument("--exe", required=True)
    p.add_argument("--work", required=True)
    p.add_argument("--src", required=True)
    p.add_argument("--data", default=os.environ.get("SHEARBENCH_DATA", ""))
    p.add_argument("--only", default="", help="run only the journeys whose name contains this")
    a = p.parse_args()
    a.data = os.path.abspath(a.data)
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    return a


def run_journeys(driver, journeys, only=""):
    """Runs each journey (a callable without arguments) whose name contains `only`, then exits."""
    try:
        for journey in journeys:
            name = getattr(journey, "__name__", None) or journey.func.__name__   # a functools.partial too
            if only not in name:
                continue
            driver.say(f"--- {name}")
            journey()
            driver.kill()
            time.sleep(1.0)   # the X server done with the last window
    finally:
        driver.kill()
    driver.say(f"{len(driver.failures)} failures in {time.time() - driver.t0:.0f} s")
    sys.exit(1 if driver.failures else 0)
