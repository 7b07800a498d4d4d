"""Policies that drive a CulinaryCut session."""
from culinarycut.policies.oracle_episode import run_oracle_episode
from culinarycut.policies.scripted_oracle import ScriptedOracle

__all__ = ["ScriptedOracle", "run_oracle_episode"]
