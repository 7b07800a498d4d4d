"""Benchmark suites as data: TOML files validated against suite_schema.json, expanded into tasks.

A task field given as a list expands into one task per combination (foods x styles x states ...), so
a suite such as "every style x state on every food" is a few lines. Suites are looked up by name in
the repository's top-level benchmarks/ folder (or $CULINARYCUT_BENCHMARKS), or given as a path.
"""
from __future__ import annotations

import dataclasses
import fnmatch
import hashlib
import itertools
import json
import os
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import jsonschema

SCHEMA_PATH = Path(__file__).with_name("suite_schema.json")
# Fields of a task that may be lists, in the order task names are made from them.
EXPANDING_FIELDS = ("food", "style", "state", "ratio", "side", "pieces", "distractors", "topology", "scene")
DEFAULT_RANDOMIZE = {"position_m": 0.02, "yaw_deg": 10.0, "scale": [0.9, 1.1]}
DEFAULT_POLICY = {"name": "oracle", "options": {}}


class SuiteError(ValueError):
    """A suite that cannot be found or does not follow the schema; the message names the field."""


@dataclass(frozen=True)
class Task:
    """One task of a suite: what to cut and how, in which scene, and how many trials."""

    name: str
    food: str
    style: str
    state: str
    ratio: float
    side: str
    pieces: int
    distractors: int
    topology: bool
    scene: str
    language: str
    quality: str
    trials: int
    max_episode_steps: int
    group: str = ""
    material_overrides: dict = field(default_factory=dict, hash=False, compare=False)
    mpm: dict = field(default_factory=dict, hash=False, compare=False)  # the preset's resolution overridden
    safety_limiter: bool = False     # the safety limiter (docs/safety.md) on in the episode's scene
    seed_name: str = ""              # the name the seeds come from: without the limiter's suffix, so the
                                     # settings of an ablation see the same scenes trial by trial
    safety: dict = field(default_factory=dict, hash=False, compare=False)  # its settings (SceneSpec.safety)

    def safety_spec(self) -> dict[str, Any] | None:
        """SceneSpec.safety for this task's scene; None with the limiter off."""
        return dict(self.safety) if self.safety_limiter else None

    def cut_spec(self) -> dict[str, Any]:
        """The task as a CutSpec dict (the Tasks service's form)."""
        spec = {"style": self.style, "state": self.state, "target_object": self.food, "reference": self.side}
        if self.state == "ratio":
            spec["ratio"] = self.ratio
        if self.state == "split":
            spec["split_pieces"] = self.pieces
        return spec


@dataclass(frozen=True)
class Suite:
    name: str
    description: str
    path: Path
    digest: str                      # sha256 of the file: a changed suite is noticed on resume
    tasks: tuple[Task, ...]
    policy: dict
    randomize: dict
    cameras: tuple

    def task(self, name: str) -> Task:
        for task in self.tasks:
            if task.name == name:
                return task
        raise KeyError(name)

    def with_trials(self, trials: int) -> "Suite":
        """The same suite with `trials` per task (a quick look; the seeds of the first trials are unchanged)."""
        return dataclasses.replace(self, tasks=tuple(dataclasses.replace(t, trials=trials) for t in self.tasks))

    def only_tasks(self, pattern: str) -> "Suite":
        """The tasks whose name matches a shell pattern (fnmatch); SuiteError when none does."""
        chosen = tuple(t for t in self.tasks if fnmatch.fnmatchcase(t.name, pattern))
        if not chosen:
            raise SuiteError(f"--tasks {pattern!r} matches none of the {len(self.tasks)} tasks of {self.name} "
                             f"(e.g. {self.tasks[0].name}); see culinarycut bench show {self.name}")
        return dataclasses.replace(self, tasks=chosen)

    @property
    def episode_count(self) -> int:
        return sum(task.trials for task in self.tasks)


def suite_dirs() -> list[Path]:
    """Where suites are looked up by name: $CULINARYCUT_BENCHMARKS, ./benchmarks, the repository's."""
    dirs = []
    if os.environ.get("CULINARYCUT_BENCHMARKS"):
        dirs.append(Path(os.environ["CULINARYCUT_BENCHMARKS"]))
    dirs.append(Path.cwd() / "benchmarks")
    dirs.append(Path(__file__).resolve().parents[4] / "benchmarks")  # client/python/culinarycut/bench -> repo
    return [d for i, d in enumerate(dirs) if d.is_dir() and d not in dirs[:i]]


def available_suites() -> list[str]:
    return sorted({p.stem for d in suite_dirs() for p in d.glob("*.toml")})


def find_suite(name_or_path: str) -> Path:
    path = Path(name_or_path)
    if path.suffix == ".toml" or os.sep in name_or_path:
        if not path.is_file():
            raise SuiteError(f"suite file {name_or_path} does not exist")
        return path
    for directory in suite_dirs():
        candidate = directory / f"{name_or_path}.toml"
        if candidate.is_file():
            return candidate
    choices = ", ".join(available_suites()) or "none found"
    raise SuiteError(f"unknown suite {name_or_path!r}; choose one of: {choices} (or give a .toml path)")


def _schema() -> dict:
    return json.loads(SCHEMA_PATH.read_text())


def _where(error: jsonschema.ValidationError) -> str:
    parts = "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in error.absolute_path)
    return "suite" + parts


def _message(error: jsonschema.ValidationError) -> str:
    """The deepest sub-error of a oneOf (a value or a list of values), which names the bad element; for an
    unknown field, the fields that may stand there."""
    while error.context:
        error = max(error.context, key=lambda e: (len(e.absolute_path), e.validator == "enum"))
    message = f"{_where(error)}: {error.message}"
    if error.validator == "additionalProperties" and error.validator_value is False:
        message += f"; valid fields: {', '.join(error.schema.get('properties', {}))}"
    return message


def validate(document: dict) -> None:
    """Raises SuiteError naming the first field that breaks the schema."""
    validator = jsonschema.Draft202012Validator(_schema())
    errors = sorted(validator.iter_errors(document), key=lambda e: list(map(str, e.absolute_path)))
    if errors:
        raise SuiteError(_message(errors[0]))


def _as_list(value) -> list:
    return value if isinstance(value, list) else [value]


ALL_GUARDS = ("speed", "force", "entry_angle")  # the safety limiter's guards (docs/safety.md)


def _safety_label(limiter: bool, settings: dict) -> str:
    """limiter-off, limiter-<F_max>N (the server's default F_max is 100 N), with the guards when not all."""
    if not limiter:
        return "limiter-off"
    label = f"limiter-{settings.get('max_force_n', 100):g}N"
    guards = settings.get("guards", ALL_GUARDS)
    return label if set(guards) == set(ALL_GUARDS) else label + "-" + "-".join(guards)


def _task_name(combo: dict, with_safety: bool = True) -> str:
    """e.g. cucumber/normal/ratio-0.3-left, apple/guillotine/middle/distractors-2/topology-off."""
    parts = [combo["food"], combo["style"]]
    state = combo["state"]
    if state == "ratio":
        state += f"-{combo['ratio']:g}" + (f"-{combo['side']}" if combo["side"] != "none" else "")
    elif state == "split":
        state += f"-{combo['pieces']}"
    parts.append(state)
    if combo["distractors"]:
        parts.append(f"distractors-{combo['distractors']}")
    if not combo["topology"]:
        parts.append("topology-off")
    if combo["scene"] != "table":
        parts.append(combo["scene"])
    if with_safety and combo.get("safety_label"):
        parts.append(combo["safety_label"])
    return "/".join(parts)


def _safety_of(entry: dict, defaults: dict, where: str) -> tuple[bool, dict, str]:
    """The task's limiter switch, its settings (the suite's, then the task's over them) and the name suffix
    (only when the suite or the task declares the limiter, so older suites keep their task names)."""
    limiter = entry.get("safety_limiter", defaults["safety_limiter"])
    if "safety" in entry and not limiter:
        raise SuiteError(f"{where}.safety: settings for a safety limiter that is off; set safety_limiter = true "
                         "in the task or the suite")
    settings = {**defaults["safety"], **entry.get("safety", {})}
    declared = "safety_limiter" in entry or defaults["safety_declared"]
    return bool(limiter), settings if limiter else {}, _safety_label(limiter, settings) if declared else ""


def _expand(entry: dict, defaults: dict, where: str = "suite.tasks[0]") -> list[Task]:
    limiter, safety, safety_label = _safety_of(entry, defaults, where)
    fixed = {"style": "normal", "ratio": 0.5, "side": "none", "pieces": 3, "distractors": 0,
             "topology": defaults["topology"], "scene": defaults["scene"], **entry}
    lists = [_as_list(fixed[name]) for name in EXPANDING_FIELDS]
    single = all(len(values) == 1 for values in lists)
    tasks = []
    for values in itertools.product(*lists):
        combo = dict(zip(EXPANDING_FIELDS, values), safety_label=safety_label)
        if combo["state"] == "ratio" and combo["side"] not in ("left", "right"):
            combo["side"] = "left"  # a ratio is measured from an end; left is the paper's default
        name, seed_name = _task_name(combo), _task_name(combo, with_safety=False)
        if "name" in entry:
            name = entry["name"] if single else f"{entry['name']}/{name}"
            seed_name = name
        tasks.append(Task(name=name, group=entry.get("group", ""),
                          language=entry.get("language", defaults["language"]),
                          quality=entry.get("quality", defaults["quality"]),
                          trials=entry.get("trials", defaults["trials"]),
                          max_episode_steps=entry.get("max_episode_steps", defaults["max_episode_steps"]),
                          material_overrides={**defaults["material_overrides"], **entry.get("material_overrides", {})},
                          mpm={**defaults["mpm"], **entry.get("mpm", {})},
                          food=combo["food"], style=combo["style"], state=combo["state"],
                          ratio=float(combo["ratio"]), side=combo["side"], pieces=int(combo["pieces"]),
                          distractors=int(combo["distractors"]), topology=bool(combo["topology"]),
                          scene=combo["scene"], safety_limiter=limiter, safety=safety, seed_name=seed_name))
    return tasks


def load_suite(name_or_path: str) -> Suite:
    """Finds, parses, validates and expands a suite; raises SuiteError with the field named."""
    path = find_suite(name_or_path)
    raw = path.read_bytes()
    try:
        document = tomllib.loads(raw.decode())
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
        raise SuiteError(f"{path}: not valid TOML: {err}") from None
    validate(document)
    if document["name"] != path.stem:
        raise SuiteError(f"suite.name: {document['name']!r} differs from the file name {path.stem!r}")
    defaults = {"trials": 20, "max_episode_steps": 600, "language": "train", "quality": "draft", "scene": "table",
                "topology": True, "material_overrides": {}, "mpm": {}, "safety_limiter": False, "safety": {}}
    defaults.update({k: document[k] for k in defaults if k in document})
    defaults["safety_declared"] = "safety_limiter" in document
    tasks: list[Task] = []
    for index, entry in enumerate(document["tasks"]):
        tasks.extend(_expand(entry, defaults, f"suite.tasks[{index}]"))
    if "safety" in document and not any(t.safety_limiter for t in tasks):
        raise SuiteError("suite.safety: settings for a safety limiter that no task turns on; set safety_limiter = "
                         "true in the suite or a task")
    names = [t.name for t in tasks]
    duplicates = sorted({n for n in names if names.count(n) > 1})
    if duplicates:
        raise SuiteError(f"suite.tasks: task names repeat ({', '.join(duplicates[:5])}); give each entry a name")
    return Suite(name=document["name"], description=document["description"], path=path,
                 digest=hashlib.sha256(raw).hexdigest(), tasks=tuple(tasks),
                 policy={**DEFAULT_POLICY, **document.get("policy", {})},
                 randomize={**DEFAULT_RANDOMIZE, **document.get("randomize", {})},
                 cameras=tuple(document.get("cameras", [])))


def episode_seed(suite: str, task: str, trial: int) -> int:
    """The episode's seed from (suite, task, trial) alone: any row can be replayed exactly."""
    digest = hashlib.sha256(f"{suite}\x00{task}\x00{trial}".encode()).digest()
    return int.from_bytes(digest[:8], "little") >> 1  # 63 bits: fits a signed 64-bit SQLite integer
