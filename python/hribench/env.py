"""An HRIBench episode as a Gymnasium 1.x environment (docs/python.md).

    env = hribench.make("handover_h2r", seed=3)
    obs, info = env.reset()
    obs, reward, terminated, truncated, info = env.step(action)

The environment is a thin shell over the C++ eval::Episode (docs/episode.md): the same spec and
actions give the same episode log, bit for bit, as `hribench eval` (env.log_bytes()).
"""

import json

import numpy as np

from . import _hribench
from . import spaces

try:  # pragma: no cover - depends on the environment
    import gymnasium as _gymnasium
    _EnvBase = _gymnasium.Env
except ImportError:  # Debian: no Gymnasium; the same methods without the base class
    _EnvBase = object

REWARDS = ("sparse", "dense")


def _cameras(cameras):
    """[(name, height, width)] from names (224 x 224) or tuples."""
    out = []
    for camera in cameras or ():
        if isinstance(camera, str):
            out.append((camera, 224, 224))
        elif isinstance(camera, (tuple, list)) and len(camera) == 3:
            out.append((str(camera[0]), int(camera[1]), int(camera[2])))
        else:
            raise TypeError(f"cameras: expected names or (name, height, width) tuples, got {camera!r}")
    return out


class HRIBenchEnv(_EnvBase):
    """One episode of a task (an EpisodeSpec), stepped one control step (0.05 s) per action.

    Terminated: the episode ended before its horizon (success held for the success hold, or
    the simulation became invalid); truncated: it reached the horizon. info["status"] is the
    episode's status, info["events"] the script's events since the previous step (privileged:
    a learner under evaluation must not use them), and at the end info["metrics"] holds the
    episode's result: its entry of results.json (status and metrics, the benchmark's score).
    """

    metadata = {"render_modes": []}
    render_mode = None

    def __init__(self, spec, *, cameras=(), state_track=False, action_space="ee_delta",
                 reward="sparse", horizon=None, policy_name="python", task=None):
        if reward not in REWARDS:
            raise ValueError(f"reward: expected one of sparse, dense, got '{reward}'")
        self.spec = spec
        self.reward_mode = reward
        self.policy_spec = _hribench.PolicySpec(cameras=_cameras(cameras), state_track=bool(state_track),
                                                action_space=action_space)
        self._horizon = 0.0 if horizon is None else float(horizon)
        self._policy_name = policy_name
        self._task = task  # the task an env of make(task, seed) re-samples on reset(seed=)
        self._build()

    def _build(self):
        self.episode = _hribench.Episode(self.spec, self.policy_spec, self._policy_name, self._horizon)
        info = self.episode.info()
        limits = self.episode.action_limits()
        if self.policy_spec.action_space == "ee_delta":
            t, r = limits["max_ee_translation"], limits["max_ee_rotation"]
            low = [-t] * 3 + [-r] * 3 + [0.0]
            high = [t] * 3 + [r] * 3 + [1.0]
        else:
            low = limits["q_min"] + [0.0]
            high = limits["q_max"] + [1.0]
        self.action_space = spaces.Box(np.array(low), np.array(high), dtype=np.float64)
        dof = len(limits["q_min"])
        observation = {
            "time": spaces.Box(0.0, np.inf, shape=(), dtype=np.float64),
            "instruction": spaces.Text(max_length=4096),
            "joint_pos": spaces.Box(np.array(limits["q_min"]), np.array(limits["q_max"]), dtype=np.float64),
            "joint_vel": spaces.Box(-np.inf, np.inf, shape=(dof,), dtype=np.float64),
            "gripper_width": spaces.Box(0.0, np.inf, shape=(1,), dtype=np.float64),
            "tcp_pos": spaces.Box(-np.inf, np.inf, shape=(3,), dtype=np.float64),
            "tcp_quat": spaces.Box(-1.0, 1.0, shape=(4,), dtype=np.float64),
            "images": spaces.Dict({name: spaces.Box(0, 255, shape=(h, w, 3), dtype=np.uint8)
                                   for name, h, w in self.policy_spec.cameras}),
        }
        if self.policy_spec.state_track:
            objects = sorted(o for o in self._object_names())
            observation["state"] = spaces.Dict({
                "human_joints": spaces.Box(-np.inf, np.inf, shape=(22, 3), dtype=np.float64),
                "objects": spaces.Dict({o: spaces.Box(-np.inf, np.inf, shape=(7,), dtype=np.float64)
                                        for o in objects}),
            })
        self.observation_space = spaces.Dict(observation)
        self.episode_info = info
        self._events_seen = 0

    def _object_names(self):
        self.episode.reset()
        return self.episode.log()["object_names"]

    # Gymnasium 1.x
    def reset(self, *, seed=None, options=None):
        """Starts the episode; returns (observation, info). seed: with an env of make(task,
        seed), re-samples the task with this seed (another episode); else it must be the
        episode's own seed. options: unused (Gymnasium's signature)."""
        if _EnvBase is not object:  # pragma: no cover - Gymnasium seeds its np_random
            super().reset(seed=seed)
        if seed is not None and seed != self.spec.seed:
            if self._task is None:
                raise ValueError(f"seed: expected this pool episode's seed {self.spec.seed}, got {seed}")
            self.spec = _hribench.sample_task(self._task, seed)
            self._build()
        self.episode.reset()
        self._events_seen = 0
        return self.episode.observe(), self._info()

    def step(self, action):
        """One control step with `action` (action_space); returns (observation, reward,
        terminated, truncated, info)."""
        observation, done, status, reason = self.episode.step(action)
        info = self._info()
        reward = 0.0
        if self.reward_mode == "dense":
            info["reward_terms"] = self.episode.dense_reward()
            reward = info["reward_terms"]["total"]
        terminated = truncated = False
        if done:
            info["reason"] = reason
            result = json.loads(self.episode.result_json())
            info["metrics"] = result
            truncated = reason == "horizon"
            terminated = not truncated
            if self.reward_mode == "sparse":
                reward = 1.0 if result["success"] else 0.0
        return observation, float(reward), terminated, truncated, info

    def _info(self):
        events = self.episode.events(self._events_seen)
        self._events_seen = self.episode.num_events
        return {"time": self.episode.time, "status": self.episode.status, "events": events}

    def close(self):
        pass

    # HRIBench's own
    def log(self):
        """The episode log so far as numpy arrays (the keys of hribench.load_log)."""
        return self.episode.log()

    def log_bytes(self):
        """The log in the .hlog encoding: equal bytes <=> identical logs (eval::identical)."""
        return self.episode.log_bytes()

    def metrics(self):
        """The episode's result so far: its entry of results.json (identity, status, metrics)."""
        return json.loads(self.episode.result_json())
