#!/usr/bin/env python3
"""Reads HRIBench datasets with the libraries their consumers use (docs/datasets.md, "Read by
the consumers' libraries"), then trains a small behaviour-cloning network on one.

The tests read every dataset with independent readers that Debian and npm provide (hyparquet,
DuckDB, h5py, ffprobe). The trainers themselves read parquet through Apache Arrow and videos
through FFmpeg bindings, which Debian 12 does not package; this script checks the datasets
through those: pyarrow (what Hugging Face `datasets` and LeRobot load parquet with), OpenCV's
FFmpeg reader (frame count, size and each frame's presentation time, which LeRobot checks
against the row's timestamp with a 1e-4 s tolerance), h5py the way ACT's `utils.py` and
robomimic's `SequenceDataset` read their files, and torch for a short training run on the ACT
files. It is not part of the test suite; run it where those packages are installed (a machine
with PyTorch), with the datasets that `hribench collect` wrote:

    check-dataset-consumers.py lerobot DIR     # LeRobot v2.1
    check-dataset-consumers.py act DIR/TASK    # ACT HDF5, one task's folder
    check-dataset-consumers.py robomimic DIR/dataset.hdf5
    check-dataset-consumers.py train-act DIR/TASK [STEPS]

Each check prints what it read and exits 1 with the first mismatch.
"""

import glob
import json
import os
import sys

import numpy as np


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def check_lerobot(root):
    import cv2
    import pyarrow.parquet as pq

    info = json.load(open(os.path.join(root, "meta", "info.json")))
    if info["codebase_version"] != "v2.1":
        fail(f"{root}: codebase_version {info['codebase_version']}")
    fps = info["fps"]
    features = info["features"]
    episodes = [json.loads(line) for line in open(os.path.join(root, "meta", "episodes.jsonl"))]
    stats = [json.loads(line) for line in open(os.path.join(root, "meta", "episodes_stats.jsonl"))]
    arrow_types = {"float32": "float", "float64": "double", "int64": "int64", "bool": "bool", "string": "string"}
    index = 0
    frames_checked = 0
    for ep in episodes:
        e = ep["episode_index"]
        chunk = e // info["chunks_size"]
        path = os.path.join(root, info["data_path"].format(episode_chunk=chunk, episode_index=e))
        table = pq.read_table(path)
        if table.num_rows != ep["length"]:
            fail(f"{path}: {table.num_rows} rows, episodes.jsonl says {ep['length']}")
        for name, feature in features.items():
            if feature["dtype"] == "video":
                continue
            if name not in table.column_names:
                fail(f"{path}: no column {name}")
            arrow = table.schema.field(name).type
            want = arrow_types[feature["dtype"]]
            shape = feature["shape"]
            if shape == [1]:
                ok = str(arrow) == want
            else:
                ok = str(arrow).startswith("list<") and str(arrow.value_type) == want
                lengths = table.column(name).combine_chunks().value_lengths().to_numpy()
                ok = ok and (lengths == shape[0]).all()
            if not ok:
                fail(f"{path}: column {name} is {arrow}, info.json says {feature['dtype']} {shape}")
        ts = table.column("timestamp").to_numpy()
        frame_index = table.column("frame_index").to_numpy()
        if not (frame_index == np.arange(len(ts))).all():
            fail(f"{path}: frame_index is not 0..n-1")
        # LeRobot's check_timestamps_sync: consecutive timestamps 1/fps apart within 1e-4 s.
        if len(ts) > 1 and np.abs(np.diff(ts) - 1.0 / fps).max() > 1e-4:
            fail(f"{path}: timestamps are not 1/fps apart")
        if not (table.column("index").to_numpy() == np.arange(index, index + len(ts))).all():
            fail(f"{path}: index is not the global frame number")
        index += len(ts)
        # Every video: one decodable frame per row, at the row's timestamp, of the declared size.
        for name, feature in features.items():
            if feature["dtype"] != "video":
                continue
            video = os.path.join(root, info["video_path"].format(episode_chunk=chunk, video_key=name, episode_index=e))
            cap = cv2.VideoCapture(video)
            n = 0
            while True:
                ok, frame = cap.read()
                if not ok:
                    break
                pts = cap.get(cv2.CAP_PROP_POS_MSEC) / 1000.0
                if abs(pts - ts[n]) > 1e-4:
                    fail(f"{video}: frame {n} at {pts:.6f} s, its row at {ts[n]:.6f} s")
                h, w = frame.shape[:2]
                if (h, w) != (feature["info"]["video.height"], feature["info"]["video.width"]):
                    fail(f"{video}: frame {n} is {w}x{h}")
                n += 1
            if n != len(ts):
                fail(f"{video}: {n} frames for {len(ts)} rows")
            frames_checked += n
        # episodes_stats.jsonl: min/max/mean/std/count per feature, images as (3, 1, 1) in [0, 1].
        st = next(s for s in stats if s["episode_index"] == e)["stats"]
        for name, feature in features.items():
            s = st.get(name)
            if s is None:
                continue
            if feature["dtype"] == "video" and np.array(s["mean"]).shape != (3, 1, 1):
                fail(f"episodes_stats.jsonl: {name} mean has shape {np.array(s['mean']).shape}")
            if s["count"] != [len(ts)]:
                fail(f"episodes_stats.jsonl: {name} count {s['count']}, {len(ts)} rows")
    print(f"lerobot {root}: {len(episodes)} episodes, {index} rows read by pyarrow "
          f"{__import__('pyarrow').__version__}, {frames_checked} video frames decoded by OpenCV "
          f"{cv2.__version__} at their rows' timestamps; dtypes, shapes, timestamps, index and stats counts agree")


def act_files(folder):
    files = sorted(glob.glob(os.path.join(folder, "episode_*.hdf5")), key=lambda p: int(p.split("_")[-1].split(".")[0]))
    if len(files) < 2:
        fail(f"{folder}: ACT needs at least two episodes, found {len(files)}")
    names = [os.path.basename(f) for f in files]
    if names != [f"episode_{i}.hdf5" for i in range(len(files))]:
        fail(f"{folder}: episodes are not episode_0.hdf5 .. episode_{len(files) - 1}.hdf5")
    return files


def check_act(folder):
    import h5py

    files = act_files(folder)
    qpos, action = [], []
    cams = None
    for path in files:
        with h5py.File(path, "r") as root:  # act/utils.py: get_norm_stats and EpisodicDataset
            if not bool(root.attrs["sim"]):
                fail(f"{path}: root attribute sim is not true")
            qpos.append(root["/observations/qpos"][()])
            root["/observations/qvel"][()]
            action.append(root["/action"][()])
            names = sorted(root["/observations/images"].keys())
            if cams is None:
                cams = names
            start = len(qpos[-1]) // 2
            for cam in names:
                image = root[f"/observations/images/{cam}"][start]
                if image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] != 3:
                    fail(f"{path}: image {cam} is {image.dtype} {image.shape}")
    all_qpos = np.stack(qpos)  # ACT stacks whole episodes: every episode the same length
    all_action = np.stack(action)
    print(f"act {folder}: {len(files)} episodes of {all_qpos.shape[1]} frames, qpos {all_qpos.shape[2]}, "
          f"action {all_action.shape[2]}, cameras {cams}; stacked for ACT's normaliser: "
          f"qpos std min {all_qpos.reshape(-1, all_qpos.shape[2]).std(0).min():.4f}")


def check_robomimic(path):
    import h5py

    with h5py.File(path, "r") as f:
        data = f["data"]
        env_args = json.loads(data.attrs["env_args"])
        demos = sorted(data.keys(), key=lambda k: int(k[5:]))
        total = 0
        for d in demos:
            demo = data[d]
            n = int(demo.attrs["num_samples"])
            actions = demo["actions"][()]
            if actions.ndim != 2 or len(actions) != n:
                fail(f"{path}: {d}/actions is {actions.shape}, num_samples {n}")
            if np.abs(actions).max() > 1.0:
                fail(f"{path}: {d}/actions outside [-1, 1]")
            for key in demo["obs"].keys():
                if len(demo["obs"][key]) != n or demo["next_obs"][key].shape != demo["obs"][key].shape:
                    fail(f"{path}: {d}/obs/{key} or next_obs/{key} is not num_samples long")
            for key in ("rewards", "dones", "states"):
                if len(demo[key]) != n:
                    fail(f"{path}: {d}/{key} is not num_samples long")
            if demo["dones"][-1] != 1:
                fail(f"{path}: {d}/dones does not end in 1")
            total += n
        if int(data.attrs["total"]) != total:
            fail(f"{path}: total {data.attrs['total']}, the demos hold {total}")
        masks = list(f["mask"].keys()) if "mask" in f else []
        obs_keys = sorted(data[demos[0]]["obs"].keys()) if demos else []
    print(f"robomimic {path}: {len(demos)} demos, {total} samples, env_args type {env_args['type']}, "
          f"obs keys {obs_keys}, masks {masks}")


def train_act(folder, steps):
    """Behaviour cloning on one task's ACT files: a small CNN + MLP from the wrist image and
    qpos to the action, trained on all episodes but the last and scored on the last."""
    import h5py
    import torch

    files = act_files(folder)
    device = "cuda" if torch.cuda.is_available() else "cpu"

    def load(path):
        with h5py.File(path, "r") as root:
            frames = int(root.attrs["frames"])
            cam = sorted(root["/observations/images"].keys())[-1]
            img = root[f"/observations/images/{cam}"][:frames]
            return (torch.tensor(img).permute(0, 3, 1, 2).float() / 255.0,
                    torch.tensor(root["/observations/qpos"][:frames]),
                    torch.tensor(root["/action"][:frames]))

    train = [load(p) for p in files[:-1]]
    test = load(files[-1])
    img = torch.cat([t[0] for t in train]).to(device)
    qpos = torch.cat([t[1] for t in train]).to(device)
    act = torch.cat([t[2] for t in train]).to(device)
    mean, std = act.mean(0), act.std(0) + 1e-6
    q_mean, q_std = qpos.mean(0), qpos.std(0) + 1e-6
    torch.manual_seed(0)
    net = torch.nn.ModuleDict({
        "cnn": torch.nn.Sequential(torch.nn.Conv2d(3, 16, 5, 2), torch.nn.ReLU(), torch.nn.Conv2d(16, 32, 5, 2),
                                   torch.nn.ReLU(), torch.nn.AdaptiveAvgPool2d(4), torch.nn.Flatten()),
        "head": torch.nn.Sequential(torch.nn.Linear(32 * 16 + qpos.shape[1], 256), torch.nn.ReLU(),
                                    torch.nn.Linear(256, act.shape[1])),
    }).to(device)

    def predict(i, q):
        return net["head"](torch.cat([net["cnn"](i), (q - q_mean) / q_std], 1))

    opt = torch.optim.Adam(net.parameters(), 1e-3)
    with torch.no_grad():
        baseline = (((test[2].to(device) - mean) / std) ** 2).mean().item()  # predicting the mean
    first = None
    for step in range(steps):
        batch = torch.randint(0, len(img), (256,), device=device)
        loss = ((predict(img[batch], qpos[batch]) - (act[batch] - mean) / std) ** 2).mean()
        opt.zero_grad()
        loss.backward()
        opt.step()
        first = loss.item() if first is None else first
    with torch.no_grad():
        held_out = ((predict(test[0].to(device), test[1].to(device)) - (test[2].to(device) - mean) / std) ** 2).mean().item()
    print(f"train-act {folder} on {device}: {len(train)} training episodes ({len(img)} frames), {steps} steps; "
          f"training loss {first:.3f} -> {loss.item():.3f}; held-out episode {held_out:.3f} "
          f"(predicting the training mean: {baseline:.3f})")
    if not held_out < baseline:
        fail("the trained network does no better than the mean on the held-out episode")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        print(__doc__)
        sys.exit(2)
    kind, target = sys.argv[1], sys.argv[2]
    if kind == "lerobot":
        check_lerobot(target)
    elif kind == "act":
        check_act(target)
    elif kind == "robomimic":
        check_robomimic(target)
    elif kind == "train-act":
        train_act(target, int(sys.argv[3]) if len(sys.argv) > 3 else 2000)
    else:
        print(__doc__)
        sys.exit(2)
