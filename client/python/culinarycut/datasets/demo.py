"""A demonstration: the knife's pose relative to the target object over time, with the resolved scene
and seed it was recorded in (the paper's "relative pose of the knife with respect to the target
object"); saved as one JSON file. Recorded by teleoperation, or from any session (demo_recorder)."""
from __future__ import annotations

import json
import os
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

FORMAT = "culinarycut-demonstration-1"


@dataclass
class Demonstration:
    spec: dict                 # the cut spec demonstrated (style, state, ratio / split_pieces, target_object)
    seed: int                  # the reset seed
    resolved_scene: dict       # the SceneSpec the server resolved (proto-JSON)
    object_pose: list          # the target at reset: [m x3, quaternion wxyz]
    half_extents_m: list       # its half extents along its own axes (m)
    time_s: list               # simulated time of each sample (s)
    relative_pose: list        # per sample: [position / half extents x3, quaternion wxyz], object frame
    knife_contact: list        # per sample: the knife touched the food
    control_mode: str = "pd_ee_delta_pose"
    operator: str = ""
    rating: str = ""           # "good", "bad" or "" (not rated)

    @property
    def cut_speed_m_s(self) -> float:
        """The knife's mean downward speed while in contact (m/s); 0 without contact."""
        t = np.asarray(self.time_s)
        z = np.asarray(self.relative_pose)[:, 2] * self.half_extents_m[2]
        contact = np.asarray(self.knife_contact, bool)
        speeds = -np.diff(z) / np.maximum(np.diff(t), 1e-9)
        speeds = speeds[contact[1:]]
        return float(np.mean(speeds[speeds > 0])) if np.any(speeds > 0) else 0.0

    def to_json(self) -> str:
        return json.dumps({"format": FORMAT, **asdict(self)}, sort_keys=True)


def write_text_atomic(path: Path, text: str) -> Path:
    """Written to a temporary name and renamed, so a reader (or a resumed run) never sees half a file."""
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(path.name + ".tmp")
    temporary.write_text(text)
    os.replace(temporary, path)
    return path


def save_demonstration(demo: Demonstration, path: str | Path) -> Path:
    return write_text_atomic(Path(path), demo.to_json())


def load_demonstration(path: str | Path) -> Demonstration:
    try:
        values = json.loads(Path(path).read_text())
    except (OSError, ValueError) as err:
        raise ValueError(f"demonstration {path}: {err}") from None
    if values.pop("format", None) != FORMAT:
        raise ValueError(f"demonstration {path}: not a {FORMAT} file")
    demo = Demonstration(**values)
    if len(demo.time_s) < 2 or len(demo.relative_pose) != len(demo.time_s):
        raise ValueError(f"demonstration {path}: needs at least 2 samples with a pose each")
    return demo
