"""ManiSkill's observation dtypes, applied to what the server sends: the env's observations and its
observation_space both go through here, so every observation lies in the space.

ManiSkill3 (its camera shader conventions and gym_utils.convert_observation_to_space) returns
- state arrays (agent/*, extra/*) and camera parameters (sensor_param/*) as float32;
- sensor_data/<camera>/rgb as uint8 H x W x 3;
- sensor_data/<camera>/depth as int16 H x W x 1 in millimetres along the optical axis, 0 = nothing hit;
- sensor_data/<camera>/segmentation as int16 H x W x 1.
The wire carries float64 states, float32 depth in metres and int32 segmentation ids (Client keeps those).
"""
from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from culinarycut.spaces import Box, array_spec_bounds, make_box

STATE_DTYPE = np.dtype(np.float32)
DEPTH_DTYPE = np.dtype(np.int16)
SEGMENTATION_DTYPE = np.dtype(np.int16)
MILLIMETRES_PER_METRE = 1000.0
INT16_MAX = int(np.iinfo(np.int16).max)  # depth saturates at 32.767 m; segmentation ids must stay below


def _camera_channel(name: str) -> str | None:
    """"depth" for "sensor_data/front/depth", and so on; None outside sensor_data."""
    parts = name.split("/")
    return parts[-1] if parts[0] == "sensor_data" and len(parts) == 3 else None


def maniskill_box(spec) -> Box:
    """The Box of an observation ArraySpec after the conversion to ManiSkill's dtypes."""
    shape, dtype, low, high = array_spec_bounds(spec)
    channel = _camera_channel(spec.name)
    if channel in ("depth", "segmentation"):
        return make_box(shape, DEPTH_DTYPE if channel == "depth" else SEGMENTATION_DTYPE,
                        np.zeros(shape), np.full(shape, INT16_MAX))
    if dtype.kind == "f":
        return make_box(shape, STATE_DTYPE, low, high)
    return make_box(shape, dtype, low, high)


def maniskill_array(name: str, value: np.ndarray) -> np.ndarray:
    """One observation array in ManiSkill's dtype (a new, writable array)."""
    channel = _camera_channel(name)
    if channel == "depth":
        millimetres = np.rint(value * MILLIMETRES_PER_METRE)
        return np.clip(millimetres, 0, INT16_MAX).astype(DEPTH_DTYPE)
    if channel == "segmentation":
        if value.size and value.max() > INT16_MAX:
            raise ValueError(f"{name}: segmentation id {int(value.max())} does not fit ManiSkill's int16")
        return value.astype(SEGMENTATION_DTYPE)
    if value.dtype.kind == "f":
        return value.astype(STATE_DTYPE)
    return value.copy()


def to_maniskill(observation: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """A nested observation dict (Client's wire dtypes) with every array converted by maniskill_array."""
    return {key: to_maniskill(value, f"{prefix}{key}/") if isinstance(value, Mapping)
            else maniskill_array(f"{prefix}{key}", value) for key, value in observation.items()}


__all__ = ["maniskill_box", "maniskill_array", "to_maniskill", "STATE_DTYPE", "DEPTH_DTYPE",
           "SEGMENTATION_DTYPE", "MILLIMETRES_PER_METRE"]
