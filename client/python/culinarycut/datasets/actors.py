"""What drives a generated episode: the server's planner (the scripted oracle with the drawn height and
speed) or a demonstration's object-relative path fitted to the episode's object."""
from __future__ import annotations

import numpy as np

from culinarycut.datasets.contact_phase import DemoContactPhase
from culinarycut.datasets.demo import Demonstration
from culinarycut.datasets.demo_recorder import target_object
from culinarycut.datasets.object_frame import half_extents_in_object_frame, to_world_frame
from culinarycut.geometry import quat_normalize
from culinarycut.policies.scripted_oracle import ScriptedOracle

SETTLE_STEPS = 10  # steps the demo follower holds its last pose so the robot catches up (0.5 s at 20 Hz)


class PlannerActor:
    control_mode = "pd_ee_pose_quat"

    def __init__(self, client, session_id: str, spec: dict, options: dict, seed: int, control_mode: str):
        self.oracle = ScriptedOracle(client, session_id)
        self.oracle.reset(spec=spec, options=options, seed=seed, control_mode=control_mode)
        self.control_mode = control_mode

    @property
    def finished(self) -> bool:
        return self.oracle.finished

    def act(self, observation: dict, info: dict) -> tuple[np.ndarray, str]:
        """The next action and the phase of the plan's segment it belongs to."""
        del observation, info  # the server's oracle reads the robot's state itself
        mode, values = self.oracle.act()
        if mode != self.control_mode:
            raise RuntimeError(f"the oracle answered in {mode}, not {self.control_mode}")
        return values, self.oracle.phase


def _slerp(a, b, u: float) -> np.ndarray:
    a, b = quat_normalize(a), quat_normalize(b)
    dot = float(np.dot(a, b))
    if dot < 0:
        b, dot = -b, -dot
    if dot > 0.9995:
        return quat_normalize(a + u * (b - a))
    theta = np.arccos(dot)
    return (np.sin((1 - u) * theta) * a + np.sin(u * theta) * b) / np.sin(theta)


def resample_path(time_s: np.ndarray, poses: np.ndarray, at_s: float) -> np.ndarray:
    """The pose at `at_s`, linear in position and slerp in rotation; held past the ends."""
    i = int(np.clip(np.searchsorted(time_s, at_s) - 1, 0, len(time_s) - 2))
    u = float(np.clip((at_s - time_s[i]) / max(time_s[i + 1] - time_s[i], 1e-9), 0.0, 1.0))
    return np.concatenate([(1 - u) * poses[i, :3] + u * poses[i + 1, :3], _slerp(poses[i, 3:], poses[i + 1, 3:], u)])


def descent_speed_m_s(time_s: np.ndarray, z_m: np.ndarray, contact: np.ndarray) -> float:
    """The knife's mean downward speed (m/s) over the steps that end in contact; 0 without contact."""
    speeds = -np.diff(z_m) / np.maximum(np.diff(time_s), 1e-9)
    speeds = speeds[np.asarray(contact, bool)[1:]]
    return float(np.mean(speeds[speeds > 0])) if np.any(speeds > 0) else 0.0


def retarget(demo: Demonstration, object_pose: np.ndarray, half_extents_m: np.ndarray, cut_height_m: float,
             cut_speed_m_s: float) -> tuple[np.ndarray, np.ndarray]:
    """The demonstration's path on another object: positions scaled by the new half extents, the whole
    path slowed or sped up so its cut runs at cut_speed_m_s on the new object, and the cut started
    cut_height_m above the object's top: the approach (every sample before the first contact) is raised
    by the difference to the demonstration's last height before contact, and a vertical descent at
    cut_speed_m_s joins it back to that sample, so the knife enters the food no faster than the cutting
    speed. A demonstration whose last sample before contact is already higher keeps its approach."""
    if cut_speed_m_s <= 0:
        raise ValueError(f"cut_speed_m_s must be > 0 m/s, got {cut_speed_m_s}")
    relative = np.asarray(demo.relative_pose, float)
    contact = np.asarray(demo.knife_contact, bool)
    world = np.array([to_world_frame(p, object_pose, half_extents_m) for p in relative])
    time_s = np.asarray(demo.time_s, float) - demo.time_s[0]
    demo_speed_m_s = descent_speed_m_s(time_s, world[:, 2], contact)  # on the new object, before retiming
    if demo_speed_m_s > 0:
        time_s = time_s * (demo_speed_m_s / cut_speed_m_s)
    if not contact.any() or contact[0]:
        return time_s, world
    entry = int(np.argmax(contact)) - 1
    raise_m = cut_height_m - (relative[entry, 2] - 1.0) * half_extents_m[2]  # object z is vertical (yaw only)
    if raise_m <= 0:
        return time_s, world
    world[: entry + 1, 2] += raise_m
    descent_s = raise_m / cut_speed_m_s
    time_s = np.concatenate([time_s[: entry + 1], [time_s[entry] + descent_s], time_s[entry + 1:] + descent_s])
    lowered = world[entry].copy()
    lowered[2] -= raise_m
    return time_s, np.insert(world, entry + 1, lowered, axis=0)


class DemoActor:
    """Follows the retargeted path with pd_ee_pose_quat targets, one per control step; the phase comes
    from the knife's state relative to the food (DemoContactPhase)."""

    control_mode = "pd_ee_pose_quat"

    def __init__(self, demo: Demonstration, resolved_scene: dict, reset_info: dict, variation: dict,
                 control_timestep_s: float):
        object_pose, _ = target_object(resolved_scene)
        piece = reset_info["food"]["pieces"][0]
        half = half_extents_in_object_frame(object_pose[3:], piece["bounds_min"], piece["bounds_max"])
        self.time_s, self.path = retarget(demo, object_pose, half, variation["cut_height_m"],
                                          variation["cut_speed_m_s"])
        self.dt = control_timestep_s
        self.steps = int(np.ceil(self.time_s[-1] / self.dt)) + SETTLE_STEPS
        self.step = 0
        self.contact_phase = DemoContactPhase(variation["cut_height_m"])

    @property
    def finished(self) -> bool:
        return self.step >= self.steps

    def act(self, observation: dict, info: dict) -> tuple[np.ndarray, str]:
        self.step += 1
        phase = self.contact_phase.phase(observation, info)
        return resample_path(self.time_s, self.path, self.step * self.dt), phase

