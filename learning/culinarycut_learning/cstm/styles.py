"""The cutting styles the style generator knows: the scripted planner's four (culinarycut.datasets.jobs.STYLES),
in a fixed order, since a style's index is a row of the generator's learned style embedding."""
from __future__ import annotations

STYLES = ("normal", "bias", "guillotine", "saw")


def style_index(style: str) -> int:
    if style not in STYLES:
        raise ValueError(f"unknown cutting style {style!r}; choose one of {', '.join(STYLES)}")
    return STYLES.index(style)
