"""Serve any Python policy over the policy protocol (culinarycut.v1.Policy; docs/policy_protocol.md), so the
benchmark runner drives it with `--policy grpc --policy-url HOST:PORT` from anywhere:

    server, port = serve(MyPolicy, address="0.0.0.0:50061")   # or: culinarycut policy serve my_module:MyPolicy
    server.wait_for_termination()

What is served:
- a `Policy` subclass (culinarycut.policies.Policy, or any class with reset/act): one instance per episode,
  made with `options`, so the episodes a runner plays at once keep apart;
- a policy instance: one episode at a time (a ResetPolicy for another episode replaces the one before; the
  replaced episode's Act is refused with FAILED_PRECONDITION);
- a plain callable `act(observation, instruction) -> actions` (or `-> (control_mode, actions)`).

Observations arrive as the nested dict of numpy arrays the runner's observation was (culinarycut.policy_tensors
unflattens them); ResetPolicy's `info` holds seed, control_frequency_hz, object_boxes (dicts as
culinarycut.tasks.object_box_to_proto takes them) and, for a policy whose metadata sets needs_session, the
episode's `session` (an EpisodeSession with a Client connected to the simulator with the address, token and
TLS the runner sent): what the runner's own info holds, so a Policy runs the same served or in-process.

The metadata comes from the policy's attributes (name, version, control_mode, cameras, needs_session and,
where set, action_dim, chunk_size, rate_hz); `metadata` overrides any of them.
"""
from __future__ import annotations

import threading
from collections import OrderedDict
from concurrent import futures
from dataclasses import dataclass
from typing import Any, Callable, Mapping

import grpc
import numpy as np

from culinarycut.client import Client
from culinarycut.errors import CulinaryCutError
from culinarycut.policies.base import ACTION_DIMS, EpisodeSession
from culinarycut.policy_tensors import TensorError, decode_observation, to_tensor
from culinarycut.tasks import object_box_to_dict
from culinarycut.v1 import policy_pb2, policy_pb2_grpc

SERVER_OPTIONS = [("grpc.max_receive_message_length", 512 * 1024 * 1024),
                  ("grpc.max_send_message_length", 512 * 1024 * 1024)]
MAX_EPISODES = 64         # episodes kept at once (a runner's workers); the oldest goes first
SESSION_TIMEOUT_S = 120.0  # per call of a needs_session policy to the simulator


def _is_policy_class(target: Any) -> bool:
    return isinstance(target, type) and callable(getattr(target, "act", None))


def _is_policy_instance(target: Any) -> bool:
    return not isinstance(target, type) and callable(getattr(target, "act", None)) and \
        callable(getattr(target, "reset", None))


def _camera(camera: Any) -> policy_pb2.PolicyCamera:
    """A PolicyCamera of a scene camera request ({"name", "width", "height", ...}), a name or a PolicyCamera."""
    if isinstance(camera, policy_pb2.PolicyCamera):
        return camera
    if isinstance(camera, str):
        return policy_pb2.PolicyCamera(name=camera)
    return policy_pb2.PolicyCamera(name=camera["name"], width=int(camera.get("width", 0) or 0),
                                   height=int(camera.get("height", 0) or 0))


def policy_metadata(policy: Any, overrides: Mapping[str, Any] | policy_pb2.PolicyMetadata | None = None
                    ) -> policy_pb2.PolicyMetadata:
    """The PolicyMetadata of a policy (instance) or callable, with `overrides` (its fields by name) applied."""
    if isinstance(overrides, policy_pb2.PolicyMetadata):
        return overrides
    fields: dict[str, Any] = {"name": getattr(policy, "name", getattr(policy, "__name__", "policy")),
                              "version": str(getattr(policy, "version", "0")),
                              "control_mode": getattr(policy, "control_mode", "pd_ee_delta_pose"),
                              "cameras": list(getattr(policy, "cameras", ())),
                              "needs_session": bool(getattr(policy, "needs_session", False))}
    for optional in ("action_dim", "chunk_size", "rate_hz"):
        if getattr(policy, optional, None) is not None:
            fields[optional] = getattr(policy, optional)
    fields.update(dict(overrides or {}))
    unknown = set(fields) - set(policy_pb2.PolicyMetadata.DESCRIPTOR.fields_by_name)
    if unknown:
        raise ValueError(f"metadata: unknown fields {sorted(unknown)}; PolicyMetadata has "
                         f"{', '.join(policy_pb2.PolicyMetadata.DESCRIPTOR.fields_by_name)}")
    fields["cameras"] = [_camera(c) for c in fields["cameras"]]
    fields.setdefault("action_dim", ACTION_DIMS.get(fields["control_mode"], 0))
    return policy_pb2.PolicyMetadata(**fields)


@dataclass
class _Episode:
    policy: Any                   # the Policy instance, or None for a callable
    instruction: str
    client: Client | None         # the simulator connection of a needs_session policy
    lock: threading.Lock


class PolicyServicer(policy_pb2_grpc.PolicyServicer):
    """The Policy service over one policy class, instance or callable (see the module's docstring)."""

    def __init__(self, policy: Any, metadata: Mapping[str, Any] | policy_pb2.PolicyMetadata | None = None,
                 options: Mapping[str, Any] | None = None):
        self.options = dict(options or {})
        if _is_policy_class(policy):
            self.kind, self.factory = "class", lambda: policy(**self.options)
            probe = self.factory()  # bad options fail here, and its attributes give the metadata
        elif _is_policy_instance(policy):
            self.kind, probe = "instance", policy
        elif callable(policy):
            self.kind, probe = "callable", policy
        else:
            raise TypeError(f"cannot serve {policy!r}: give a Policy class or instance, or a callable "
                            "act(observation, instruction) -> actions")
        if self.options and self.kind != "class":
            raise ValueError(f"options {sorted(self.options)} need a policy class to make instances with")
        self.target = policy
        self.metadata = policy_metadata(probe, metadata)
        self._episodes: OrderedDict[str, _Episode] = OrderedDict()
        self._lock = threading.Lock()

    # --- the three calls ---
    def GetPolicyMetadata(self, request, context):
        return self.metadata

    def ResetPolicy(self, request, context):
        info: dict[str, Any] = {"seed": int(request.seed),
                                "control_frequency_hz": request.control_frequency_hz or None,
                                "object_boxes": [object_box_to_dict(box) for box in request.objects]}
        client = None
        if self.metadata.needs_session:
            if not request.HasField("session") or not request.session.session_id:
                context.abort(grpc.StatusCode.INVALID_ARGUMENT, "ResetPolicy: this policy plans on the simulator "
                              "(needs_session) and the request carries no session")
            session = request.session
            client = Client(session.address, timeout_s=SESSION_TIMEOUT_S, token=session.token or None,
                            tls=session.tls)
            info["session"] = EpisodeSession(client, session.session_id)
        policy = self.factory() if self.kind == "class" else self.target if self.kind == "instance" else None
        episode = _Episode(policy, request.instruction, client, threading.Lock())
        with self._lock:
            if self.kind == "instance":  # one instance plays one episode at a time
                for old in self._episodes.values():
                    _close(old, keep_policy=True)
                self._episodes.clear()
            self._episodes[request.episode_id] = episode
            while len(self._episodes) > MAX_EPISODES:
                _close(self._episodes.popitem(last=False)[1], keep_policy=False)
        if policy is not None:
            with episode.lock:
                self._run(context, "reset", lambda: policy.reset(request.instruction, info))
        return policy_pb2.PolicyResetResponse()

    def Act(self, request, context):
        with self._lock:
            episode = self._episodes.get(request.episode_id)
        if episode is None:
            why = " (this server holds one policy instance and was reset for another episode since; serve the " \
                  "policy's class to play episodes at once)" if self.kind == "instance" else ""
            context.abort(grpc.StatusCode.FAILED_PRECONDITION,
                          f"Act for episode {request.episode_id!r}, which no ResetPolicy started{why}")
        try:
            observation = decode_observation(request.observation)
        except TensorError as err:
            context.abort(grpc.StatusCode.INVALID_ARGUMENT, f"observation {err}")
        with episode.lock:
            if episode.policy is None:
                answer = self._run(context, "act", lambda: self.target(observation, episode.instruction))
                finished = False
            else:
                answer = self._run(context, "act", lambda: episode.policy.act(observation))
                finished = bool(getattr(episode.policy, "finished", False))
        mode, actions = answer if isinstance(answer, tuple) else (self.metadata.control_mode, answer)
        actions = np.asarray(actions)
        if actions.dtype.name not in ("float32", "float64"):
            actions = actions.astype(np.float64)
        if finished:
            self._forget(request.episode_id)
        return policy_pb2.PolicyActResponse(actions=to_tensor(actions, "actions"), finished=finished,
                                            control_mode="" if mode == self.metadata.control_mode else mode)

    # --- helpers ---
    @staticmethod
    def _run(context, what: str, call: Callable):
        """call(); a policy's exception becomes INTERNAL (a simulator error keeps its status) with its text."""
        try:
            return call()
        except CulinaryCutError as err:
            context.abort(err.code, f"{what}: simulator: {err.details}")
        except Exception as err:  # the policy's own fault, reported to the runner as this episode's policy_error
            context.abort(grpc.StatusCode.INTERNAL, f"{what}: {type(err).__name__}: {err}")

    def _forget(self, episode_id: str) -> None:
        with self._lock:
            episode = self._episodes.pop(episode_id, None)
        if episode is not None:
            _close(episode, keep_policy=self.kind == "instance")

    def close(self) -> None:
        with self._lock:
            episodes, self._episodes = list(self._episodes.values()), OrderedDict()
        for episode in episodes:
            _close(episode, keep_policy=self.kind == "instance")


def _close(episode: _Episode, keep_policy: bool) -> None:
    """Closes an episode's simulator connection and, unless it is the served instance, its policy."""
    if episode.client is not None:
        episode.client.close()
    close = getattr(episode.policy, "close", None)
    if close is not None and not keep_policy:
        try:
            close()
        except Exception:  # already gone: nothing left to close
            pass


def serve(policy: Any, address: str = "127.0.0.1:0", metadata: Mapping[str, Any] | None = None,
          options: Mapping[str, Any] | None = None, *, max_workers: int = 8, tls_cert: str | None = None,
          tls_key: str | None = None) -> tuple[grpc.Server, int]:
    """Starts a gRPC server of the Policy service for `policy` on `address` (port 0: a free one) and returns
    (server, port); stop it with server.stop(grace). `options`: the constructor's, for a policy class;
    `metadata`: PolicyMetadata fields that override the policy's attributes; tls_cert and tls_key (PEM files):
    serve TLS (the runner connects with grpcs://HOST:PORT)."""
    servicer = PolicyServicer(policy, metadata, options)
    server = grpc.server(futures.ThreadPoolExecutor(max_workers=max_workers, thread_name_prefix="policy"),
                         options=SERVER_OPTIONS)
    policy_pb2_grpc.add_PolicyServicer_to_server(servicer, server)
    if bool(tls_cert) != bool(tls_key):
        raise ValueError("a TLS policy server needs both tls_cert and tls_key")
    if tls_cert:
        with open(tls_cert, "rb") as cert, open(tls_key, "rb") as key:
            credentials = grpc.ssl_server_credentials([(key.read(), cert.read())])
        port = server.add_secure_port(address, credentials)
    else:
        port = server.add_insecure_port(address)
    if port == 0:
        raise OSError(f"cannot listen on {address}")
    server.start()
    server.servicer = servicer  # for close() and tests
    return server, port


__all__ = ["PolicyServicer", "policy_metadata", "serve"]
