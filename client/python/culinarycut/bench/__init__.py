"""Benchmark suites run remotely: suites as data (suite), episodes (episode_scene, episode), the
results database (store), Dask dispatch (dispatch), the runner (runner) and reports (report)."""
