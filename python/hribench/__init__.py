"""HRIBench from Python (docs/python.md).

    import hribench
    env = hribench.make("handover_h2r", seed=3)
    obs, info = env.reset()
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

A thin layer over the C++ library (hribench._hribench): errors in arguments raise ValueError /
TypeError with the CLI's one-line messages; a failed internal check raises hribench.CheckError.
"""

from . import _hribench
from . import spaces
from ._hribench import CheckError, EpisodeSpec, PolicySpec, __version__, policy_names, task_names
from .env import HRIBenchEnv
from .results import Results, load_results
from .evaluate import evaluate

__all__ = ["make", "HRIBenchEnv", "CheckError", "EpisodeSpec", "PolicySpec", "load_log", "load_results", "Results", "evaluate",
           "policy_names", "task_names", "spaces", "__version__"]


def make(task=None, seed=0, *, pool=None, split="eval", index=0, cameras=(), state_track=False,
         action_space="ee_delta", reward="sparse", horizon=None, policy_name="python"):
    """An environment of one episode: a task (id "I1", name or script) sampled with `seed`, or
    episode `index` of a pool's split (with `task`, of that task's episodes in the split).

    cameras: names (224 x 224) or (name, height, width); state_track: observe the human's
    joints and the objects' poses; action_space: "ee_delta" or "joint_pos"; reward: "sparse"
    (1 at the last step when the episode succeeds, else 0); horizon: seconds (default the
    script's); policy_name: the policy the episode log names.
    """
    if pool is None:
        if task is None:
            raise ValueError("make: expected a task or pool=, got neither")
        spec = _hribench.sample_task(str(task), int(seed))
        sampled_task = str(task)
    else:
        episodes = _hribench.pool_episodes(str(pool), split, [] if task is None else [str(task)])
        if not 0 <= index < len(episodes):
            raise ValueError(f"index: expected 0..{len(episodes) - 1} (episodes of split {split}), "
                             f"got {index}")
        spec = episodes[index]
        sampled_task = None
    return HRIBenchEnv(spec, cameras=cameras, state_track=state_track, action_space=action_space,
                       reward=reward, horizon=horizon, policy_name=policy_name, task=sampled_task)


def load_log(path):
    """An episode log (.hlog, `hribench eval --save-logs`) as numpy arrays, one row per control
    step: time, joint_pos, joint_vel, tcp_pose, gripper_width, actions (NaN where none), human_joints,
    object_poses, separation, approach_speed, predicates; contacts (flat arrays with their step);
    events (dicts); and the episode's identity and status."""
    return _hribench.load_log(str(path))
