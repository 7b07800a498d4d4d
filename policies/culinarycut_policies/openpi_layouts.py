"""How CulinaryCut's one Panda holding a knife fills the observation layouts of openpi's examples, and how
their actions drive it; the one place these decisions are made (docs/policies.md explains them).

LIBERO (examples/libero/main.py): the knife's TCP as the end effector (actions.py).

DROID (examples/droid/main.py, droid_policy.py): DROID is a Panda too, so its 7 joints are ours.
- `observation/joint_position`: the Panda's 7 joint angles (rad, float64 as DROID's robot state).
- `observation/gripper_position`: 1.0, DROID's closed gripper (0 open, 1 closed): the hand that would
  hold a knife by its handle is closed on it, as LIBERO's zero finger slots already say.
- actions (H, 8): 7 joint velocities and a gripper position, clipped to [-1, 1] as the example does.
  DROID's RobotEnv(action_space="joint_velocity") turns a velocity v into the joint target
  q + 0.2 v rad (droid/robot_ik/robot_ik_solver.py: max_joint_delta 0.2 per 15 Hz step) from the
  measured joints. The server has no joint-velocity mode, so this is pd_joint_pos with the same target,
  the velocity integrated over the control step in the model's time (chunking.TimedChunks): at 15 Hz
  exactly DROID's target, at the default 20 Hz 0.75 of a model step per control step, so the joints
  keep DROID's speed (up to 3 rad/s, beyond what pd_joint_delta_pos's 0.1 rad per step allows; the
  server scales a command down to the joints' speed limits). The gripper dimension is ignored.

ALOHA (examples/aloha_real/real_env.py and env.py, aloha_policy.py): two 6-joint ViperX arms, state
and actions [left arm (6), left gripper, right arm (6), right gripper] in standard ALOHA space (the
server's AlohaInputs flips joints and converts grippers for pi's runtime itself, adapt_to_pi).
- Our arm is the left arm. The ViperX's joints (waist, shoulder, elbow, forearm_roll, wrist_angle,
  wrist_rotate) are the Panda's with its redundant upper-arm roll (joint 3) left out: joints 1, 2, 4,
  5, 6, 7 (yaw, pitch, pitch, roll, pitch, roll, in the same order along the arm). The values are the
  Panda's own angles, not calibrated to the ViperX's zero or signs: a model must have been trained on
  this mapping (a checkpoint fine-tuned on CulinaryCut data in the ALOHA layout), not on ALOHA's arms.
  Joint 3 is held at its angle when the episode's first chunk arrives.
- The left gripper reads 0.0, ALOHA's closed (0 close, 1 open), the hand closed on the knife.
- The right arm does not exist: its state is held at rest, the server's `reset_pose` (openpi's ALOHA
  configs' policy_metadata, where aloha_real resets both arms) or RealEnv's DEFAULT_RESET_POSITION
  without one, its gripper 1.0 (open, as the runtime's reset leaves it); its actions are ignored.
- Cameras: `cam_high` is the scene's camera (front), `cam_left_wrist` the wrist camera; `cam_low`
  and `cam_right_wrist` are not sent: AlohaInputs never reads `cam_low`, and fills a missing
  `cam_right_wrist` with black and masks it out, as it does for aloha_sim (only `cam_high`).
- actions (H, 14): the left arm's 6 absolute joint positions become the Panda's targets (joint 3 held)
  through pd_joint_pos, each chunk element the target at the end of its 50 Hz step, interpolated at
  the control step's end (TimedChunks.sample); both grippers and the right arm are ignored.
"""
from __future__ import annotations

import numpy as np

LAYOUTS = ("libero", "droid", "aloha")
# The top-level keys each layout's input transform reads (its example's request, in its order).
LAYOUT_KEYS = {
    "libero": ("observation/image", "observation/wrist_image", "observation/state", "prompt"),
    "droid": ("observation/exterior_image_1_left", "observation/wrist_image_left", "observation/joint_position",
              "observation/gripper_position", "prompt"),
    "aloha": ("state", "images", "prompt"),
}

DROID_MAX_JOINT_DELTA_RAD = 0.2  # RobotIKSolver.max_joint_delta: velocity 1 = 0.2 rad per DROID step
DROID_GRIPPER_POSITION = 1.0     # closed (DROID: 0 open, 1 closed)

ALOHA_REST_ARM = (0.0, -0.96, 1.16, 0.0, -0.3, 0.0)  # examples/aloha_real/real_env.py DEFAULT_RESET_POSITION
ALOHA_LEFT_GRIPPER = 0.0         # closed on the knife (ALOHA: 0 close, 1 open)
ALOHA_RIGHT_GRIPPER = 1.0        # open, as aloha_real's reset leaves it
PANDA_JOINTS_AS_ALOHA = (0, 1, 3, 4, 5, 6)  # Panda joints 1, 2, 4, 5, 6, 7 as waist ... wrist_rotate
PANDA_HELD_JOINT = 2             # joint 3, the upper-arm roll a ViperX lacks


def layout_of_key(key: str) -> str | None:
    """The layout whose request carries `key` (prompt: any), None for a key of none."""
    for layout, keys in LAYOUT_KEYS.items():
        if key in keys and key != "prompt":
            return layout
    return None


def panda_joints(observation: dict) -> np.ndarray:
    """The Panda's 7 measured joint angles (rad), float64."""
    return np.asarray(observation["agent"]["qpos"], dtype=np.float64)[:7].copy()


def droid_joint_target(joints: np.ndarray, velocity: np.ndarray) -> np.ndarray:
    """DROID's joint-velocity action (already integrated over the control step in model steps, so one
    model step of velocity v is v) as a pd_joint_pos target from the measured joints."""
    return np.asarray(joints, dtype=np.float64) + DROID_MAX_JOINT_DELTA_RAD * np.asarray(velocity)[:7]


def aloha_state(joints: np.ndarray, right_arm_rest: np.ndarray) -> np.ndarray:
    """The 14-D ALOHA state of our arm as the left arm and a right arm at rest."""
    left = np.asarray(joints, dtype=np.float64)[list(PANDA_JOINTS_AS_ALOHA)]
    return np.concatenate([left, [ALOHA_LEFT_GRIPPER], np.asarray(right_arm_rest, dtype=np.float64)[:6],
                           [ALOHA_RIGHT_GRIPPER]])


def aloha_panda_target(action: np.ndarray, held_joint: float) -> np.ndarray:
    """The Panda's 7 joint targets from a 14-D ALOHA action: the left arm's 6, joint 3 held."""
    target = np.empty(7)
    target[list(PANDA_JOINTS_AS_ALOHA)] = np.asarray(action, dtype=np.float64)[:6]
    target[PANDA_HELD_JOINT] = held_joint
    return target
