"""TLS and bearer tokens through the Python client: calls need the right token over TLS, sessions belong to
the token that made them, mutual TLS asks for a client certificate, and bad input names its field as a
structured detail."""
from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from culinarycut import Client, errors
from culinarycut.launch import ServerProcess, server_binary

PKI_SCRIPT = Path(__file__).resolve().parents[1] / "support" / "make_test_pki.sh"


@pytest.fixture(scope="module")
def pki(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("pki")
    subprocess.run(["bash", str(PKI_SCRIPT), str(folder)], check=True, timeout=120)
    return folder


def tokens(pki: Path) -> dict[str, str]:
    return dict(line.split() for line in (pki / "tokens.txt").read_text().splitlines())


@pytest.fixture(scope="module")
def tls_server(pki):
    with ServerProcess(server_binary(), extra_args=["--tls-cert", str(pki / "server.pem"), "--tls-key",
                                                    str(pki / "server.key"), "--token-file",
                                                    str(pki / "tokens.txt")]) as server:
        yield server


def test_a_token_over_tls_drives_a_session(tls_server, pki):
    with Client(tls_server.address, tls_ca=str(pki / "ca.pem"), token=tokens(pki)["alice"]) as client:
        session = client.create_session().session_id
        client.reset(session, seed=0)
        assert len(client.step(session, "pd_ee_delta_pose", [0] * 6).observation.agent.qpos) == 7
        client.close_session(session)


@pytest.mark.parametrize("token, error", [(None, errors.Unauthenticated), ("x" * 48, errors.Unauthenticated)])
def test_calls_without_the_right_token_are_refused(tls_server, pki, token, error, monkeypatch):
    monkeypatch.delenv("CULINARYCUT_TOKEN", raising=False)
    with Client(tls_server.address, tls_ca=str(pki / "ca.pem"), token=token, timeout_s=10) as client:
        with pytest.raises(error):
            client.create_session()


def test_a_plaintext_client_cannot_talk_to_a_tls_server(tls_server):
    with Client(tls_server.address, timeout_s=5) as client:
        with pytest.raises(errors.Unavailable):
            client.server_info()


def test_another_token_can_neither_see_nor_close_a_session(tls_server, pki):
    names = tokens(pki)
    with Client(tls_server.address, tls_ca=str(pki / "ca.pem"), token=names["alice"]) as alice, \
            Client(tls_server.address, tls_ca=str(pki / "ca.pem"), token=names["bob"]) as bob:
        session = alice.create_session().session_id
        for call in (lambda: bob.reset(session), lambda: bob.observe(session), lambda: bob.close_session(session),
                     lambda: bob.session_stats(session), lambda: bob.save_snapshot(session)):
            with pytest.raises(errors.NotFound, match="no session"):
                call()
        alice.reset(session)  # still there, still alice's
        alice.close_session(session)


def test_one_token_cannot_take_every_session(pki):
    args = ["--tls-cert", str(pki / "server.pem"), "--tls-key", str(pki / "server.key"), "--token-file",
            str(pki / "tokens.txt"), "--max-sessions-per-owner", "1"]
    names = tokens(pki)
    with ServerProcess(server_binary(), extra_args=args) as server, \
            Client(server.address, tls_ca=str(pki / "ca.pem"), token=names["alice"]) as alice, \
            Client(server.address, tls_ca=str(pki / "ca.pem"), token=names["bob"]) as bob:
        alice.create_session()
        with pytest.raises(errors.ResourceExhausted, match="--max-sessions-per-owner 1"):
            alice.create_session()
        bob.create_session()  # the server has room; alice's quota does not touch bob's


def test_mutual_tls_needs_a_client_certificate_signed_by_the_ca(pki):
    args = ["--tls-cert", str(pki / "server.pem"), "--tls-key", str(pki / "server.key"),
            "--tls-client-ca", str(pki / "ca.pem")]
    with ServerProcess(server_binary(), extra_args=args) as server:
        with Client(server.address, tls_ca=str(pki / "ca.pem"), tls_cert=str(pki / "client.pem"),
                    tls_key=str(pki / "client.key")) as client, \
                Client(server.address, tls_ca=str(pki / "ca.pem"), tls_cert=str(pki / "client2.pem"),
                       tls_key=str(pki / "client2.key")) as same_subject:
            session = client.create_session().session_id
            # Another certificate with the same subject is another client: the session is not its.
            with pytest.raises(errors.NotFound, match="no session"):
                same_subject.reset(session)
            client.close_session(session)
        with Client(server.address, tls_ca=str(pki / "ca.pem"), timeout_s=5) as anonymous:
            with pytest.raises(errors.Unavailable):
                anonymous.server_info()


@pytest.mark.parametrize("args, message", [
    (["--listen", "0.0.0.0:0", "--tls-cert", "{pki}/server.pem", "--tls-key", "{pki}/server.key"],
     "not a loopback address"),  # TLS without authentication is not enough off loopback
    (["--token-file", "{pki}/tokens.txt"], "--token-file needs --tls-cert and --tls-key"),
    (["--tls-cert", "{pki}/server.pem"], "TLS needs both --tls-cert and --tls-key"),
    (["--tls-cert", "{pki}/server.pem", "--tls-key", "/nonexistent.key"], "--tls-key /nonexistent.key: cannot be read"),
])
def test_unsafe_or_incomplete_access_options_are_refused_at_start(pki, args, message):
    done = subprocess.run([str(server_binary()), *[a.format(pki=pki) for a in args]], capture_output=True,
                          text=True, timeout=30)
    assert done.returncode != 0 and message in done.stdout + done.stderr


def test_a_non_loopback_address_is_served_with_tls_and_tokens(pki):
    args = ["--tls-cert", str(pki / "server.pem"), "--tls-key", str(pki / "server.key"),
            "--token-file", str(pki / "tokens.txt")]
    server = ServerProcess(server_binary(), extra_args=args, listen="0.0.0.0:0")
    try:
        port = server.address.rsplit(":", 1)[1]
        with Client(f"127.0.0.1:{port}", tls_ca=str(pki / "ca.pem"), token=tokens(pki)["bob"]) as client:
            assert client.server_info().version
    finally:
        server.stop()


def test_bad_input_names_its_field_as_a_structured_detail(client):
    with pytest.raises(errors.InvalidArgument) as caught:
        client.create_session({"objects": [{"food": "cucumber", "scale": -2}], "effects": {"mpm": True}})
    assert caught.value.field == "scene.objects[0].scale"
    with pytest.raises(errors.InvalidArgument) as caught:
        client.reset("")
    assert caught.value.field == "session_id"
    # One-word fields are named too: the field travels with the status, not parsed from the message.
    spec = client.tasks.parse_instruction("cut the banana in the middle")["spec"]
    with pytest.raises(errors.InvalidArgument) as caught:
        client.tasks.generate_instructions(spec, count=1_000_000)
    assert caught.value.field == "count"
    session = client.create_session(None).session_id
    with pytest.raises(errors.InvalidArgument) as caught:
        client.restore_snapshot(session, b"not a snapshot")
    assert caught.value.field == "snapshot"
    client.close_session(session)
