"""The container files are safe by default, read without docker (CI has none): the server image serves
TLS with tokens and no telemetry unless told otherwise, the build id comes in as a build argument, the
client image has every package its commands import, keys stay out of images and git, and
docker-compose.yml follows the Compose Specification (its JSON schema; `docker compose config` too where
that tool is installed)."""
from __future__ import annotations

import ipaddress
import json
import os
import re
import shutil
import subprocess

import pytest

from container_support import (COMPOSE, IMAGE_SECRETS, ROOT, apt_packages, compose, default_command, flag_values,
                               stages)

COMPOSE_SCHEMA = ROOT / "tests" / "data" / "compose-spec.json"
INSTALL_DEPS = ROOT / "scripts" / "install_deps.sh"
# Debian Python packages only the build or the tests use, not a command of the client image.
BUILD_ONLY_PYTHON = {"python3-venv", "python3-grpc-tools", "python3-pytest"}


def _listen_host(address: str) -> str:
    return address.rsplit(":", 1)[0].strip("[]")


def _is_loopback(host: str) -> bool:
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return host == "localhost"


def unsafe_defaults(argv: list[str]) -> list[str]:
    """Why a server command line is not safe to publish, or [] when it is."""
    problems = []
    if "--insecure" in argv:
        problems.append("--insecure")
    if flag_values(argv, "--telemetry"):
        problems.append(f"telemetry (unencrypted) on: {flag_values(argv, '--telemetry')}")
    authenticated = (bool(flag_values(argv, "--tls-cert")) and bool(flag_values(argv, "--tls-key"))
                     and bool(flag_values(argv, "--token-file") or flag_values(argv, "--tls-client-ca")))
    for address in flag_values(argv, "--listen"):
        if not address.startswith("unix:") and not _is_loopback(_listen_host(address)) and not authenticated:
            problems.append(f"--listen {address} without TLS and tokens")
    if not flag_values(argv, "--listen"):
        problems.append("no --listen: the server's default, loopback, which a published port cannot reach")
    return problems


def test_the_check_catches_the_unsafe_command_lines():
    assert unsafe_defaults(["s", "--listen", "0.0.0.0:50051", "--telemetry", "tcp://0.0.0.0:5556", "--insecure"])
    assert unsafe_defaults(["s", "--listen", "0.0.0.0:50051", "--tls-cert", "c", "--tls-key", "k"])
    assert unsafe_defaults(["s", "--listen=[::]:50051"])
    assert not unsafe_defaults(["s", "--listen", "127.0.0.1:50051"])
    assert not unsafe_defaults(["s", "--listen", "0.0.0.0:1", "--tls-cert", "c", "--tls-key", "k", "--token-file", "t"])


def test_the_server_image_serves_tls_with_tokens_and_no_telemetry_by_default():
    argv = default_command("server")
    assert argv, "the server stage has no ENTRYPOINT or CMD"
    assert not unsafe_defaults(argv), f"the server image's default command {argv}: {unsafe_defaults(argv)}"
    for flag in ("--tls-cert", "--tls-key", "--token-file"):
        assert all(v.startswith(IMAGE_SECRETS) for v in flag_values(argv, flag)), f"{flag} outside {IMAGE_SECRETS}"
    exposed = [a for i, a in stages()["server"] if i == "EXPOSE"]
    assert exposed == ["50051"], f"the server image exposes {exposed}: the gRPC port only (telemetry is off)"


def test_the_server_image_puts_the_mpm_library_where_the_binary_looks_for_it():
    # The server loads libculinarycut_mpm.so (one build per x86-64 level) from $ORIGIN/../lib: the image must
    # copy the build's lib/ there, beside the bin/ it copies the binary into.
    copies = {args.split()[-2]: args.split()[-1] for i, args in stages()["server"] if i == "COPY" and "--from=build" in args}
    assert copies.get("/opt/culinarycut/build/server/culinarycut-server") == "/opt/culinarycut/bin/culinarycut-server"
    assert copies.get("/opt/culinarycut/build/lib") == "/opt/culinarycut/lib"
    binary = ROOT / "build" / "server" / "culinarycut-server"
    if shutil.which("readelf") and binary.is_file():
        dynamic = subprocess.run(["readelf", "-d", str(binary)], capture_output=True, text=True).stdout
        assert "$ORIGIN/../lib" in dynamic, "the server's RUNPATH lacks $ORIGIN/../lib"


def test_the_build_id_is_a_build_argument_the_build_reads():
    build = stages()["build"]
    steps = [f"{i} {a}" for i, a in build]
    declared = next((n for n, step in enumerate(steps) if step == "ARG CULINARYCUT_BUILD_ID"), None)
    built = next(n for n, step in enumerate(steps) if step.startswith("RUN") and "scripts/build.sh" in step)
    assert declared is not None, "the build stage takes no CULINARYCUT_BUILD_ID build argument"
    assert declared < built, "the ARG must come before the build that reads it"
    assert any('test -n "$CULINARYCUT_BUILD_ID"' in step for step in steps[declared:built]), \
        "a build without the id must stop, not report 'unknown'"
    for name, service in compose()["services"].items():
        assert "CULINARYCUT_BUILD_ID" in service["build"]["args"], f"compose's {name} does not pass the build id"


@pytest.mark.parametrize("env, expected", [({"CULINARYCUT_BUILD_ID": "0123abcd4567"}, "0123abcd4567"),
                                           ({}, "unknown")])
def test_cmake_takes_the_build_id_from_the_environment(tmp_path, env, expected):
    """Outside a git checkout (as in the image's build), the id is the variable's or 'unknown'."""
    script = tmp_path / "print_build_id.cmake"
    script.write_text(f'include("{ROOT / "cmake" / "CulinaryCutBuildId.cmake"}")\n'
                      'message("build id: ${CULINARYCUT_BUILD_ID}")\n')
    environ = {k: v for k, v in os.environ.items() if k != "CULINARYCUT_BUILD_ID"}
    environ.update(env, GIT_CEILING_DIRECTORIES=str(tmp_path.parent))
    done = subprocess.run(["cmake", "-P", str(script)], cwd=tmp_path, env=environ, capture_output=True, text=True,
                          timeout=30)
    assert done.returncode == 0, done.stderr
    assert f"build id: {expected}" in done.stderr


def test_the_client_image_installs_what_its_commands_import():
    """Every Debian Python package install_deps.sh installs for the package's commands (h5py for
    `data`, scipy for `safety fit`, ...) is in the client image too."""
    deps = INSTALL_DEPS.read_text()
    packages = re.search(r"^PACKAGES=\((.*?)^\)", deps, re.S | re.M).group(1)
    wanted = {w for w in re.sub(r"#.*", "", packages).split() if w.startswith("python3-")} - BUILD_ONLY_PYTHON
    assert {"python3-h5py", "python3-scipy"} <= wanted
    missing = wanted - apt_packages("client")
    assert not missing, f"the client image lacks {sorted(missing)}"


def test_keys_and_tokens_stay_out_of_images_and_git():
    ignored = (ROOT / ".dockerignore").read_text().split()
    assert "secrets/" in ignored and "**/*.key" in ignored and "**/*.token" in ignored
    assert "/secrets/" in (ROOT / ".gitignore").read_text().split()


def test_compose_follows_the_compose_specification():
    import jsonschema
    schema = json.loads(COMPOSE_SCHEMA.read_text())
    errors = [f"{'/'.join(map(str, e.absolute_path))}: {e.message}"
              for e in jsonschema.Draft7Validator(schema).iter_errors(compose())]
    assert not errors, "\n".join(errors)


def test_compose_mounts_what_the_images_read_and_publishes_on_loopback():
    services = compose()["services"]
    for port in services["server"]["ports"]:
        assert str(port).startswith("127.0.0.1:"), f"port {port} is published beyond the host's loopback"
    server_reads = {v[len(IMAGE_SECRETS):] for flag in ("--tls-cert", "--tls-key", "--token-file")
                    for v in flag_values(default_command("server"), flag)}
    assert server_reads <= set(services["server"]["secrets"]), "the server's default flags name files not mounted"
    client_ca = services["client"]["environment"]["CULINARYCUT_TLS_CA"]
    assert client_ca[len(IMAGE_SECRETS):] in services["client"]["secrets"]
    assert "/run/secrets/client.token" in " ".join(services["client"]["command"])
    assert set(compose()["secrets"]) >= set(services["server"]["secrets"]) | set(services["client"]["secrets"])


def _compose_tool() -> list[str] | None:
    for tool in (["docker", "compose"], ["docker-compose"]):
        if shutil.which(tool[0]) and subprocess.run([*tool, "version"], capture_output=True).returncode == 0:
            return tool
    return None


@pytest.mark.skipif(_compose_tool() is None, reason="neither `docker compose` nor docker-compose is installed")
def test_docker_compose_config_accepts_the_file(tmp_path):
    for name in ("server.pem", "server.key", "tokens.txt", "ca.pem", "client.token"):
        (tmp_path / name).write_text("placeholder\n")
    env = {**os.environ, "CULINARYCUT_BUILD_ID": "0123abcd4567", "CULINARYCUT_SECRETS": str(tmp_path)}
    done = subprocess.run([*_compose_tool(), "-f", str(COMPOSE), "config", "-q"], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
