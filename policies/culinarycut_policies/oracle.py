"""The scripted oracle, re-exported: it plans and acts on the CulinaryCut server itself (Tasks.StartOracle),
so it lives in the culinarycut package; here it sits beside the model adapters."""
from culinarycut.policies.oracle_episode import run_oracle_episode
from culinarycut.policies.oracle_policy import OraclePolicy
from culinarycut.policies.scripted_oracle import ScriptedOracle

__all__ = ["OraclePolicy", "ScriptedOracle", "run_oracle_episode"]
