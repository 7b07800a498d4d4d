"""What to generate: episode jobs drawn from a dataset config and a seed, grouped into shards.

A job is data only (the key, the seed, the cut spec, the scene and planner options it runs with), so
the same config gives the same jobs on any machine and a resumed run finds the same keys.
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from culinarycut.bench.episode_scene import BOARD_CENTER_XY_M, CUTTING_EFFECTS, _yaw_quaternion

STYLES = ("normal", "bias", "guillotine", "saw")
SCENES = ("table", "kitchen")  # the paper collects in both: a standard table and a realistic kitchen
RATIOS = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9)
SPLITS = (3, 4, 5)


@dataclass(frozen=True)
class Randomisation:
    """Ranges each episode draws from (the paper's O_p, O_s, O_r, O_t, h and v)."""

    position_m: float = 0.03                  # +- offset of the target's centre on the board, x and y
    yaw_deg: float = 15.0                     # +- rotation about world z
    scale: tuple[float, float] = (0.85, 1.15)
    foods: tuple[str, ...] = ()               # object types to draw from; empty: the task's own food
    cut_height_m: tuple[float, float] = (0.01, 0.03)   # edge above the object's top where the cut begins
    cut_speed_m_s: tuple[float, float] = (0.02, 0.05)  # knife speed through the food
    saw_cut_speed_m_s: tuple[float, float] = (0.008, 0.015)


@dataclass(frozen=True)
class DatasetConfig:
    name: str
    seed: int
    tasks: tuple[dict, ...]                   # cut specs: style, state, ratio/split_pieces, target_object
    episodes_per_task: int
    demos: tuple[str, ...] = ()               # demonstration files replayed as a second source
    randomisation: Randomisation = field(default_factory=Randomisation)
    quality: str = "draft"
    cameras: tuple[str, ...] = ("front", "left", "right")
    image_size: int = 224                     # square camera images, pixels
    control_mode: str = "pd_ee_pose_quat"
    instructions_per_episode: int = 5
    max_episode_steps: int = 600
    material_overrides: dict = field(default_factory=dict)  # the foods' real presets unless overridden
    # optional paraphrases of the instructions by an OpenAI-compatible endpoint (culinarycut.paraphrase);
    # off when empty. Only paraphrases the server parses back to the same cut are added.
    paraphrase_endpoint: str = ""
    paraphrase_model: str = ""
    scenes: tuple[str, ...] = SCENES          # each episode draws one; both by default, as the paper collects
    topology: bool = True                     # pieces tracked while cutting (off: the topology ablation's data)

    def __post_init__(self):
        unknown = sorted(set(self.scenes) - set(SCENES))
        if not self.scenes or unknown:
            raise ValueError(f"scenes: {', '.join(unknown) or 'none given'}; choose from {', '.join(SCENES)}")

    def to_json(self) -> str:
        return json.dumps(dataclasses.asdict(self), sort_keys=True)

    @staticmethod
    def from_json(text: str) -> "DatasetConfig":
        values = json.loads(text)
        values["randomisation"] = Randomisation(**{k: tuple(v) if isinstance(v, list) else v
                                                   for k, v in values["randomisation"].items()})
        # Datasets written before scenes were drawn were all on the table, with topology on.
        values.setdefault("scenes", ["table"])
        for key in ("tasks", "demos", "cameras", "scenes"):
            values[key] = tuple(values[key])
        return DatasetConfig(**values)


@dataclass(frozen=True)
class EpisodeJob:
    key: str                  # unique within the dataset, e.g. planner/saw-ratio-0.3/00012
    seed: int
    source: str               # "planner" or the demonstration file's name
    spec: dict[str, Any]      # the cut spec, target_object set
    scene: dict[str, Any]     # SceneSpec proto-JSON (the instruction is added at run time)
    variation: dict[str, Any]  # what was drawn: position, yaw, scale, food, cut height and speed


def all_style_state_specs(food: str) -> list[dict]:
    """Every style x state of the paper (4 styles x (9 ratios + middle + 3 splits)) on one food."""
    specs = []
    for style in STYLES:
        specs += [{"style": style, "state": "ratio", "ratio": r, "reference": "left", "target_object": food}
                  for r in RATIOS]
        specs.append({"style": style, "state": "middle", "target_object": food})
        specs += [{"style": style, "state": "split", "split_pieces": n, "target_object": food} for n in SPLITS]
    return specs


def spec_name(spec: dict) -> str:
    state = spec.get("state", "middle")
    if state == "ratio":
        state += f"-{spec['ratio']:g}"
        if spec.get("reference") == "right":  # left keeps its old name, so existing datasets' keys stay
            state += "-right"
    elif state == "split":
        state += f"-{spec['split_pieces']}"
    return f"{spec.get('style', 'normal')}-{state}"


def derive_seed(*parts: Any) -> int:
    """A 63-bit seed from the parts (sha256), the same on every platform."""
    digest = hashlib.sha256("/".join(map(str, parts)).encode()).digest()
    return int.from_bytes(digest[:8], "little") >> 1


def draw_variation(config: DatasetConfig, spec: dict, seed: int) -> dict[str, Any]:
    rng = np.random.Generator(np.random.PCG64(seed))
    r = config.randomisation
    offset = rng.uniform(-r.position_m, r.position_m, size=2)
    speeds = r.saw_cut_speed_m_s if spec.get("style") == "saw" else r.cut_speed_m_s
    food = str(rng.choice(r.foods)) if r.foods else spec["target_object"]
    return {"position_m": [BOARD_CENTER_XY_M[0] + float(offset[0]), BOARD_CENTER_XY_M[1] + float(offset[1])],
            "yaw_deg": float(rng.uniform(-r.yaw_deg, r.yaw_deg)),
            "scale": float(rng.uniform(*r.scale)),
            "food": food,
            "cut_height_m": float(rng.uniform(*r.cut_height_m)),
            "cut_speed_m_s": float(rng.uniform(*speeds)),
            # Drawn last, so every earlier draw is what it was before scenes were drawn.
            "scene": str(rng.choice(config.scenes))}


def job_scene(config: DatasetConfig, variation: dict, seed: int) -> dict:
    food = {"food": variation["food"], "scale": variation["scale"],
            "pose": {"position": variation["position_m"],
                     "quaternion": _yaw_quaternion(math.radians(variation["yaw_deg"]))}}  # about the default 90 deg
    if config.material_overrides:
        food["material_overrides"] = dict(config.material_overrides)
    size = config.image_size
    return {"seed": str(seed), "quality": config.quality, "effects": {**CUTTING_EFFECTS, "topology": config.topology},
            "scene": variation["scene"], "objects": [food], "max_episode_steps": config.max_episode_steps,
            "cameras": [{"name": c, "width": size, "height": size, "channels": ["rgb"]} for c in config.cameras]}


def planner_options(spec: dict, variation: dict) -> dict:
    """The drawn height and speed as point ranges, so the planner uses exactly them."""
    height = {"min": variation["cut_height_m"], "max": variation["cut_height_m"]}
    speed = {"min": variation["cut_speed_m_s"], "max": variation["cut_speed_m_s"]}
    key = "saw_cut_speed_m_s" if spec.get("style") == "saw" else "cut_speed_m_s"
    return {"cut_start_height_m": height, key: speed}


def make_jobs(config: DatasetConfig) -> list[EpisodeJob]:
    """Every job of the dataset: per task the planner's own trajectories, then per demonstration its
    replays on randomised scenes; seeds depend on (dataset seed, source, task, index) only."""
    from culinarycut.datasets.demo import load_demonstration
    sources = [("planner", spec) for spec in config.tasks]
    sources += [(path, load_demonstration(path).spec) for path in config.demos]
    jobs = []
    for source, spec in sources:
        name = f"{_source_key(source)}/{spec_name(spec)}-{spec['target_object']}"
        for index in range(config.episodes_per_task):
            seed = derive_seed(config.seed, name, index)
            variation = draw_variation(config, spec, seed)
            jobs.append(EpisodeJob(key=f"{name}/{index:05d}", seed=seed, source=source,
                                   spec={**spec, "target_object": variation["food"]},
                                   scene=job_scene(config, variation, seed), variation=variation))
    return jobs


def _source_key(source: str) -> str:
    return "planner" if source == "planner" else "demo-" + source.rsplit("/", 1)[-1].removesuffix(".json")


def shards(jobs: list[EpisodeJob], shard_size: int) -> list[list[EpisodeJob]]:
    return [jobs[i:i + shard_size] for i in range(0, len(jobs), shard_size)]
