"""Minimal Box and Dict spaces with gymnasium.spaces semantics, used when gymnasium is not installed."""
from __future__ import annotations

from collections import OrderedDict
from typing import Any, Mapping, Sequence

import numpy as np


class Space:
    """Base: owns a lazily created np.random.Generator, reseedable with seed()."""

    def __init__(self, shape, dtype, seed=None):
        self._shape = None if shape is None else tuple(int(d) for d in shape)
        self.dtype = None if dtype is None else np.dtype(dtype)
        self._np_random: np.random.Generator | None = None
        if seed is not None:
            self.seed(seed)

    @property
    def shape(self):
        return self._shape

    @property
    def np_random(self) -> np.random.Generator:
        if self._np_random is None:
            self.seed()
        return self._np_random

    def seed(self, seed: int | None = None) -> list[int]:
        seq = np.random.SeedSequence(seed)
        self._np_random = np.random.Generator(np.random.PCG64(seq))
        return [int(seq.entropy)]

    def __contains__(self, x) -> bool:
        return self.contains(x)


class Box(Space):
    """A (possibly unbounded) box in R^n: low <= x <= high elementwise."""

    def __init__(self, low, high, shape: Sequence[int] | None = None, dtype=np.float64, seed=None):
        dtype = np.dtype(dtype)
        if shape is None:
            shape = np.shape(low) if np.ndim(low) > 0 else np.shape(high)
        shape = tuple(int(d) for d in shape)
        low = np.broadcast_to(np.asarray(low, dtype=np.float64), shape)
        high = np.broadcast_to(np.asarray(high, dtype=np.float64), shape)
        if np.any(np.isnan(low)) or np.any(np.isnan(high)):
            raise ValueError("Box bounds must not be NaN")
        if np.any(low > high):
            raise ValueError(f"Box low must be <= high, got low={low}, high={high}")
        super().__init__(shape, dtype, seed)
        self.low = low.astype(dtype, copy=True)
        self.high = high.astype(dtype, copy=True)
        self.bounded_below = np.isfinite(low)
        self.bounded_above = np.isfinite(high)

    def is_bounded(self, manner: str = "both") -> bool:
        below, above = bool(np.all(self.bounded_below)), bool(np.all(self.bounded_above))
        if manner == "both":
            return below and above
        if manner == "below":
            return below
        if manner == "above":
            return above
        raise ValueError(f"manner must be 'both', 'below' or 'above', not {manner!r}")

    def sample(self) -> np.ndarray:
        """Uniform if bounded, shifted exponential if half-bounded, normal if unbounded (as gymnasium)."""
        rng = self.np_random
        high = self.high.astype(np.float64) if self.dtype.kind == "f" else self.high.astype(np.float64) + 1
        sample = np.empty(self.shape, dtype=np.float64)
        unb = ~self.bounded_below & ~self.bounded_above
        low_only = self.bounded_below & ~self.bounded_above
        up_only = ~self.bounded_below & self.bounded_above
        both = self.bounded_below & self.bounded_above
        sample[unb] = rng.normal(size=unb[unb].shape)
        sample[low_only] = rng.exponential(size=low_only[low_only].shape) + self.low[low_only]
        sample[up_only] = high[up_only] - rng.exponential(size=up_only[up_only].shape)
        sample[both] = rng.uniform(self.low[both], high[both], size=both[both].shape)
        if self.dtype.kind in "iu":
            sample = np.floor(sample)
        return np.clip(sample, self.low, self.high).astype(self.dtype)

    def contains(self, x: Any) -> bool:
        if not isinstance(x, np.ndarray):
            try:
                x = np.asarray(x, dtype=self.dtype)
            except (ValueError, TypeError):
                return False
        return bool(np.can_cast(x.dtype, self.dtype) and x.shape == self.shape
                    and np.all(x >= self.low) and np.all(x <= self.high))

    def _bound_repr(self, b: np.ndarray) -> str:
        return str(b.flat[0]) if b.size and np.all(b == b.flat[0]) else str(b)

    def __repr__(self) -> str:
        return f"Box({self._bound_repr(self.low)}, {self._bound_repr(self.high)}, {self.shape}, {self.dtype})"

    def __eq__(self, other) -> bool:
        return (isinstance(other, Box) and self.shape == other.shape and self.dtype == other.dtype
                and np.array_equal(self.low, other.low) and np.array_equal(self.high, other.high))


class Dict(Space, Mapping):
    """An ordered mapping of named subspaces; samples are dicts of samples."""

    def __init__(self, spaces: Mapping[str, Space] | None = None, seed=None, **kwargs: Space):
        self.spaces: OrderedDict[str, Space] = OrderedDict(spaces or {})
        self.spaces.update(kwargs)
        super().__init__(None, None, None)
        if seed is not None:
            self.seed(seed)

    def seed(self, seed: int | None = None) -> list[int]:
        """Seed this space and, from it, every subspace deterministically."""
        seeds = super().seed(seed)
        for space in self.spaces.values():
            seeds += space.seed(int(self._np_random.integers(2**62)))
        return seeds

    def sample(self) -> dict[str, Any]:
        if self._np_random is None:
            self.seed()
        return OrderedDict((k, s.sample()) for k, s in self.spaces.items())

    def contains(self, x: Any) -> bool:
        return (isinstance(x, Mapping) and set(x.keys()) == set(self.spaces.keys())
                and all(s.contains(x[k]) for k, s in self.spaces.items()))

    def __getitem__(self, key: str) -> Space:
        return self.spaces[key]

    def __iter__(self):
        return iter(self.spaces)

    def __len__(self) -> int:
        return len(self.spaces)

    def __repr__(self) -> str:
        return "Dict(" + ", ".join(f"{k!r}: {s!r}" for k, s in self.spaces.items()) + ")"

    def __eq__(self, other) -> bool:
        return isinstance(other, Dict) and self.spaces == other.spaces


__all__ = ["Space", "Box", "Dict"]
