"""The two wire protocols over real loopback sockets: the real openpi-client against our stand-in websocket
server, our client against a server built from openpi-client's own serialisation, json-numpy requests
against the REST stand-in, and the error, health, API key and timeout behaviour of each."""
from __future__ import annotations

import asyncio
import http.client
import json
import socket
import threading
import time
import urllib.request

import json_numpy
import numpy as np
import pytest
import websockets.asyncio.server
import websockets.exceptions
import websockets.sync.client

import policy_support
from culinarycut_policies.standins.fake_models import FakeOpenVLA
from culinarycut_policies.standins.rest_server import JsonNumpyRestServer
from culinarycut_policies.standins.websocket_server import WebsocketPolicyServer
from culinarycut_policies.statistics import load_statistics
from culinarycut_policies.transports.faults import (PolicyServerError, PolicyServerUnreachable, Timeouts)
from culinarycut_policies.transports.json_numpy_rest import JsonNumpyRestClient
from culinarycut_policies.transports.openpi_websocket import OpenPIWebsocketClient

# openpi-client 0.1.2 opens its websocket the way websockets 17.1 deprecated (it still works).
pytestmark = pytest.mark.filterwarnings("ignore:connect\\(\\) must be used as a context manager:DeprecationWarning")

FAST = Timeouts(connect_s=2.0, query_s=2.0, retries=2, backoff_s=0.2)


def echo_model(observation: dict) -> dict:
    if observation.get("prompt") == "fail":
        raise RuntimeError("the model refused")
    return {"actions": np.full((3, 7), float(np.asarray(observation["state"]).sum()), dtype=np.float32)}


@pytest.fixture
def ws_server():
    server = WebsocketPolicyServer(echo_model, {"model_family": "echo", "action_horizon": 3}).start()
    yield server
    server.stop()


# --- openpi websocket ---------------------------------------------------------------------------------
def test_openpi_client_talks_to_our_server(ws_server):
    from openpi_client.websocket_client_policy import WebsocketClientPolicy
    client = WebsocketClientPolicy(ws_server.host, ws_server.port)
    assert client.get_server_metadata() == {"model_family": "echo", "action_horizon": 3}
    first = client.infer({"state": np.array([1.0, 2.0]), "prompt": "cut"})
    second = client.infer({"state": np.array([3.0]), "prompt": "cut"})
    np.testing.assert_array_equal(first["actions"], np.full((3, 7), 3.0, np.float32))
    assert first["actions"].dtype == np.float32 and second["actions"][0, 0] == 3.0
    assert set(first["server_timing"]) == {"infer_ms"}  # prev_total_ms only once there was a previous query
    assert set(second["server_timing"]) == {"infer_ms", "prev_total_ms"}
    with pytest.raises(RuntimeError, match="Error in inference server:\n(.|\n)*the model refused"):
        client.infer({"state": np.zeros(1), "prompt": "fail"})


def test_error_is_a_text_frame_then_close_1011(ws_server):
    with websockets.sync.client.connect(ws_server.url, compression=None, max_size=None) as ws:
        ws.recv()  # metadata
        from openpi_client import msgpack_numpy as upstream
        ws.send(upstream.packb({"state": np.zeros(1), "prompt": "fail"}))
        text = ws.recv(timeout=5)
        assert isinstance(text, str) and "RuntimeError: the model refused" in text
        with pytest.raises(websockets.exceptions.ConnectionClosed) as closed:
            ws.recv(timeout=5)
        assert closed.value.rcvd.code == 1011
    ours = OpenPIWebsocketClient(ws_server.url, FAST)
    ours.connect()
    with pytest.raises(PolicyServerError, match="the model refused"):
        ours.infer({"state": np.zeros(1), "prompt": "fail"})


def test_healthz_and_api_key():
    server = WebsocketPolicyServer(echo_model, {"model_family": "echo"}, api_key="s3cret").start()
    try:
        with urllib.request.urlopen(f"http://127.0.0.1:{server.port}/healthz", timeout=5) as reply:
            assert reply.status == 200 and reply.read() == b"OK\n"
        from openpi_client.websocket_client_policy import WebsocketClientPolicy
        upstream = WebsocketClientPolicy(server.host, server.port, api_key="s3cret")
        assert upstream.infer({"state": np.ones(2), "prompt": "x"})["actions"][0, 0] == 2.0
        with pytest.raises(PolicyServerError, match="HTTP 401 \\(option api_key\\)"):
            OpenPIWebsocketClient(server.url, FAST).connect()
        ours = OpenPIWebsocketClient(server.url, FAST, api_key="s3cret")
        assert ours.connect() == {"model_family": "echo"}
        assert ours.infer({"state": np.ones(4), "prompt": "x"})["actions"][0, 0] == 4.0
        summary = ours.latency.summary()
        assert summary["queries"] == 1 and 0 <= summary["server_infer_p50_ms"] <= summary["p50_ms"]
        ours.close()
    finally:
        server.stop()


def test_our_client_against_a_server_of_openpi_client_serialisation():
    """A server written the way openpi's websocket_policy_server.py is, with openpi-client's msgpack_numpy."""
    from openpi_client import msgpack_numpy as upstream
    ready, stop, port = threading.Event(), threading.Event(), []

    async def handler(ws):
        packer = upstream.Packer()
        await ws.send(packer.pack({"model_family": "upstream-serialised"}))
        async for frame in ws:
            obs = upstream.unpackb(frame)
            await ws.send(packer.pack({"actions": obs["observation/state"][None].repeat(2, 0),
                                       "echo": obs["prompt"], "scalar": np.float32(2.5)}))

    async def main():
        async with websockets.asyncio.server.serve(handler, "127.0.0.1", 0, compression=None, max_size=None) as srv:
            port.append(srv.sockets[0].getsockname()[1])
            ready.set()
            while not stop.is_set():
                await asyncio.sleep(0.02)

    thread = threading.Thread(target=lambda: asyncio.run(main()), daemon=True)
    thread.start()
    assert ready.wait(10)
    try:
        client = OpenPIWebsocketClient(f"ws://127.0.0.1:{port[0]}", FAST)
        assert client.connect() == {"model_family": "upstream-serialised"}
        reply = client.infer({"observation/state": np.arange(8, dtype=np.float32), "prompt": "cut"})
        assert reply["actions"].shape == (2, 8) and reply["actions"].dtype == np.float32
        assert reply["echo"] == "cut" and reply["scalar"] == 2.5 and isinstance(reply["scalar"], np.float32)
        assert client.latency.summary()["queries"] == 1
        client.close()
    finally:
        stop.set()
        thread.join(10)


def test_websocket_connect_retries_then_gives_up():
    with pytest.raises(PolicyServerUnreachable, match="no connection after 3 attempts"):
        started = time.monotonic()
        OpenPIWebsocketClient("ws://127.0.0.1:9", FAST).connect()
    assert time.monotonic() - started >= 0.2 + 0.4  # backoff 0.2 s, then doubled


# --- OpenVLA REST -------------------------------------------------------------------------------------
@pytest.fixture
def rest_server(tmp_path):
    path = policy_support.write_statistics(tmp_path)
    fake = FakeOpenVLA({policy_support.DELTA_KEY: load_statistics(path, policy_support.DELTA_KEY, policy="t")})
    server = JsonNumpyRestServer(fake).start()
    yield server, fake
    server.stop()


def post(url: str, body: bytes, method: str = "POST") -> tuple[int, bytes]:
    request = urllib.request.Request(url, data=body if method == "POST" else None, method=method,
                                     headers={"Content-Type": "application/json"})
    try:
        with urllib.request.urlopen(request, timeout=5) as reply:
            return reply.status, reply.read()
    except urllib.error.HTTPError as err:
        return err.code, err.read()


def test_json_numpy_request_as_deploy_py_documents(rest_server):
    server, fake = rest_server
    image = np.zeros((224, 224, 3), dtype=np.uint8)
    status, body = post(server.url + "/act", json_numpy.dumps(
        {"image": image, "instruction": "Cut The Apple", "unnorm_key": policy_support.DELTA_KEY}).encode())
    action = json_numpy.loads(body)
    assert status == 200 and isinstance(action, np.ndarray) and action.shape == (7,) and action.dtype == np.float64
    assert b'"__numpy__"' in body and fake.last_prompt == "In: What action should the robot take to cut the apple?\nOut:"
    # deploy.py's "double-encoded" form for clients without json-numpy: `encoded` must be the only key, and
    # the answer is JSONResponse(json_numpy.dumps(action)), a JSON string holding the json-numpy text.
    encoded = json_numpy.dumps({"image": image, "instruction": "Cut The Apple", "unnorm_key": policy_support.DELTA_KEY})
    status, body2 = post(server.url + "/act", json.dumps({"encoded": encoded}).encode())
    text = json.loads(body2)  # plain JSON: a client without json-numpy gets a string
    assert status == 200 and isinstance(text, str) and text.startswith('{"__numpy__"')
    np.testing.assert_array_equal(json_numpy.loads(text), action)
    assert post(server.url + "/act", json.dumps({"encoded": encoded, "extra": 1}).encode()) == (200, b'"error"')
    # our client reads a double-encoded answer too
    client = JsonNumpyRestClient(server.url, FAST)
    np.testing.assert_array_equal(client.query({"encoded": encoded}), action)
    client.close()


def test_failure_is_the_string_error_with_http_200(rest_server):
    server, _ = rest_server
    status, body = post(server.url + "/act", json_numpy.dumps(
        {"image": np.zeros((4, 4, 3), np.uint8), "instruction": "x", "unnorm_key": "bridge_orig"}).encode())
    assert (status, body) == (200, b'"error"')
    assert post(server.url + "/act", b"", method="GET")[0] == 405
    assert post(server.url + "/act", b"not json")[0] == post(server.url + "/act", b"[1, 2]")[0] == 422
    assert post(server.url + "/predict", b"{}")[0] == 404
    client = JsonNumpyRestClient(server.url, FAST)
    with pytest.raises(PolicyServerError, match='answered "error" \\(HTTP 200\\)'):
        client.query({"image": np.zeros((4, 4, 3), np.uint8), "instruction": "x", "unnorm_key": "bridge_orig"})
    assert server.errors == 2


def test_rest_query_timeout_and_reconnect(tmp_path):
    def slow(payload):
        time.sleep(float(payload["sleep"]))
        return np.zeros(7)
    server = JsonNumpyRestServer(slow).start()
    try:
        client = JsonNumpyRestClient(server.url, Timeouts(connect_s=2.0, query_s=0.3, retries=1, backoff_s=0.1))
        assert client.query({"sleep": 0.0}).shape == (7,)
        started = time.monotonic()
        with pytest.raises(TimeoutError, match="did not answer within 0.3 s \\(option query_timeout_s\\)"):
            client.query({"sleep": 1.0})
        assert time.monotonic() - started < 0.9
        assert client.query({"sleep": 0.0}).shape == (7,)  # a fresh connection after the timeout
        assert client.latency.summary()["queries"] == 2
    finally:
        server.stop()
    with pytest.raises(PolicyServerUnreachable, match="no connection after 3 attempts"):
        JsonNumpyRestClient(server.url, FAST).query({"sleep": 0.0})


class CountingHttpServer:
    """A raw HTTP/1.1 server on a real socket that counts the complete requests it reads and, per request,
    either answers (then closes the idle connection: a stale keep-alive for the client) or closes without
    answering (the model side died after receiving the query)."""

    def __init__(self, answer: bool):
        self.answer = answer
        self.requests = 0
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.url = f"http://127.0.0.1:{self.listener.getsockname()[1]}"
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self):
        while True:
            try:
                connection, _ = self.listener.accept()
            except OSError:
                return
            with connection:
                data = b""
                while b"\r\n\r\n" not in data:
                    data += connection.recv(65536)
                head, body = data.split(b"\r\n\r\n", 1)
                length = int(next(line.split(b":")[1] for line in head.split(b"\r\n")
                                  if line.lower().startswith(b"content-length")))
                while len(body) < length:
                    body += connection.recv(65536)
                self.requests += 1
                if self.answer:
                    reply = json_numpy.dumps(np.zeros(7)).encode()
                    connection.sendall(b"HTTP/1.1 200 OK\r\nContent-Type: application/json\r\nContent-Length: "
                                       + str(len(reply)).encode() + b"\r\n\r\n" + reply)
                    time.sleep(0.05)  # the reply is read; then the idle keep-alive connection is closed

    def close(self):
        self.listener.close()


def test_rest_query_that_was_sent_is_never_sent_again():
    server = CountingHttpServer(answer=False)
    try:
        client = JsonNumpyRestClient(server.url, FAST)
        with pytest.raises(PolicyServerUnreachable, match="after the query was sent \\(not sent again"):
            client.query({"x": np.zeros(3)})
        time.sleep(0.1)
        assert server.requests == 1
    finally:
        server.close()


def test_rest_stale_keep_alive_is_reopened_before_sending():
    server = CountingHttpServer(answer=True)
    try:
        client = JsonNumpyRestClient(server.url, FAST)
        client.query({"x": np.zeros(3)})
        time.sleep(0.2)  # the server has closed the idle connection
        assert client.query({"x": np.zeros(3)}).shape == (7,)
        assert server.requests == 2  # one per query: the stale connection was noticed before sending
    finally:
        server.close()


def test_url_errors_name_the_option():
    with pytest.raises(ValueError, match="option url='ws://h:1': expected http://HOST:PORT"):
        JsonNumpyRestClient("ws://h:1")
    with pytest.raises(ValueError, match="option url='http://h:1': expected ws://HOST:PORT"):
        OpenPIWebsocketClient("http://h:1")


def test_keep_alive_connection_is_reused(rest_server):
    server, _ = rest_server
    client = JsonNumpyRestClient(server.url, FAST)
    payload = {"image": np.zeros((8, 8, 3), np.uint8), "instruction": "x", "unnorm_key": policy_support.DELTA_KEY}
    client.query(payload)
    connection = client._connection
    client.query(payload)
    assert client._connection is connection and isinstance(connection, http.client.HTTPConnection)


def test_adapters_check_the_server_metadata(tmp_path):
    from culinarycut_policies.octo import OctoPolicy
    from culinarycut_policies.rdt import RDTPolicy
    statistics = policy_support.write_statistics(tmp_path)
    aloha = WebsocketPolicyServer(echo_model, {"model_family": "octo", "window": 2, "action_horizon": 50}).start()
    try:
        octo = OctoPolicy(url=aloha.url, statistics=statistics, unnorm_key=policy_support.DELTA_KEY)
        with pytest.raises(PolicyServerError, match="has action_horizon 50; set option action_horizon=50"):
            octo.reset("cut", {})
        octo.close()
        rdt = RDTPolicy(url=aloha.url)
        with pytest.raises(PolicyServerError, match="policy rdt: the server at .* serves .octo., not .rdt."):
            rdt.reset("cut", {})
        rdt.close()
    finally:
        aloha.stop()
    unnormalising = WebsocketPolicyServer(echo_model, {"model_family": "octo", "normalized_actions": False}).start()
    try:
        octo = OctoPolicy(url=unnormalising.url, statistics=statistics)
        with pytest.raises(PolicyServerError, match="answers un-normalised actions \\(normalized_actions false"):
            octo.reset("cut", {})
        octo.close()
    finally:
        unnormalising.stop()
    short = WebsocketPolicyServer(echo_model, {"model_family": "rdt", "action_horizon": 32}).start()
    try:
        rdt = RDTPolicy(url=short.url, execute_steps=48)
        with pytest.raises(PolicyServerError, match="execute_steps=48 exceeds the action_horizon 32 .*<=32"):
            rdt.reset("cut", {})
        rdt.close()
        rdt = RDTPolicy(url=short.url, execute_steps=32)
        rdt.reset("cut", {})  # within the server's chunk: accepted
        rdt.close()
    finally:
        short.stop()


# --- adapters over the wire, on a synthetic observation -----------------------------------------------
TCP_QUATERNION = np.array([0.9, 0.1, 0.3, 0.2]) / np.linalg.norm([0.9, 0.1, 0.3, 0.2])  # R is not symmetric


def observation(seed: int = 0) -> dict:
    rng = np.random.Generator(np.random.PCG64(seed))
    return {"sensor_data": {"front": {"rgb": rng.integers(0, 256, (60, 80, 3), dtype=np.uint8)},
                            "wrist": {"rgb": rng.integers(0, 256, (60, 80, 3), dtype=np.uint8)}},
            "extra": {"tcp_pose": np.array([0.45, -0.05, 0.25, *TCP_QUATERNION], np.float32)},
            "agent": {"qpos": np.linspace(-1, 1, 7).astype(np.float32)}}


def test_openvla_executes_the_servers_action_and_refuses_one_outside_the_statistics(tmp_path):
    from culinarycut_policies.openvla import OpenVLAPolicy
    statistics = policy_support.write_statistics(tmp_path)
    answer = {"action": np.array([0.005, -0.004, 0.0, 0.01, -0.02, 0.015, 0.3])}
    server = JsonNumpyRestServer(lambda payload: answer["action"]).start()
    try:
        policy = OpenVLAPolicy(url=server.url, statistics=statistics, unnorm_key=policy_support.DELTA_KEY)
        policy.reset("cut", {})
        mode, values = policy.act(observation())
        assert mode == "pd_ee_delta_pose"
        np.testing.assert_allclose(values, [0.05, -0.04, 0.0, 0.1, -0.2, 0.15])
        answer["action"] = np.array([0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5])  # normalised: no statistics applied
        with pytest.raises(PolicyServerError, match=r"action dimensions \[0, 1, 2, 3, 4, 5\] .* lie outside"):
            policy.act(observation())
        policy.close()
    finally:
        server.stop()


def test_octo_unnormalises_mean_std_and_ensembles_over_the_wire(tmp_path):
    from culinarycut_policies.octo import OctoPolicy
    statistics = policy_support.write_statistics(tmp_path)
    chunks = iter([np.full((1, 4, 7), 1.0, np.float32), np.full((1, 4, 7), -1.0, np.float32)])
    server = WebsocketPolicyServer(lambda request: {"actions": next(chunks)}, {"model_family": "octo"}).start()
    try:
        policy = OctoPolicy(url=server.url, statistics=statistics, unnorm_key=policy_support.DELTA_KEY)
        policy.reset("cut", {})
        action = policy.stats.action
        _, first = policy.act(observation())
        np.testing.assert_allclose(first, ((action.mean + action.std) / 0.1)[:6], rtol=1e-6)
        _, second = policy.act(observation(1))  # the mean of +1 and -1 predictions: the dataset mean
        np.testing.assert_allclose(second, (action.mean / 0.1)[:6], rtol=1e-6, atol=1e-12)
        policy.close()
    finally:
        server.stop()


def test_rdt_min_max_normalisation_over_the_wire(tmp_path):
    from culinarycut_policies.rdt import RDTPolicy
    from culinarycut_policies.rotation import quat_wxyz_to_matrix
    statistics = policy_support.write_statistics(tmp_path)
    seen = {}

    def model(request):
        seen.update(request)
        target = np.array(request["state"], dtype=np.float32)
        target[0, 0, 30] = 0.0  # x to the middle of its [-0.9, 0.9] m bounds
        return {"actions": np.repeat(target, 64, axis=1)}

    server = WebsocketPolicyServer(model, {"model_family": "rdt"}).start()
    try:
        policy = RDTPolicy(url=server.url, statistics=statistics, unnorm_key=policy_support.RDT_KEY,
                           control_frequency=20, normalization="bounds")
        policy.reset("cut", {})
        mode, target = policy.act(observation())
        policy.close()
    finally:
        server.stop()
    state = seen["state"][0, 0]
    # The test statistics' min/max: z in [-0.15, 1.8] m, so 0.25 m -> 2 (0.4 / 1.95) - 1; the 6-D rotation
    # (R's first two columns) in [-1.5, 1.5] -> v / 1.5.
    np.testing.assert_allclose(state[32], 2 * 0.4 / 1.95 - 1, rtol=1e-6)
    rotation = quat_wxyz_to_matrix(TCP_QUATERNION)
    np.testing.assert_allclose(state[33:39], np.concatenate([rotation[:, 0], rotation[:, 1]]) / 1.5, atol=1e-6)
    assert np.count_nonzero(seen["state_elem_mask"]) == 16 and seen["ctrl_freq"] == 20.0
    assert mode == "pd_ee_pose_quat"
    np.testing.assert_allclose(target[:3], [0.0, -0.05, 0.25], atol=1e-6)
    np.testing.assert_allclose(target[3:], TCP_QUATERNION, atol=1e-6)  # the pose it was sent comes back


def test_rdt_sends_and_executes_raw_values_as_its_hdf5_fine_tune_trains_on_them():
    from culinarycut_policies.rdt import RDTPolicy
    from culinarycut_policies.rotation import quat_wxyz_to_matrix
    seen = {}

    def model(request):
        seen.update(request)
        target = np.array(request["state"], dtype=np.float32)
        target[0, 0, 30] = 0.4  # right_eef_pos_x: an absolute position in metres
        return {"actions": np.repeat(target, 64, axis=1)}

    server = WebsocketPolicyServer(model, {"model_family": "rdt"}).start()
    try:
        policy = RDTPolicy(url=server.url)  # normalization=none, no statistics
        policy.reset("cut", {})
        mode, target = policy.act(observation())
        policy.close()
    finally:
        server.stop()
    # data/hdf5_vla_dataset.py fill_in_state: zeros, the raw qpos at its unified indices, the indicator 1 there.
    rotation = quat_wxyz_to_matrix(TCP_QUATERNION)
    expected = np.zeros(128)
    expected[list(range(7))] = np.linspace(-1, 1, 7)
    expected[[30, 31, 32]] = [0.45, -0.05, 0.25]
    expected[33:39] = np.concatenate([rotation[:, 0], rotation[:, 1]])
    np.testing.assert_allclose(seen["state"][0, 0], expected, atol=1e-6)
    np.testing.assert_array_equal(np.flatnonzero(seen["state_elem_mask"][0]), [0, 1, 2, 3, 4, 5, 6, 30, 31, 32,
                                                                               33, 34, 35, 36, 37, 38])
    assert mode == "pd_ee_pose_quat"
    np.testing.assert_allclose(target[:3], [0.4, -0.05, 0.25], atol=1e-6)
    np.testing.assert_allclose(target[3:], TCP_QUATERNION, atol=1e-6)
    with pytest.raises(ValueError, match="statistics and unnorm_key are read only with normalization=bounds"):
        RDTPolicy(statistics="stats.json")
    with pytest.raises(ValueError, match="normalization must be one of"):
        RDTPolicy(normalization="minmax")


def test_rdt_images_are_jpeg_round_tripped_and_t_minus_1_is_the_previous_step():
    from culinarycut_policies.images import jpeg_roundtrip, pad_square_resize
    from culinarycut_policies.rdt import RDTPolicy
    requests = []

    def model(request):
        requests.append(request)
        return {"actions": np.repeat(np.asarray(request["state"], dtype=np.float32), 64, axis=1)}

    server = WebsocketPolicyServer(model, {"model_family": "rdt", "action_horizon": 64}).start()
    try:
        policy = RDTPolicy(url=server.url, execute_steps=2)
        policy.reset("cut", {})
        frames = [observation(seed) for seed in range(4)]
        for frame in frames:
            policy.act(frame)
        policy.close()
    finally:
        server.stop()

    def expected(step, camera):  # agilex_inference.py's jpeg_mapping, then expand2square and the 384 resize
        return pad_square_resize(jpeg_roundtrip(frames[step]["sensor_data"][camera]["rgb"]), 384)

    assert len(requests) == 2  # steps 0 and 2; step 1 only keeps its raw frames
    first, second = requests[0]["images"], requests[1]["images"]
    assert first[:3] == [None, None, None] and first[5] is None and second[2] is None and second[5] is None
    for got, (step, camera) in ((first[3], (0, "front")), (first[4], (0, "wrist")), (second[0], (1, "front")),
                                (second[1], (1, "wrist")), (second[3], (2, "front")), (second[4], (2, "wrist"))):
        np.testing.assert_array_equal(got, expected(step, camera))
    without_jpeg = pad_square_resize(frames[2]["sensor_data"]["front"]["rgb"], 384)
    assert np.abs(second[3].astype(int) - without_jpeg).max() > 8  # the round trip changes noisy frames


def test_rest_reopens_a_keep_alive_connection_the_server_closed():
    """uvicorn closes idle keep-alive connections after 5 s: the next query must open a new one."""
    import socket
    listener = socket.create_server(("127.0.0.1", 0))
    accepted = []

    def serve_two_then_stop():
        for _ in range(2):
            connection, _ = listener.accept()
            accepted.append(connection)
            request = b""
            while b"\r\n\r\n" not in request:
                request += connection.recv(65536)
            head, _, body = request.partition(b"\r\n\r\n")
            length = int(next(line.split(b":")[1] for line in head.split(b"\r\n")
                              if line.lower().startswith(b"content-length")))
            while len(body) < length:
                body += connection.recv(65536)
            answer = json_numpy.dumps(np.arange(7.0)).encode()
            connection.sendall(b"HTTP/1.1 200 OK\r\nContent-Type: application/json\r\nContent-Length: %d\r\n\r\n%s"
                               % (len(answer), answer))
            connection.close()  # no "Connection: close": the client still thinks it may reuse it

    thread = threading.Thread(target=serve_two_then_stop, daemon=True)
    thread.start()
    client = JsonNumpyRestClient(f"http://127.0.0.1:{listener.getsockname()[1]}", FAST)
    try:
        for _ in range(2):
            np.testing.assert_array_equal(client.query({"image": np.zeros((2, 2, 3), np.uint8)}), np.arange(7.0))
    finally:
        client.close()
        listener.close()
    thread.join(5)
    assert len(accepted) == 2 and client.latency.summary()["queries"] == 2
