"""Matplotlib without a display, and figures saved the one way every page's images are."""
from __future__ import annotations

from pathlib import Path


def pyplot():
    """matplotlib.pyplot on the Agg backend (files only, no display)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def save_figure(figure, path: Path, dpi: int | None = 110) -> Path:
    """Writes the figure (its folder made as needed) and closes it."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, **({"dpi": dpi} if dpi else {}))
    pyplot().close(figure)
    return path
