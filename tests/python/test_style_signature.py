"""A cut style's signature in the knife's motion: a saw's strokes along the blade, a guillotine's pivot."""
from __future__ import annotations

import numpy as np
import pytest

from culinarycut.bench.style_signature import along_blade_m, blade_pitch_deg, saw_strokes, signature


def pose(position, pitch_deg: float = 0.0, yaw_deg: float = 0.0) -> list[float]:
    """[x, y, z, qw, qx, qy, qz]: the blade (TCP +x) turned by yaw about z, then tipped up by pitch."""
    yaw, pitch = np.radians(yaw_deg) / 2, -np.radians(pitch_deg) / 2  # tip up: negative rotation about y
    qz = np.array([np.cos(yaw), 0, 0, np.sin(yaw)])
    qy = np.array([np.cos(pitch), 0, np.sin(pitch), 0])
    w1, x1, y1, z1 = qz
    w2, x2, y2, z2 = qy
    q = [w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
         w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2]
    return [*position, *q]


def test_strokes_count_reversals_beyond_the_wobble():
    t = np.linspace(0.0, 2.0, 400)
    assert saw_strokes(list(0.01 * np.sin(2 * np.pi * 2 * t))) == 8  # 2 Hz for 2 s: 8 turns
    assert saw_strokes(list(0.0005 * np.sin(2 * np.pi * 2 * t))) == 0  # half-millimetre wobble
    assert saw_strokes(list(0.05 * t)) == 0 and saw_strokes([]) == 0


@pytest.mark.parametrize("yaw_deg", [0.0, 90.0, 30.0])
def test_the_signature_reads_the_blade_frame_and_only_the_steps_in_the_food(yaw_deg):
    blade = np.array([np.cos(np.radians(yaw_deg)), np.sin(np.radians(yaw_deg)), 0.0])
    t = np.linspace(0.0, 1.0, 100)
    # Sawing: back and forth along the blade while descending; the steps above the food move the same way.
    poses = [pose(np.array([0.5, 0.0, 0.1 - 0.05 * s]) + 0.01 * np.sin(2 * np.pi * 3 * s) * blade, 0.0, yaw_deg)
             for s in t]
    contact = [int(s >= 0.5) for s in t]  # in the food for the second half only: 1.5 periods, 3 turns
    along = [along_blade_m(p) for p in poses]
    pitch = [blade_pitch_deg(p) for p in poses]
    assert signature(along, pitch, contact) == {"saw_strokes": 3, "pivot_deg": pytest.approx(0.0, abs=1e-9)}
    # A guillotine: the blade pivots from 30 deg tip-up to level while pressing down.
    pivoting = [pose([0.5, 0.0, 0.05], 30.0 * (1 - s), yaw_deg) for s in t]
    assert blade_pitch_deg(pivoting[0]) == pytest.approx(30.0)
    result = signature([along_blade_m(p) for p in pivoting], [blade_pitch_deg(p) for p in pivoting], [1] * len(t))
    assert result["pivot_deg"] == pytest.approx(30.0) and result["saw_strokes"] == 0
