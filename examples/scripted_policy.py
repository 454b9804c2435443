"""A scripted Python policy evaluated by the benchmark (docs/python.md): it reaches for the
object nearest to the tool (state track), closes the gripper on it and lifts it. It is not
good at the tasks; it shows the shape of a policy: spec(), reset(info), act(obs).

    PYTHONPATH=build/python /usr/bin/python3 examples/scripted_policy.py OUT_DIR [TASK] [EPISODES]
"""

import sys

import numpy as np

import hribench


class ReachAndLift:
    name = "reach_and_lift"

    def spec(self):
        return hribench.PolicySpec(state_track=True, action_space="ee_delta")

    def reset(self, info):
        self.grasped_at = None  # the time the gripper closed

    def act(self, obs):
        tcp = obs["tcp_pos"]
        objects = obs["state"]["objects"]
        target = min(objects.values(), key=lambda pose: np.linalg.norm(pose[:3] - tcp))[:3]
        action = np.zeros(7)
        if self.grasped_at is None:
            error = target - tcp
            action[:3] = np.clip(error, -0.02, 0.02)  # at most 2 cm per step
            action[6] = 1.0
            if np.linalg.norm(error) < 0.01:
                self.grasped_at = obs["time"]
        else:
            action[6] = 0.0                                 # close
            if obs["time"] - self.grasped_at > 0.5:
                action[2] = 0.01                            # then lift
        return action


def main(out, task="I1", episodes=2, horizon=None):
    results = hribench.evaluate(ReachAndLift(), tasks=task, episodes=episodes, horizon=horizon, out=out,
                                force=True)
    for row in results:
        print(f"{row['task']} seed {row['seed']}: success {row['success']}, status {row['status']}, "
              f"CT {row['completion_time']:.2f} s")
    return results


if __name__ == "__main__":
    main(sys.argv[1], *(sys.argv[2:3] or ["I1"]), *([int(sys.argv[3])] if len(sys.argv) > 3 else []))
