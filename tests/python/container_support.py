"""The container files as the tests read them, without docker: the Dockerfile's stages and instructions,
a stage's default command (ENTRYPOINT + CMD) and the Debian packages it installs, and docker-compose.yml."""
from __future__ import annotations

import json
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOCKERFILE = ROOT / "Dockerfile"
COMPOSE = ROOT / "docker-compose.yml"
SECRETS_SCRIPT = ROOT / "scripts" / "make_server_secrets.sh"
ENTRYPOINT_SCRIPT = ROOT / "scripts" / "container_entrypoint.sh"
# where the server stage puts the binary and the entrypoint script
IMAGE_SERVER = "/opt/culinarycut/bin/culinarycut-server"
IMAGE_ENTRYPOINT = "/opt/culinarycut/bin/container-entrypoint"
IMAGE_SECRETS = "/run/secrets/"


def stages(text: str | None = None) -> dict[str, list[tuple[str, str]]]:
    """{stage name: [(INSTRUCTION, arguments)]}, continuation lines joined, comments dropped."""
    text = DOCKERFILE.read_text() if text is None else text
    lines = [line for line in text.splitlines() if not line.lstrip().startswith("#")]
    joined = re.sub(r"\\\n", " ", "\n".join(lines))
    result: dict[str, list[tuple[str, str]]] = {}
    current = None
    for line in filter(str.strip, joined.splitlines()):
        instruction, _, args = line.strip().partition(" ")
        instruction = instruction.upper()
        if instruction == "FROM":
            current = args.split()[-1] if " AS " in args.upper() else args.split()[0]
            result[current] = []
        result[current].append((instruction, args.strip()))
    return result


def _exec_form(args: str) -> list[str]:
    try:
        value = json.loads(args)
    except ValueError:
        raise AssertionError(f"not the JSON (exec) form, which runs without a shell: {args}") from None
    assert isinstance(value, list) and all(isinstance(v, str) for v in value), args
    return value


def default_command(stage: str) -> list[str]:
    """What a stage runs with no arguments to `docker run`: its last ENTRYPOINT then its last CMD."""
    instructions = stages()[stage]
    entrypoint = [_exec_form(a) for i, a in instructions if i == "ENTRYPOINT"]
    cmd = [_exec_form(a) for i, a in instructions if i == "CMD"]
    return (entrypoint[-1] if entrypoint else []) + (cmd[-1] if cmd else [])


def apt_packages(stage: str) -> set[str]:
    """The packages the stage's RUN instructions `apt-get install`."""
    packages = set()
    for instruction, args in stages()[stage]:
        for command in re.findall(r"apt-get install ([^&;|]*)", args) if instruction == "RUN" else []:
            packages.update(word for word in command.split() if not word.startswith(("-", "$")))
    return packages


def flag_values(argv: list[str], flag: str) -> list[str]:
    """Every value given to `flag` (as `flag VALUE` or `flag=VALUE`)."""
    values = [argv[i + 1] for i, arg in enumerate(argv[:-1]) if arg == flag]
    return values + [arg.split("=", 1)[1] for arg in argv if arg.startswith(flag + "=")]


def compose() -> dict:
    import yaml
    return yaml.safe_load(COMPOSE.read_text())
