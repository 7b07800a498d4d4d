"""How a predicted action chunk becomes one action per control step: open loop (execute the first k,
then query again: OpenVLA-OFT, Octo's receding horizon, RDT, openpi's ActionChunkBroker) or Octo's
temporal ensemble (query every step, average the predictions that cover this step)."""
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
