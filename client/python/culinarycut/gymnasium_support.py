"""Gymnasium when it is importable, else the package's stand-ins: the env base class, the spaces and seeding.

Everything in culinarycut that needs gymnasium takes it from here, so the package decides once and works
the same way without it (`pip install culinarycut[gymnasium]` adds it).
"""
from __future__ import annotations

try:
    import gymnasium
except ImportError:
    gymnasium = None

if gymnasium is not None:
    from gymnasium import Env
    from gymnasium.spaces import Box, Dict, Space
    from gymnasium.utils.seeding import np_random
else:
    from culinarycut.minimal_env import Env, np_random
    from culinarycut.minimal_spaces import Box, Dict, Space

__all__ = ["gymnasium", "Env", "Box", "Dict", "Space", "np_random"]
