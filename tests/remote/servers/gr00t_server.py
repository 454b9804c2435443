#!/usr/bin/python3
"""A reference GR00T inference server, written from Isaac-GR00T's published protocol
(docs/remote-policies.md): ZeroMQ REP bound to tcp://127.0.0.1:PORT, msgpack envelopes
{"endpoint", "data"?, "api_token"?}, arrays as {"__ndarray_class__": True, "as_npy": <.npy bytes>}
(MsgSerializer), endpoints ping / kill / get_modality_config / get_action, and reset for N1.6.

--era n15: get_action(observation) with flat keys ("video.<cam>" uint8 (T, H, W, 3), "state.<k>"
  (T, D), "annotation.human.task_description" list[str]); replies "action.<k>" squeezed as N1.5
  does: (16, D), and (16,) for 1-D groups.
--era n16: get_action(observation, options) with the nested layout, dtypes asserted as N1.6 does
  (video uint8 (B, T, H, W, 3), state float32 (B, T, D), language {"task": [[str]]}); replies
  [action, info] with action {k: float32 (B, 16, D)}.
The policy holds still: eef_delta zeros, gripper open. --mode makes it misbehave from request
--after on (get_action requests, counted from 1): ok, slow (answer after --delay s), garbage,
wrong_keys, wrong_shape, nan, range, error ({"error": ...}), raw_error (b"ERROR"), die (exit).
--once: only request --after misbehaves. --token T: requests must carry api_token T. Prints "PORT <n>" once bound (--port 0: a free port).
"""
import argparse
import json
import os
import sys
import time

import msgpack
import numpy as np
import zmq

from msgpack_forms import packb_gr00t, unpackb_gr00t

HORIZON = 16


def check_n15(obs):
    if not any(k.startswith("state.") for k in obs):
        raise KeyError("no state.* key")
    for k, v in obs.items():
        if k.startswith("video."):
            assert isinstance(v, np.ndarray) and v.dtype == np.uint8 and v.ndim == 4 and v.shape[3] == 3, k
        elif k.startswith("state."):
            assert isinstance(v, np.ndarray) and v.ndim == 2, k
    lang = obs["annotation.human.task_description"]
    assert isinstance(lang, list) and isinstance(lang[0], str), "language"


def check_n16(observation):
    for k, v in observation["video"].items():
        assert v.dtype == np.uint8 and v.ndim == 5 and v.shape[4] == 3, f"video.{k}: {v.dtype} {v.shape}"
    for k, v in observation["state"].items():
        assert v.dtype == np.float32, f"state.{k} must be float32, got {v.dtype}"
        assert v.ndim == 3, f"state.{k}: {v.shape}"
    task = observation["language"]["task"]
    assert isinstance(task, list) and isinstance(task[0], list) and isinstance(task[0][0], str), "language.task"


def actions(mode, era):
    arm = np.zeros((HORIZON, 6), dtype=np.float32)
    gripper = np.ones((HORIZON,), dtype=np.float32)
    if mode == "nan":
        arm[0, 0] = np.nan
    elif mode == "range":
        arm[0, 0] = 1.0
    groups = {"eef_delta": arm, "gripper": gripper}
    if mode == "wrong_keys":
        groups = {"arm": arm}
    elif mode == "wrong_shape":
        groups = {"eef_delta": np.zeros((HORIZON, 4), dtype=np.float32), "gripper": gripper}
    if era == "n15":
        return {f"action.{k}": v for k, v in groups.items()}
    return [{k: v.reshape(1, HORIZON, -1) for k, v in groups.items()}, {}]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--port", type=int, default=0)
    parser.add_argument("--era", default="n16")
    parser.add_argument("--mode", default="ok")
    parser.add_argument("--after", type=int, default=1)
    parser.add_argument("--delay", type=float, default=2.0)
    parser.add_argument("--token", default="")
    parser.add_argument("--once", action="store_true", help="misbehave on request --after only")
    args = parser.parse_args()
    context = zmq.Context()
    socket = context.socket(zmq.REP)
    if args.port == 0:
        port = socket.bind_to_random_port("tcp://127.0.0.1")
    else:
        socket.bind(f"tcp://127.0.0.1:{args.port}")
        port = args.port
    print(f"PORT {port}", flush=True)
    count = 0
    while True:
        raw = socket.recv()
        try:
            request = unpackb_gr00t(raw)
            if args.token and request.get("api_token") != args.token:
                socket.send(msgpack.packb({"error": "Unauthorized: Invalid API token"}))
                continue
            endpoint = request.get("endpoint", "get_action")
            data = request.get("data", {})
            if endpoint == "ping":
                reply = {"status": "ok", "message": "Server is running"}
            elif endpoint == "kill":
                socket.send(msgpack.packb(None))
                return
            elif endpoint == "get_modality_config":
                config = {"delta_indices": [0], "modality_keys": ["video.agentview", "video.wrist"]}
                reply = {"video": {"__ModalityConfig_class__": True,
                                   "as_json": config if args.era == "n16" else json.dumps(config)}}
            elif endpoint == "reset" and args.era == "n16":
                reply = {}
            elif endpoint == "get_action":
                count += 1
                active = count == args.after if args.once else count >= args.after
                mode = args.mode if active else "ok"
                if args.era == "n16":
                    check_n16(data["observation"])
                else:
                    check_n15(data)
                if mode == "die":
                    os._exit(0)
                if mode == "slow":
                    time.sleep(args.delay)
                if mode == "garbage":
                    socket.send(b"\xc1\xc1 not msgpack")
                    continue
                if mode == "raw_error":
                    socket.send(b"ERROR")
                    continue
                if mode == "error":
                    raise RuntimeError("policy exploded on purpose")
                reply = actions(mode, args.era)
            else:
                raise ValueError(f"Unknown endpoint: {endpoint}")
            socket.send(packb_gr00t(reply))
        except Exception as e:  # the service's error reply
            socket.send(msgpack.packb({"error": str(e)}))


if __name__ == "__main__":
    try:
        main()
    except KeyboardInterrupt:
        sys.exit(0)
