"""hribench.evaluate (python/hribench/evaluate.py over gen/evaluation.h): a Python policy in
the benchmark writes what `hribench eval` writes for the same policy served in C++."""

import json
import re

import numpy as np
import pytest

import hribench

TASKS = "I1,C3"
FLAGS = dict(episodes=2, seed=0, horizon=1.0)
CLI_FLAGS = ["--episodes", "2", "--seed", "0", "--horizon", "1"]


class Noop:
    """policy/builtin.cc's noop in Python: zero deltas, the gripper kept at its opening."""

    name = "noop"

    def spec(self):
        return {"action_space": "ee_delta"}

    def reset(self, info):
        self.max_width = info["gripper_max_width"]

    def act(self, obs):
        action = np.zeros(7)
        action[6] = min(max(obs["gripper_width"][0] / self.max_width, 0.0), 1.0)
        return action


def episodes_of(path):
    return json.loads((path / "results.json").read_text())["episodes"]


def without_git_hash(text):
    return re.sub(rb"\(git [0-9a-f]+(-dirty)?\)", b"(git)", text)


def files_of(path):
    return {p.name: p.read_bytes() for p in path.iterdir() if p.is_file()}


def test_a_python_noop_equals_the_cli_noop(tmp_path, run_cli):
    cli = run_cli("eval", "--tasks", TASKS, "--policy", "noop", *CLI_FLAGS, "--out", tmp_path / "cli")
    assert cli.returncode == 0, cli.stderr
    rows = hribench.evaluate(Noop(), tasks=TASKS, out=tmp_path / "py", **FLAGS)
    assert len(rows) == 4 and {r["policy"] for r in rows} == {"noop"}
    assert episodes_of(tmp_path / "py") == episodes_of(tmp_path / "cli")
    cli_files, py_files = files_of(tmp_path / "cli"), files_of(tmp_path / "py")
    assert sorted(py_files) == sorted(cli_files)
    # Byte for byte, but for the build's git hash in the provenance (the module and the command
    # are two binaries, which an incremental build can leave at different commits).
    for name in ("options.json", "summary.md", "summary.csv", "report.html"):
        assert without_git_hash(py_files[name]) == without_git_hash(cli_files[name]), name


def test_one_and_two_threads_give_identical_results(tmp_path):
    flags = dict(FLAGS, episodes=1)  # two jobs, one per task
    hribench.evaluate(Noop(), tasks=TASKS, out=tmp_path / "t1", threads=1, **flags)
    hribench.evaluate(Noop(), tasks=TASKS, out=tmp_path / "t2", threads=2, **flags)
    assert episodes_of(tmp_path / "t1") == episodes_of(tmp_path / "t2")


def test_a_fixed_action_sequence_equals_its_cpp_replay(tmp_path):
    # A callable policy playing a fixed sequence, and the same sequence stepped in C++.
    sequence = np.zeros((20, 7))
    sequence[:, 2] = 0.01
    sequence[:, 6] = np.linspace(1.0, 0.0, 20)

    class Sequence:
        name = "sequence"

        def spec(self):
            return hribench.PolicySpec(replan_every=20)

        def reset(self, info):
            pass

        def act(self, obs):
            return sequence

    hribench.evaluate(Sequence(), tasks="I1", out=tmp_path / "py", episodes=1, horizon=1.0,
                      save_logs=True)
    (log_file,) = (tmp_path / "py" / "logs").iterdir()
    env = hribench.make("I1", seed=0, horizon=1.0, policy_name="sequence")
    env.reset()
    assert env.episode.replay(sequence) == 20
    assert env.log_bytes() == hribench._hribench.log_bytes_of_file(str(log_file))


def test_an_exception_in_act_ends_the_episode_as_policy_error(tmp_path):
    def explode(obs):
        raise RuntimeError("the model is not loaded")

    rows = hribench.evaluate(explode, tasks="I1", out=tmp_path / "x", episodes=1, horizon=1.0)
    assert rows[0]["policy"] == "explode"
    assert rows[0]["status"] == "policy_error"
    assert "RuntimeError: the model is not loaded" in rows[0]["status_reason"]


def test_bad_actions_and_arguments(tmp_path, run_cli):
    rows = hribench.evaluate(lambda obs: np.zeros(3), tasks="I1", out=tmp_path / "short",
                             episodes=1, horizon=1.0, name="short")
    assert rows[0]["status"] == "policy_error" and "expected 7 values" in rows[0]["status_reason"]
    # The CLI's one-line messages.
    cli = run_cli("eval", "--tasks", "I1", "--policy", "noop", "--threads", "0", "--out", tmp_path / "c")
    with pytest.raises(ValueError) as error:
        hribench.evaluate("noop", tasks="I1", out=tmp_path / "c", threads=0)
    assert str(error.value) in cli.stderr
    with pytest.raises(ValueError, match="--tasks: "):
        hribench.evaluate(Noop(), tasks="nosuchtask", out=tmp_path / "n")
    with pytest.raises(TypeError, match="policy: expected"):
        hribench.evaluate(42, tasks="I1", out=tmp_path / "n")
    with pytest.raises(TypeError, match="spec\\(\\): expected"):
        hribench.evaluate(lambda obs: None, tasks="I1", out=tmp_path / "n", spec=7)


def test_resume_skips_finished_episodes(tmp_path):
    out = tmp_path / "r"
    hribench.evaluate(Noop(), tasks="I1", out=out, episodes=1, horizon=1.0)
    with pytest.raises(ValueError, match="already holds a run; use --resume"):
        hribench.evaluate(Noop(), tasks="I1", out=out, episodes=1, horizon=1.0)
    calls = []

    def counting(obs):
        calls.append(1)
        return np.array([0, 0, 0, 0, 0, 0, 1.0])

    rows = hribench.evaluate(counting, tasks="I1", out=out, episodes=1, horizon=1.0, resume=True,
                             name="noop")
    assert len(rows) == 1 and calls == []
