"""CstmPolicy: any runner policy with the CulinaryCut paper's CSTM on top. Each step the inner policy gives
its action a_hat; the contact classifier C looks at the camera image; while C says the knife touches the food,
the action is f(a_hat, style), else a_hat unchanged:

    culinarycut bench run SUITE --policy culinarycut_learning.cstm.policy:CstmPolicy \\
        --policy-option inner=openpi --policy-url ws://HOST:8000 --policy-option inner.camera_size=96 \\
        --policy-option classifier=runs/cstm-classifier --policy-option generator=runs/cstm-generator \\
        --policy-option style=saw

Options: `inner` (a policy name as --policy takes it: oracle, openpi, module:Class, ...), `classifier` and
`generator` (run folders or checkpoint files), `style` (normal, bias, guillotine, saw), `camera` (the camera C
sees; default the one it was trained on), `camera_size` (its render size, pixels; default the training
frames'), `threshold` (contact when P > it; 0.5), `release_steps` (non-contact steps after which a contact
run ends and the phase restarts; 3), `threads` (torch threads; 1). Every `inner.KEY=VALUE` is the inner
policy's option KEY; --policy-url (option url) goes to the inner policy. The camera is added to the inner
policy's `cameras` (the runner renders what a policy's `cameras` lists) unless it already asks for it.

How a^s is made from a per-step policy: the inner policy is asked for one action per step, a_hat_t, in its own
control mode (pd_ee_pose_quat or pd_ee_delta_pose), turned into the learned policy's units (OSC_POSE deltas
from the measured TCP, trajectories.py). The runner's policies expose no predicted future (an openpi chunk is
the adapter's own), so the chunk f reads is a_hat_t held for the chunk's H steps (a normal cut's contact
segment is a constant-speed descent), with the steps since this contact run began; the first action of f's
chunk is executed, as pd_ee_delta_pose (what the openpi adapter executes for the learned policy). Outside
contact the inner action passes through untouched, in its own mode.

What it did is reported through the runner's `latency_summary()` hook, stored in the episode row's
`policy_latency` (the inner policy's own summary, when it has one, beside it): under "cstm", the steps, the
steps C said contact and f was applied (`transformed_steps`), the first such step, and C's and f's time per call."""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import torch

from culinarycut.datasets.adapter_layouts import DELTA_MODES
from culinarycut.policies.base import Policy
from culinarycut.policies.registry import make_policy, policy_class
from culinarycut_learning.cstm.classifier_train import load_classifier
from culinarycut_learning.cstm.generator_train import load_generator
from culinarycut_learning.cstm.styles import STYLES, style_index
from culinarycut_learning.features import osc_actions
from culinarycut_policies.actions import delta_to_ee_delta_pose
from culinarycut_policies.images import camera_rgb
from culinarycut_policies.remote_policy import camera_request

INNER_PREFIX = "inner."
GRIPPER_SLOT = -1.0   # LIBERO's gripper column, dropped by delta_to_ee_delta_pose (the knife has no gripper)


class ContactRun:
    """Steps since the current contact run began: a run starts at a contact step and ends after more than
    `release_steps` steps without contact (a classifier's single-frame miss does not restart the phase)."""

    def __init__(self, release_steps: int = 3):
        self.release_steps = int(release_steps)
        self.reset()

    def reset(self) -> None:
        self.step: int | None = None
        self.gap = 0

    def update(self, contact: bool) -> int | None:
        """This step's steps since the run began when in contact, else None."""
        if self.step is None:
            if not contact:
                return None
            self.step, self.gap = 0, 0
            return 0
        self.step += 1
        if contact:
            self.gap = 0
            return self.step
        self.gap += 1
        if self.gap > self.release_steps:
            self.reset()
        return None


def _checkpoint(option: str, path, loader):
    if not path:
        raise ValueError(f"policy cstm needs option {option}=PATH (a run folder or checkpoint file of "
                         f"`python -m culinarycut_learning cstm-{option} train`)")
    try:
        return loader(Path(str(path)))
    except (FileNotFoundError, ValueError) as err:
        raise ValueError(f"policy cstm: option {option}: {err}") from None   # err names the path


class CstmPolicy(Policy):
    name = "cstm"
    version = "1"

    def __init__(self, inner: str = "", classifier: str = "", generator: str = "", style: str = "saw",
                 camera: str | None = None, camera_size: int | None = None, threshold: float = 0.5,
                 release_steps: int = 3, threads: int = 1, url: str | None = None, **options):
        super().__init__()
        unknown = sorted(k for k in options if not k.startswith(INNER_PREFIX))
        if unknown:
            raise ValueError(f"policy cstm: unknown option {', '.join(unknown)}; its options are inner, classifier, "
                             "generator, style, camera, camera_size, threshold, release_steps, threads, and "
                             "inner.KEY=VALUE for the inner policy's own options")
        if style not in STYLES:
            raise ValueError(f"policy cstm: option style={style!r}: unknown cutting style; choose one of "
                             f"{', '.join(STYLES)}")
        if not inner:
            raise ValueError("policy cstm needs option inner=NAME: the policy whose actions it restyles "
                             "(e.g. oracle, openpi, module:Class)")
        if policy_class(str(inner)) is CstmPolicy:
            raise ValueError("policy cstm: option inner names cstm itself")
        if not 0.0 < float(threshold) < 1.0:
            raise ValueError(f"policy cstm: option threshold must lie in (0, 1), got {threshold}")
        torch.set_num_threads(int(threads))
        self.classifier, classifier_payload = _checkpoint("classifier", classifier, load_classifier)
        self.generator, generator_payload = _checkpoint("generator", generator, load_generator)
        trained = generator_payload.get("styles", [])
        if style not in trained:
            raise ValueError(f"policy cstm: option style={style}: the generator {generator} was trained on "
                             f"{', '.join(trained) or 'no'} pairs, not {style}")
        self.style, self.style_id = style, style_index(style)
        self.threshold = float(threshold)
        self.run = ContactRun(release_steps)
        inner_options = {k[len(INNER_PREFIX):]: v for k, v in options.items()}
        if url is not None:
            inner_options["url"] = url
        self.inner = make_policy(str(inner), inner_options)
        self.inner_name = str(inner)
        self.control_mode = self.inner.control_mode
        self.needs_session = bool(getattr(self.inner, "needs_session", False))
        data = classifier_payload.get("data", {})
        self.camera = camera or self.classifier.config.camera
        inner_cameras = tuple(dict(c) for c in getattr(self.inner, "cameras", ()))
        size = int(camera_size or data.get("camera_size") or self.classifier.config.image_size)
        if any(c.get("name") == self.camera for c in inner_cameras):
            self.cameras = inner_cameras   # the inner policy's render of it is resized for C (features.model_image)
        else:
            self.cameras = inner_cameras + (camera_request(self.camera, size),)
        self.chunk = self.generator.config.chunk
        self._reset_counts()

    def _reset_counts(self) -> None:
        self.steps = 0
        self.transformed_steps = 0
        self.first_transformed_step: int | None = None
        self.classifier_s: list[float] = []
        self.generator_s: list[float] = []

    def reset(self, instruction, info):
        super().reset(instruction, info)
        self.run.reset()
        self._reset_counts()
        self.inner.reset(instruction, info)

    def contact(self, observation) -> bool:
        clock = time.perf_counter()
        probability = self.classifier.contact_probability(camera_rgb(observation, self.camera))
        self.classifier_s.append(time.perf_counter() - clock)
        return probability > self.threshold

    def stylise(self, mode: str, action: np.ndarray, observation, contact_step: int) -> tuple[str, np.ndarray]:
        """f(a_hat held over the chunk, style)'s first action, as pd_ee_delta_pose."""
        if mode not in DELTA_MODES:
            raise ValueError(f"policy cstm restyles end-effector actions ({', '.join(DELTA_MODES)}); the inner "
                             f"policy {self.inner_name} acts in {mode}")
        tcp_pose = np.asarray(observation["extra"]["tcp_pose"], dtype=np.float64)
        a_hat = osc_actions(np.asarray(action, dtype=np.float64)[None], tcp_pose[None], mode)[0]
        clock = time.perf_counter()
        chunk = torch.from_numpy(np.tile(a_hat, (self.chunk, 1)))
        styled = self.generator.stylise(chunk, self.style_id, contact_step)[0].numpy()
        self.generator_s.append(time.perf_counter() - clock)
        return delta_to_ee_delta_pose(np.append(styled, GRIPPER_SLOT), "robosuite_osc", "axis_angle")

    def act(self, observation):
        mode, action = self.inner.act(observation)
        self.finished = bool(self.inner.finished)
        step, self.steps = self.steps, self.steps + 1
        contact_step = self.run.update(self.contact(observation))
        if contact_step is None:
            return mode, action
        self.transformed_steps += 1
        if self.first_transformed_step is None:
            self.first_transformed_step = step
        return self.stylise(mode, action, observation, contact_step)

    def latency_summary(self) -> dict:
        inner = getattr(self.inner, "latency_summary", None)
        summary = dict(inner()) if inner is not None else {}
        summary["cstm"] = {
            "style": self.style, "camera": self.camera, "steps": self.steps,
            "transformed_steps": self.transformed_steps, "first_transformed_step": self.first_transformed_step,
            "classifier_ms_mean": 1e3 * float(np.mean(self.classifier_s)) if self.classifier_s else None,
            "generator_ms_mean": 1e3 * float(np.mean(self.generator_s)) if self.generator_s else None}
        return summary

    def preflight(self) -> None:
        check = getattr(self.inner, "preflight", None)
        if check is not None:
            check()

    def close(self) -> None:
        close = getattr(self.inner, "close", None)
        if close is not None:
            close()
