"""Stand-in model servers: deterministic fake models behind the exact upstream wire protocols (same routes,
encodings, metadata and error behaviour), so every adapter is tested end to end without weights.
`python -m culinarycut_policies.standins MODEL --port PORT --statistics FILE` serves one."""
