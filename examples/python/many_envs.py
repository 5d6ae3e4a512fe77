#!/usr/bin/env python3
"""Many environments from a plain NumPy loop: the shape of a training loop's tactile observation.

E environments, each a 4 mm sphere pressed into a GelSight Mini at its own random depth, then dragged along
its own random direction (a stand-in for a policy's actions); every control step the module turns the E poses
into E x 63 x 2 marker displacements (pixels) in one batched call, written into a preallocated array. The
"observation" here is the field itself, the "reward" the mean shear magnitude (a placeholder for a task's).

    python3 examples/python/many_envs.py --envs 1024 --steps 60
(from a build folder: PYTHONPATH=build/python /usr/bin/python3 examples/python/many_envs.py)
"""
import argparse
import time

import numpy as np

import shearbench


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--envs", type=int, default=1024)
    ap.add_argument("--steps", type=int, default=60)
    ap.add_argument("--model", default="hydroshear")
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()

    rng = np.random.default_rng(a.seed)
    E, R, dt = a.envs, 0.004, 1 / 60
    model = shearbench.SensorModel(a.model, indenter='{"shape": "sphere", "radius_m": 0.004}', envs=E)
    depth = rng.uniform(0.3e-3, 1.2e-3, E)      # m, per env
    heading = rng.uniform(0, 2 * np.pi, E)      # drag direction in the gel plane
    speed = rng.uniform(0, 1.5e-3, E)           # m over the drag
    X = np.zeros((E, 7))
    X[:, 3] = 1                                 # no rotation: qw = 1
    field = np.empty((E, model.markers, 2))     # the module writes here in place
    t_model = 0.0
    for k in range(a.steps):
        press = min(1.0, k / 20)                # press over the first third, then drag
        drag = max(0.0, (k - 20) / (a.steps - 20))
        X[:, 0] = speed * drag * np.cos(heading)
        X[:, 1] = speed * drag * np.sin(heading)
        X[:, 2] = R + 0.2e-3 - (depth + 0.2e-3) * press
        t0 = time.perf_counter()
        model.step(X, dt, out=field)
        t_model += time.perf_counter() - t0
        reward = np.linalg.norm(field, axis=2).mean(axis=1)  # per env
        if k % 20 == 19 or k == a.steps - 1:
            print(f"step {k + 1:3d}: mean |disp| {reward.mean():.3f} px (max env {reward.max():.3f} px)")
    print(f"{a.model}: {E} envs x {model.markers} markers, {1e3 * t_model / a.steps:.2f} ms per batched step")


if __name__ == "__main__":
    main()
