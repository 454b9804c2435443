"""The Python module's overhead per step (docs/python.md "Performance"): env.step from Python
against the C++ Episode::step (Episode.replay: the same steps in a C++ loop, observations built
and dropped) on the same episode and actions, state-only and with two 224 x 224 cameras, as
ratios measured in one run. Each side runs the same episode from reset `repeats` times,
interleaved; the best of each is compared, in process CPU time (robust to other processes on
the machine; it includes the renderer's threads) and in wall-clock time.

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
        cpu, wall = time.process_time(), time.perf_counter()
        for a in actions:
            env.step(a)
        return time.process_time() - cpu, time.perf_counter() - wall

    def cpp_loop():
        env.episode.reset()
        cpu, wall = time.process_time(), time.perf_counter()
        taken = env.episode.replay(actions)
        elapsed = time.process_time() - cpu, time.perf_counter() - wall
        assert taken == steps
        return elapsed

    # Interleaved, in alternating order, so both sides see the same machine load.
    py_times, cpp_times = [], []
    for r in range(repeats):
        if r % 2:
            py_times.append(python_loop())
            cpp_times.append(cpp_loop())
        else:
            cpp_times.append(cpp_loop())
            py_times.append(python_loop())
    best = lambda times, i: min(t[i] for t in times) / steps
    return (best(py_times, 0), best(cpp_times, 0)), (best(py_times, 1), best(cpp_times, 1))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    print(f"I1 seed 0, {args.steps} steps, best of {args.repeats}")
    for label, cameras in (("state-only", []),
                           ("two 224x224 cameras", [("agentview", 224, 224), ("wrist", 224, 224)])):
        (py, cpp), (py_wall, cpp_wall) = measure(cameras, args.steps, args.repeats)
        print(f"{label:20s} CPU: env.step {py * 1e3:7.3f} ms, Episode::step {cpp * 1e3:7.3f} ms, "
              f"ratio {py / cpp:.3f} | wall: {py_wall * 1e3:7.3f} / {cpp_wall * 1e3:7.3f} ms, "
              f"ratio {py_wall / cpp_wall:.3f}")


if __name__ == "__main__":
    main()
