"""Collects observations with env.step (docs/python.md): one episode of a pool's eval split
with a camera and the state track, a small scripted motion as the actions, and the frames,
proprioception and rewards stacked into arrays saved as an .npz file.

    PYTHONPATH=build/python /usr/bin/python3 examples/collect_observations.py OUT.npz [STEPS]
"""

import sys

import numpy as np

import hribench


def collect(path, steps=40):
    env = hribench.make(pool="pool/v8", split="eval", index=0, cameras=[("agentview", 96, 128)],
                        state_track=True)
    obs, info = env.reset()
    frames, tcp, humans, rewards = [obs["images"]["agentview"]], [obs["tcp_pos"]], [], []
    for k in range(steps):
        action = np.zeros(env.action_space.shape)
        action[2] = 0.01 if k < steps // 2 else -0.01  # up 1 cm per step, then down again
        action[6] = 1.0                                 # gripper open
        obs, reward, terminated, truncated, info = env.step(action)
        frames.append(obs["images"]["agentview"])
        tcp.append(obs["tcp_pos"])
        humans.append(obs["state"]["human_joints"])
        rewards.append(reward)
        if terminated or truncated:
            break
    np.savez_compressed(path, frames=np.stack(frames), tcp_pos=np.stack(tcp),
                        human_joints=np.stack(humans), rewards=np.array(rewards))
    return len(frames)


if __name__ == "__main__":
    n = collect(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 40)
    print(f"{n} frames written to {sys.argv[1]}")
