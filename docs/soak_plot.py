#!/usr/bin/env python3
"""Plots a soak's minutes (tests/cli/soak.py -> <work>/soak_minutes.csv): resident memory and frame-time
p50/p95 over the run, restarts (SIGKILL, reopen, open) marked where a new process begins.
Usage: python3 docs/soak_plot.py <work>/soak_minutes.csv docs/soak_1h.png   (needs python3-matplotlib;
a documentation tool, not run by the tests)."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(src, out):
    rows = list(csv.DictReader(open(src)))
    m = [float(r["t_s"]) / 60 for r in rows]   # when the minute's row closed (rows close after an action)
    quiet = bool(rows and rows[0].get("rss_quiet_mb"))   # soaks since the quiet point: memory read after 12 s idle
    rss = [float(r["rss_quiet_mb"] if quiet else r["rss_mb"]) for r in rows]
    p50 = [float(r["frame_ms_p50"]) for r in rows]
    p95 = [float(r["frame_ms_p95"]) for r in rows]
    fig, (a, b) = plt.subplots(2, 1, figsize=(10, 6.5), sharex=True)
    a.plot(m, rss, "o-", ms=3, color="tab:blue", label="resident" + (" (each minute's quiet point)" if quiet else ""))
    if rows and rows[0].get("rss_anon_mb"):   # soaks since the stats carry RssAnon: the heap part of it
        anon = [float(r["rss_anon_quiet_mb"] if quiet else r["rss_anon_mb"]) for r in rows]
        a.plot(m, anon, "o-", ms=3, color="tab:cyan", label="of which heap (RssAnon)")
        a.legend(loc="lower right", fontsize=8)
    a.set_ylabel("resident memory (MB)")
    a.set_ylim(0, max(rss) * 1.15)
    a.grid(alpha=0.3)
    b.plot(m, p95, "o-", ms=3, color="tab:red", label="p95")
    b.plot(m, p50, "o-", ms=3, color="tab:gray", label="p50")
    b.axhline(1.5 * p95[0], color="tab:red", ls=":", lw=1, label="1.5x first-minute p95")
    b.set_ylabel("frame time (ms)")
    b.set_xlabel("minutes into the soak")
    b.set_ylim(0, max(max(p95), 1.5 * p95[0]) * 1.15)
    b.grid(alpha=0.3)
    first = True
    for i in range(1, len(rows)):
        if rows[i]["pid"] != rows[i - 1]["pid"]:
            for ax in (a, b):
                ax.axvline((m[i] + m[i - 1]) / 2, color="k", alpha=0.15, lw=1, label="new process" if first and ax is b else None)
            first = False
    b.legend(loc="upper left", fontsize=8)
    a.set_title("shearbench gui soak: memory and frame time per minute (grey lines: a new process)")
    fig.tight_layout()
    fig.savefig(out, dpi=100)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
