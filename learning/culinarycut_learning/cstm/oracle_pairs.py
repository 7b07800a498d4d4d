"""Paired cuts recorded through a live server: the scripted oracle (Tasks.StartOracle / OracleAction, the
server's ScriptedOracle) cuts the same scene twice, once normally and once in the wanted style, and each
pair is saved as one .npz file of a pairs folder (the style generator's training data).

Same scene: the scene and the planner's draws come from culinarycut.datasets.jobs (draw_variation, job_scene,
planner_options: what `culinarycut data generate` uses) with one seed for both cuts, so the food's position,
yaw, scale, the scene and the cutting height are the same; the cut speed is drawn from each style's own range
(a saw descends at 8-15 mm/s, the other styles at 20-50 mm/s), and the oracle's seed, the same for both, draws
the style's own parameters (saw frequency and amplitude, bias angle, guillotine pitch).

Per step the recording keeps the oracle's action (pd_ee_pose_quat: the TCP target), the measured TCP pose
before the step and the knife's contact with the food at that moment (info["food"]["knife_contact"] of the
observation the action was chosen for, as the episode recorder stores it). No camera is rendered."""
from __future__ import annotations

import hashlib
import json
import os
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from culinarycut_learning.cstm.styles import STYLES
from culinarycut_learning.cstm.trajectories import Trajectory

CONTROL_MODE = "pd_ee_pose_quat"   # the oracle's absolute TCP targets: the recorder turns them into OSC deltas
PAIR_FORMAT = "culinarycut-cstm-pair/1"
MAX_STEPS = 600


@dataclass
class Recording:
    style: str
    actions: np.ndarray        # (T, 7) pd_ee_pose_quat targets [m x3, quaternion wxyz]
    tcp_poses: np.ndarray      # (T, 7) measured TCP before each step
    contact: np.ndarray        # (T,) bool
    seed: int

    def trajectory(self) -> Trajectory:
        return Trajectory.from_recording(self.style, self.actions, self.tcp_poses, self.contact, CONTROL_MODE,
                                         self.seed)


def parse_state(text: str) -> dict:
    """middle, ratio-R (from the left) or split-N as the cut spec's fields (jobs.spec_name's names)."""
    if text == "middle":
        return {"state": "middle"}
    kind, _, value = text.partition("-")
    try:
        if kind == "ratio":
            return {"state": "ratio", "ratio": float(value), "reference": "left"}
        if kind == "split":
            return {"state": "split", "split_pieces": int(value)}
    except ValueError:
        pass
    raise ValueError(f"state {text!r}: use middle, ratio-R (e.g. ratio-0.3) or split-N (e.g. split-3)")


def pair_scene(food: str, state: str, seed: int, quality: str = "draft", mpm: dict | None = None):
    """(scene, {style: planner options}) of one pair: one scene, each style's planner draws."""
    from culinarycut.datasets.jobs import DatasetConfig, draw_variation, job_scene, planner_options
    config = DatasetConfig(name="cstm-pairs", seed=seed, tasks=(), episodes_per_task=1, quality=quality,
                           cameras=(), scenes=("table",), max_episode_steps=MAX_STEPS)
    spec = {"style": "normal", **parse_state(state), "target_object": food}
    variation = draw_variation(config, spec, seed)
    scene = job_scene(config, variation, seed)
    if mpm:
        scene["mpm"] = dict(mpm)
    options = {}
    for style in STYLES:
        styled = {**spec, "style": style}
        options[style] = (styled, planner_options(styled, draw_variation(config, styled, seed)))
    return scene, options


def record_oracle_cut(client, scene: dict, spec: dict, options: dict, seed: int,
                      max_steps: int = MAX_STEPS) -> Recording:
    """One oracle cut of `spec` on `scene`, run until the oracle's plan ends (or max_steps, or the task fails)."""
    from culinarycut.env import CulinaryCutEnv
    from culinarycut.policies.scripted_oracle import ScriptedOracle
    actions, poses, contact = [], [], []
    with CulinaryCutEnv(client=client, scene=scene, control_mode=CONTROL_MODE) as env:
        observation, info = env.reset(seed=seed)
        oracle = ScriptedOracle(client, env.session_id)
        oracle.reset(spec=spec, control_mode=CONTROL_MODE, seed=seed, options=options)
        for _ in range(max_steps):
            _, values = oracle.act()
            if oracle.finished:
                break
            actions.append(values)
            poses.append(np.asarray(observation["extra"]["tcp_pose"], dtype=np.float64))
            contact.append(bool(info.get("food", {}).get("knife_contact", False)))
            observation, _, _, truncated, info = env.step(values)
            if truncated or info["fail"]:
                break
    return Recording(spec["style"], np.asarray(actions).reshape(-1, 7), np.asarray(poses).reshape(-1, 7),
                     np.asarray(contact, dtype=bool), seed)


def oracle_pair(client, food: str, style: str, state: str = "middle", seed: int = 0, quality: str = "draft",
                mpm: dict | None = None, max_steps: int = MAX_STEPS) -> tuple[Recording, Recording]:
    """(normal cut, `style` cut) of one scene through the server `client` talks to."""
    if style not in STYLES or style == "normal":
        raise ValueError(f"style {style!r}: choose one of {', '.join(s for s in STYLES if s != 'normal')}")
    scene, options = pair_scene(food, state, seed, quality, mpm)
    return tuple(record_oracle_cut(client, scene, *options[s], seed=seed, max_steps=max_steps)
                 for s in ("normal", style))


def pair_seed(seed: int, food: str, state: str, index: int) -> int:
    from culinarycut.datasets.jobs import derive_seed
    return derive_seed(seed, "cstm-pairs", food, state, index)


def save_pair(path: Path, normal: Recording, styled: Recording, meta: dict) -> Path:
    """One pair as an .npz, written to a temporary file and renamed (a kill leaves none or all of it)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    arrays = {}
    for role, recording in (("normal", normal), ("styled", styled)):
        arrays.update({f"{role}_actions": recording.actions, f"{role}_tcp_poses": recording.tcp_poses,
                       f"{role}_contact": recording.contact.astype(np.uint8)})
    meta = {"format": PAIR_FORMAT, "control_mode": CONTROL_MODE, "style": styled.style, "seed": normal.seed, **meta}
    temporary = path.with_name(path.name + ".tmp.npz")
    np.savez(temporary, meta=np.array(json.dumps(meta, sort_keys=True)), **arrays)
    with open(temporary, "rb") as file:
        os.fsync(file.fileno())
    os.replace(temporary, path)
    return path


def pair_files(folder: Path) -> list[Path]:
    files = sorted(Path(folder).glob("*.npz")) if Path(folder).is_dir() else []
    files = [f for f in files if not f.name.endswith(".tmp.npz")]
    if not files:
        raise FileNotFoundError(f"{folder}: no pair files (*.npz): record them with "
                                "`python -m culinarycut_learning cstm-generator pairs --out FOLDER ...`")
    return files


def load_pair(path: Path) -> tuple[Trajectory, Trajectory, dict]:
    with np.load(path) as data:
        meta = json.loads(str(data["meta"]))
        if meta.get("format") != PAIR_FORMAT:
            raise ValueError(f"{path}: not a CSTM pair file ({PAIR_FORMAT})")
        trajectories = [Trajectory.from_recording(style, data[f"{role}_actions"], data[f"{role}_tcp_poses"],
                                                  data[f"{role}_contact"], meta["control_mode"], meta["seed"])
                        for role, style in (("normal", "normal"), ("styled", meta["style"]))]
    return trajectories[0], trajectories[1], meta


def pairs_digest(files: list[Path]) -> str:
    """sha256 over the pair files' names and contents, in order: what the generator was trained on."""
    digest = hashlib.sha256()
    for path in files:
        digest.update(path.name.encode() + b"\0" + hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()


def generate_pairs(server: str, out: Path, foods: list[str], style: str, states: list[str], pairs: int,
                   seed: int = 0, quality: str = "draft", mpm: dict | None = None, max_steps: int = MAX_STEPS,
                   log=print) -> dict:
    """`pairs` pairs per food and state into the folder `out` (FOOD-STATE-INDEX.npz); files already there are
    kept, so a killed run goes on where it stopped. Returns counts and the wall time."""
    from culinarycut.client import Client
    started, made, kept = time.monotonic(), 0, 0
    with Client(server, timeout_s=600.0) as client:
        for food in foods:
            for state in states:
                parse_state(state)
                for index in range(pairs):
                    path = Path(out) / f"{food}-{state}-{style}-{index:04d}.npz"
                    if path.is_file():
                        kept += 1
                        continue
                    scene_seed = pair_seed(seed, food, state, index)
                    clock = time.monotonic()
                    normal, styled = oracle_pair(client, food, style, state, scene_seed, quality, mpm, max_steps)
                    save_pair(path, normal, styled, {"food": food, "state": state, "quality": quality,
                                                     "index": index, "mpm": mpm or {}})
                    made += 1
                    log(f"{path.name}: normal {len(normal.actions)} steps ({int(normal.contact.sum())} in contact), "
                        f"{style} {len(styled.actions)} ({int(styled.contact.sum())}), "
                        f"{time.monotonic() - clock:.1f} s")
    return {"made": made, "kept": kept, "wall_s": time.monotonic() - started, "out": str(out)}
