"""The Tasks service through the Python client: parse, generate, plan, score, oracle, paraphrase."""
from __future__ import annotations

import json
import threading
from http.server import BaseHTTPRequestHandler, HTTPServer

import numpy as np
import pytest

from culinarycut import errors
from culinarycut.cli import main as cli_main
from culinarycut.geometry import quat_rotate
from culinarycut.paraphrase import ParaphraseError, paraphrase
from culinarycut.policies import ScriptedOracle

CUCUMBER = {"name": "cucumber_0", "food": "cucumber", "position": [0.5, 0.02, 0.04],
            "quaternion": [np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)], "extent_m": [0.2, 0.04, 0.04]}
APPLE = {"name": "apple_0", "food": "apple", "position": [0.45, -0.12, 0.06], "extent_m": [0.08, 0.08, 0.08]}
KNIFE_START = [0.45, 0.0, 0.3, 0.0, 1.0, 0.0, 0.0]


def test_parse_instruction_returns_spec_and_cut_positions(client):
    parsed = client.tasks.parse_instruction("Bias cut the banana at 0.4 ratio from the right side")
    assert parsed["spec"]["style"] == "bias"
    assert parsed["spec"]["state"] == "ratio"
    assert parsed["spec"]["ratio"] == pytest.approx(0.4)
    assert parsed["spec"]["reference"] == "right"
    assert parsed["target_fractions"] == pytest.approx([0.6])


def test_unparseable_instruction_says_what_is_missing(client):
    with pytest.raises(errors.InvalidArgument) as raised:
        client.tasks.parse_instruction("cut it in half")
    assert "food" in raised.value.details or "object" in raised.value.details


def test_generated_instructions_are_deterministic_and_parse_back(client):
    spec = {"style": "saw", "state": "split", "split_pieces": 4, "target_object": "melon"}
    first = client.tasks.generate_instructions(spec, seed=3, count=6)
    assert first == client.tasks.generate_instructions(spec, seed=3, count=6)
    assert first != client.tasks.generate_instructions(spec, seed=4, count=6)
    assert len(set(first)) == 6
    for text in first + client.tasks.generate_instructions(spec, seed=3, count=5, split="held_out"):
        parsed = client.tasks.parse_instruction(text)["spec"]
        assert (parsed["style"], parsed["state"], parsed["split_pieces"], parsed["target_object"]) == \
            ("saw", "split", 4, "melon"), text


def test_generate_rejects_bad_spec_and_split(client):
    with pytest.raises(errors.InvalidArgument, match="ratio 0.95 is outside"):
        client.tasks.generate_instructions({"state": "ratio", "ratio": 0.95, "target_object": "apple"})
    with pytest.raises(ValueError, match="split must be one of"):
        client.tasks.generate_instructions({"target_object": "apple"}, split="test")


@pytest.mark.parametrize("style", ["normal", "bias", "guillotine", "saw"])
def test_plan_cut_puts_the_blade_plane_on_the_target(client, style):
    plan = client.tasks.plan_cut(CUCUMBER, KNIFE_START, spec={"style": style, "state": "ratio", "ratio": 0.3,
                                                              "reference": "left", "target_object": "cucumber"},
                                 seed=1, sample_rate_hz=200)
    cut = plan["cuts"][0]
    assert cut["fraction_from_left"] == pytest.approx(0.3)
    in_cut = (plan["time_s"] > cut["start_time_s"]) & (plan["time_s"] < cut["end_time_s"])
    assert in_cut.sum() > 10
    for pose in plan["tcp_pose"][in_cut]:
        blade_normal = quat_rotate(pose[3:], [0, 1, 0])
        assert abs(np.dot(cut["target_point_m"] - pose[:3], blade_normal)) < 1e-3
    speeds = np.linalg.norm(plan["linear_velocity_m_s"], axis=1)
    assert speeds.max() <= 0.25 + 1e-9  # the planner's default TCP speed limit


def test_score_cuts_through_the_client(client):
    spec = {"state": "split", "split_pieces": 3, "target_object": "cucumber"}
    cut_at = lambda fraction: {"object_name": "cucumber_0",  # noqa: E731
                               "plane_point_m": [0.5, 0.12 - 0.2 * fraction, 0.05], "plane_normal": [0, 1, 0]}
    score = client.tasks.score_cuts(spec, CUCUMBER, [cut_at(1 / 3), cut_at(0.7)])
    assert score["success"] is True
    missing = client.tasks.score_cuts(spec, CUCUMBER, [cut_at(1 / 3)])
    assert (missing["success"], missing["cuts_correct"], missing["cuts_required"]) == (False, 1, 2)
    assert missing["cuts_within_position_tolerance"] == 1
    assert [r["placed"] for r in missing["required"]] == [True, False]
    with pytest.raises(errors.InvalidArgument, match="object_name is empty"):
        client.tasks.score_cuts(spec, CUCUMBER, [{"plane_point_m": [0.5, 0, 0.05]}])


def test_scripted_oracle_runs_a_cut_on_a_session(client, session):
    oracle = ScriptedOracle(client, session)
    plan = oracle.reset("saw the cucumber at 30% from the right", objects=[APPLE, CUCUMBER],
                        control_mode="pd_ee_pose_quat", seed=2)
    assert plan["target_name"] == "cucumber_0"
    assert plan["spec"]["style"] == "saw"
    target = plan["cuts"][0]["target_point_m"]
    phases, lowest_z, steps = set(), 1.0, 0
    while steps < 1000:
        mode, values = oracle.act()
        if oracle.finished:
            break
        assert mode == "pd_ee_pose_quat" and values.shape == (7,)
        phases.add(oracle.phase)
        tcp = np.asarray(client.step(session, mode, values).observation.tcp_pose)
        lowest_z = min(lowest_z, tcp[2])
        if oracle.phase == "cut":
            assert abs(np.dot(target - tcp[:3], quat_rotate(tcp[3:], [0, 1, 0]))) < 3e-3
        steps += 1
    assert oracle.finished
    assert {"approach", "cut", "retreat"} <= phases
    assert lowest_z < 0.022


def test_oracle_errors(client, session):
    oracle = ScriptedOracle(client, session)
    with pytest.raises(errors.InvalidArgument, match="the scene has apple_0"):
        oracle.reset("cut the banana in half", objects=[APPLE])
    with pytest.raises(errors.InvalidArgument, match="scene.task"):
        oracle.reset(objects=[APPLE])  # neither instruction nor spec, and the scene has no task
    with pytest.raises(ValueError, match="unknown keys"):
        oracle.reset("cut the apple in half", objects=[{**APPLE, "size": 1}])


class _FakeChatEndpoint(BaseHTTPRequestHandler):
    """An OpenAI-compatible /chat/completions that answers one faithful and one wrong paraphrase."""

    reply = ("1. Please slice the cucumber 30% of the way in from the left end\n"
             "2) cut the cucumber at 0.6 ratio from the left\n"
             "- 0.3 ratio from the left: cut the cucumber there\n"
             "* cut the cucumber at the midpoint")

    def do_POST(self):  # noqa: N802 (http.server's naming)
        body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
        assert self.path == "/v1/chat/completions" and body["messages"][0]["role"] == "user"
        payload = json.dumps({"choices": [{"message": {"role": "assistant", "content": self.reply}}]}).encode()
        self.send_response(200)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(payload)))
        self.end_headers()
        self.wfile.write(payload)

    def log_message(self, *args):
        pass


def test_paraphrases_that_change_the_meaning_are_rejected(client):
    http = HTTPServer(("127.0.0.1", 0), _FakeChatEndpoint)
    threading.Thread(target=http.serve_forever, daemon=True).start()
    try:
        endpoint = f"http://127.0.0.1:{http.server_port}/v1"
        kept, rejected = paraphrase(client.tasks, ["cut the cucumber at 0.3 ratio from the left"], endpoint, "any")
        assert kept == ["Please slice the cucumber 30% of the way in from the left end",
                        "0.3 ratio from the left: cut the cucumber there"]  # the 0.3 is not a list marker
        assert rejected == ["cut the cucumber at 0.6 ratio from the left", "cut the cucumber at the midpoint"]
    finally:
        http.shutdown()
    with pytest.raises(ParaphraseError, match="unreachable"):
        paraphrase(client.tasks, ["cut the apple in half"], endpoint, "any", timeout_s=2)


def test_cli_parse_and_instructions(address, capsys):
    assert cli_main(["parse", "--address", address, "guillotine cut the peach at the center"]) == 0
    assert "guillotine cut, middle, peach" in capsys.readouterr().out
    assert cli_main(["instructions", "--address", address, "--object", "orange", "--state", "ratio",
                     "--ratio", "0.25", "--side", "right", "--count", "5"]) == 0
    assert len(capsys.readouterr().out.strip().splitlines()) == 5
    assert cli_main(["instructions", "--address", address, "--state", "split", "--pieces", "4"]) == 0
    assert len(capsys.readouterr().out.strip().splitlines()) == 5
    assert cli_main(["parse", "--address", address, "do a little dance"]) == 4
    assert "server rejected a request: INVALID_ARGUMENT" in capsys.readouterr().err
