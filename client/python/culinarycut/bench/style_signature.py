"""What a cut style leaves in the knife's motion while the blade is in the food (the paper's trajectory
figures): a saw cut's reciprocating strokes along the blade, a guillotine's pivot of the blade about its tip.
Read from the TCP poses of the steps with knife contact; stored with each episode, scored by no rule yet."""
from __future__ import annotations

import numpy as np

MIN_STROKE_M = 0.002  # a change of direction along the blade counts once the knife has moved this far back


def blade_axis(tcp_pose) -> np.ndarray:
    """The blade's direction (TCP +x, heel to tip) in the world, from the pose [x, y, z, qw, qx, qy, qz]."""
    w, x, y, z = (float(v) for v in tcp_pose[3:7])
    return np.array([1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)])


def saw_strokes(along_blade_m: list[float], min_stroke_m: float = MIN_STROKE_M) -> int:
    """Reversals of the knife's motion along its blade: the motion turns and then runs at least
    `min_stroke_m` the other way (smaller wobbles are not strokes)."""
    strokes, direction = 0, 0  # direction: +1 or -1 once the knife has moved min_stroke_m one way
    extreme = along_blade_m[0] if along_blade_m else 0.0  # the farthest point of the current stroke
    for position in along_blade_m[1:]:
        if direction == 0:
            if abs(position - extreme) >= min_stroke_m:
                direction, extreme = (1 if position > extreme else -1), position
        elif (position - extreme) * direction > 0:
            extreme = position  # still going the same way
        elif abs(position - extreme) >= min_stroke_m:
            strokes, direction, extreme = strokes + 1, -direction, position
    return strokes


def pivot_deg(pitches_deg: list[float]) -> float:
    """The range of the blade's pitch (its tilt from horizontal, deg) over the cut: a guillotine pivots."""
    return float(max(pitches_deg) - min(pitches_deg)) if pitches_deg else 0.0


def blade_pitch_deg(tcp_pose) -> float:
    """The blade's tilt from horizontal (deg), positive with the tip up."""
    return float(np.degrees(np.arcsin(np.clip(blade_axis(tcp_pose)[2], -1.0, 1.0))))


def along_blade_m(tcp_pose) -> float:
    """The TCP's position on the blade's horizontal direction: its change is the motion along the blade, and a
    pivot (pitch only) does not turn that direction."""
    axis = blade_axis(tcp_pose)
    horizontal = np.array([axis[0], axis[1], 0.0])
    length = np.linalg.norm(horizontal)
    return float(np.dot(np.asarray(tcp_pose[:3], dtype=float), horizontal / length)) if length > 1e-9 else 0.0


def signature(along_blade: list[float], pitch_deg: list[float], contact: list[int]) -> dict:
    """`saw_strokes` and `pivot_deg` over the steps with the knife in the food (per-step traces)."""
    in_food = [i for i, touching in enumerate(contact) if touching]
    return {"saw_strokes": saw_strokes([along_blade[i] for i in in_food]),
            "pivot_deg": pivot_deg([pitch_deg[i] for i in in_food])}
