"""How a predicted action chunk becomes one action per control step: open loop (execute the first k,
then query again: OpenVLA-OFT, Octo's receding horizon, RDT, openpi's ActionChunkBroker), the same in
simulated time for a model whose rate need not divide the control rate (openpi's DROID and ALOHA
layouts), or Octo's temporal ensemble (query every step, average the predictions that cover this step)."""
from __future__ import annotations

from collections import deque

import numpy as np


class OpenLoopChunks:
    """Executes `execute_steps` actions of each chunk in order, then asks for a new chunk
    (octo/utils/gym_wrappers.py RHCWrapper; openpi_client/action_chunk_broker.py)."""

    def __init__(self, execute_steps: int):
        if execute_steps < 1:
            raise ValueError(f"execute_steps must be at least 1, got {execute_steps}")
        self.execute_steps = int(execute_steps)
        self._queue: deque = deque()

    def reset(self) -> None:
        self._queue.clear()

    @property
    def needs_chunk(self) -> bool:
        return not self._queue

    def add(self, chunk: np.ndarray) -> None:
        chunk = np.asarray(chunk)
        if chunk.ndim != 2 or len(chunk) < self.execute_steps:
            raise ValueError(f"expected an action chunk of at least {self.execute_steps} steps (H x D), "
                             f"got shape {chunk.shape}")
        self._queue.extend(chunk[: self.execute_steps])

    def next(self) -> np.ndarray:
        return self._queue.popleft()


class TemporalEnsemble:
    """Octo's TemporalEnsembleWrapper (octo/utils/gym_wrappers.py): keeps the last `horizon` chunks; the
    action for this step averages each kept chunk's prediction for this step (the chunk made k steps ago
    gives its element k), weighted exp(-w * n) for n = 0 (oldest chunk) ... newest, normalised: w > 0
    trusts older predictions more, as upstream; w = 0 (upstream's default) is the plain mean."""

    needs_chunk = True  # a new chunk every step

    def __init__(self, horizon: int, exp_weight: float = 0.0):
        if horizon < 1:
            raise ValueError(f"ensemble horizon must be at least 1, got {horizon}")
        self.horizon = int(horizon)
        self.exp_weight = float(exp_weight)
        self._history: deque = deque(maxlen=self.horizon)
        self._pending: np.ndarray | None = None

    def reset(self) -> None:
        self._history = deque(maxlen=self.horizon)
        self._pending = None

    def add(self, chunk: np.ndarray) -> None:
        chunk = np.asarray(chunk)
        if chunk.ndim != 2 or len(chunk) < self.horizon:
            raise ValueError(f"expected an action chunk of at least {self.horizon} steps (H x D), got {chunk.shape}")
        self._history.append(chunk[: self.horizon])
        count = len(self._history)
        predictions = np.stack([c[i] for i, c in zip(range(count - 1, -1, -1), self._history)])
        weights = self.weights(count)
        self._pending = np.sum(weights[:, None] * predictions, axis=0)

    def weights(self, count: int) -> np.ndarray:
        """Weights of the `count` predictions, oldest chunk first."""
        weights = np.exp(-self.exp_weight * np.arange(count))
        return weights / weights.sum()

    def next(self) -> np.ndarray:
        if self._pending is None:
            raise RuntimeError("TemporalEnsemble.next before a chunk was added")
        action, self._pending = self._pending, None
        return action


class TimedChunks:
    """A chunk of a model trained at `model_rate_hz` executed in simulated time at the simulator's control
    rate, whatever their ratio: element i of a chunk lasts from i to i + 1 model steps after the query,
    each control step covers model rate / control rate of them (DROID's 15 Hz at 20 Hz: 0.75), and a new
    chunk is asked for at the first control step that starts at or past the end of `execute_steps`
    elements (openpi's examples: open_loop_horizon, action_horizon). The last step of a chunk may reach
    into element `execute_steps`, what the model predicted for that time; past the chunk's end its last
    element holds."""

    def __init__(self, execute_steps: int, model_rate_hz: float):
        if execute_steps < 1:
            raise ValueError(f"execute_steps must be at least 1, got {execute_steps}")
        if not model_rate_hz > 0:
            raise ValueError(f"the model's rate must be positive, got {model_rate_hz}")
        self.execute_steps = int(execute_steps)
        self.model_rate_hz = float(model_rate_hz)
        self.per_step = 1.0  # elements per control step
        self._chunk: np.ndarray | None = None
        self._steps = 0

    def reset(self, control_rate_hz: float | None) -> None:
        """The simulator's control rate (None: one element per control step)."""
        self.per_step = self.model_rate_hz / float(control_rate_hz) if control_rate_hz else 1.0
        self._chunk = None
        self._steps = 0

    @property
    def needs_chunk(self) -> bool:
        return self._chunk is None or self._steps * self.per_step >= self.execute_steps - 1e-9

    def add(self, chunk: np.ndarray) -> None:
        chunk = np.asarray(chunk, dtype=np.float64)
        if chunk.ndim != 2 or len(chunk) < self.execute_steps:
            raise ValueError(f"expected an action chunk of at least {self.execute_steps} steps (H x D), "
                             f"got shape {chunk.shape}")
        self._chunk = chunk
        self._steps = 0

    def integrate(self) -> np.ndarray:
        """The elements this control step covers, each weighted by the fraction of its model step covered
        (one whole element when the rates are equal); advances one control step. For rate-like actions
        (DROID's joint velocities, each worth one model step)."""
        chunk = self._current()
        start, end = self._steps * self.per_step, (self._steps + 1) * self.per_step
        self._steps += 1
        total = np.zeros(chunk.shape[1])
        for i in range(int(np.floor(start)), int(np.ceil(end - 1e-9))):
            total += (min(end, i + 1) - max(start, i)) * chunk[min(i, len(chunk) - 1)]
        return total

    def sample(self) -> np.ndarray:
        """The chunk at the end of this control step, element i being the target at the end of model step
        i, linear between elements (the element itself when the rates are equal); advances one control
        step. For targets (ALOHA's absolute joint positions)."""
        chunk = self._current()
        self._steps += 1
        x = min(max(self._steps * self.per_step - 1.0, 0.0), len(chunk) - 1.0)
        low = int(np.floor(x + 1e-9))
        high = min(low + 1, len(chunk) - 1)
        return chunk[low] + max(x - low, 0.0) * (chunk[high] - chunk[low])

    def _current(self) -> np.ndarray:
        if self._chunk is None:
            raise RuntimeError("TimedChunks: a step before the first chunk was added")
        return self._chunk
