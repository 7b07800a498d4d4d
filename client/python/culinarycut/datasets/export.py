"""`culinarycut data export`: the kept episodes in the formats training code reads, plus the
OpenVLA / Octo dataset_statistics.json."""
from __future__ import annotations

from pathlib import Path

from culinarycut.datasets.episodes import iter_episodes, proprio
from culinarycut.datasets.export_lerobot import export_lerobot
from culinarycut.datasets.export_rdt import export_rdt
from culinarycut.datasets.export_robomimic import export_robomimic
from culinarycut.datasets.statistics import dataset_statistics, write_statistics

FORMATS = ("robomimic", "lerobot", "rdt")
STATISTICS_NAME = "dataset_statistics.json"


def export(root: Path, out: Path, formats: tuple[str, ...] = FORMATS, name: str = "culinarycut") -> dict[str, Path]:
    unknown = set(formats) - set(FORMATS)
    if unknown:
        raise ValueError(f"unknown formats {sorted(unknown)}; choose from {', '.join(FORMATS)}")
    out.mkdir(parents=True, exist_ok=True)
    written = {}
    if "robomimic" in formats:
        written["robomimic"] = export_robomimic(root, out / "robomimic" / f"{name}.hdf5")
    if "lerobot" in formats:
        written["lerobot"] = export_lerobot(root, out / "lerobot")
    if "rdt" in formats:
        written["rdt"] = export_rdt(root, out / "rdt")
    actions, states = [], []
    for _, _, steps in iter_episodes(root):
        actions.append(steps["actions"])
        states.append(proprio(steps))
    written["statistics"] = out / STATISTICS_NAME
    write_statistics(written["statistics"], dataset_statistics(name, actions, states))
    return written
