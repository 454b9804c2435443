#!/usr/bin/python3
"""A reference openpi policy server, written from openpi's published protocol
(docs/remote-policies.md): websockets without compression or size limit, GET /healthz -> 200
"OK\\n", the metadata frame first, then one msgpack-numpy reply per request; an exception is
sent as a text frame (the traceback) followed by close 1011, as openpi's
websocket_policy_server does. Arrays use openpi's msgpack_numpy form: the marker keys
__ndarray__/data/dtype/shape are bytes (msgpack bin); a request whose arrays are not in that
form is an error here, as it is there.

The policy holds still: `actions` (H, 7) with zero deltas and the gripper open (ee_delta), in
--dtype. --mode makes it misbehave on purpose from request --after on (counted per
connection, from 1; --after 0 applies to the upgrade itself):
  ok, close (close the connection), hang (never answer), garbage (bytes that are not msgpack),
  wrong_keys, wrong_shape, nan, range (an out-of-range action), error (an exception: text frame
  + close 1011), die (the process exits: later connections are refused).
--preset hribench|libero|droid: the request keys checked and the actions' width and length
(libero (10, 7), droid (15, 8)). Prints "PORT <n>" once listening (--port 0 picks a free port). Stops on SIGTERM.
"""
import argparse
import asyncio
import functools
import http
import os
import sys
import time
import traceback

import numpy as np
import websockets
import websockets.server

from msgpack_forms import packb_openpi as packb
from msgpack_forms import unpackb_openpi as unpackb


# The keys each preset's request must hold, and its action width and chunk length, as the stock
# configs expect them (pi05_libero: examples/libero/main.py; pi05_droid: examples/droid/main.py).
PRESETS = {
    "hribench": (("observation/joint_position", "observation/gripper_width", "observation/tcp_pose"), 7, None),
    "libero": (("observation/image", "observation/wrist_image", "observation/state"), 7, 10),
    "droid": (("observation/exterior_image_1_left", "observation/wrist_image_left", "observation/joint_position",
               "observation/gripper_position"), 8, 15),
}


def check_request(obs, preset):
    """The preset's request, as a stock openpi server's transforms would read it."""
    if not isinstance(obs, dict):
        raise TypeError(f"request is {type(obs).__name__}, not a dict")
    if not isinstance(obs.get("prompt"), str):
        raise KeyError("prompt (a str) missing")
    for key, value in obs.items():
        if key.startswith("observation/") and not isinstance(value, np.ndarray):
            raise TypeError(f"{key} is {type(value).__name__}, not an ndarray (marker keys must be bin)")
    for key in PRESETS[preset][0]:
        if key not in obs:
            raise KeyError(key)
    if preset == "libero":
        assert obs["observation/state"].shape == (8,), obs["observation/state"].shape
        assert obs["observation/image"].shape == (224, 224, 3)
    if preset == "droid":
        assert obs["observation/joint_position"].shape == (7,)
        assert obs["observation/gripper_position"].shape == (1,)
    for key, value in obs.items():
        if key.startswith("observation/") and value.dtype == np.uint8:
            if value.ndim != 3 or value.shape[2] != 3:
                raise ValueError(f"{key}: image shape {value.shape}, expected (H, W, 3)")


def actions_for(mode, horizon, dtype, preset):
    width = PRESETS[preset][1]
    horizon = PRESETS[preset][2] or horizon
    actions = np.zeros((horizon, width), dtype=dtype)
    # Hold still with the gripper open: hribench opening 1; LIBERO -1 (open); DROID 0 (open).
    actions[:, width - 1] = {"hribench": 1.0, "libero": -1.0, "droid": 0.0}[preset]
    reply = {"actions": actions, "policy_timing": {"infer_ms": 0.1}}
    if mode == "wrong_keys":
        reply = {"action": actions}
    elif mode == "wrong_shape":
        reply = {"actions": np.zeros((horizon, 5), dtype=dtype)}
    elif mode == "nan":
        actions[0, 0] = np.nan
    elif mode == "range":
        actions[0, 0] = 1.0  # 1 m in one control step
    return reply


async def handler(args, websocket, path=None):
    await websocket.send(packb({}))  # the metadata frame
    count = 0
    prev_total = None
    while True:
        try:
            message = await websocket.recv()
        except websockets.ConnectionClosed:
            return
        count += 1
        start = time.monotonic()
        active = count >= args.after
        mode = args.mode if active else "ok"
        try:
            obs = unpackb(message)
            check_request(obs, args.preset)
            if mode == "close":
                await websocket.close()
                return
            if mode == "hang":
                await asyncio.sleep(3600)
            if mode == "die":
                os._exit(0)
            if mode == "garbage":
                await websocket.send(b"\xc1\xc1 not msgpack")
                continue
            if mode == "error":
                raise RuntimeError("policy exploded on purpose")
            reply = actions_for(mode, args.horizon, np.dtype(args.dtype), args.preset)
            reply["server_timing"] = {"infer_ms": (time.monotonic() - start) * 1000}
            if prev_total is not None:
                reply["server_timing"]["prev_total_ms"] = prev_total
            await websocket.send(packb(reply))
            prev_total = (time.monotonic() - start) * 1000
        except Exception:
            await websocket.send(traceback.format_exc())
            await websocket.close(code=1011, reason="Internal server error. Traceback included in previous frame.")
            return


async def health_check(path, request_headers):
    if path == "/healthz":
        return http.HTTPStatus.OK, [], b"OK\n"
    return None


async def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--port", type=int, default=0)
    parser.add_argument("--mode", default="ok")
    parser.add_argument("--after", type=int, default=1)
    parser.add_argument("--horizon", type=int, default=10)
    parser.add_argument("--dtype", default="<f4")
    parser.add_argument("--preset", default="hribench", choices=sorted(PRESETS))
    args = parser.parse_args()
    async with websockets.serve(functools.partial(handler, args), "127.0.0.1", args.port, compression=None,
                                max_size=None, process_request=health_check) as server:
        port = server.sockets[0].getsockname()[1]
        print(f"PORT {port}", flush=True)
        await asyncio.Future()


if __name__ == "__main__":
    try:
        asyncio.run(main())
    except KeyboardInterrupt:
        sys.exit(0)
