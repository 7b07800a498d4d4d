"""The policy protocol without a simulator: the tensor codec (every dtype, scalars, empty shapes, bad byte
counts), and GrpcPolicy against culinarycut.policy_server on loopback (chunks, the rate, finished, what
is refused, the session's token only for a policy that asks for it, TLS with a CA and a token)."""
from __future__ import annotations

import subprocess
from concurrent import futures
from pathlib import Path
from types import SimpleNamespace

import grpc
import numpy as np
import pytest

from culinarycut.policies.base import EpisodeSession, Policy
from culinarycut.policies.grpc_policy import GrpcPolicy, PolicyServerError, PolicyServerUnreachable, policy_address
from culinarycut.policy_server import PolicyServicer, serve
from culinarycut.policy_tensors import (DTYPES, TensorError, decode_observation, encode_observation, flatten,
                                        from_tensor, to_tensor, unflatten)
from culinarycut.v1 import policy_pb2, policy_pb2_grpc

OBSERVATION = {"agent": {"qpos": np.linspace(0, 1, 7, dtype=np.float32)},
               "extra": {"tcp_pose": np.arange(7, dtype=np.float32)},
               "sensor_data": {"front": {"rgb": np.full((4, 5, 3), 7, np.uint8),
                                         "depth": np.full((4, 5, 1), 300, np.int16)}}}


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("shape", [(), (0,), (3,), (2, 0, 4), (2, 3, 4)])
def test_every_dtype_and_shape_round_trips(dtype, shape):
    rng = np.random.default_rng(0)
    array = (rng.uniform(-100, 100, size=shape) if dtype.startswith("float") else
             rng.integers(0, 2 if dtype == "bool" else 100, size=shape)).astype(dtype)
    tensor = to_tensor(array)
    assert (tensor.dtype, list(tensor.shape)) == (dtype, list(shape))
    assert len(tensor.data) == array.size * array.dtype.itemsize
    back = from_tensor(policy_pb2.Tensor.FromString(tensor.SerializeToString()))
    assert back.dtype == array.dtype and back.shape == shape and np.array_equal(back, array)
    back.flags.writeable = True  # a copy the policy may change


def test_bytes_are_little_endian_c_order_and_numbers_become_arrays():
    tensor = to_tensor(np.array([[1, 2], [3, 4]], dtype=">i4").T)  # big-endian, Fortran order in memory
    assert tensor.data == np.array([1, 3, 2, 4], "<i4").tobytes()
    assert (to_tensor(2.5).dtype, list(to_tensor(2.5).shape)) == ("float64", [])
    assert from_tensor(to_tensor(True)).item() is True


def test_bad_tensors_are_refused_naming_the_key():
    with pytest.raises(TensorError, match=r"agent/qpos: 27 bytes, but a float32 tensor of shape \[7\] has 28"):
        from_tensor(policy_pb2.Tensor(dtype="float32", shape=[7], data=bytes(27)), "agent/qpos")
    with pytest.raises(TensorError, match="x: dtype 'complex64' is not one of"):
        from_tensor(policy_pb2.Tensor(dtype="complex64", shape=[1], data=bytes(8)), "x")
    with pytest.raises(TensorError, match="dtype float16 is not one the policy protocol carries"):
        to_tensor(np.zeros(2, np.float16))
    with pytest.raises(TensorError, match="a value and a level"):
        unflatten({"a": 1, "a/b": 2})
    with pytest.raises(TensorError, match="may not be empty or contain"):
        flatten({"a/b": 1})


def test_observations_flatten_with_slashes_skipping_what_is_not_numeric():
    observation = {**OBSERVATION, "instruction": "cut", "none": None, "extra": {**OBSERVATION["extra"],
                                                                               "pieces": [{"a": 1}], "n": 3}}
    flat = flatten(observation)
    assert sorted(flat) == ["agent/qpos", "extra/n", "extra/tcp_pose", "sensor_data/front/depth",
                            "sensor_data/front/rgb"]
    back = decode_observation(encode_observation(observation))
    assert back["sensor_data"]["front"]["depth"].dtype == np.int16
    assert np.array_equal(back["agent"]["qpos"], OBSERVATION["agent"]["qpos"]) and back["extra"]["n"] == 3


def test_policy_urls():
    assert policy_address("127.0.0.1:5") == ("127.0.0.1:5", False)
    assert policy_address("grpcs://host:443") == ("host:443", True)
    assert policy_address("[::1]:5") == ("[::1]:5", False)
    for bad in ("http://h:1", "host", "h:port", "grpc://h:1/path"):
        with pytest.raises(ValueError, match="expected HOST:PORT"):
            policy_address(bad)
    with pytest.raises(ValueError, match="sent over TLS only"):
        GrpcPolicy(url="h:1", token="secret")


@pytest.fixture
def served():
    """serve(...) -> a GrpcPolicy connected to it; servers stopped afterwards."""
    servers = []

    def start(policy, **metadata):
        server, port = serve(policy, metadata=metadata)
        servers.append(server)
        return GrpcPolicy(url=f"127.0.0.1:{port}", retries=0)
    yield start
    for server in servers:
        server.stop(0)


def play(policy: GrpcPolicy, steps: int, rate_hz: float = 20.0) -> list:
    policy.reset("cut the cucumber", {"seed": 1, "control_frequency_hz": rate_hz})
    return [policy.act(OBSERVATION) for _ in range(steps)]


def test_a_chunk_runs_step_by_step_and_finished_ends_after_it(served):
    class Counting(Policy):
        name, version, control_mode = "counting", "3", "pd_joint_pos"
        chunk_size = 4

        def act(self, observation):
            assert observation["sensor_data"]["front"]["rgb"].shape == (4, 5, 3)
            self.finished = True
            return self.control_mode, np.arange(28, dtype=np.float32).reshape(4, 7)
    policy = served(Counting())
    assert (policy.control_mode, policy.metadata.action_dim, policy.name, policy.version) == \
        ("pd_joint_pos", 7, "counting", "3")
    actions = play(policy, 1)
    while not policy.finished:
        actions.append(policy.act(OBSERVATION))
    assert len(actions) == 4 and policy.latency_summary()["queries"] == 1
    assert [a[1][0] for a in actions] == [0.0, 7.0, 14.0, 21.0] and actions[0][1].dtype == np.float64


def test_a_slower_policy_s_deltas_are_split_and_its_targets_held(served):
    delta = served(lambda observation, instruction: np.full(6, 0.6), rate_hz=10.0)
    assert [a[1][0] for a in play(delta, 4)] == pytest.approx([0.3] * 4)
    assert delta.latency_summary()["queries"] == 2
    absolute = served(lambda observation, instruction: ("pd_ee_pose_quat", np.array([0.5, 0, 0.3, 0, 1, 0, 0.])),
                      rate_hz=5.0)
    assert [a[1][0] for a in play(absolute, 4)] == [0.5] * 4 and absolute.latency_summary()["queries"] == 1
    with pytest.raises(PolicyServerError, match="rate 7 Hz does not divide the control rate 20 Hz"):
        play(served(lambda observation, instruction: np.zeros(6), rate_hz=7.0), 1)


@pytest.mark.parametrize("answer, message", [
    (np.zeros(5), r"actions of shape \[5\]; expected \[6\] or \[1, 6\]"),
    (np.zeros((2, 6)), r"actions of shape \[2, 6\]; expected \[6\] or \[1, 6\]"),
    (np.array([0, 0, np.nan, 0, 0, 0]), r"non-finite action value \(nan at action 0, value 2\)"),
    (("pd_warp", np.zeros(6)), "control_mode 'pd_warp', not one of"),
])
def test_bad_actions_are_refused_with_a_clear_error(served, answer, message):
    policy = served(lambda observation, instruction: answer)
    with pytest.raises(PolicyServerError, match=message):
        play(policy, 1)
    # What the helper never sends, another language's server might.
    for tensor, message in [(to_tensor(np.zeros(6, np.int32)), "dtype 'int32'; expected float32 or float64"),
                            (policy_pb2.Tensor(dtype="float32", shape=[6], data=bytes(20)),
                             r"actions: 20 bytes, but a float32 tensor of shape \[6\] has 24")]:
        with pytest.raises(PolicyServerError, match=message):
            policy.check_actions(policy_pb2.PolicyActResponse(actions=tensor))


def test_errors_keep_their_status_text(served):
    def refuse(observation, instruction):
        raise KeyError("sensor_data/wrist/rgb")
    with pytest.raises(PolicyServerError, match=r"Act: INTERNAL: act: KeyError: 'sensor_data/wrist/rgb'"):
        play(served(refuse), 1)
    policy = served(lambda observation, instruction: np.zeros(6))
    policy.reset("cut", {"seed": 0})
    policy.episode_id = "another"
    with pytest.raises(PolicyServerError, match="Act: FAILED_PRECONDITION: Act for episode 'another', which no "
                                                "ResetPolicy started"):
        policy.act(OBSERVATION)
    with pytest.raises(PolicyServerError, match="metadata cannot be used: action_dim 5, but pd_ee_delta_pose takes 6"):
        served(lambda observation, instruction: np.zeros(5), action_dim=5).cameras


def test_an_instance_serves_one_episode_at_a_time_a_class_several(served):
    class Remembering(Policy):
        def reset(self, instruction, info):
            super().reset(instruction, info)
            self.seed = info["seed"]

        def act(self, observation):
            return self.control_mode, np.full(6, self.seed / 10)
    first, second = served(Remembering), None
    second = GrpcPolicy(url=first.address)
    first.reset("cut", {"seed": 1})
    second.reset("cut", {"seed": 2})
    assert (first.act(OBSERVATION)[1][0], second.act(OBSERVATION)[1][0]) == (0.1, 0.2)
    one, other = served(Remembering()), None
    other = GrpcPolicy(url=one.address)
    one.reset("cut", {"seed": 1})
    other.reset("cut", {"seed": 2})
    with pytest.raises(PolicyServerError, match="holds one policy instance and was reset for another episode"):
        one.act(OBSERVATION)


class Recording(PolicyServicer):
    def ResetPolicy(self, request, context):
        self.request = request
        return super().ResetPolicy(request, context)


class Refusing(PolicyServicer):
    """A server in another language: it cannot read the observation it was sent."""

    def Act(self, request, context):
        context.abort(grpc.StatusCode.INVALID_ARGUMENT, "observation: no sensor_data/wrist/rgb (camera wrist)")


def started(servicer) -> tuple[grpc.Server, int]:
    server = grpc.server(futures.ThreadPoolExecutor(2))
    policy_pb2_grpc.add_PolicyServicer_to_server(servicer, server)
    port = server.add_insecure_port("127.0.0.1:0")
    server.start()
    return server, port


def test_an_act_error_keeps_its_status_and_text():
    server, port = started(Refusing(lambda observation, instruction: np.zeros(6)))
    try:
        with pytest.raises(PolicyServerError, match=r"^policy server 127.0.0.1:\d+: Act: INVALID_ARGUMENT: "
                                                    r"observation: no sensor_data/wrist/rgb \(camera wrist\)$"):
            play(GrpcPolicy(url=f"127.0.0.1:{port}"), 1)
    finally:
        server.stop(0)


@pytest.mark.parametrize("needs_session", [False, True])
def test_the_session_and_its_token_go_only_to_a_policy_that_asks(needs_session):
    class Planner(Policy):
        def reset(self, instruction, info):
            self.session = info.get("session")

        def act(self, observation):
            return self.control_mode, np.zeros(6)
    planner = Planner()
    planner.needs_session = needs_session
    servicer = Recording(planner)
    server, port = started(servicer)
    try:
        simulator = SimpleNamespace(address="sim.example:50051", token="secret", tls=True)
        boxes = [{"name": "cucumber_0", "food": "cucumber", "position": [0.5, 0, 0.04], "quaternion": [1, 0, 0, 0],
                  "extent_m": [0.19, 0.036, 0.038]}]
        GrpcPolicy(url=f"127.0.0.1:{port}").reset("cut", {"seed": 5, "control_frequency_hz": 20.0,
                                                           "session": EpisodeSession(simulator, "s-1"),
                                                           "object_boxes": boxes})
    finally:
        server.stop(0)
    request = servicer.request
    assert (request.seed, request.control_frequency_hz, request.objects[0].name) == (5, 20.0, "cucumber_0")
    assert list(request.objects[0].extent_m) == boxes[0]["extent_m"] and len(request.episode_id) == 32
    if needs_session:
        assert (request.session.address, request.session.session_id, request.session.token, request.session.tls) == \
            ("sim.example:50051", "s-1", "secret", True)
        assert planner.session.session_id == "s-1" and planner.session.client.tls
    else:
        assert not request.HasField("session") and planner.session is None


def test_a_server_that_does_not_listen_is_unreachable():
    policy = GrpcPolicy(url="127.0.0.1:9", retries=1, backoff_s=0.01)
    with pytest.raises(PolicyServerUnreachable, match="127.0.0.1:9 does not answer after 2 attempts"):
        policy.preflight()


class Authenticating(PolicyServicer):
    """Remembers the authorization metadata of the metadata call."""

    def GetPolicyMetadata(self, request, context):
        self.authorization = dict(context.invocation_metadata()).get("authorization")
        return super().GetPolicyMetadata(request, context)


def test_tls_with_the_runner_s_ca_and_a_token(tmp_path):
    pki = tmp_path / "pki"
    subprocess.run(["bash", str(Path(__file__).resolve().parents[1] / "support" / "make_test_pki.sh"), str(pki)],
                   check=True, timeout=120)
    servicer = Authenticating(lambda observation, instruction: np.full(6, 0.5))
    server = grpc.server(futures.ThreadPoolExecutor(2))
    policy_pb2_grpc.add_PolicyServicer_to_server(servicer, server)
    credentials = grpc.ssl_server_credentials([((pki / "server.key").read_bytes(), (pki / "server.pem").read_bytes())])
    port = server.add_secure_port("127.0.0.1:0", credentials)
    server.start()
    try:
        policy = GrpcPolicy(url=f"grpcs://127.0.0.1:{port}", tls_ca=str(pki / "ca.pem"), token="t" * 24)
        assert play(policy, 1)[0][1].tolist() == [0.5] * 6 and servicer.authorization == "Bearer " + "t" * 24
        with pytest.raises(PolicyServerUnreachable):  # plaintext to a TLS server
            GrpcPolicy(url=f"127.0.0.1:{port}", retries=0, connect_timeout_s=2).preflight()
    finally:
        server.stop(0)
