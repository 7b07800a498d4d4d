"""Shared by the policy adapter tests: the stand-ins' example statistics, a one-task suite of short draft
episodes. culinarycut_policies is the installed package (scripts/install_deps.sh installs policies/ into the
project's .venv, editable)."""
from __future__ import annotations

from pathlib import Path

# The example statistics the stand-ins come with (re-exported for the tests).
from culinarycut_policies.standins.example_statistics import DELTA_KEY, RDT_KEY, write_statistics  # noqa: F401

REPO = Path(__file__).resolve().parents[2]
POLICIES = REPO / "policies"  # the package's sources (test_policy_episodes installs a copy of them)


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

