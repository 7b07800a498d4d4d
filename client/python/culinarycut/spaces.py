"""Spaces from the server's handshake: an ArraySpec proto to a Box, flat names ("agent/qpos") to nested Dicts.

Box and Dict are gymnasium.spaces' when gymnasium is installed, else the package's stand-ins with the same
semantics (see gymnasium_support).
"""
from __future__ import annotations

from collections import OrderedDict
from typing import Callable

import numpy as np

from culinarycut.gymnasium_support import Box, Dict, Space


def array_spec_bounds(spec) -> tuple[tuple[int, ...], np.dtype, np.ndarray, np.ndarray]:
    """(shape, dtype, low, high) of an ArraySpec; empty low/high means unbounded (-inf/inf)."""
    shape = tuple(int(d) for d in spec.shape)
    n = int(np.prod(shape)) if shape else 1

    def bound(values, default: float) -> np.ndarray:
        values = np.asarray(list(values), dtype=np.float64)
        if values.size == 0:
            return np.full(shape, default)
        if values.size not in (1, n):
            raise ValueError(f"ArraySpec {spec.name!r}: {values.size} bounds for shape {shape}")
        return np.broadcast_to(values, (n,)).reshape(shape)

    return shape, np.dtype(spec.dtype or "float64"), bound(spec.low, -np.inf), bound(spec.high, np.inf)


def make_box(shape, dtype, low: np.ndarray, high: np.ndarray) -> Box:
    """A Box whose bounds are already of its dtype (gymnasium warns when it has to narrow them)."""
    dtype = np.dtype(dtype)
    if dtype.kind in "iu":  # integer boxes: infinite bounds mean the dtype's range
        info = np.iinfo(dtype)
        low, high = np.clip(low, info.min, info.max), np.clip(high, info.min, info.max)
    return Box(np.asarray(low).astype(dtype), np.asarray(high).astype(dtype), shape, dtype)


def box_from_array_spec(spec) -> Box:
    """The Box an ArraySpec declares, dtype included."""
    return make_box(*array_spec_bounds(spec))


def dict_from_array_specs(specs, box_from_spec: Callable = box_from_array_spec) -> Dict:
    """Flat keys such as "agent/qpos" to a nested Dict of Boxes, in the order given."""
    tree: OrderedDict = OrderedDict()
    for spec in specs:
        *parents, leaf = spec.name.split("/")
        node = tree
        for p in parents:
            node = node.setdefault(p, OrderedDict())
        node[leaf] = box_from_spec(spec)

    def build(node) -> Dict:
        return Dict(OrderedDict((k, build(v) if isinstance(v, OrderedDict) else v) for k, v in node.items()))

    return build(tree)


__all__ = ["Space", "Box", "Dict", "array_spec_bounds", "make_box", "box_from_array_spec", "dict_from_array_specs"]
