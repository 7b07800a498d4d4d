"""`--policy grpc --policy-url HOST:PORT`: a policy in any language that serves the policy protocol
(culinarycut.v1.Policy, proto/culinarycut/v1/policy.proto; docs/policy_protocol.md).

The policy's metadata (GetPolicyMetadata) is asked once per instance, when the runner first needs it: its
cameras are added to the episode's scene, its control_mode and action_dim are what its actions are checked
against. Each episode: ResetPolicy (instruction, seed, control rate, the food objects' boxes and, only to a
policy whose metadata sets needs_session, the simulator session with its bearer token), then Act with the
observation flattened to tensors (culinarycut.policy_tensors) whenever the actions of its last answer are
used up. An answer's chunk of actions is executed one per control step, in order (open loop); a policy
trained at rate_hz below the simulator's control rate has each action executed over k = control rate /
rate_hz steps as the adapters of policies/ do (control_rate.py): a delta action (pd_*_delta_*) in k equal
parts, an absolute target held for k steps. An answer with `finished` ends the episode after its actions.

Options: url (host:port; grpc://host:port or grpcs://host:port for TLS), tls_ca, tls_cert, tls_key (PEM files,
TLS as for the simulator), token (a bearer token, sent over TLS only), connect_timeout_s (10), query_timeout_s
(30), retries (3) and backoff_s (0.5): as the model adapters'.
"""
from __future__ import annotations

import time
import uuid
from dataclasses import dataclass, field
from typing import Any

import grpc
import numpy as np

from culinarycut.client import MAX_MESSAGE_BYTES, _read_pem
from culinarycut.policies.base import ACTION_DIMS, Policy
from culinarycut.policy_tensors import TensorError, encode_observation, from_tensor
from culinarycut.tasks import object_box_to_proto
from culinarycut.v1 import policy_pb2, policy_pb2_grpc

ACTION_DTYPES = ("float32", "float64")
CHANNEL_OPTIONS = [("grpc.max_receive_message_length", MAX_MESSAGE_BYTES),
                   ("grpc.max_send_message_length", MAX_MESSAGE_BYTES)]


class PolicyServerError(RuntimeError):
    """The policy server answered with an error status, or something the protocol does not allow."""


class PolicyServerUnreachable(ConnectionError):
    """The policy server did not answer its metadata call (after the retries)."""


def policy_address(url: str) -> tuple[str, bool]:
    """(host:port, TLS by the scheme) of a policy url: HOST:PORT, grpc://HOST:PORT or grpcs://HOST:PORT."""
    scheme, sep, rest = str(url).partition("://")
    if not sep:
        scheme, rest = "grpc", str(url)
    host, _, port = rest.rstrip("/").rpartition(":")
    if scheme not in ("grpc", "grpcs") or not host or not port.isdigit() or "/" in rest.rstrip("/"):
        raise ValueError(f"policy 'grpc': option url={url!r}: expected HOST:PORT, grpc://HOST:PORT or "
                         "grpcs://HOST:PORT (where the policy server listens)")
    return f"{host}:{port}", scheme == "grpcs"


def _status(err: grpc.RpcError) -> str:
    return f"{err.code().name}: {err.details()}"


@dataclass
class QueryLatency:
    """Wall time of each Act (s): encoding the observation, the round trip, decoding the actions."""

    seconds: list = field(default_factory=list)

    def summary(self) -> dict:
        if not self.seconds:
            return {"queries": 0}
        values = np.asarray(self.seconds) * 1000.0
        return {"queries": len(values), "mean_ms": round(float(values.mean()), 3),
                "p50_ms": round(float(np.percentile(values, 50)), 3),
                "p95_ms": round(float(np.percentile(values, 95)), 3), "max_ms": round(float(values.max()), 3)}


def camera_requests(cameras) -> tuple[dict, ...]:
    """The scene cameras of PolicyCamera messages (RGB; 0 width or height: the scene's default)."""
    requests = []
    for camera in cameras:
        request = {"name": camera.name, "channels": ["rgb"]}
        if camera.width:
            request["width"] = int(camera.width)
        if camera.height:
            request["height"] = int(camera.height)
        requests.append(request)
    return tuple(requests)


def check_metadata(metadata: policy_pb2.PolicyMetadata, where: str) -> policy_pb2.PolicyMetadata:
    """The metadata with action_dim and chunk_size filled in; PolicyServerError for what cannot be used."""
    metadata = policy_pb2.PolicyMetadata.FromString(metadata.SerializeToString())
    problems = []
    if not metadata.control_mode:
        problems.append("no control_mode")
    elif metadata.control_mode not in ACTION_DIMS:
        problems.append(f"control_mode {metadata.control_mode!r} is not one of {', '.join(ACTION_DIMS)}")
    else:
        dims = ACTION_DIMS[metadata.control_mode]
        if metadata.action_dim == 0:
            metadata.action_dim = dims
        elif metadata.action_dim != dims:
            problems.append(f"action_dim {metadata.action_dim}, but {metadata.control_mode} takes {dims} values")
    if not (np.isfinite(metadata.rate_hz) and metadata.rate_hz >= 0):
        problems.append(f"rate_hz {metadata.rate_hz} (0: the server's control rate, or a positive rate)")
    names = [c.name for c in metadata.cameras]
    if any(not n or "/" in n for n in names) or len(set(names)) != len(names):
        problems.append(f"camera names {names} (each non-empty, without '/', once)")
    if problems:
        raise PolicyServerError(f"{where}: its metadata cannot be used: " + "; ".join(problems))
    metadata.chunk_size = max(1, metadata.chunk_size)
    return metadata


def action_steps(rate_hz: float, control_frequency_hz: float | None, where: str) -> int:
    """Control steps per policy action: control rate / the policy's rate (1 when it follows the server's)."""
    if not rate_hz:
        return 1
    if not control_frequency_hz:
        raise PolicyServerError(f"{where}: its rate_hz {rate_hz:g} needs the episode's control rate")
    ratio = float(control_frequency_hz) / rate_hz
    steps = int(round(ratio))
    if steps < 1 or abs(ratio - steps) > 1e-6:
        raise PolicyServerError(f"{where}: its rate {rate_hz:g} Hz does not divide the control rate "
                                f"{float(control_frequency_hz):g} Hz; set the scene's control rate to a multiple of it")
    return steps


class GrpcPolicy(Policy):
    name = "grpc"
    version = "0"

    def __init__(self, url: str | None = None, tls_ca: str | None = None, tls_cert: str | None = None,
                 tls_key: str | None = None, token: str | None = None, connect_timeout_s: float = 10.0,
                 query_timeout_s: float = 30.0, retries: int = 3, backoff_s: float = 0.5):
        super().__init__()
        if not url:
            raise ValueError("policy 'grpc' needs option url (or --policy-url): HOST:PORT where its policy server "
                             "listens")
        self.address, scheme_tls = policy_address(url)
        self.where = f"policy server {self.address}"
        self.tls = bool(scheme_tls or tls_ca or tls_cert)
        if token and not self.tls:
            raise ValueError("policy 'grpc': option token is sent over TLS only: use grpcs://HOST:PORT or tls_ca")
        if bool(tls_cert) != bool(tls_key):
            raise ValueError("policy 'grpc': a client certificate needs both tls_cert and tls_key")
        self._pem = {"root_certificates": _read_pem(tls_ca, "tls_ca"), "private_key": _read_pem(tls_key, "tls_key"),
                     "certificate_chain": _read_pem(tls_cert, "tls_cert")}
        self._call_metadata = (("authorization", f"Bearer {token}"),) if token else ()
        self.connect_timeout_s, self.query_timeout_s = float(connect_timeout_s), float(query_timeout_s)
        self.retries, self.backoff_s = int(retries), float(backoff_s)
        if self.connect_timeout_s <= 0 or self.query_timeout_s <= 0:
            raise ValueError("policy 'grpc': options connect_timeout_s and query_timeout_s must be positive")
        if self.retries < 0 or self.backoff_s < 0:
            raise ValueError("policy 'grpc': options retries and backoff_s must be >= 0")
        self._channel: grpc.Channel | None = None
        self._stub: policy_pb2_grpc.PolicyStub | None = None
        self._metadata: policy_pb2.PolicyMetadata | None = None
        self.latency = QueryLatency()
        self._queue: list[tuple[str, np.ndarray]] = []
        self._answered_finished = False
        self._steps_per_action = 1
        self._step = 0
        self.episode_id = ""

    # The metadata, asked for once when first needed (nothing is contacted in __init__: the runner builds a
    # policy once to check its options).
    @property
    def metadata(self) -> policy_pb2.PolicyMetadata:
        if self._metadata is None:
            self._metadata = check_metadata(self._ask_metadata(), self.where)
            self.name = self._metadata.name or type(self).name
            self.version = self._metadata.version or type(self).version
        return self._metadata

    @property
    def control_mode(self) -> str:
        return self.metadata.control_mode

    @property
    def cameras(self) -> tuple[dict, ...]:
        return camera_requests(self.metadata.cameras)

    @property
    def needs_session(self) -> bool:
        return self.metadata.needs_session

    def _connect(self) -> policy_pb2_grpc.PolicyStub:
        if self._stub is None:
            if self.tls:
                credentials = grpc.ssl_channel_credentials(**self._pem)
                self._channel = grpc.secure_channel(self.address, credentials, options=CHANNEL_OPTIONS)
            else:
                self._channel = grpc.insecure_channel(self.address, options=CHANNEL_OPTIONS)
            self._stub = policy_pb2_grpc.PolicyStub(self._channel)
        return self._stub

    def _ask_metadata(self) -> policy_pb2.PolicyMetadata:
        """GetPolicyMetadata, retried with backoff while the server cannot be reached (UNAVAILABLE, or no
        answer within connect_timeout_s)."""
        stub, delay, last = self._connect(), self.backoff_s, ""
        for attempt in range(self.retries + 1):
            try:
                return stub.GetPolicyMetadata(policy_pb2.PolicyMetadataRequest(), timeout=self.connect_timeout_s,
                                              metadata=self._call_metadata)
            except grpc.RpcError as err:
                if err.code() not in (grpc.StatusCode.UNAVAILABLE, grpc.StatusCode.DEADLINE_EXCEEDED):
                    raise PolicyServerError(f"{self.where}: GetPolicyMetadata: {_status(err)}") from None
                last = _status(err)
            if attempt < self.retries:
                time.sleep(delay)
                delay *= 2
        attempts = f"{self.retries + 1} attempt" + ("s" if self.retries else "")
        raise PolicyServerUnreachable(f"{self.where} does not answer after {attempts} ({last}); "
                                      "is it running there (e.g. culinarycut policy serve MODULE:CLASS --listen "
                                      f"{self.address})?")

    def preflight(self) -> None:
        """The runner's check before a run's first episode: the server answers with usable metadata."""
        try:
            self.metadata
        finally:
            self.close()

    def reset(self, instruction: str, info: dict[str, Any]) -> None:
        super().reset(instruction, info)
        metadata = self.metadata
        self._steps_per_action = action_steps(metadata.rate_hz, info.get("control_frequency_hz"), self.where)
        self._queue, self._answered_finished, self._step = [], False, 0
        self.episode_id = uuid.uuid4().hex
        request = policy_pb2.PolicyResetRequest(
            instruction=instruction, seed=int(info.get("seed") or 0),
            control_frequency_hz=float(info.get("control_frequency_hz") or 0.0),
            objects=[object_box_to_proto(box) for box in info.get("object_boxes", ())], episode_id=self.episode_id)
        if metadata.needs_session:  # the token goes only to a policy that plans on the simulator
            session = info.get("session")
            if session is None:
                raise PolicyServerError(f"{self.where}: the policy needs the simulator session (needs_session), "
                                        "and this episode has none")
            client = session.client
            request.session.CopyFrom(policy_pb2.SimulatorSession(
                address=client.address, session_id=session.session_id, token=getattr(client, "token", "") or "",
                tls=bool(getattr(client, "tls", False))))
        try:
            self._connect().ResetPolicy(request, timeout=self.query_timeout_s, metadata=self._call_metadata)
        except grpc.RpcError as err:
            raise PolicyServerError(f"{self.where}: ResetPolicy: {_status(err)}") from None

    def act(self, observation: dict[str, Any]) -> tuple[str, np.ndarray]:
        if not self._queue:
            self._query(observation)
        mode, values = self._queue.pop(0)
        self._step += 1
        if not self._queue and self._answered_finished:
            self.finished = True
        return mode, values

    def _query(self, observation: dict[str, Any]) -> None:
        started = time.perf_counter()
        request = policy_pb2.PolicyActRequest(observation=encode_observation(observation), step=self._step,
                                              episode_id=self.episode_id)
        try:
            response = self._connect().Act(request, timeout=self.query_timeout_s, metadata=self._call_metadata)
        except grpc.RpcError as err:
            raise PolicyServerError(f"{self.where}: Act: {_status(err)}") from None
        mode, actions = self.check_actions(response)
        self.latency.seconds.append(time.perf_counter() - started)
        steps = self._steps_per_action
        for action in actions:
            if steps > 1 and "delta" in mode:  # k equal parts of a delta, as control_rate.py
                self._queue += [(mode, action / steps)] * steps
            else:
                self._queue += [(mode, action)] * steps
        self._answered_finished = response.finished

    def check_actions(self, response: policy_pb2.PolicyActResponse) -> tuple[str, np.ndarray]:
        """(control mode, actions as [n, dim] float64) of an Act answer; PolicyServerError naming what is wrong."""
        metadata = self.metadata
        mode = response.control_mode or metadata.control_mode
        if mode not in ACTION_DIMS:
            raise PolicyServerError(f"{self.where}: Act answered control_mode {mode!r}, not one of "
                                    f"{', '.join(ACTION_DIMS)}")
        dim = metadata.action_dim if mode == metadata.control_mode else ACTION_DIMS[mode]
        tensor = response.actions
        if tensor.dtype not in ACTION_DTYPES:
            raise PolicyServerError(f"{self.where}: Act answered actions of dtype {tensor.dtype or '(none)'!r}; "
                                    "expected float32 or float64")
        try:
            actions = from_tensor(tensor, "actions")
        except TensorError as err:
            raise PolicyServerError(f"{self.where}: Act answered {err}") from None
        chunk = metadata.chunk_size
        if actions.ndim == 1 and actions.shape == (dim,):
            actions = actions[None]
        elif not (actions.ndim == 2 and actions.shape[1] == dim and 1 <= actions.shape[0] <= chunk):
            expected = f"[{dim}] or [n, {dim}] with 1 <= n <= chunk_size {chunk}" if chunk > 1 else \
                f"[{dim}] or [1, {dim}]"
            raise PolicyServerError(f"{self.where}: Act answered actions of shape {list(actions.shape)}; expected "
                                    f"{expected} ({mode} takes {dim} values)")
        bad = ~np.isfinite(actions)
        if bad.any():
            row, column = (int(i) for i in np.argwhere(bad)[0])
            raise PolicyServerError(f"{self.where}: Act answered a non-finite action value ({actions[row, column]} "
                                    f"at action {row}, value {column})")
        return mode, actions.astype(np.float64)

    def latency_summary(self) -> dict:
        return self.latency.summary()

    def close(self) -> None:
        if self._channel is not None:
            self._channel.close()
            self._channel = self._stub = None
