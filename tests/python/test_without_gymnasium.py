"""The package without gymnasium: a Python where `import gymnasium` fails still gets a working env with the
package's own spaces, the same dtypes, and Gymnasium's seeding (the same server seeds as with gymnasium)."""
from __future__ import annotations

import json
import subprocess
import sys

import numpy as np

from culinarycut import CulinaryCutEnv

SCENE = {"seed": 42, "cameras": [{"name": "front", "width": 32, "height": 24, "channels": ["rgb", "depth"]}]}

# Runs in a fresh interpreter; sys.modules["gymnasium"] = None makes every `import gymnasium` fail, as if
# it were not installed.
HIDDEN_GYMNASIUM = """
import json, sys
sys.modules["gymnasium"] = None
import numpy as np
import culinarycut
from culinarycut import CulinaryCutEnv, minimal_env, minimal_spaces
from culinarycut.gymnasium_support import gymnasium
assert gymnasium is None

scene = json.loads(sys.argv[2])
with CulinaryCutEnv(sys.argv[1], scene=scene, control_mode="pd_joint_delta_pos", render_mode="rgb_array") as env:
    assert isinstance(env, minimal_env.Env) and type(env.action_space) is minimal_spaces.Box
    assert type(env.observation_space) is minimal_spaces.Dict
    first_seed = env.reset()[1]["seed"]
    obs, info = env.reset(seed=5)
    seeds = [env.reset()[1]["seed"] for _ in range(3)]
    env.action_space.seed(0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    assert obs in env.observation_space, "observation outside the observation space"
    assert env.render().shape == (24, 32, 3)
    dtypes = {f"{group}/{key}": str(value.dtype) for group in ("agent", "extra") for key, value in obs[group].items()}
    dtypes.update({f"sensor_data/front/{key}": str(value.dtype) for key, value in obs["sensor_data"]["front"].items()})
    print(json.dumps({"first_seed": first_seed, "seeds": seeds, "dtypes": dtypes, "elapsed_steps": info["elapsed_steps"],
                      "timings": sorted(env.last_step_timings)}))
"""


def test_the_env_works_without_gymnasium_as_it_does_with_it(address):
    result = subprocess.run([sys.executable, "-c", HIDDEN_GYMNASIUM, address, json.dumps(SCENE)],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    without = json.loads(result.stdout.strip().splitlines()[-1])

    with CulinaryCutEnv(address, scene=SCENE, control_mode="pd_joint_delta_pos") as env:
        assert env.reset()[1]["seed"] == without["first_seed"] == 42  # the scene's seed
        env.reset(seed=5)
        assert [env.reset()[1]["seed"] for _ in range(3)] == without["seeds"]  # np_random: the same stream
        obs, *_, info = env.step(np.zeros(7))
    assert without["dtypes"] == {**{f"{group}/{key}": str(value.dtype) for group in ("agent", "extra")
                                    for key, value in obs[group].items()},
                                 "sensor_data/front/rgb": "uint8", "sensor_data/front/depth": "int16"}
    assert set(without["dtypes"].values()) == {"float32", "uint8", "int16"}
    assert without["elapsed_steps"] == 1 and "step_wall_time_ms" in without["timings"]
