"""The Python module's overhead per step (docs/python.md "Performance"): env.step from Python
against the C++ Episode::step (Episode.replay: the same steps in a C++ loop, observations built
and dropped) on the same episode and actions, state-only and with two 224 x 224 cameras, as
ratios measured in one run. Each side runs the same episode from reset `repeats` times; the
best time of each is compared.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py [--steps N] [--repeats R]
"""

import argparse
import time

import numpy as np

import hribench


def actions_for(env, steps):
    # A small back-and-forth motion, open gripper: valid in every ee_delta episode.
    a = np.zeros((steps, 7))
    a[:, 0] = 0.004 * np.sign(np.sin(np.arange(steps) / 10.0) + 1e-9)
    a[:, 6] = 1.0
    return a


def best_of(repeats, run):
    times = []
    for _ in range(repeats):
        times.append(run())
    return min(times)


def measure(cameras, steps, repeats):
    env = hribench.make("I1", seed=0, cameras=cameras, horizon=steps * 0.05 + 1.0)
    actions = actions_for(env, steps)

    def python_loop():
        env.reset()
        start = time.perf_counter()
        for a in actions:
            env.step(a)
        return time.perf_counter() - start

    def cpp_loop():
        env.episode.reset()
        start = time.perf_counter()
        taken = env.episode.replay(actions)
        elapsed = time.perf_counter() - start
        assert taken == steps
        return elapsed

    # Interleaved, so both sides see the same machine load.
    py_times, cpp_times = [], []
    for _ in range(repeats):
        cpp_times.append(cpp_loop())
        py_times.append(python_loop())
    py, cpp = min(py_times), min(cpp_times)
    return py / steps, cpp / steps


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    print(f"I1 seed 0, {args.steps} steps, best of {args.repeats}")
    for label, cameras in (("state-only", []),
                           ("two 224x224 cameras", [("agentview", 224, 224), ("wrist", 224, 224)])):
        py, cpp = measure(cameras, args.steps, args.repeats)
        print(f"{label:22s} env.step {py * 1e3:8.3f} ms   Episode::step {cpp * 1e3:8.3f} ms   "
              f"ratio {py / cpp:.3f}")


if __name__ == "__main__":
    main()
