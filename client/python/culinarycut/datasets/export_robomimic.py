"""robomimic HDF5: data (attrs total, env_args) / demo_i (attrs num_samples, model_file, init_state) with
obs/<key>, next_obs/<key>, actions, rewards, dones, states; train / valid masks under mask/. One file for
the whole dataset. env_args is robomimic's env metadata for a Gym environment (EnvType.GYM_TYPE, 2, in
robomimic/envs/env_base.py: EnvGym calls make(env_name, **env_kwargs)): CulinaryCut's registered
Gymnasium id, with the control mode; each demo's scene is its model_file."""
from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np

from culinarycut.datasets.episodes import PHASES, camera_names, iter_episodes, phase_codes, scene_conditions

ROBOMIMIC_GYM_TYPE = 2          # robomimic/envs/env_base.py EnvType.GYM_TYPE (1 robosuite, 3 iGibson)
GYM_ENV_NAME = "CulinaryCut/Robot-v0"  # registration.py; robomimic's EnvGym makes it with env_kwargs


def _obs(steps: dict) -> dict[str, np.ndarray]:
    obs = {f"{camera}_image": steps[f"obs/{camera}_rgb"] for camera in camera_names(steps)}
    obs.update(joint_states=steps["obs/qpos"], joint_velocities=steps["obs/qvel"],
               ee_states=steps["obs/tcp_pose"], ee_velocities=steps["obs/tcp_velocity"],
               wrist_wrench=steps["obs/wrist_wrench"], contact_phase=phase_codes(steps),
               knife_contact=steps["knife_contact"].astype(np.uint8))
    return obs


def robomimic_env_args(control_mode: str) -> dict:
    """robomimic's env metadata: only make() keywords in env_kwargs, as EnvGym passes them on."""
    return {"env_name": GYM_ENV_NAME, "type": ROBOMIMIC_GYM_TYPE, "env_kwargs": {"control_mode": control_mode}}


def export_robomimic(root: Path, out: Path, valid_fraction: float = 0.1) -> Path:
    """Writes out (a .hdf5 file); every 1/valid_fraction-th demo goes to the valid mask."""
    out.parent.mkdir(parents=True, exist_ok=True)
    names, total = [], 0
    with h5py.File(out, "w") as file:
        data = file.create_group("data")
        env_args = None
        for index, meta, steps in iter_episodes(root):
            name = f"demo_{index}"
            demo = data.create_group(name)
            obs = _obs(steps)
            for key, values in obs.items():
                demo.create_dataset(f"obs/{key}", data=values)
                # next_obs[t] = obs[t + 1]; the last step repeats its own observation
                demo.create_dataset(f"next_obs/{key}", data=np.concatenate([values[1:], values[-1:]]))
            demo.create_dataset("actions", data=steps["actions"].astype(np.float64))
            demo.create_dataset("rewards", data=steps["rewards"].astype(np.float64))
            demo.create_dataset("dones", data=steps["dones"].astype(np.int64))
            # robomimic's states flatten the simulator state; ours is the robot's (qpos, qvel), the
            # food's is recovered by replaying the actions from the seed and resolved scene (model_file)
            demo.create_dataset("states", data=np.concatenate([steps["obs/qpos"], steps["obs/qvel"]], axis=1))
            demo.attrs["num_samples"] = len(steps["actions"])
            demo.attrs["model_file"] = json.dumps(meta["resolved_scene"], sort_keys=True)
            demo.attrs["init_state"] = json.dumps({"seed": meta["seed"]})
            demo.attrs["instructions"] = json.dumps(meta["instructions"])
            demo.attrs["language_instruction"] = meta["instructions"][0]
            demo.attrs["cut_spec"] = json.dumps(meta["cut_spec"], sort_keys=True)
            demo.attrs["source"] = meta["source"]
            demo.attrs["key"] = meta["key"]
            conditions = scene_conditions(meta)
            demo.attrs["scene"] = conditions["scene"]
            demo.attrs["topology"] = conditions["topology"]
            names.append(name)
            total += len(steps["actions"])
            if env_args is None:  # the first demo's, as before: one control mode per dataset
                env_args = robomimic_env_args(meta["control_mode"])
                data.attrs["quality"] = json.dumps(meta["resolved_scene"].get("quality", ""))
        if not names:
            raise ValueError(f"{root}: no kept episodes to export")
        data.attrs["total"] = total
        data.attrs["env_args"] = json.dumps(env_args)
        data.attrs["contact_phases"] = json.dumps(list(PHASES))  # the names of obs/contact_phase's codes
        data.attrs["problem_info"] = json.dumps({"problem_name": "culinarycut", "domain_name": "cutting"})
        stride = max(1, round(1 / valid_fraction)) if valid_fraction > 0 else 0
        valid = [n for i, n in enumerate(names) if stride and i % stride == stride - 1]
        train = [n for n in names if n not in valid]
        file.create_dataset("mask/train", data=np.array(train, dtype="S"))
        file.create_dataset("mask/valid", data=np.array(valid, dtype="S"))
    return out
