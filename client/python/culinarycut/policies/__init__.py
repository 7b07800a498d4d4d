"""Policies that drive a CulinaryCut session: the scripted oracle, and the floor (no-op, random)."""
from culinarycut.policies.base import EpisodeSession, Policy
from culinarycut.policies.floor_policies import NoOpPolicy, RandomPolicy
from culinarycut.policies.oracle_episode import run_oracle_episode
from culinarycut.policies.oracle_policy import OraclePolicy
from culinarycut.policies.registry import make_policy, policy_class, policy_names
from culinarycut.policies.scripted_oracle import ScriptedOracle

__all__ = ["EpisodeSession", "NoOpPolicy", "OraclePolicy", "Policy", "RandomPolicy", "ScriptedOracle",
           "make_policy", "policy_class", "policy_names", "run_oracle_episode"]
