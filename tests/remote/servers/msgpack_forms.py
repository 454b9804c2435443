"""The two msgpack array forms of the remote-policy protocols (docs/remote-policies.md), shared by
the reference servers and clients of this folder:
  openpi (openpi_client/msgpack_numpy.py): {b"__ndarray__": True, b"data", b"dtype", b"shape"}
    with bytes (msgpack bin) marker keys; numpy scalars as {b"__npgeneric__": True, ...};
  GR00T (MsgSerializer): {"__ndarray_class__": True, "as_npy": <np.save bytes>}.
"""
import io

import msgpack
import numpy as np


def pack_openpi(obj):
    if isinstance(obj, np.ndarray):
        if obj.dtype.kind in ("V", "O", "c"):
            raise ValueError(f"Unsupported dtype: {obj.dtype}")
        return {b"__ndarray__": True, b"data": obj.tobytes(), b"dtype": obj.dtype.str, b"shape": obj.shape}
    if isinstance(obj, np.generic):
        return {b"__npgeneric__": True, b"data": obj.item(), b"dtype": obj.dtype.str}
    return obj


def unpack_openpi(obj):
    if b"__ndarray__" in obj:
        return np.ndarray(buffer=obj[b"data"], dtype=np.dtype(obj[b"dtype"]), shape=obj[b"shape"])
    if b"__npgeneric__" in obj:
        return np.dtype(obj[b"dtype"]).type(obj[b"data"])
    return obj


def pack_gr00t(obj):
    if isinstance(obj, np.ndarray):
        out = io.BytesIO()
        np.save(out, obj, allow_pickle=False)
        return {"__ndarray_class__": True, "as_npy": out.getvalue()}
    return obj


def unpack_gr00t(obj):
    if isinstance(obj, dict) and "__ndarray_class__" in obj:
        return np.load(io.BytesIO(obj["as_npy"]), allow_pickle=False)
    return obj


def packb_openpi(obj):
    return msgpack.packb(obj, default=pack_openpi)


def unpackb_openpi(data):
    return msgpack.unpackb(data, object_hook=unpack_openpi)


def packb_gr00t(obj):
    return msgpack.packb(obj, default=pack_gr00t)


def unpackb_gr00t(data):
    return msgpack.unpackb(data, object_hook=unpack_gr00t)
