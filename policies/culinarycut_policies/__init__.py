"""CulinaryCut policy clients: adapters that turn CulinaryCut observations into what OpenVLA, OpenVLA-OFT,
Octo, RDT-1B and openpi policies saw in training and their answers into CulinaryCut actions, the two wire
protocols they are served with, stand-in model servers for tests, and the scripted oracle.

The adapters are registered for `culinarycut bench run --policy NAME` (see pyproject.toml); importing
this package does not import them, so a missing optional dependency only matters to the adapter using it.
"""
from culinarycut_policies.oracle import OraclePolicy, ScriptedOracle, run_oracle_episode

__all__ = ["OraclePolicy", "ScriptedOracle", "run_oracle_episode"]
