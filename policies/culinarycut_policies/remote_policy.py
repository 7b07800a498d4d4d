"""What every adapter of a remote model shares: the options for reaching its server (url, timeouts,
retries), the cameras it asks the scene for, connecting at reset, closing, and the query latencies."""
from __future__ import annotations

from typing import Any

from culinarycut.policies.base import Policy

from culinarycut_policies.transports.faults import LatencyLog, PolicyServerError, Timeouts

DEFAULT_CAMERA_SIZE = 256  # what LIBERO and Bridge evaluations render before the model's own resize


def camera_request(name: str, size: int) -> dict:
    if size < 8:
        raise ValueError(f"camera size must be at least 8 pixels, got {size}")
    return {"name": name, "width": int(size), "height": int(size), "channels": ["rgb"]}


class RemotePolicy(Policy):
    """Subclasses set `name`, `control_mode`, make `self.transport` in __init__ (nothing is contacted
    there: the runner builds a policy once to check its options) and implement `act`. A websocket model
    server's metadata may name its `model_family`; one that names another family is refused."""

    model_family: str | None = None

    def __init__(self, *, url: str, connect_timeout_s: float = 10.0, query_timeout_s: float = 30.0,
                 retries: int = 3, backoff_s: float = 0.5):
        super().__init__()
        if not url:
            raise ValueError(f"policy {self.name!r} needs option url (or --policy-url): where its model server listens")
        self.url = str(url)
        self.timeouts = Timeouts(connect_s=float(connect_timeout_s), query_s=float(query_timeout_s),
                                 retries=int(retries), backoff_s=float(backoff_s))
        self.transport: Any = None
        self.instruction = ""

    def reset(self, instruction: str, info: dict[str, Any]) -> None:
        super().reset(instruction, info)
        self.instruction = instruction
        self.connect()

    def use_cameras(self, camera: str, wrist_camera: str | None, size: int) -> None:
        """The scene cameras this adapter reads: `camera`, and `wrist_camera` unless it is empty."""
        self.camera, self.wrist_camera = camera, wrist_camera or None
        self.cameras = tuple(camera_request(c, size) for c in (camera, self.wrist_camera) if c)

    def connect(self) -> None:
        """Opens the transport and checks what the server says it serves."""
        metadata = self.transport.connect() or {}
        family = metadata.get("model_family", self.model_family)
        if self.model_family and family != self.model_family:
            raise PolicyServerError(f"policy {self.name}: the server at {self.url} serves {family!r}, "
                                    f"not {self.model_family!r}")
        self.check_metadata(metadata)

    def preflight(self) -> None:
        """The runner's check before a run's first episode: connects (with the retries of the timeouts), checks
        the server's metadata and closes; raises what connect() raises, naming the URL."""
        try:
            self.connect()
        finally:
            self.close()

    def check_metadata(self, metadata: dict) -> None:
        """Subclasses compare the server's metadata with their options."""

    def close(self) -> None:
        if self.transport is not None:
            self.transport.close()

    @property
    def latency(self) -> LatencyLog:
        return self.transport.latency

    def latency_summary(self) -> dict:
        return self.latency.summary()
