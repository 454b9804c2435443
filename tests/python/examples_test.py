"""The examples of examples/ run (docs/python.md shows them)."""

import importlib.util
import pathlib

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]


def load(name):
    spec = importlib.util.spec_from_file_location(name, ROOT / "examples" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_collect_observations(tmp_path):
    n = load("collect_observations").collect(tmp_path / "obs.npz", steps=20)
    data = np.load(tmp_path / "obs.npz")
    assert n == 21 and data["frames"].shape == (21, 96, 128, 3) and data["frames"].dtype == np.uint8
    assert data["human_joints"].shape == (20, 22, 3)
    # The tool went up (1 cm per step commanded; the servos follow), then down.
    assert data["tcp_pos"][10, 2] > data["tcp_pos"][0, 2] + 0.02
    assert data["tcp_pos"][20, 2] < data["tcp_pos"][10, 2]


def test_scripted_policy(tmp_path):
    rows = load("scripted_policy").main(tmp_path / "run", "I1", 1, horizon=5.0)
    assert len(rows) == 1 and rows[0]["policy"] == "reach_and_lift" and rows[0]["status"] == "ok"
    assert (tmp_path / "run" / "summary.md").exists()
