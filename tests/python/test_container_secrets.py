"""The server image's default command, run here without docker: with the files scripts/make_server_secrets.sh
makes in place of the mounts, the real server starts over TLS and a client with the CA and the client
token uses it (one without the token is refused); without them the entrypoint refuses to start and says
what to mount."""
from __future__ import annotations

import subprocess
from pathlib import Path

import pytest
from culinarycut import Client, errors
from culinarycut.launch import server_binary

from container_support import (ENTRYPOINT_SCRIPT, IMAGE_ENTRYPOINT, IMAGE_SECRETS, IMAGE_SERVER, SECRETS_SCRIPT,
                               default_command)

LISTENING = "culinarycut-server listening on "


def local_command(secrets: Path) -> list[str]:
    """The image's default command with this checkout's scripts and server, the files in `secrets`, and
    loopback with a free port in place of the container's interfaces."""
    argv = []
    for arg in default_command("server"):
        arg = {IMAGE_ENTRYPOINT: str(ENTRYPOINT_SCRIPT), IMAGE_SERVER: str(server_binary())}.get(arg, arg)
        arg = arg.replace(IMAGE_SECRETS, f"{secrets}/") if arg.startswith(IMAGE_SECRETS) else arg
        argv.append("127.0.0.1:0" if arg == "0.0.0.0:50051" else arg)
    assert "127.0.0.1:0" in argv, f"the image no longer listens on 0.0.0.0:50051: update this test ({argv})"
    return argv


@pytest.fixture(scope="module")
def secrets(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("container") / "secrets"
    done = subprocess.run(["bash", str(SECRETS_SCRIPT), str(folder), "sim.lab"], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    return folder


def test_the_script_makes_a_ca_signed_certificate_for_the_compose_names(secrets):
    assert sorted(p.name for p in secrets.iterdir()) == ["ca.key", "ca.pem", "client.token", "server.key",
                                                         "server.pem", "tokens.txt"]
    assert secrets.stat().st_mode & 0o077 == 0, "the folder must be the user's alone"
    names = subprocess.run(["openssl", "x509", "-in", str(secrets / "server.pem"), "-noout", "-ext", "subjectAltName"],
                           capture_output=True, text=True, check=True).stdout
    for name in ("DNS:localhost", "DNS:server", "IP Address:127.0.0.1", "DNS:sim.lab"):
        assert name in names
    token = (secrets / "client.token").read_text().strip()
    assert (secrets / "tokens.txt").read_text() == f"client {token}\n" and len(token) >= 32
    again = subprocess.run(["bash", str(SECRETS_SCRIPT), str(secrets)], capture_output=True, text=True, timeout=60)
    assert again.returncode != 0 and "exists" in again.stderr, "it must not overwrite deployed secrets"


def test_the_default_command_serves_tls_with_the_scripts_token(secrets):
    process = subprocess.Popen(local_command(secrets), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        output, address = [], None
        for line in process.stdout:
            output.append(line)
            if LISTENING in line:
                address = line.split(LISTENING)[1].split()[0]  # 127.0.0.1, which the certificate names
                break
        assert address, f"the server did not start:\n{''.join(output)}"
        token = (secrets / "client.token").read_text().strip()
        with Client(address, tls_ca=str(secrets / "ca.pem"), token=token, timeout_s=30) as client:
            client.close_session(client.create_session().session_id)
        with Client(address, tls_ca=str(secrets / "ca.pem"), token=None, timeout_s=10) as stranger:
            with pytest.raises(errors.Unauthenticated):
                stranger.create_session()
    finally:
        process.terminate()
        process.wait(timeout=20)


def test_without_the_mounts_the_entrypoint_refuses_and_says_what_to_mount(tmp_path):
    done = subprocess.run(local_command(tmp_path / "not-mounted"), capture_output=True, text=True, timeout=30)
    assert done.returncode == 2, done.stdout + done.stderr
    assert LISTENING not in done.stdout
    for name in ("server.pem", "server.key", "tokens.txt"):
        assert str(tmp_path / "not-mounted" / name) in done.stderr
    assert "scripts/make_server_secrets.sh" in done.stderr and "docs/deployment.md" in done.stderr
