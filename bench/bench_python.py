#!/usr/bin/env python3
"""The Python module's batched step against the C++ one, on BENCH_WORKLOAD.md (peg grasp, 2 pads per env).

Times `SensorModel.step` on the workload exactly as `shearbench bench` times the C++ step: the poses of every
step prepared first (shearbench.bench_poses), steps 0..22, the median over k = 3..22, the lowest median of
--repeat runs; the field goes into a preallocated array (out=). Then runs `shearbench bench` for the same
case in the same session and prints both medians and their ratio (Python / C++).

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_python.py --exe build/shearbench --envs 1024 --repeat 5
"""
import argparse
import json
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import shearbench

WARMUP, STEPS = 3, 23


def python_median_ms(model_name: str, envs: int, repeat: int) -> float:
    poses = shearbench.bench_poses(envs, STEPS)
    model = shearbench.SensorModel(model_name, param_set="published", indenter="bench_peg", envs=2 * envs)
    out = np.empty((2 * envs, model.markers, 2))
    best = float("inf")
    for _ in range(repeat):
        model.reset()
        ms = []
        for X in poses:
            t0 = time.perf_counter()
            model.step(X, shearbench.bench_dt, out=out)
            ms.append(1e3 * (time.perf_counter() - t0))
        best = min(best, float(np.median(ms[WARMUP:])))
    return best


def cpp_median_ms(exe: str, model_name: str, envs: int, repeat: int) -> float:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "bench.json"
        subprocess.run([exe, "bench", "--model", model_name, "--envs", str(envs), "--repeat", str(repeat),
                        "--json", str(out)], check=True, capture_output=True)
        return json.loads(out.read_text())["results"][0]["median_ms"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default="shearbench")
    ap.add_argument("--model", default="hydroshear")
    ap.add_argument("--envs", type=int, default=1024)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--rounds", type=int, default=2, help="alternate Python and C++ this many times")
    a = ap.parse_args()
    py, cpp = [], []
    for _ in range(a.rounds):  # alternated, so a change of the machine's load hits both
        py.append(python_median_ms(a.model, a.envs, a.repeat))
        cpp.append(cpp_median_ms(a.exe, a.model, a.envs, a.repeat))
    p, c = min(py), min(cpp)
    print(f"{a.model}, {a.envs} envs x 2 sensors: Python {p:.3f} ms, C++ {c:.3f} ms per batched step "
          f"(best of {a.rounds} rounds x {a.repeat} repeats; Python rounds {', '.join(f'{v:.3f}' for v in py)}, "
          f"C++ {', '.join(f'{v:.3f}' for v in cpp)}): ratio {p / c:.3f}")


if __name__ == "__main__":
    main()
