"""Observation and action spaces the Gymnasium way (docs/python.md).

With Gymnasium importable these are gymnasium.spaces.Box / Dict / Text; without it (Debian has
no Gymnasium package) the small stand-ins below with the same attributes: shape, dtype, low,
high, contains() and sample().
"""

import numpy as np

try:  # pragma: no cover - depends on the environment
    from gymnasium import spaces as _gym_spaces
except ImportError:  # Debian: no Gymnasium
    _gym_spaces = None


class Box:
    """A box in R^shape: low <= x <= high elementwise (gymnasium.spaces.Box's attributes)."""

    def __init__(self, low, high, shape=None, dtype=np.float64, seed=None):
        self.dtype = np.dtype(dtype)
        if shape is None:
            shape = np.shape(low) if np.ndim(low) else np.shape(high)
        self.shape = tuple(int(s) for s in shape)
        self.low = np.broadcast_to(np.asarray(low, dtype=self.dtype), self.shape).copy()
        self.high = np.broadcast_to(np.asarray(high, dtype=self.dtype), self.shape).copy()
        self._rng = np.random.default_rng(seed)

    def contains(self, x):
        x = np.asarray(x)
        return (x.shape == self.shape and np.can_cast(x.dtype, self.dtype)
                and bool(np.all(x >= self.low)) and bool(np.all(x <= self.high)))

    def sample(self):
        low = np.where(np.isfinite(self.low), self.low, -1.0)
        high = np.where(np.isfinite(self.high), self.high, 1.0)
        if self.dtype.kind in "ui":
            return self._rng.integers(low, high, size=self.shape, endpoint=True).astype(self.dtype)
        return self._rng.uniform(low, high, size=self.shape).astype(self.dtype)

    def seed(self, seed=None):
        self._rng = np.random.default_rng(seed)

    def __contains__(self, x):
        return self.contains(x)

    def __repr__(self):
        return f"Box({self.low.min()}, {self.high.max()}, {self.shape}, {self.dtype})"


class Dict:
    """Named subspaces (gymnasium.spaces.Dict's attributes: spaces, keys, [])."""

    def __init__(self, spaces, seed=None):
        self.spaces = dict(spaces)
        self.shape = None
        self.dtype = None

    def contains(self, x):
        return (isinstance(x, dict) and x.keys() == self.spaces.keys()
                and all(self.spaces[k].contains(v) for k, v in x.items()))

    def sample(self):
        return {k: s.sample() for k, s in self.spaces.items()}

    def seed(self, seed=None):
        for s in self.spaces.values():
            s.seed(seed)

    def keys(self):
        return self.spaces.keys()

    def __getitem__(self, key):
        return self.spaces[key]

    def __contains__(self, x):
        return self.contains(x)

    def __repr__(self):
        return "Dict(" + ", ".join(f"{k}: {s!r}" for k, s in self.spaces.items()) + ")"


class Text:
    """A string of at most max_length characters (gymnasium.spaces.Text's attributes)."""

    def __init__(self, max_length, min_length=0, seed=None):
        self.max_length = max_length
        self.min_length = min_length
        self.shape = None
        self.dtype = str

    def contains(self, x):
        return isinstance(x, str) and self.min_length <= len(x) <= self.max_length

    def sample(self):
        return ""

    def seed(self, seed=None):
        pass

    def __contains__(self, x):
        return self.contains(x)

    def __repr__(self):
        return f"Text({self.min_length}, {self.max_length})"


if _gym_spaces is not None:  # pragma: no cover
    Box, Dict, Text = _gym_spaces.Box, _gym_spaces.Dict, _gym_spaces.Text
