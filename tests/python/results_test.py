"""hribench.load_results and hribench.load_log (python/hribench/results.py, bindings/eval.cc)."""

import numpy as np
import pytest

import hribench


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "noop"
    hribench.evaluate("noop", tasks="I1", out=out, episodes=2, horizon=1.0, save_logs=True)
    return out


def test_load_results_rows(run_dir):
    rows = hribench.load_results(run_dir, dataframe=False)
    assert [r["seed"] for r in rows] == [0, 1]
    assert {r["task"] for r in rows} == {"point_pick"} and rows[0]["success"] is False
    assert rows.info["options"]["episodes"] == 2
    with pytest.raises(ValueError, match="nothing_here: cannot open the results file"):
        hribench.load_results(run_dir / "nothing_here")


def test_load_results_dataframe_needs_pandas(run_dir):
    try:
        import pandas  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError, match="needs pandas"):
            hribench.load_results(run_dir, dataframe=True)
        return
    frame = hribench.load_results(run_dir)
    assert list(frame["seed"]) == [0, 1]


def test_load_log_arrays(run_dir):
    (path, _) = sorted((run_dir / "logs").iterdir())
    log = hribench.load_log(path)
    n = len(log["time"])
    assert n == 21 and log["time"][-1] == pytest.approx(1.0)
    assert log["joint_pos"].shape == (n, 7) and log["tcp_pose"].shape == (n, 7)
    assert log["human_joints"].shape == (n, 22, 3)
    assert log["actions"].shape == (n, 7) and np.isnan(log["actions"][0]).all()
    assert log["predicates"].dtype == np.uint8 and log["predicates"].shape[0] == n
    assert "success" in log["predicate_names"]
    assert log["object_poses"].shape == (n, len(log["object_names"]), 7)
    assert log["separation"].shape == (n,)
    assert set(log["contacts"]) == {"step", "normal_force", "robot_part", "other", "region"}
    assert all({"time", "kind", "actor", "name", "detail"} <= set(e) for e in log["events"])
    assert log["policy"] == "noop" and log["status"] == "ok"
    with pytest.raises(ValueError):
        hribench.load_log(run_dir / "missing.hlog")
