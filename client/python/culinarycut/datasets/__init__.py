"""Dataset generation: demonstrations (demo), randomised episode jobs (jobs), one recorded episode
(record), its file (episode_file), the generation store (store), sharded Dask generation (generate),
the exports (robomimic, LIBERO, LeRobot v2.1, RDT, statistics) and the check of a finished dataset (verify)."""
