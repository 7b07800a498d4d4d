"""Fixtures that run the real culinarycut-server binary on ephemeral ports (the culinarycut package comes
from the Python running pytest: the project's .venv, where scripts/install_deps.sh installs it)."""
from __future__ import annotations

import pytest
from culinarycut import Client
from culinarycut.launch import ServerProcess, server_binary


def start_server(max_sessions: int) -> ServerProcess:
    """Start a server or fail (never skip): these tests exist to exercise the real binary."""
    binary = server_binary()
    if not binary.is_file():
        pytest.fail(f"culinarycut-server not found at {binary}: build it (scripts/build.sh) "
                    "or set CULINARYCUT_SERVER to the binary's path", pytrace=False)
    try:
        return ServerProcess(binary, max_sessions=max_sessions, idle_timeout_s=60)
    except (OSError, RuntimeError, TimeoutError) as err:
        pytest.fail(f"could not start {binary}: {err}", pytrace=False)


def stop_server(server: ServerProcess) -> None:
    code = server.stop()
    assert code == 0, f"server exited with {code} after SIGTERM; output:\n{server.output()}"


@pytest.fixture(scope="session")
def server():
    """The shared server (--max-sessions 8); yields the ServerProcess."""
    srv = start_server(max_sessions=8)
    yield srv
    stop_server(srv)


@pytest.fixture(scope="session")
def address(server) -> str:
    """host:port of the shared server's gRPC endpoint."""
    return server.address


@pytest.fixture(scope="session")
def telemetry_endpoint(server) -> str:
    return server.telemetry


@pytest.fixture
def client(address):
    with Client(address, timeout_s=30.0) as c:
        yield c


@pytest.fixture
def session(client):
    """A reset robot-only session (seed 0); closed afterwards."""
    sid = client.create_session(None).session_id
    client.reset(sid, seed=0)
    yield sid
    client.close_session(sid)
