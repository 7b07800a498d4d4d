"""Policies that drive a CulinaryCut session."""
from culinarycut.policies.scripted_oracle import ScriptedOracle

__all__ = ["ScriptedOracle"]
