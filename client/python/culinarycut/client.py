"""Low-level synchronous client for the culinarycut.v1.Simulator gRPC service (and Tasks, as .tasks)."""
from __future__ import annotations

import os
from typing import Any, Mapping, Sequence

import grpc
import numpy as np
from google.protobuf import json_format

from culinarycut.errors import from_rpc_error
from culinarycut.tasks import TaskClient
from culinarycut.v1 import scene_pb2, simulator_pb2, simulator_pb2_grpc


def scene_to_proto(scene) -> scene_pb2.SceneSpec:
    """Accept a SceneSpec, a plain dict in proto-JSON form (camelCase or snake_case keys) or None.

    In a dict, `quality` may be an accuracy target instead of a preset name, e.g. {"force_error": 0.1}:
    it becomes SceneSpec.accuracy_target (docs/accuracy.md)."""
    if scene is None:
        return scene_pb2.SceneSpec()
    if isinstance(scene, scene_pb2.SceneSpec):
        return scene
    if isinstance(scene, Mapping):
        scene = dict(scene)
        if isinstance(scene.get("quality"), Mapping):
            scene["accuracy_target"] = scene.pop("quality")
        try:
            return json_format.ParseDict(scene, scene_pb2.SceneSpec())
        except json_format.ParseError as err:
            raise ValueError(f"scene: {err} (see proto/culinarycut/v1/scene.proto for the fields)") from None
    raise TypeError(f"scene must be a dict, SceneSpec or None, not {type(scene).__name__}")


def _f64(values) -> np.ndarray:
    return np.asarray(values, dtype=np.float64)


# Replies with camera images exceed gRPC's default 4 MB limit (three 640x480 RGB-D-segmentation views
# are 10 MB); the server caps a scene at 8 cameras of 2048 x 2048.
MAX_MESSAGE_BYTES = 512 * 1024 * 1024


def _decode_rgb(image: simulator_pb2.CameraImage) -> np.ndarray:
    if image.rgb_encoding in ("", "raw"):
        return np.frombuffer(image.rgb, dtype=np.uint8).reshape(image.height, image.width, 3)
    import cv2  # only for PNG / JPEG images (Debian: python3-opencv)
    bgr = cv2.imdecode(np.frombuffer(image.rgb, dtype=np.uint8), cv2.IMREAD_COLOR)
    if bgr is None or bgr.shape[:2] != (image.height, image.width):
        raise ValueError(f"camera {image.name!r}: the {image.rgb_encoding} image could not be decoded")
    return np.ascontiguousarray(bgr[:, :, ::-1])


def cameras_to_dict(obs: simulator_pb2.Observation) -> tuple[dict, dict]:
    """ManiSkill's sensor_data (rgb uint8 HxWx3, depth float32 HxWx1 in m, segmentation int32 HxWx1)
    and sensor_param (intrinsic_cv 3x3, extrinsic_cv 3x4, cam2world_gl 4x4) of each camera."""
    sensor_data, sensor_param = {}, {}
    for image in obs.cameras:
        data = {}
        if image.rgb:
            data["rgb"] = _decode_rgb(image)
        if image.depth:
            data["depth"] = np.frombuffer(image.depth, dtype="<f4").reshape(image.height, image.width, 1)
        if image.segmentation:
            data["segmentation"] = np.frombuffer(image.segmentation, dtype="<i4").reshape(image.height, image.width, 1)
        sensor_data[image.name] = data
        sensor_param[image.name] = {
            "intrinsic_cv": _f64(image.intrinsic_cv).reshape(3, 3),   # pixels
            "extrinsic_cv": _f64(image.extrinsic_cv).reshape(3, 4),   # world -> OpenCV camera, m
            "cam2world_gl": _f64(image.cam2world_gl).reshape(4, 4),   # OpenGL camera -> world, m
        }
    return sensor_data, sensor_param


def segmentation_labels_to_dict(obs: simulator_pb2.Observation) -> dict[int, dict[str, Any]]:
    """id -> {kind, object, piece, food} for the ids in this observation's segmentation images."""
    return {int(label.id): {"kind": label.kind, "object": int(label.object), "piece": int(label.piece),
                            "food": label.food} for label in obs.segmentation_labels}


def observation_to_dict(obs: simulator_pb2.Observation) -> dict[str, dict[str, Any]]:
    """Observation proto to a ManiSkill-style nested dict as the wire carries it: float64 arrays in SI
    units, plus sensor_data / sensor_param when the scene has cameras (CulinaryCutEnv converts these to
    ManiSkill's dtypes, see observation_conventions)."""
    result = _state_to_dict(obs)
    if len(obs.cameras):
        sensor_data, sensor_param = cameras_to_dict(obs)
        result["sensor_param"] = sensor_param  # ManiSkill's order: agent, extra, sensor_param, sensor_data
        result["sensor_data"] = sensor_data
    return result


def _state_to_dict(obs: simulator_pb2.Observation) -> dict[str, dict[str, np.ndarray]]:
    return {
        "agent": {
            "qpos": _f64(obs.agent.qpos),                # rad
            "qvel": _f64(obs.agent.qvel),                # rad/s
            "qpos_target": _f64(obs.agent.qpos_target),  # rad
        },
        "extra": {
            "tcp_pose": _f64(obs.tcp_pose),              # [m x3, quaternion wxyz]
            "tcp_velocity": _f64(obs.tcp_velocity),      # [m/s x3, rad/s x3]
            "flange_pose": _f64(obs.flange_pose),        # [m x3, quaternion wxyz]
            # food -> knife wrench at the flange, flange frame: [N x3, N m x3]; zeros without food
            "wrist_wrench": _f64(obs.wrist_wrench),
        },
    }


def food_to_dict(obs: simulator_pb2.Observation) -> dict[str, Any]:
    """The food part of an observation (variable length, so it travels in `info`, not in the spaces)."""
    return {
        "pieces": [{"object": int(p.object), "particles": int(p.particles), "volume": float(p.volume),  # m^3
                    "centroid": _f64(p.centroid), "bounds_min": _f64(p.bounds_min),  # m, world
                    "bounds_max": _f64(p.bounds_max)} for p in obs.food.pieces],
        "knife_contact": bool(obs.food.knife_contact),
        "mpm_awake": bool(obs.food.mpm_awake),
    }


def stamp_to_dict(stamp: simulator_pb2.FrameStamp) -> dict[str, Any]:
    return {"frame_id": int(stamp.frame_id), "sim_time": float(stamp.sim_time)}


def safety_step_to_dict(safety: simulator_pb2.SafetyStepInfo) -> dict[str, Any]:
    """What the safety limiter did this step (docs/safety.md); v_safe and the force are None when no food was near."""
    return {
        "acted": bool(safety.acted),                              # the step's joint target was shortened
        "guard_counts": {name: int(count) for name, count in sorted(safety.guard_counts.items())},
        "reason": safety.reason,
        "v_safe_m_s": float(safety.v_safe_m_s) if safety.assessed else None,
        "predicted_force_n": float(safety.predicted_force_n) if safety.assessed else None,
        "out_of_range": bool(safety.out_of_range),                # the force model extrapolated
        "commanded_speed_m_s": float(safety.commanded_speed_m_s),  # into the food, before the limit
        "target_scale": float(safety.target_scale),
    }


def step_info_to_dict(info: simulator_pb2.StepInfo) -> dict[str, Any]:
    """What the step did; the same on every run of the same seed and actions (wall times excluded).
    With the safety limiter on, "safety" holds what it did (safety_step_to_dict)."""
    fields = {
        "substeps": int(info.substeps),
        "action_clipped": bool(info.action_clipped),
        "ik_converged": bool(info.ik_converged),
        "ik_position_error": float(info.ik_position_error),        # m
        "ik_orientation_error": float(info.ik_orientation_error),  # rad
        "mpm_substeps": int(info.mpm_substeps),
        "first_contact": bool(info.first_contact),                 # the contact phase began
        "knife_stalled": bool(info.knife_stalled),                 # in the food, the arm at its effort limit
    }
    if info.HasField("safety"):
        fields["safety"] = safety_step_to_dict(info.safety)
    return fields


def step_timings_to_dict(info: simulator_pb2.StepInfo) -> dict[str, float]:
    """The server's wall-clock time for the step, by stage (ms); varies from run to run."""
    return {
        "step_wall_time_ms": float(info.step_wall_time_ms),
        "control_wall_time_ms": float(info.control_wall_time_ms),  # action -> joint targets (IK)
        "physics_wall_time_ms": float(info.physics_wall_time_ms),  # robot physics substeps
        "mpm_wall_time_ms": float(info.mpm_wall_time_ms),
        "topology_wall_time_ms": float(info.topology_wall_time_ms),
        "render_wall_time_ms": float(info.render_wall_time_ms),    # the scene's cameras
        "safety_wall_time_ms": float(info.safety_wall_time_ms),    # the safety limiter (0 with it off)
        "rollback_wall_time_ms": float(info.rollback_wall_time_ms),  # saving what a cancelled step puts back
    }


def _read_pem(path: str | None, what: str) -> bytes | None:
    if not path:
        return None
    try:
        with open(path, "rb") as file:
            return file.read()
    except OSError as err:
        raise ValueError(f"{what} {path}: {err.strerror}") from None


def _channel(address: str, tls_ca: str | None, tls_cert: str | None, tls_key: str | None,
             token: str | None, tls: bool = False) -> tuple[grpc.Channel, tuple]:
    """The channel, and the metadata every call sends on it (the bearer token, over TLS only). TLS when
    `tls` or any of the CA, the client certificate or the token is given."""
    options = [("grpc.max_receive_message_length", MAX_MESSAGE_BYTES)]
    if not (tls or tls_ca or tls_cert or token):
        return grpc.insecure_channel(address, options=options), ()
    if bool(tls_cert) != bool(tls_key):
        raise ValueError("a client certificate needs both tls_cert and tls_key")
    credentials = grpc.ssl_channel_credentials(root_certificates=_read_pem(tls_ca, "tls_ca"),
                                               private_key=_read_pem(tls_key, "tls_key"),
                                               certificate_chain=_read_pem(tls_cert, "tls_cert"))
    # The token as plain call metadata: what access_token_call_credentials sends, without its per-call
    # Python callback (which made a Step round trip about 20 % slower; docs/benchmarks/tls_overhead.md).
    metadata = (("authorization", f"Bearer {token}"),) if token else ()
    return grpc.secure_channel(address, credentials, options=options), metadata


class Client:
    """One channel to a CulinaryCut server; every call raises a CulinaryCutError on failure.

    Plaintext by default (a server on loopback). For a server started with --tls-cert and --token-file:
    `tls_ca` (PEM file of the CA that signed its certificate; None: the system's roots) and `token`;
    `tls_cert` and `tls_key` for a server that asks for client certificates. Unset, they come from
    CULINARYCUT_TLS_CA, CULINARYCUT_TOKEN, CULINARYCUT_TLS_CERT and CULINARYCUT_TLS_KEY. `tls=True`
    asks for TLS without any of them (the system's roots). `tls` and `token` say afterwards what the
    client connects with (a policy that plans on the server is given them: docs/policy_protocol.md).
    """

    def __init__(self, address: str = "127.0.0.1:50051", timeout_s: float = 30.0, *, tls_ca: str | None = None,
                 token: str | None = None, tls_cert: str | None = None, tls_key: str | None = None,
                 tls: bool = False):
        self.address = address
        self.timeout_s = timeout_s
        environ = os.environ
        tls_ca = tls_ca or environ.get("CULINARYCUT_TLS_CA")
        tls_cert = tls_cert or environ.get("CULINARYCUT_TLS_CERT")
        self.token = token or environ.get("CULINARYCUT_TOKEN") or ""
        self.tls = bool(tls or tls_ca or tls_cert or self.token)
        self._channel, self._metadata = _channel(address, tls_ca, tls_cert,
                                 tls_key or environ.get("CULINARYCUT_TLS_KEY"), self.token, tls)
        self._stub = simulator_pb2_grpc.SimulatorStub(self._channel)
        self.tasks = TaskClient(self._channel, timeout_s, self._metadata)  # the Tasks service on the same channel

    def _call(self, method, request):
        try:
            return method(request, timeout=self.timeout_s, metadata=self._metadata)
        except grpc.RpcError as err:
            raise from_rpc_error(err) from None  # the grpc traceback adds nothing for the caller

    def server_info(self) -> simulator_pb2.ServerInfo:
        return self._call(self._stub.GetServerInfo, simulator_pb2.GetServerInfoRequest())

    def create_session(self, scene=None) -> simulator_pb2.CreateSessionResponse:
        request = simulator_pb2.CreateSessionRequest(scene=scene_to_proto(scene))
        return self._call(self._stub.CreateSession, request)

    def reset(self, session_id: str, seed: int | None = None,
              initial_qpos: Sequence[float] | None = None) -> simulator_pb2.ResetResponse:
        request = simulator_pb2.ResetRequest(session_id=session_id)
        if seed is not None:
            request.seed.value = int(seed)  # UInt64Value wrapper: set means "use this seed"
        if initial_qpos is not None:
            request.initial_qpos.extend(_f64(initial_qpos).ravel().tolist())
        return self._call(self._stub.Reset, request)

    def step(self, session_id: str, control_mode: str | None,
             values: Sequence[float]) -> simulator_pb2.StepResponse:
        """One control step; control_mode None or "" means the session's default mode."""
        action = simulator_pb2.Action(control_mode=control_mode or "",
                                      values=_f64(values).ravel().tolist())
        return self._call(self._stub.Step, simulator_pb2.StepRequest(session_id=session_id, action=action))

    def observe(self, session_id: str) -> simulator_pb2.ObserveResponse:
        return self._call(self._stub.Observe, simulator_pb2.ObserveRequest(session_id=session_id))

    def close_session(self, session_id: str) -> simulator_pb2.CloseSessionResponse:
        return self._call(self._stub.CloseSession, simulator_pb2.CloseSessionRequest(session_id=session_id))

    def save_snapshot(self, session_id: str) -> bytes:
        response = self._call(self._stub.SaveSnapshot, simulator_pb2.SaveSnapshotRequest(session_id=session_id))
        return response.snapshot

    def restore_snapshot(self, session_id: str, snapshot: bytes) -> simulator_pb2.RestoreSnapshotResponse:
        request = simulator_pb2.RestoreSnapshotRequest(session_id=session_id, snapshot=snapshot)
        return self._call(self._stub.RestoreSnapshot, request)

    def session_stats(self, session_id: str) -> simulator_pb2.SessionStats:
        """What the session built and ran: MPM allocation, substep counts, stage times."""
        return self._call(self._stub.GetSessionStats, simulator_pb2.GetSessionStatsRequest(session_id=session_id))

    def close(self) -> None:
        self._channel.close()

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"Client(address={self.address!r}, timeout_s={self.timeout_s})"
