"""`culinarycut data card`: a dataset card (README.md) for a generated dataset: counts per task, the
success filter's keep rate and reasons, formats, provenance, sample frames and knife trajectories
drawn with matplotlib."""
from __future__ import annotations

import collections
import json
import time
from pathlib import Path

import numpy as np

from culinarycut.datasets.episode_file import read_episode
from culinarycut.datasets.export import FORMATS
from culinarycut.datasets.generate import CONFIG_NAME
from culinarycut.datasets.store import GenerationStore, require_dataset

SAMPLES = 3  # episodes drawn in the pictures


def _task_of(key: str) -> str:
    return key.rsplit("/", 1)[0]


def _frames_figure(samples: list[tuple[dict, dict]], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cameras = sorted(k for k in samples[0][1] if k.endswith("_rgb"))
    figure, axes = plt.subplots(len(samples), 3 * len(cameras), figsize=(2 * 3 * len(cameras), 2 * len(samples)),
                                squeeze=False)
    for row, (meta, steps) in enumerate(samples):
        length = len(steps["actions"])
        for c, camera in enumerate(cameras):
            for j, t in enumerate((0, length // 2, length - 1)):
                ax = axes[row][3 * c + j]
                ax.imshow(steps[camera][t])
                ax.set_axis_off()
                ax.set_title(f"{camera[4:-4]} t={t}", fontsize=7)
        axes[row][0].annotate(f'"{meta["instructions"][0]}"', (0, 1.3), xycoords="axes fraction", fontsize=8)
    figure.subplots_adjust(left=0.01, right=0.99, top=0.9, bottom=0.02, hspace=0.6, wspace=0.05)
    figure.savefig(path, dpi=80)
    plt.close(figure)


def _trajectories_figure(samples: list[tuple[dict, dict]], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, (top, height, force) = plt.subplots(1, 3, figsize=(13, 3.6))
    for meta, steps in samples:
        tcp = steps["obs/tcp_pose"]
        t = steps["sim_time_s"]
        label = meta["key"].split("/", 1)[1]
        top.plot(tcp[:, 1] * 1e3, tcp[:, 0] * 1e3, label=label)
        height.plot(t, tcp[:, 2] * 1e3)
        force.plot(t, np.linalg.norm(steps["obs/wrist_wrench"][:, :3], axis=1))
    top.set(xlabel="y (mm, robot's left +)", ylabel="x (mm)", title="knife path from above")
    height.set(xlabel="time (s)", ylabel="TCP height (mm)", title="knife height")
    force.set(xlabel="time (s)", ylabel="wrist force (N)", title="force at the wrist")
    top.legend(fontsize=6)
    figure.tight_layout()
    figure.savefig(path, dpi=90)
    plt.close(figure)


def write_card(root: Path, out: Path | None = None) -> Path:
    require_dataset(root)
    out = out or root
    out.mkdir(parents=True, exist_ok=True)
    config = json.loads((root / CONFIG_NAME).read_text())
    with GenerationStore(root) as store:
        rows, metadata = store.rows(), store.metadata()
    if not rows:
        raise ValueError(f"{root}: no finished jobs yet")
    per_task = collections.defaultdict(lambda: [0, 0])
    for row in rows:
        per_task[_task_of(row["key"])][0] += 1
        per_task[_task_of(row["key"])][1] += row["kept"]
    kept = [row for row in rows if row["kept"]]
    reasons = collections.Counter(row["reason"].split(":")[0] for row in rows if not row["kept"])
    lines = [f"# Dataset card: {config['name']}", "",
             f"{len(kept)} kept trajectories of {len(rows)} generated ({100 * len(kept) / len(rows):.0f} % pass the "
             f"success filter), {sum(r['steps'] for r in kept)} steps, {len(per_task)} tasks. "
             f"Written {time.strftime('%Y-%m-%d', time.gmtime())} by `culinarycut data card`.", "",
             "## Tasks", "", "| task (source/style-state-food) | generated | kept |", "|---|---|---|"]
    lines += [f"| {task} | {n} | {k} |" for task, (n, k) in sorted(per_task.items())]
    per_scene = collections.defaultdict(lambda: [0, 0])
    for row in rows:
        per_scene[row.get("scene") or "table"][0] += 1  # rows written before scenes were drawn: the table
        per_scene[row.get("scene") or "table"][1] += row["kept"]
    lines += ["", "## Scenes", "", f"Topology {'on' if config.get('topology', True) else 'off'} while cutting.", "",
              "| scene | generated | kept |", "|---|---|---|"]
    lines += [f"| {scene} | {n} | {k} |" for scene, (n, k) in sorted(per_scene.items())]
    lines += ["", "## Success filter", ""]
    lines += [f"- {reason}: {count}" for reason, count in reasons.most_common()] or ["- every episode succeeded"]
    pending = sorted((root / "errors").glob("*.json")) if (root / "errors").is_dir() else []
    if pending:
        lines += ["", f"{len(pending)} jobs failed with transient server errors and are not counted above; "
                  "running `culinarycut data generate` again retries them."]
    lines += ["", "## Contents and formats", "",
              f"Every step: {', '.join(config['cameras'])} RGB ({config['image_size']} px), joint positions and "
              "velocities, TCP pose and velocity, wrist force/torque, the action in "
              f"`{config['control_mode']}`, reward, done, contact phase and knife contact; per episode "
              f"{config['instructions_per_episode']} train-template instructions, the cut spec, the seed, the "
              "resolved scene and the drawn variation (position, yaw, scale, type, cutting height and speed).", "",
              f"`culinarycut data export` writes {', '.join(FORMATS)} and `dataset_statistics.json` (docs/datasets.md).",
              "", "## Provenance", "",
              f"- dataset seed {config['seed']}, quality `{config['quality']}`, "
              f"{config['episodes_per_task']} episodes per task and source",
              f"- demonstrations: {', '.join(Path(d).name for d in config['demos']) or 'none'}",
              f"- servers (version, build): {metadata.get('servers', 'not recorded')}",
              f"- randomisation: `{json.dumps(config['randomisation'], sort_keys=True)}`", ""]
    samples = [read_episode(root / row["file"]) for row in kept[:: max(1, len(kept) // SAMPLES)][:SAMPLES]]
    if samples:
        _frames_figure(samples, out / "card_frames.png")
        _trajectories_figure(samples, out / "card_trajectories.png")
        lines += ["## Samples", "", "![First, middle and last frames](card_frames.png)", "",
                  "![Knife paths, heights and wrist force](card_trajectories.png)", ""]
    path = out / "README.md"
    path.write_text("\n".join(lines))
    return path
