"""hribench.make / HRIBenchEnv (python/hribench/env.py): the Gymnasium 1.x signature and spaces,
errors, images without copies, and an episode stepped from Python equal to the C++ one."""

import math

import numpy as np
import pytest

import hribench


def test_reset_and_step_have_the_gymnasium_signature():
    env = hribench.make("I1", seed=0, horizon=0.5)
    obs, info = env.reset()
    assert set(obs) == set(env.observation_space.keys())
    assert obs["joint_pos"].shape == env.observation_space["joint_pos"].shape == (7,)
    assert obs["joint_pos"].dtype == np.float64
    assert env.observation_space["joint_pos"].contains(obs["joint_pos"])
    assert obs["instruction"] == env.episode_info["instruction"] != ""
    assert info["status"] == "ok" and info["time"] == 0.0
    assert env.action_space.shape == (7,)
    np.testing.assert_array_equal(env.action_space.high, [0.05] * 3 + [0.25] * 3 + [1.0])
    action = np.zeros(7)
    action[6] = 1.0
    steps = 0
    while True:
        obs, reward, terminated, truncated, info = env.step(action)
        steps += 1
        assert isinstance(reward, float)
        if terminated or truncated:
            break
        assert reward == 0.0 and "metrics" not in info
    assert steps == 10 and truncated and not terminated  # 0.5 s at 20 Hz: the horizon
    assert info["reason"] == "horizon"
    assert reward == 0.0 and info["metrics"]["success"] is False
    assert math.isclose(obs["time"], 0.5)


def test_reset_with_another_seed_samples_another_episode():
    env = hribench.make("I1", seed=0, horizon=0.1)
    env.reset()
    assert env.spec.seed == 0 and env.spec.robot == "panda"
    env.reset(seed=1)
    assert env.spec.seed == 1 and env.spec.hash != hribench.make("I1", seed=0).spec.hash


def test_pool_episode_and_state_track():
    env = hribench.make(pool="pool/v8", split="eval", index=7, state_track=True, horizon=0.1)
    obs, _ = env.reset()
    assert obs["state"]["human_joints"].shape == (22, 3)
    assert set(obs["state"]["objects"]) == set(env.observation_space["state"]["objects"].keys())
    with pytest.raises(ValueError, match="seed: expected this pool episode's seed"):
        env.reset(seed=env.spec.seed + 1)
    with pytest.raises(ValueError, match=r"index: expected 0\.\.[0-9]+ \(episodes of split eval\), got 100000"):
        hribench.make(pool="pool/v8", index=100000)


def test_bad_arguments_raise_with_the_cli_messages():
    with pytest.raises(ValueError, match="no task matches 'nosuchtask'|nosuchtask"):
        hribench.make("nosuchtask")
    with pytest.raises(ValueError, match="action_space: expected"):
        hribench.make("I1", action_space="torque")
    with pytest.raises(ValueError, match="reward: expected one of"):
        hribench.make("I1", reward="shaped")
    with pytest.raises(TypeError, match="cameras: expected"):
        hribench.make("I1", cameras=[3])
    with pytest.raises(ValueError, match="split: expected"):
        hribench.make(pool="pool/v8", split="train")
    env = hribench.make("I1", seed=0, horizon=0.1)
    env.reset()
    with pytest.raises(ValueError, match="expected 7 values"):
        env.step(np.zeros(6))
    with pytest.raises(ValueError, match="action: expected an action"):
        env.step("left")
    bad = np.zeros(7)
    bad[0] = 1.0  # 1 m in one control step
    with pytest.raises(ValueError, match="out_of_range|outside|range"):
        env.step(bad)


def test_a_failed_check_raises_instead_of_aborting():
    env = hribench.make("I1", seed=0, horizon=0.1)
    # Stepping before reset is a caller's error (an InputError), the module stays alive.
    with pytest.raises(ValueError):
        env.step(np.zeros(7))
    assert issubclass(hribench.CheckError, RuntimeError)
    with pytest.raises(hribench.CheckError, match="check failed"):
        hribench._hribench._fail_check_for_tests()


def test_images_are_uint8_hw3_views_of_the_rendered_buffer():
    env = hribench.make("I1", seed=0, cameras=[("agentview", 64, 96)], horizon=0.1)
    obs, _ = env.reset()
    image = obs["images"]["agentview"]
    assert image.dtype == np.uint8 and image.shape == (64, 96, 3)
    assert env.observation_space["images"]["agentview"].contains(image)
    assert image.base is not None and not image.flags["OWNDATA"]  # owns no copy: a view
    assert image.std() > 0  # a picture, not a blank buffer
    action = np.zeros(7)
    obs2, *_ = env.step(action)
    assert not np.shares_memory(obs2["images"]["agentview"], image)


def test_replaying_the_oracle_from_python_reproduces_the_cpp_log(tmp_path, run_cli):
    # The C++ run (hribench eval --save-logs) and the same actions stepped from Python.
    # 6 s of I1 (the oracle reaches and grasps; the full episode is the C++ tests' business).
    result = run_cli("eval", "--tasks", "I1", "--policy", "oracle", "--episodes", "1", "--seed", "0",
                     "--horizon", "6", "--save-logs", "--out", tmp_path / "run")
    assert result.returncode == 0, result.stderr
    (log_file,) = (tmp_path / "run" / "logs").iterdir()
    log = hribench.load_log(log_file)
    env = hribench.make("I1", seed=0, action_space=log["action_space"], policy_name="oracle",
                        horizon=6)
    env.reset()
    for k in range(1, len(log["time"])):
        obs, reward, terminated, truncated, info = env.step(log["actions"][k])
    assert truncated and len(log["time"]) == 121
    assert np.linalg.norm(np.diff(log["tcp_pose"][:, :3], axis=0), axis=1).sum() > 0.1  # it moved
    assert env.log_bytes() == hribench._hribench.log_bytes_of_file(str(log_file))
    np.testing.assert_array_equal(env.log()["joint_pos"], log["joint_pos"])


def test_the_dense_reward_pays_the_success_bonus_at_the_end_of_a_successful_episode(tmp_path, run_cli):
    # The oracle's whole I1 episode, replayed with reward="dense" (docs/python.md "Rewards").
    result = run_cli("eval", "--tasks", "I1", "--policy", "oracle", "--episodes", "1", "--seed", "0",
                     "--save-logs", "--out", tmp_path / "run")
    assert result.returncode == 0, result.stderr
    (log_file,) = (tmp_path / "run" / "logs").iterdir()
    log = hribench.load_log(log_file)
    env = hribench.make("I1", seed=0, action_space=log["action_space"], policy_name="oracle",
                        reward="dense")
    env.reset()
    terms = []
    for k in range(1, len(log["time"])):
        obs, reward, terminated, truncated, info = env.step(log["actions"][k])
        terms.append(info["reward_terms"])
        assert reward == info["reward_terms"]["total"]
    assert terminated and info["metrics"]["success"]
    assert [t["success"] for t in terms[:-1]] == [0.0] * (len(terms) - 1)
    assert terms[-1]["success"] == 10.0
    assert all(t["premature_motion"] == 0.0 for t in terms)  # the oracle waits for the point
    assert sum(t["progress"] for t in terms) > 0
