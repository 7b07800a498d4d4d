"""The rate a model was trained at, and its delta actions executed at the simulator's control rate.

A delta end-effector action of a model trained at f_model Hz moves the TCP over 1 / f_model s. At the
simulator's f_sim Hz it is executed by interpolation: k = f_sim / f_model equal steps of delta / k (a
repeated delta would move k times as far), and the model is queried (or its chunk advanced) once per k
steps, so its history and chunks keep its own rate. Option model_rate_hz sets f_model; by default the rate
of the statistics' dataset where it is a known upstream one, else the simulator's (a model trained on
CulinaryCut's export)."""
from __future__ import annotations

from collections import deque
from typing import Callable

import numpy as np

LIBERO_HZ = 20.0  # LIBERO's environments: control_freq=20 (libero/libero/envs/bddl_base_domain.py)
# RDT's configs/dataset_control_freq.json: bridgev2 5, fractal20220817_data 3, droid 15.
UPSTREAM_RATES_HZ = {
    "bridge_orig": 5.0, "bridge_dataset": 5.0, "fractal20220817_data": 3.0, "droid": 15.0,
    **{f"libero_{suite}{suffix}": LIBERO_HZ for suite in ("spatial", "object", "goal", "10", "90")
       for suffix in ("", "_no_noops")},
}


class ModelRate:
    def __init__(self, option: float | None, dataset_key: str | None, policy: str):
        if option is not None and not float(option) > 0:
            raise ValueError(f"policy {policy!r}: option model_rate_hz must be positive, got {option}")
        self.option = None if option is None else float(option)
        self.upstream = UPSTREAM_RATES_HZ.get(dataset_key or "")
        self.policy = policy
        self.steps = 1
        self.pending: deque = deque()

    def reset(self, info: dict) -> None:
        """Takes the simulator's rate from the episode's info; the model's must divide it."""
        self.pending.clear()
        simulator = info.get("control_frequency_hz")
        model = self.option or self.upstream
        if model is None or simulator is None:
            if self.option is not None:
                raise ValueError(f"policy {self.policy!r}: option model_rate_hz needs the episode's control rate "
                                 "(info control_frequency_hz)")
            self.steps = 1
            return
        ratio = float(simulator) / model
        self.steps = int(round(ratio))
        if self.steps < 1 or abs(ratio - self.steps) > 1e-6:
            raise ValueError(f"policy {self.policy!r}: the model's rate {model:g} Hz does not divide the control rate "
                             f"{float(simulator):g} Hz; set the scene's control rate to a multiple of it, or option "
                             "model_rate_hz")

    def execute(self, model_action: Callable, observation: dict) -> tuple[str, np.ndarray]:
        """This step's (mode, values): the next of the k interpolation steps of the model's last action."""
        if not self.pending:
            mode, values = model_action(observation)
            self.pending.extend([(mode, np.asarray(values, dtype=np.float64) / self.steps)] * self.steps)
        return self.pending.popleft()
