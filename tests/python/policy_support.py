"""Shared by the policy adapter tests: this tree's policies/ on sys.path, the stand-ins' example statistics,
a one-task suite of short draft episodes."""
from __future__ import annotations

import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
POLICIES = REPO / "policies"
if str(POLICIES) not in sys.path:
    sys.path.insert(0, str(POLICIES))  # this tree's adapters, ahead of any installed copy

# The example statistics the stand-ins come with (re-exported for the tests).
from culinarycut_policies.standins.example_statistics import DELTA_KEY, RDT_KEY, write_statistics  # noqa: E402,F401


def write_suite(folder: Path, steps: int, trials: int = 1) -> Path:
    """A one-task suite (a cucumber, cut in the middle, draft) of `steps`-step episodes."""
    path = folder / "policy-adapters.toml"
    path.write_text(f'''name = "policy-adapters"
description = "Short draft episodes for the policy adapter tests."
trials = {trials}
max_episode_steps = {steps}
quality = "draft"

[[tasks]]
food = "cucumber"
state = "middle"
''')
    return path

