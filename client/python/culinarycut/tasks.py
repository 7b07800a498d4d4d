"""Client for the culinarycut.v1.Tasks service: instructions, cut specs, plans, scores and the oracle.

The logic runs on the server (sim/task, sim/policy in C++); these are thin typed wrappers that take
and return plain dicts and numpy arrays. Cut positions are fractions of the object's long axis from
its left end; "left" is the robot's left (+y in the world frame).
"""
from __future__ import annotations

from typing import Any, Mapping, Sequence

import grpc
import numpy as np
from google.protobuf import json_format

from culinarycut.errors import from_rpc_error
from culinarycut.v1 import scene_pb2, task_pb2, task_pb2_grpc

SPLITS = ("train", "held_out", "all")


def cut_spec_to_proto(spec) -> task_pb2.CutSpec:
    """A CutSpec proto from a dict such as {"style": "saw", "state": "ratio", "ratio": 0.3,
    "reference": "left", "target_object": "cucumber"} (unset fields take the server's defaults)."""
    if isinstance(spec, task_pb2.CutSpec):
        return spec
    if isinstance(spec, Mapping):
        try:
            return json_format.ParseDict(dict(spec), task_pb2.CutSpec())
        except json_format.ParseError as err:
            raise ValueError(f"spec: {err} (fields: style, state, ratio, split_pieces, "
                             "target_object, reference)") from None
    raise TypeError(f"spec must be a dict or CutSpec, not {type(spec).__name__}")


def cut_spec_to_dict(spec: task_pb2.CutSpec) -> dict[str, Any]:
    return {"style": spec.style, "state": spec.state, "ratio": float(spec.ratio),
            "split_pieces": int(spec.split_pieces), "target_object": spec.target_object,
            "reference": spec.reference}


def object_box_to_proto(box) -> task_pb2.ObjectBox:
    """An ObjectBox proto from {"name", "food", "position" [m], "quaternion" [w, x, y, z],
    "extent_m" [full side lengths along the box axes, m]}; quaternion defaults to identity."""
    if isinstance(box, task_pb2.ObjectBox):
        return box
    if not isinstance(box, Mapping):
        raise TypeError(f"object box must be a dict or ObjectBox, not {type(box).__name__}")
    unknown = set(box) - {"name", "food", "position", "quaternion", "extent_m"}
    if unknown:
        raise ValueError(f"object box: unknown keys {sorted(unknown)}; use name, food, position, "
                         "quaternion, extent_m")
    pose = scene_pb2.Pose(position=np.asarray(box.get("position", []), dtype=float).ravel().tolist(),
                          quaternion=np.asarray(box.get("quaternion", [1, 0, 0, 0]),
                                                dtype=float).ravel().tolist())
    return task_pb2.ObjectBox(name=box.get("name", ""), food=box.get("food", ""), pose=pose,
                              extent_m=np.asarray(box.get("extent_m", []), dtype=float).ravel().tolist())


def object_box_to_dict(box: task_pb2.ObjectBox) -> dict[str, Any]:
    """The inverse of object_box_to_proto: {"name", "food", "position", "quaternion", "extent_m"}."""
    return {"name": box.name, "food": box.food, "position": list(box.pose.position),
            "quaternion": list(box.pose.quaternion) or [1.0, 0.0, 0.0, 0.0], "extent_m": list(box.extent_m)}


def pose_to_proto(pose) -> scene_pb2.Pose:
    """[x, y, z, qw, qx, qy, qz] to a Pose proto."""
    pose = np.asarray(pose, dtype=float).ravel()
    if pose.size != 7:
        raise ValueError(f"pose must have 7 values [x, y, z, qw, qx, qy, qz], got {pose.size}")
    return scene_pb2.Pose(position=pose[:3].tolist(), quaternion=pose[3:].tolist())


def _planner_options(options) -> task_pb2.PlannerOptions:
    if options is None:
        return task_pb2.PlannerOptions()
    if isinstance(options, task_pb2.PlannerOptions):
        return options
    try:
        return json_format.ParseDict(dict(options), task_pb2.PlannerOptions())
    except json_format.ParseError as err:
        raise ValueError(f"planner options: {err} (see PlannerOptions in task.proto)") from None


def plan_to_dict(plan: task_pb2.CutPlan) -> dict[str, Any]:
    """A CutPlan as numpy arrays: time_s (N,), tcp_pose (N, 7), velocities (N, 3), phase (N,)."""
    samples = plan.samples
    return {
        "spec": cut_spec_to_dict(plan.spec),
        "target_name": plan.target_name,
        "duration_s": float(plan.duration_s),
        "cuts": [{"fraction_from_left": c.fraction_from_left,
                  "target_point_m": np.asarray(c.target_point_m),
                  "target_plane_normal": np.asarray(c.target_plane_normal),
                  "blade_plane_normal": np.asarray(c.blade_plane_normal),
                  "start_time_s": c.start_time_s, "end_time_s": c.end_time_s} for c in plan.cuts],
        "parameters": _fields(plan.parameters),
        "time_s": np.array([s.time_s for s in samples]),
        "tcp_pose": np.array([list(s.tcp_pose.position) + list(s.tcp_pose.quaternion)
                              for s in samples]).reshape(-1, 7),
        "linear_velocity_m_s": np.array([list(s.linear_velocity_m_s) for s in samples]).reshape(-1, 3),
        "angular_velocity_rad_s": np.array([list(s.angular_velocity_rad_s)
                                            for s in samples]).reshape(-1, 3),
        "phase": [s.phase for s in samples],
    }


def _fields(message) -> dict[str, Any]:
    """Every field of a flat message, defaults included (MessageToDict's option for that was
    renamed in protobuf 5.26, so it is not used)."""
    return {field.name: getattr(message, field.name) for field in message.DESCRIPTOR.fields}


def score_to_dict(score) -> dict[str, Any]:
    """A TaskScore (score_pb2) to a dict: success, cut counts, per required cut errors, summary."""
    result = _fields(score)
    result["required"] = [_fields(required) for required in score.required]
    return result


def _measured_cut(cut) -> task_pb2.MeasuredCut:
    if isinstance(cut, task_pb2.MeasuredCut):
        return cut
    return task_pb2.MeasuredCut(object_name=cut.get("object_name", ""),
                                plane_point_m=np.asarray(cut.get("plane_point_m", []), float).tolist(),
                                plane_normal=np.asarray(cut.get("plane_normal", []), float).tolist(),
                                blade_normal=np.asarray(cut.get("blade_normal", []), float).tolist())


class TaskClient:
    """Calls of the Tasks service over an existing channel (Client.tasks makes one for you)."""

    def __init__(self, channel: grpc.Channel, timeout_s: float = 30.0, metadata: tuple = ()):
        self._stub = task_pb2_grpc.TasksStub(channel)
        self.timeout_s = timeout_s
        self._metadata = metadata  # the bearer token, when the channel has one

    def _call(self, method, request):
        try:
            return method(request, timeout=self.timeout_s, metadata=self._metadata)
        except grpc.RpcError as err:
            raise from_rpc_error(err) from None

    def parse_instruction(self, instruction: str) -> dict[str, Any]:
        """Instruction text -> {"spec": dict, "description": str, "target_fractions": [..]}."""
        response = self._call(self._stub.ParseInstruction,
                              task_pb2.ParseInstructionRequest(instruction=instruction))
        return {"spec": cut_spec_to_dict(response.spec), "description": response.description,
                "target_fractions": list(response.target_fractions)}

    def generate_instructions(self, spec, seed: int = 0, count: int = 5,
                              split: str = "train") -> list[str]:
        if split not in SPLITS:
            raise ValueError(f"split must be one of {SPLITS}, got {split!r}")
        request = task_pb2.GenerateInstructionsRequest(spec=cut_spec_to_proto(spec), seed=int(seed),
                                                       count=int(count), split=split)
        return list(self._call(self._stub.GenerateInstructions, request).instructions)

    def plan_cut(self, target, start_tcp_pose: Sequence[float], *, instruction: str | None = None,
                 spec=None, options=None, seed: int = 0, sample_rate_hz: float = 20.0) -> dict[str, Any]:
        """Plan the knife trajectory for one object; give exactly one of instruction or spec."""
        request = task_pb2.PlanCutRequest(target=object_box_to_proto(target),
                                          start_tcp_pose=pose_to_proto(start_tcp_pose),
                                          options=_planner_options(options), seed=int(seed),
                                          sample_rate_hz=float(sample_rate_hz))
        _set_task(request, instruction, spec)
        return plan_to_dict(self._call(self._stub.PlanCut, request).plan)

    def score_cuts(self, spec, target, cuts: Sequence, tolerances: Mapping | None = None) -> dict[str, Any]:
        """Score measured cuts ({"object_name", "plane_point_m", "plane_normal"?, "blade_normal"?}) on target."""
        request = task_pb2.ScoreCutsRequest(spec=cut_spec_to_proto(spec), target=object_box_to_proto(target),
                                            cuts=[_measured_cut(c) for c in cuts])
        if tolerances:
            json_format.ParseDict(dict(tolerances), request.tolerances)
        return score_to_dict(self._call(self._stub.ScoreCuts, request).score)

    def start_oracle(self, session_id: str, objects: Sequence = (), *, instruction: str | None = None,
                     spec=None, target_name: str = "", control_mode: str = "", options=None,
                     seed: int | None = None, sample_rate_hz: float = 0.0) -> dict[str, Any]:
        request = task_pb2.StartOracleRequest(session_id=session_id,
                                              objects=[object_box_to_proto(o) for o in objects],
                                              target_name=target_name, control_mode=control_mode,
                                              options=_planner_options(options),
                                              sample_rate_hz=float(sample_rate_hz))
        if seed is not None:
            request.seed.value = int(seed)
        _set_task(request, instruction, spec, scene_task_allowed=True)
        return plan_to_dict(self._call(self._stub.StartOracle, request).plan)

    def oracle_action(self, session_id: str) -> task_pb2.OracleActionResponse:
        return self._call(self._stub.OracleAction, task_pb2.OracleActionRequest(session_id=session_id))


def _set_task(request, instruction: str | None, spec, scene_task_allowed: bool = False) -> None:
    if instruction is None and spec is None and scene_task_allowed:
        return  # the session's scene task
    if (instruction is None) == (spec is None):
        raise ValueError("give exactly one of instruction (text) or spec (dict)")
    if instruction is not None:
        request.instruction = instruction
    else:
        request.spec.CopyFrom(cut_spec_to_proto(spec))
