"""Training pairs of the style generator, from two recordings of one scene (same scene seed and planner
draws): a normal cut and the same cut in another style (the CulinaryCut paper's CSTM trains f by behaviour
cloning on "the contact segments of normal cutting trajectories and their style-specific counterparts").

- Contact segments (trajectories.contact_segments): the k-th of the normal recording is paired with the k-th
  of the styled one (a split cuts several times); recordings with other segment counts are refused.
- Common length: both segments are resampled (linear interpolation over normalised time, trajectories.resample)
  to the styled segment's own length by default, so the targets stay one action per 20 Hz control step, what
  the wrapper executes; the normal segment is stretched (a saw cut takes 2-3 times a normal one's steps) and
  its actions are the normal policy's, unscaled: f learns to map "the normal cut at this point of its contact
  segment" to "the style's action at this step".
- Windows: every step i of a segment gives one sample: the chunk of the (resampled) normal actions from i
  on, the style's chunk from i on (steps past the segment's end are masked out of the loss), and i, the steps
  since contact began (the generator's phase input: a chunk of straight-down normal actions does not say
  where in a saw stroke the knife is). With `identity`, each normal segment also gives normal -> normal
  samples, so f(a_hat, normal) is trained to leave a_hat as it is."""
from __future__ import annotations

import numpy as np
import torch

from culinarycut_learning.cstm.styles import style_index
from culinarycut_learning.cstm.trajectories import Trajectory, contact_segments, resample


def contact_pairs(normal: Trajectory, styled: Trajectory, length: int | None = None, max_gap: int = 2,
                  min_steps: int = 3) -> list[tuple[np.ndarray, np.ndarray]]:
    """[(normal segment, styled segment)], each (L, 6) in OSC units, L = `length` or the styled segment's length."""
    if normal.style != "normal":
        raise ValueError(f"the first trajectory of a pair must be a normal cut, not {normal.style!r}")
    normal_segments = contact_segments(normal.contact, max_gap, min_steps)
    styled_segments = contact_segments(styled.contact, max_gap, min_steps)
    if not normal_segments or len(normal_segments) != len(styled_segments):
        raise ValueError(f"seed {normal.seed}: the normal cut has {len(normal_segments)} contact segments, the "
                         f"{styled.style} cut {len(styled_segments)}: no pairs (the same scene should give the "
                         "same number of cuts, at least one)")
    pairs = []
    for (a, b), (c, d) in zip(normal_segments, styled_segments):
        size = length or d - c
        pairs.append((resample(normal.actions[a:b], size), resample(styled.actions[c:d], size)))
    return pairs


def segment_windows(source: np.ndarray, target: np.ndarray, chunk: int) -> tuple[np.ndarray, ...]:
    """Every step's (source chunk, target chunk, mask, steps since contact) of two aligned (L, 6) segments;
    past the end the last action is repeated and masked out."""
    length = len(source)
    ahead = np.arange(length)[:, None] + np.arange(chunk)[None, :]          # (L, H)
    inside = ahead < length
    clamped = np.minimum(ahead, length - 1)
    return source[clamped], target[clamped], inside.astype(np.float32), np.arange(length, dtype=np.float32)


def pair_windows(pairs: list[tuple[Trajectory, Trajectory]], chunk: int, length: int | None = None,
                 identity: bool = True, max_gap: int = 2, min_steps: int = 3) -> dict[str, torch.Tensor]:
    """The generator's training tensors from (normal, styled) trajectory pairs: inputs and targets (N, H, 6)
    OSC units, mask (N, H), style (N,) indices into styles.STYLES, contact_step (N,) steps since contact began."""
    parts = {"inputs": [], "targets": [], "mask": [], "style": [], "contact_step": []}

    def add(source, target, style):
        inputs, targets, mask, steps = segment_windows(source, target, chunk)
        for key, value in zip(("inputs", "targets", "mask", "contact_step"), (inputs, targets, mask, steps)):
            parts[key].append(value)
        parts["style"].append(np.full(len(inputs), style_index(style), dtype=np.int64))

    for normal, styled in pairs:
        for normal_segment, styled_segment in contact_pairs(normal, styled, length, max_gap, min_steps):
            add(normal_segment, styled_segment, styled.style)
        if identity and styled.style != "normal":
            for a, b in contact_segments(normal.contact, max_gap, min_steps):
                add(normal.actions[a:b], normal.actions[a:b], "normal")
    if not parts["inputs"]:
        raise ValueError("no pairs: nothing to train on")
    return {key: torch.from_numpy(np.concatenate(values)) for key, values in parts.items()}
