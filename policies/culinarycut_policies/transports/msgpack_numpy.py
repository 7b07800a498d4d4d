"""openpi's msgpack encoding of numpy values (packages/openpi-client/src/openpi_client/msgpack_numpy.py):
arrays as {"__ndarray__": True, "data": bytes, "dtype": dtype.str, "shape": [...]}, numpy scalars as
{"__npgeneric__": True, "data": item, "dtype": dtype.str}. Object, void and complex dtypes are refused
both ways: nothing from the network is ever unpickled or turned into Python objects."""
from __future__ import annotations

from typing import Any

import msgpack
import numpy as np

_REFUSED_KINDS = ("V", "O", "c")


def _encode(value: Any) -> Any:
    if isinstance(value, (np.ndarray, np.generic)) and value.dtype.kind in _REFUSED_KINDS:
        raise ValueError(f"cannot send numpy dtype {value.dtype} (object, void and complex are refused)")
    if isinstance(value, np.ndarray):
        return {b"__ndarray__": True, b"data": np.ascontiguousarray(value).tobytes(), b"dtype": value.dtype.str,
                b"shape": value.shape}
    if isinstance(value, np.generic):
        return {b"__npgeneric__": True, b"data": value.item(), b"dtype": value.dtype.str}
    raise TypeError(f"cannot send a {type(value).__name__} over the openpi protocol")


def _decode(obj: dict) -> Any:
    # openpi packs these keys as msgpack bin (bytes); a client in another language may send str keys.
    if b"__ndarray__" in obj or "__ndarray__" in obj:
        field = _fields(obj)
        return np.ndarray(buffer=field("data"), dtype=_safe_dtype(field("dtype")), shape=tuple(field("shape")))
    if b"__npgeneric__" in obj or "__npgeneric__" in obj:
        field = _fields(obj)
        return _safe_dtype(field("dtype")).type(field("data"))
    return obj


def _fields(obj: dict):
    return lambda name: obj[name.encode()] if name.encode() in obj else obj[name]


def _safe_dtype(descr) -> np.dtype:
    dtype = np.dtype(descr.decode() if isinstance(descr, bytes) else descr)
    if dtype.kind in _REFUSED_KINDS:
        raise ValueError(f"refusing numpy dtype {dtype} from the network")
    return dtype


def packb(value: Any) -> bytes:
    return msgpack.packb(value, default=_encode)


def unpackb(data: bytes) -> Any:
    return msgpack.unpackb(data, object_hook=_decode)
