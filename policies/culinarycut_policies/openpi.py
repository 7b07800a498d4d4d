"""Any openpi policy server (pi0, pi0-FAST, pi0.5: scripts/serve_policy.py) in one of the observation
layouts of openpi's own examples, option `layout` (the server's config decides which one it reads; its
input transform is in src/openpi/policies/):

- `libero` (default; examples/libero/main.py, LiberoInputs): `observation/image` and
  `observation/wrist_image` resized with pad to 224, `observation/state` (8), `prompt`; the answer's
  `actions` (H, 7) are delta end-effector actions in option `action_units`: by default robosuite's OSC
  units (1 = 0.05 m / 0.5 rad), what LIBERO-trained checkpoints (pi0_libero, pi05_libero) answer;
  `metres_radians` for a model trained on CulinaryCut's delta layout (gripper: see actions.py);
  executed `replan_steps` at a time (5 in the example) at the model's rate (control_rate.py).
- `droid` (examples/droid/main.py, DroidInputs): `observation/exterior_image_1_left`,
  `observation/wrist_image_left` (224, resize with pad), `observation/joint_position` (7),
  `observation/gripper_position` (1), `prompt`; `actions` (H, 8): 7 joint velocities and a gripper
  position, executed `replan_steps` (8) at a time at DROID's 15 Hz.
- `aloha` (examples/aloha_real/, AlohaInputs): `state` (14, two arms), `images` {`cam_high`,
  `cam_left_wrist`} 3 x 224 x 224, `prompt`; `actions` (H, 14) absolute joint positions, executed
  `replan_steps` (25) at a time at ALOHA's 50 Hz.

How the Panda with its knife fills each layout (the joints, the grippers it does not have, ALOHA's
second arm) is decided in openpi_layouts.py. openpi servers normalise and un-normalise with the
statistics stored in their own checkpoint, so this adapter takes none.

A server may ask for observations beyond its layout's keys in its metadata, `extra_observations` (a list
of keys of EXTRA_OBSERVATIONS): they are added after the layout's keys. openpi's own servers ask for none,
so their requests stay exactly the example's; CulinaryCut's trained policy (culinarycut_learning) asks for
the wrist force, which openpi's layouts do not carry."""
from __future__ import annotations

import re

import numpy as np

from culinarycut_policies.actions import (delta_to_ee_delta_pose, pad_state, resolve_action_units,
                                          resolve_rotation_delta, tcp_position_axis_angle)
from culinarycut_policies.chunking import OpenLoopChunks, TimedChunks
from culinarycut_policies.control_rate import ModelRate
from culinarycut_policies.images import camera_rgb, resize_with_pad
from culinarycut_policies.openpi_layouts import (ALOHA_REST_ARM, DROID_GRIPPER_POSITION, LAYOUT_KEYS, LAYOUTS,
                                                 aloha_panda_target, aloha_state, droid_joint_target, layout_of_key,
                                                 panda_joints)
from culinarycut_policies.remote_policy import DEFAULT_CAMERA_SIZE, RemotePolicy
from culinarycut_policies.transports.faults import PolicyServerError
from culinarycut_policies.transports.openpi_websocket import OpenPIWebsocketClient

IMAGE_SIZE = 224
STATE_DIM = 8  # LIBERO: eef position, rotation vector, two gripper joints
LIBERO_UNITS = "robosuite_osc"
# What each layout's example executes per query and at what rate (None: LIBERO's rate logic, control_rate.py).
REPLAN_STEPS = {"libero": 5, "droid": 8, "aloha": 25}   # replan_steps, open_loop_horizon, action_horizon
MODEL_RATE_HZ = {"libero": None, "droid": 15.0, "aloha": 50.0}  # DROID_CONTROL_FREQUENCY, Runtime(max_hz=50)
ACTION_DIMS = {"droid": 8, "aloha": 14}  # DroidOutputs, AlohaOutputs; LIBERO: at least the 6 pose deltas
LIBERO_ONLY_OPTIONS = ("state_dim", "action_units", "rotation_delta")
# What a server may ask for in its metadata's `extra_observations`, and where it comes from.
EXTRA_OBSERVATIONS = {
    # food -> knife wrench at the flange, flange frame: [N x3, N m x3] (CulinaryCutEnv's extra/wrist_wrench)
    "observation/wrist_wrench": lambda observation: np.asarray(observation["extra"]["wrist_wrench"],
                                                               dtype=np.float64).reshape(-1)[:6].copy(),
}


class OpenPIPolicy(RemotePolicy):
    name = "openpi"
    version = "1"
    control_mode = "pd_ee_delta_pose"  # libero; droid and aloha: pd_joint_pos

    def __init__(self, url: str = "ws://127.0.0.1:8000", layout: str = "libero", camera: str = "front",
                 wrist_camera: str | None = "wrist", camera_size: int = DEFAULT_CAMERA_SIZE,
                 replan_steps: int | None = None, state_dim: int | None = None, action_units: str | None = None,
                 model_rate_hz: float | None = None, rotation_delta: str | None = None, api_key: str | None = None,
                 **transport):
        super().__init__(url=url, **transport)
        if layout not in LAYOUTS:
            raise ValueError(f"policy 'openpi': option layout={layout!r}; choose one of {', '.join(LAYOUTS)} "
                             "(the layout of openpi's example the server's config was trained for)")
        self.layout = layout
        given = {"state_dim": state_dim, "action_units": action_units, "rotation_delta": rotation_delta}
        if layout != "libero" and any(v is not None for v in given.values()):
            raise ValueError(f"policy 'openpi': option {', '.join(k for k, v in given.items() if v is not None)} "
                             f"applies to layout=libero only, not {layout} (its actions are joint "
                             f"{'velocities' if layout == 'droid' else 'positions'})")
        if not wrist_camera and layout != "aloha":
            raise ValueError(f"policy 'openpi': layout {layout} sends a wrist image, which openpi's "
                             f"{layout.capitalize()}Inputs requires: option wrist_camera must name a camera")
        self.use_cameras(camera, wrist_camera, camera_size)
        replan_steps = REPLAN_STEPS[layout] if replan_steps is None else int(replan_steps)
        if layout == "libero":
            self.action_units = resolve_action_units(None, action_units or LIBERO_UNITS, self.name)
            self.rotation_delta = resolve_rotation_delta(rotation_delta, self.action_units, self.name)
            self.state_dim = STATE_DIM if state_dim is None else int(state_dim)
            self.chunks = OpenLoopChunks(replan_steps)
            self.rate = ModelRate(model_rate_hz, None, self.name)
        else:
            if model_rate_hz is not None and not float(model_rate_hz) > 0:
                raise ValueError(f"policy 'openpi': option model_rate_hz must be positive, got {model_rate_hz}")
            self.control_mode = "pd_joint_pos"
            self.chunks = TimedChunks(replan_steps, float(model_rate_hz or MODEL_RATE_HZ[layout]))
        self.right_arm_rest = np.array(ALOHA_REST_ARM)
        self.held_joint: float | None = None
        self.extra_observations: tuple[str, ...] = ()
        self.transport = OpenPIWebsocketClient(self.url, self.timeouts, api_key=api_key)

    def reset(self, instruction, info):
        if self.layout == "libero":
            self.chunks.reset()
            self.rate.reset(info)
        else:
            self.chunks.reset(info.get("control_frequency_hz"))
        self.held_joint = None
        super().reset(instruction, info)

    def check_metadata(self, metadata: dict) -> None:
        """A server that names its layout (CulinaryCut's stand-in) must serve ours; an ALOHA server's
        `reset_pose` (openpi's ALOHA configs' policy_metadata, where aloha_real resets both arms) is the
        rest of the arm we do not have."""
        served = metadata.get("layout")
        if served in LAYOUTS and served != self.layout:
            raise PolicyServerError(f"policy openpi: the server at {self.url} serves openpi's {served} layout, "
                                    f"not {self.layout}: set option layout={served}")
        extras = metadata.get("extra_observations") or []
        unknown = [key for key in extras if key not in EXTRA_OBSERVATIONS] if isinstance(extras, (list, tuple)) else []
        if not isinstance(extras, (list, tuple)) or unknown:
            raise PolicyServerError(f"policy openpi: the server at {self.url} asks for extra observations "
                                    f"{unknown or extras!r}; this adapter can send {', '.join(EXTRA_OBSERVATIONS)}")
        self.extra_observations = tuple(extras)
        if self.layout == "aloha" and metadata.get("reset_pose") is not None:
            pose = np.asarray(metadata["reset_pose"], dtype=np.float64).reshape(-1)
            if pose.size < 6:
                raise PolicyServerError(f"policy openpi: the server's reset_pose has {pose.size} values, not 6")
            self.right_arm_rest = pose[:6]

    def request(self, observation: dict) -> dict:
        """The observation dict in the layout's keys and order, as its example builds it, then the extra
        observations the server asked for."""
        request = self.layout_request(observation)
        request.update((key, EXTRA_OBSERVATIONS[key](observation)) for key in self.extra_observations)
        return request

    def layout_request(self, observation: dict) -> dict:
        image = resize_with_pad(camera_rgb(observation, self.camera), IMAGE_SIZE, IMAGE_SIZE)
        wrist = (resize_with_pad(camera_rgb(observation, self.wrist_camera), IMAGE_SIZE, IMAGE_SIZE)
                 if self.wrist_camera else None)
        if self.layout == "libero":
            return {"observation/image": image, "observation/wrist_image": wrist,
                    "observation/state": pad_state(tcp_position_axis_angle(observation), self.state_dim),
                    "prompt": self.instruction}
        if self.layout == "droid":
            return {"observation/exterior_image_1_left": image, "observation/wrist_image_left": wrist,
                    "observation/joint_position": panda_joints(observation),
                    "observation/gripper_position": np.array([DROID_GRIPPER_POSITION]),
                    "prompt": self.instruction}
        images = {"cam_high": _channels_first(image)}
        if wrist is not None:
            images["cam_left_wrist"] = _channels_first(wrist)
        return {"state": aloha_state(panda_joints(observation), self.right_arm_rest), "images": images,
                "prompt": self.instruction}

    def act(self, observation):
        if self.layout == "libero":
            return self.rate.execute(self.model_action, observation)
        if self.chunks.needs_chunk:
            self.chunks.add(self.query(observation))
        joints = panda_joints(observation)
        if self.layout == "droid":
            return "pd_joint_pos", droid_joint_target(joints, self.chunks.integrate())
        if self.held_joint is None:
            self.held_joint = float(joints[2])
        return "pd_joint_pos", aloha_panda_target(self.chunks.sample(), self.held_joint)

    def model_action(self, observation):
        if self.chunks.needs_chunk:
            self.chunks.add(self.query(observation))
        return delta_to_ee_delta_pose(self.chunks.next(), self.action_units, self.rotation_delta)

    def query(self, observation) -> np.ndarray:
        """One query: the answer's `actions` (H, D), D the layout's (DROID's joint velocities clipped to
        [-1, 1] as examples/droid/main.py does before stepping)."""
        request = self.request(observation)
        try:
            reply = self.transport.infer(request)
        except PolicyServerError as err:
            raise self.explain_layout_error(err, request) from None
        actions = np.asarray(reply.get("actions"))
        dim = ACTION_DIMS.get(self.layout)
        if actions.ndim != 2 or (dim is not None and actions.shape[1] != dim):
            expected = f"(H, {dim})" if dim else "(H, D)"
            raise PolicyServerError(f"policy openpi: expected `actions` {expected} of the {self.layout} layout from "
                                    f"{self.url}, got {actions.shape}: does the server serve another layout "
                                    "(option layout)?")
        return np.clip(actions, -1.0, 1.0) if self.layout == "droid" else actions

    def explain_layout_error(self, err: PolicyServerError, request: dict) -> PolicyServerError:
        """A real openpi server given another layout than its config's fails in its input transform with a
        KeyError traceback; say which layout the missing key belongs to."""
        missing = re.findall(r"KeyError: '([^']+)'", str(err))
        served = layout_of_key(missing[-1]) if missing else None
        if served is None or served == self.layout or missing[-1] in request:
            return err
        return PolicyServerError(f"policy openpi: the server at {self.url} reads {missing[-1]!r}, a key of openpi's "
                                 f"{served} layout (its input transform raised KeyError), and was sent the "
                                 f"{self.layout} layout ({', '.join(LAYOUT_KEYS[self.layout])}): set option "
                                 f"layout={served}")


def _channels_first(image: np.ndarray) -> np.ndarray:
    """HxWx3 -> 3xHxW, as ALOHA's runtime sends its images (examples/aloha_real/env.py)."""
    return np.ascontiguousarray(np.transpose(image, (2, 0, 1)))
