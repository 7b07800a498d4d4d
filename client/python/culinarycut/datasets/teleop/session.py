"""One teleoperated session: the scene reset from its seed, driven by end-effector deltas, recorded as a
Demonstration (object-relative knife poses) between start and stop, saved with the person's rating;
reset puts the scene back to its seed, so every recording can start from the same state."""
from __future__ import annotations

import threading
from pathlib import Path

import numpy as np
from google.protobuf import json_format

from culinarycut.client import Client
from culinarycut.datasets.demo import load_demonstration, save_demonstration
from culinarycut.datasets.demo_recorder import DemoRecorder
from culinarycut.env import CulinaryCutEnv

CONTROL_MODE = "pd_ee_delta_pose"
RATINGS = ("good", "bad")
MIN_SAMPLES = 2  # what load_demonstration accepts


class TeleopSession:
    def __init__(self, client: Client, scene: dict, spec: dict, seed: int, out_dir: Path, operator: str = ""):
        self.env = CulinaryCutEnv(client=client, scene=scene, control_mode=CONTROL_MODE)
        self.resolved = json_format.MessageToDict(self.env.handshake.resolved_scene, preserving_proto_field_name=True)
        self.observation, self.info = self.env.reset(seed=seed)
        self.spec, self.seed, self.out_dir, self.operator = dict(spec), int(seed), Path(out_dir), operator
        self.lock = threading.Lock()
        self.recorder: DemoRecorder | None = None
        self.saved: list[Path] = []
        self.steps = 0

    @property
    def session_id(self) -> str:
        return self.env.session_id

    def step(self, action) -> dict:
        """One control step of the normalised delta (6 values in [-1, 1]: position, then axis-angle)."""
        action = np.clip(np.asarray(action, dtype=np.float64).ravel(), -1.0, 1.0)
        if action.size != 6:
            raise ValueError(f"a {CONTROL_MODE} action has 6 values, not {action.size}")
        with self.lock:
            self.observation, _, _, _, self.info = self.env.step(action)
            self.steps += 1
            if self.recorder is not None:
                self.recorder.add(self.observation, self.info)
        return self.state()

    def reset(self) -> dict:
        """The scene back to its seed (food whole, robot at home); a recording in progress is dropped."""
        with self.lock:
            self.observation, self.info = self.env.reset(seed=self.seed)
            self.recorder = None
            self.steps = 0
        return self.state()

    def start_recording(self) -> None:
        with self.lock:
            self.recorder = DemoRecorder(self.resolved, self.seed, self.spec, self.info, CONTROL_MODE)
            self.recorder.add(self.observation, self.info)

    def stop_recording(self) -> Path:
        """Saves the demonstration (unrated) and returns its file. A recording of fewer than MIN_SAMPLES
        samples (no step driven) stops without a file, with a ValueError saying so."""
        with self.lock:
            if self.recorder is None:
                raise ValueError("not recording")
            demo, self.recorder = self.recorder.result(operator=self.operator), None
        if len(demo.time_s) < MIN_SAMPLES:
            raise ValueError(f"nothing saved: the recording has {len(demo.time_s)} sample(s), a demonstration "
                             f"needs {MIN_SAMPLES}; drive the knife while recording")
        path = save_demonstration(demo, self.out_dir / f"demo_{self.session_id[:8]}_{len(self.saved):03d}.json")
        self.saved.append(path)
        return path

    def rate_last(self, rating: str) -> Path:
        if rating not in RATINGS:
            raise ValueError(f"rating must be one of {RATINGS}")
        if not self.saved:
            raise ValueError("no recorded demonstration to rate")
        demo = load_demonstration(self.saved[-1])
        demo.rating = rating
        return save_demonstration(demo, self.saved[-1])

    def state(self) -> dict:
        extra = self.observation["extra"]
        return {"session_id": self.session_id, "steps": self.steps, "recording": self.recorder is not None,
                "tcp_position_m": extra["tcp_pose"][:3].tolist(),
                "force_n": float(np.linalg.norm(extra["wrist_wrench"][:3])),
                "saved": [p.name for p in self.saved]}

    def close(self) -> None:
        self.env.close()
