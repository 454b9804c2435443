#!/usr/bin/python3
"""The Python reference clients for the overhead benchmark (bench/remote_bench.cc): the round
trip of one inference with two 224x224 images and the state, as openpi's
openpi_client.WebsocketClientPolicy makes it (msgpack-numpy, one binary frame each way; Debian's
websockets 10.4 has no sync client, so the asyncio client is used) and as GR00T's PolicyClient
makes it (ZeroMQ REQ, msgpack with .npy arrays). The observation has the hribench preset's keys.

  reference_client.py openpi|gr00t PORT N   ->  prints "median_us <m> mean_us <a>"
"""
import asyncio
import statistics
import sys
import time

import numpy as np

from msgpack_forms import packb_gr00t, packb_openpi, unpackb_gr00t, unpackb_openpi


def observation():
    rng = np.random.default_rng(0)
    obs = {
        "agentview": rng.integers(0, 255, (224, 224, 3), dtype=np.uint8),
        "wrist": rng.integers(0, 255, (224, 224, 3), dtype=np.uint8),
        "joint_position": np.zeros(7), "joint_velocity": np.zeros(7), "gripper_width": np.zeros(1),
        "tcp_pose": np.zeros(7), "time": np.zeros(1),
    }
    return obs


async def openpi(port, n):
    import websockets
    request = {f"observation/{k}": v for k, v in observation().items()}
    request["prompt"] = "hand me the cup"
    times = []
    async with websockets.connect(f"ws://127.0.0.1:{port}", compression=None, max_size=None) as ws:
        unpackb_openpi(await ws.recv())  # metadata
        for _ in range(n):
            start = time.perf_counter()
            await ws.send(packb_openpi(request))
            reply = unpackb_openpi(await ws.recv())
            assert "actions" in reply
            times.append(time.perf_counter() - start)
    return times


def gr00t(port, n):
    import zmq
    obs = observation()
    data = {"observation": {"video": {k: obs[k][None, None] for k in ("agentview", "wrist")},
                            "state": {k: obs[k].astype(np.float32)[None, None] for k in obs if obs[k].dtype != np.uint8},
                            "language": {"task": [["hand me the cup"]]}},
            "options": None}
    socket = zmq.Context().socket(zmq.REQ)
    socket.connect(f"tcp://127.0.0.1:{port}")
    times = []
    for _ in range(n):
        start = time.perf_counter()
        socket.send(packb_gr00t({"endpoint": "get_action", "data": data}))
        reply = unpackb_gr00t(socket.recv())
        assert isinstance(reply, list)
        times.append(time.perf_counter() - start)
    return times


def main():
    protocol, port, n = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    times = asyncio.run(openpi(port, n)) if protocol == "openpi" else gr00t(port, n)
    times = times[min(10, n // 10):]  # warm-up
    print(f"median_us {statistics.median(times) * 1e6:.1f} mean_us {statistics.mean(times) * 1e6:.1f}", flush=True)


if __name__ == "__main__":
    main()
