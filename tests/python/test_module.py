"""The Python module `shearbench` against the CLI it shares its code with.

Run by ctest (`python_module`) with Debian's interpreter: /usr/bin/python3 -m pytest tests/python, PYTHONPATH
holding the built module and SHEARBENCH_EXE the built executable.
"""
import csv
import json
import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import shearbench

EXE = os.environ.get("SHEARBENCH_EXE", "shearbench")
SRC = Path(__file__).resolve().parents[2]
# The agreement asked of the module with `simulate`: the poses pass through poses.csv (17 significant digits)
# and a quaternion, which moves the last bits of a pose, not the field's 1e-9 px.
FIELD_TOL_PX = 1e-9


def read_sample(dataset: Path, sample: str):
    """Poses [frames, 7] and the field [frames, markers, 2] of a tsd/1 sample."""
    meta = json.loads((dataset / "dataset.json").read_text())
    dt = next(s["dt_s"] for s in meta["samples"] if s["id"] == sample)
    with open(dataset / sample / "poses.csv") as f:
        rows = list(csv.DictReader(f))
    poses = np.array([[float(r[k]) for k in ("x_m", "y_m", "z_m", "qw", "qx", "qy", "qz")] for r in rows])
    markers = len(meta["sensor"]["markers_rest_px"])
    field = np.zeros((len(rows), markers, 2))
    with open(dataset / sample / "markers.csv") as f:
        for r in csv.DictReader(f):
            field[int(r["frame"]), int(r["marker"])] = (float(r["du_px"]), float(r["dv_px"]))
    return poses, field, dt


def simulate(tmp_path: Path, scene: str, model: str, *extra: str):
    out = tmp_path / "sim"
    subprocess.run([EXE, "-q", "simulate", "--scene", scene, "--model", model, "--out", str(out), *extra], check=True)
    sample = json.loads((out / "dataset.json").read_text())["samples"][0]["id"]
    return read_sample(out, sample)


def replay(model: shearbench.SensorModel, poses: np.ndarray, dt: float) -> np.ndarray:
    return np.stack([model.step(X[None, :], dt)[0] for X in poses])


@pytest.mark.parametrize("model_name", ["hydroshear", "fots-reimpl", "tacsl"])
def test_field_equals_cli_simulate(tmp_path, model_name):
    scene = str(SRC / "scenes" / "shear_sphere.json")
    poses, field, dt = simulate(tmp_path, scene, model_name)
    model = shearbench.SensorModel(model_name, scene=scene)
    got = replay(model, poses, dt)
    assert np.abs(field).max() > 0.1  # the scene presses and shears: the comparison is not of zeros
    np.testing.assert_allclose(got, field, rtol=0, atol=FIELD_TOL_PX)


def test_loop_answer_by_name_equals_cli_simulate(tmp_path):
    answer = shearbench.loop_answer("twin_sphere35_hydroshear")
    assert answer["model"] == "hydroshear-contact+tool_frame"
    scene = str(SRC / "scenes" / "twist_sphere35.json")
    poses, field, dt = simulate(tmp_path, scene, answer["model"], "--params", answer["params_file"])
    model = shearbench.SensorModel(answer["model"], params_file=answer["params_file"], scene=scene)
    np.testing.assert_allclose(replay(model, poses, dt), field, rtol=0, atol=FIELD_TOL_PX)


def test_names():
    assert "hydroshear" in shearbench.model_names() and "tacsl" in shearbench.model_names()
    assert "tool_frame" in shearbench.effect_names()
    assert "twin_sphere35" in shearbench.param_set_names()
    assert shearbench.__version__.count(".") == 2


def test_batch_out_is_written_in_place_and_envs_are_independent():
    E = 64
    model = shearbench.SensorModel("hydroshear", indenter='{"shape": "sphere", "radius_m": 0.004}', envs=E)
    assert (model.envs, model.markers) == (E, 63)
    assert model.markers_rest_px.shape == (63, 2) and model.mm_per_px == pytest.approx(0.0634)
    # Env e pressed e/E mm; env 0 stays 1 mm above the gel (sphere centre at R + 1 mm).
    X = np.zeros((E, 7))
    X[:, 2] = 0.004 - 1e-3 * np.arange(E) / E
    X[0, 2] = 0.005
    X[:, 3] = 1
    out = np.empty((E, 63, 2))
    result = model.step(X, 1 / 60, out=out)
    assert result is out  # no copy: the module wrote into the caller's array
    assert np.all(out[0] == 0)
    # The deeper press spreads wider: the summed |field| grows with depth.
    size = np.abs(out).sum(axis=(1, 2))
    assert size[E - 1] > size[E // 2] > 0
    field, contact = model.step(X, 1 / 60, contact=True)
    assert contact.shape == (E, 63) and contact[E - 1, 3 * 9 + 4] == 1 and contact[0].sum() == 0
    model.reset(E - 1)
    model.reset()


def test_bad_pose_raises_and_names_the_env():
    model = shearbench.SensorModel("hydroshear", envs=2)
    X = np.tile([0, 0, 0.01, 1, 0, 0, 0], (2, 1)).astype(float)
    X[1, 0] = math.nan
    with pytest.raises(shearbench.Error, match=r"X_EI\[env 1\]: a pose value is not finite"):
        model.step(X, 0.02)
    with pytest.raises(ValueError, match=r"expected shape \(2, 7\)"):
        model.step(X[:1], 0.02)
    with pytest.raises(shearbench.Error, match="out: expected a writeable C-contiguous float64"):
        model.step(np.tile([0, 0, 0.01, 1, 0, 0, 0], (2, 1)), 0.02, out=np.zeros((2, 63, 2), dtype=np.float32))


def test_unknown_model_raises_with_the_cli_message(tmp_path):
    with pytest.raises(shearbench.Error) as caught:
        shearbench.SensorModel("hydroshear-nope")
    cli = subprocess.run([EXE, "simulate", "--scene", str(SRC / "scenes" / "shear_sphere.json"), "--model",
                          "hydroshear-nope", "--out", str(tmp_path / "x")], capture_output=True, text=True)
    assert cli.returncode == 2
    # The CLI names its flag (--model), the module its argument (model); the rest is one message.
    detail = str(caught.value).removeprefix("model: ")
    assert f"--model: {detail}" in cli.stderr
    with pytest.raises(shearbench.Error, match="no residual run 'nope'"):
        shearbench.loop_answer("nope")


def test_bench_field_equals_shearbench_bench(tmp_path):
    envs = 4
    subprocess.run([EXE, "bench", "--model", "hydroshear", "--envs", str(envs), "--field-out",
                    str(tmp_path / "field.json")], check=True, capture_output=True)
    want = json.loads((tmp_path / "field.json").read_text())
    poses = shearbench.bench_poses(envs, want["steps"])
    model = shearbench.SensorModel("hydroshear", param_set="published", indenter="bench_peg", envs=2 * envs)
    for X in poses:
        field = model.step(X, shearbench.bench_dt)
    assert np.abs(field).max() > 0.1
    np.testing.assert_array_equal(field.ravel(), np.array(want["field_px"]))


def test_many_envs_example_runs():
    """examples/python/many_envs.py, small: the NumPy loop of many envs keeps working."""
    import sys
    run = subprocess.run([sys.executable, str(SRC / "examples" / "python" / "many_envs.py"), "--envs", "32",
                          "--steps", "30"], check=True, capture_output=True, text=True)
    assert "32 envs x 63 markers" in run.stdout
    last = [line for line in run.stdout.splitlines() if line.startswith("step")][-1]
    assert float(last.split("mean |disp|")[1].split()[0]) > 0.1  # the drags shear the field
