"""CulinaryCutEnv: a gymnasium.Env backed by one server session, with ManiSkill's observation layout and dtypes.

Without gymnasium installed it derives from the package's stand-in (gymnasium_support) and behaves the same.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from culinarycut.client import (Client, food_to_dict, observation_to_dict, segmentation_labels_to_dict,
                                stamp_to_dict, step_info_to_dict, step_timings_to_dict)
from culinarycut.errors import InvalidArgument, NotFound
from culinarycut.gymnasium_support import Env, np_random
from culinarycut.observation_conventions import maniskill_box, to_maniskill
from culinarycut.spaces import box_from_array_spec, dict_from_array_specs
from culinarycut.tasks import score_to_dict

_RESET_OPTIONS = {"initial_qpos"}


def task_failed(score) -> bool:
    """A cut that can never count towards the task was made: through another object, or one more than the
    task asks for (pieces do not join again, so the episode cannot succeed any more)."""
    return score.wrong_object_cuts > 0 or score.extra_cuts > 0


class CulinaryCutEnv(Env):
    """reset/step/render/close with observation_space and action_space from the CreateSession handshake.

    The session is created in __init__ because the spaces come from the handshake; the action space is the
    server's for `control_mode`, the observation space ManiSkill's dtypes of what the server declares.
    Seeding is Gymnasium's: reset(seed=s) seeds np_random and the server with s; reset() without a seed
    uses the scene's seed for the first episode, then draws each episode's server seed from np_random.
    info after a step: frame_id, sim_time, elapsed_steps, success, fail, the server's step diagnostics and,
    with a scene task, its score. Wall-clock stage times vary from run to run, so they stay out of info
    (which is reproducible, as Gymnasium's checker wants) and go to last_step_timings.
    """

    metadata: dict[str, Any] = {"render_modes": ["rgb_array"]}  # the class's; an instance lists its scene's

    def __init__(self, address: str = "127.0.0.1:50051", scene=None, control_mode: str = "pd_ee_delta_pose",
                 client: Client | None = None, render_mode: str | None = None):
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode must be None or 'rgb_array', not {render_mode!r}")
        self.render_mode = render_mode
        self.last_step_timings: dict[str, float] = {}  # ms per server stage of the last step
        self._last_sensor_data = None  # the last reply's images, for render()
        self._owns_client = client is None
        self.client = client if client is not None else Client(address)
        self._session_id: str | None = None
        try:
            handshake = self.client.create_session(scene)
        except Exception:
            if self._owns_client:
                self.client.close()
            raise
        self._session_id = handshake.session_id
        self.handshake = handshake
        modes = {m.name: m for m in handshake.control_modes}
        if control_mode not in modes:
            self.close()
            raise ValueError(f"control_mode {control_mode!r} is not offered by the server; "
                             f"choose one of {sorted(modes)}")
        self.control_mode = control_mode
        self.action_space = box_from_array_spec(modes[control_mode].action)
        self.observation_space = dict_from_array_specs(handshake.observation_spec, maniskill_box)
        self.control_timestep = float(handshake.control_timestep)  # s of sim time per step
        has_rgb = any("rgb" in camera.channels for camera in handshake.resolved_scene.cameras)
        if render_mode == "rgb_array" and not has_rgb:
            self.close()
            raise ValueError("render_mode='rgb_array' needs a camera with an rgb channel in the scene, "
                             "e.g. scene={'cameras': [{'name': 'front'}]}")
        # What this scene can render, at this session's control rate.
        self.metadata = {"render_modes": ["rgb_array"] if has_rgb else []}
        if self.control_timestep > 0:
            self.metadata["render_fps"] = 1.0 / self.control_timestep

    @property
    def session_id(self) -> str | None:
        return self._session_id

    def _require_open(self) -> str:
        if self._session_id is None:
            raise RuntimeError("CulinaryCutEnv is closed")
        return self._session_id

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        """Start an episode; options may carry "initial_qpos" (7 joint angles, rad)."""
        session_id = self._require_open()
        options = dict(options or {})
        unknown = set(options) - _RESET_OPTIONS
        if unknown:
            raise ValueError(f"unknown reset option(s) {sorted(unknown)}; supported: {sorted(_RESET_OPTIONS)}")
        first_episode = self._np_random is None
        super().reset(seed=seed)
        if seed is not None:
            server_seed = int(seed)
        elif first_episode:
            server_seed = None  # the scene's seed
        else:
            server_seed = int(self.np_random.integers(2**63))
        response = self.client.reset(session_id, seed=server_seed, initial_qpos=options.get("initial_qpos"))
        if self._np_random is None:  # seeded from the scene's seed, so unseeded runs repeat too
            self._np_random, self._np_random_seed = np_random(int(response.seed))
        self.last_step_timings = {}
        info = stamp_to_dict(response.stamp)
        info["seed"] = int(response.seed)
        return self._observation(response.observation, info), info

    def _observation(self, observation, info: dict[str, Any]) -> dict[str, Any]:
        """The observation dict; its variable-length parts go to info, its images are kept for render()."""
        result = to_maniskill(observation_to_dict(observation))
        self._last_sensor_data = result.get("sensor_data", {})
        if observation.HasField("food"):
            info["food"] = food_to_dict(observation)
        if observation.instruction:
            info["instruction"] = observation.instruction
        if len(observation.segmentation_labels):
            info["segmentation_labels"] = segmentation_labels_to_dict(observation)
        return result

    def step(self, action):
        """Apply one action for control_timestep seconds; returns (obs, reward, terminated, truncated, info)."""
        session_id = self._require_open()
        values = np.asarray(action, dtype=np.float64)
        try:
            response = self.client.step(session_id, self.control_mode, values)
        except InvalidArgument as err:
            # The server decides; we only add what the client knows about the expected shape.
            expected = int(np.prod(self.action_space.shape))
            if values.size != expected:
                raise InvalidArgument(field=err.field, details=f"{err.details} (client: action has {values.size} values, "
                                      f"{self.control_mode} expects shape {self.action_space.shape})") from None
            raise
        self.last_step_timings = step_timings_to_dict(response.info)
        info = stamp_to_dict(response.stamp)
        info.update(step_info_to_dict(response.info))
        info["elapsed_steps"] = int(response.stamp.frame_id)  # steps since reset, as ManiSkill counts
        has_task = response.HasField("task_score")
        info["success"] = has_task and bool(response.task_score.success)
        info["fail"] = has_task and task_failed(response.task_score)
        if has_task:  # the success metrics, final at the episode's end
            info["task"] = score_to_dict(response.task_score)
        observation = self._observation(response.observation, info)
        return (observation, float(response.reward),
                bool(response.terminated), bool(response.truncated), info)

    def render(self):
        """render_mode 'rgb_array': the RGB images of the scene's cameras at the last reset or step, side
        by side (H x sum(W) x 3 uint8; cameras of different heights are padded with black).
        None when render_mode is None (as in gymnasium)."""
        if self.render_mode is None:
            return None
        if self._last_sensor_data is None:
            raise RuntimeError("render() before reset(): there is nothing to show yet")
        images = [data["rgb"] for data in self._last_sensor_data.values() if "rgb" in data]
        height = max(image.shape[0] for image in images)
        padded = [np.pad(image, ((0, height - image.shape[0]), (0, 0), (0, 0))) for image in images]
        return np.concatenate(padded, axis=1)

    def close(self) -> None:
        """Close the server session (and the channel if this env created it); safe to call twice."""
        session_id, self._session_id = self._session_id, None
        try:
            if session_id is not None:
                self.client.close_session(session_id)
        except NotFound:
            pass  # already gone (e.g. idle timeout): the goal of close() is met
        finally:
            if self._owns_client and session_id is not None:
                self.client.close()

    def __str__(self) -> str:
        return f"<CulinaryCutEnv session={self._session_id} control_mode={self.control_mode}>"
