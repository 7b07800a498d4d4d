"""A stand-in for gymnasium.Env, used when gymnasium is not installed: the same seeding and attributes.

Seeding is gymnasium's (gymnasium.utils.seeding.np_random): a PCG64 generator from a SeedSequence, so an
env seeded with s draws the same numbers with or without gymnasium.
"""
from __future__ import annotations

from typing import Any

import numpy as np


def np_random(seed: int | None = None) -> tuple[np.random.Generator, int]:
    """(generator, seed it was made from); a random seed when seed is None."""
    if seed is not None and not (isinstance(seed, (int, np.integer)) and seed >= 0):
        raise ValueError(f"seed must be a non-negative int or None, not {seed!r}")
    seed_sequence = np.random.SeedSequence(seed)
    return np.random.Generator(np.random.PCG64(seed_sequence)), int(seed_sequence.entropy)


class Env:
    """What CulinaryCutEnv takes from gymnasium.Env: metadata, render_mode, spec, np_random and
    reset(seed=...) seeding it, unwrapped, close, and the context manager."""

    metadata: dict[str, Any] = {"render_modes": []}
    render_mode: str | None = None
    spec = None
    _np_random: np.random.Generator | None = None
    _np_random_seed: int | None = None

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        if seed is not None:
            self._np_random, self._np_random_seed = np_random(seed)

    @property
    def np_random(self) -> np.random.Generator:
        if self._np_random is None:
            self._np_random, self._np_random_seed = np_random()
        return self._np_random

    @np_random.setter
    def np_random(self, value: np.random.Generator) -> None:
        self._np_random = value
        self._np_random_seed = -1  # as gymnasium: the seed of a generator set from outside is unknown

    @property
    def np_random_seed(self) -> int:
        if self._np_random_seed is None:
            self._np_random, self._np_random_seed = np_random()
        return self._np_random_seed

    @property
    def unwrapped(self) -> "Env":
        return self

    def close(self) -> None:
        pass

    def __enter__(self) -> "Env":
        return self

    def __exit__(self, *exc) -> bool:
        self.close()
        return False

    def __str__(self) -> str:
        return f"<{type(self).__name__} instance>"
