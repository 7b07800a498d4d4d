"""The policy protocol's observation and actions on the wire (proto/culinarycut/v1/policy.proto): numpy
arrays as `Tensor` messages, nested observation dicts as one flat map with "/" between levels.

- A Tensor is numpy's dtype name (one of DTYPES), the shape (empty: a scalar) and the values' bytes in C
  order, little-endian, product(shape) * itemsize of them (a bool is one byte, 0 or 1).
- flatten({"agent": {"qpos": q}, "sensor_data": {"front": {"rgb": image}}}) is
  {"agent/qpos": q, "sensor_data/front/rgb": image}; unflatten is its inverse. Values that are not numbers
  (text, None, lists of dicts) are left out; numbers and lists of numbers become arrays.

Every decoding error is a TensorError that names the key, so a policy server can answer INVALID_ARGUMENT
with it.
"""
from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from culinarycut.v1 import policy_pb2

# The dtypes the protocol carries: what a ManiSkill-layout observation holds (uint8 images, int16 depth and
# segmentation, float32 states) and what actions are (float32, float64).
DTYPES = ("bool", "uint8", "int16", "int32", "int64", "float32", "float64")
SEPARATOR = "/"


class TensorError(ValueError):
    """A tensor that cannot be encoded or decoded; the message names its key."""


def _where(key: str) -> str:
    return f"{key}: " if key else ""


def to_tensor(value: Any, key: str = "") -> policy_pb2.Tensor:
    """A Tensor of `value` (an array, a numpy scalar, a number or a list of numbers)."""
    array = np.asarray(value)
    name = array.dtype.name
    if name not in DTYPES:
        raise TensorError(f"{_where(key)}dtype {name} is not one the policy protocol carries ({', '.join(DTYPES)})")
    little = array.astype(array.dtype.newbyteorder("<"), copy=False)
    return policy_pb2.Tensor(dtype=name, shape=list(array.shape), data=np.ascontiguousarray(little).tobytes())


def from_tensor(tensor: policy_pb2.Tensor, key: str = "") -> np.ndarray:
    """The array of `tensor` (a new, writable array in native byte order)."""
    if tensor.dtype not in DTYPES:
        raise TensorError(f"{_where(key)}dtype {tensor.dtype!r} is not one of {', '.join(DTYPES)}")
    dtype = np.dtype(tensor.dtype).newbyteorder("<")
    shape = tuple(int(n) for n in tensor.shape)
    count = int(np.prod(shape, dtype=np.int64))
    expected = count * dtype.itemsize
    if len(tensor.data) != expected:
        raise TensorError(f"{_where(key)}{len(tensor.data)} bytes, but a {tensor.dtype} tensor of shape "
                          f"{list(shape)} has {expected}")
    array = np.frombuffer(tensor.data, dtype=dtype, count=count).reshape(shape)
    return array.astype(array.dtype.newbyteorder("="))  # a copy: frombuffer's array is read-only


def _numeric(value: Any) -> np.ndarray | None:
    """value as an array if it is numeric (bool, int, float), else None."""
    if isinstance(value, (str, bytes)) or value is None:
        return None
    try:
        array = np.asarray(value)
    except (ValueError, TypeError):  # ragged lists
        return None
    return array if array.dtype.kind in "biuf" else None


def flatten(observation: Mapping[str, Any], prefix: str = "") -> dict[str, np.ndarray]:
    """{"a/b/c": array} from nested dicts; values that are not numeric are left out."""
    flat: dict[str, np.ndarray] = {}
    for key, value in observation.items():
        key = str(key)
        if not key or SEPARATOR in key:
            raise TensorError(f"{prefix}{key!r}: an observation key may not be empty or contain {SEPARATOR!r}")
        name = prefix + key
        if isinstance(value, Mapping):
            flat.update(flatten(value, name + SEPARATOR))
            continue
        array = _numeric(value)
        if array is not None:
            flat[name] = array
    return flat


def unflatten(flat: Mapping[str, Any]) -> dict[str, Any]:
    """The nested dict of a flat {"a/b/c": value} map."""
    nested: dict[str, Any] = {}
    for name in sorted(flat):
        parts = name.split(SEPARATOR)
        if not all(parts):
            raise TensorError(f"{name!r}: an empty level in the key")
        node = nested
        for depth, part in enumerate(parts[:-1]):
            node = node.setdefault(part, {})
            if not isinstance(node, dict):
                raise TensorError(f"{name!r}: {SEPARATOR.join(parts[:depth + 1])!r} is a value and a level at once")
        if parts[-1] in node:
            raise TensorError(f"{name!r}: a value and a level at once")
        node[parts[-1]] = flat[name]
    return nested


def encode_observation(observation: Mapping[str, Any]) -> dict[str, policy_pb2.Tensor]:
    """The observation as PolicyActRequest.observation: flattened, each array a Tensor."""
    return {name: to_tensor(array, name) for name, array in flatten(observation).items()}


def decode_observation(tensors: Mapping[str, policy_pb2.Tensor]) -> dict[str, Any]:
    """PolicyActRequest.observation back to the nested dict of arrays."""
    return unflatten({name: from_tensor(tensor, name) for name, tensor in tensors.items()})


__all__ = ["DTYPES", "TensorError", "to_tensor", "from_tensor", "flatten", "unflatten", "encode_observation",
           "decode_observation"]
