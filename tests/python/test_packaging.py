"""client/python as a package, from a clean copy of the sources (no generated stubs): a wheel built with
--no-build-isolation, and an editable install, each in a fresh virtualenv (--system-site-packages, so
Debian's grpcio and protobuf serve, without the project's .venv), talking to the real server."""
from __future__ import annotations

import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]
STUBS = {"scene_pb2.py", "score_pb2.py", "simulator_pb2.py", "simulator_pb2_grpc.py", "task_pb2.py", "task_pb2_grpc.py"}


def run(command: list, cwd: Path, timeout_s: float = 300) -> str:
    result = subprocess.run([str(part) for part in command], cwd=cwd, capture_output=True, text=True,
                            timeout=timeout_s)
    assert result.returncode == 0, f"{' '.join(map(str, command))} failed:\n{result.stdout}\n{result.stderr}"
    return result.stdout


@pytest.fixture
def clean_checkout(tmp_path) -> Path:
    """The package sources and the protos as a fresh clone has them: nothing generated, nothing built."""
    root = tmp_path / "checkout"
    shutil.copytree(REPO_ROOT / "proto", root / "proto")
    shutil.copytree(REPO_ROOT / "client" / "python", root / "client" / "python",
                    ignore=shutil.ignore_patterns("v1", "build", "*.egg-info", "__pycache__"))
    assert not (root / "client" / "python" / "culinarycut" / "v1").exists()
    return root


def fresh_venv(path: Path) -> Path:
    """A virtualenv of the base Python that sees its system packages (Debian's) and not the project's .venv;
    pip comes from those system packages."""
    run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", path], cwd=path.parent)
    return path / "bin" / "python"


def assert_package_serves(python: Path, package_dir: Path, address: str, cwd: Path) -> None:
    """The installed package imports from package_dir, and its client and CLI talk to the server."""
    location = run([python, "-c", "import culinarycut, culinarycut.v1.simulator_pb2 as s; print(culinarycut.__file__)"],
                   cwd=cwd).strip()
    assert Path(location).parent == package_dir, location
    info = run([python.parent / "culinarycut", "info", "--address", address], cwd=cwd)  # the console script
    assert "culinarycut.v1" in info and "pd_joint_pos" in info, info
    assert "standard" in info and "unmeasured" in info, info  # the fine preset: no numbers, not zeros
    assert re.search(r"connections +at most \d+, \d+ per client address", info), info
    run([python, "-c", "from culinarycut import CulinaryCutEnv; import sys\n"
         "with CulinaryCutEnv(sys.argv[1]) as env: env.reset(seed=0); env.step(env.action_space.sample())", address],
        cwd=cwd)


def test_a_wheel_built_without_isolation_carries_the_stubs_and_serves(clean_checkout, tmp_path, address):
    package = clean_checkout / "client" / "python"
    wheels = tmp_path / "wheels"
    run([sys.executable, "-m", "pip", "wheel", "--no-build-isolation", "--no-deps", "--no-index", "--wheel-dir",
         wheels, package], cwd=tmp_path)
    (wheel,) = wheels.glob("culinarycut-*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    assert {f"culinarycut/v1/{stub}" for stub in STUBS} <= names
    assert "culinarycut/env.py" in names and "generate_stubs.py" not in names  # a build helper, not the package
    assert "culinarycut/bench/suite_schema.json" in names  # data the suites are validated against
    assert not (package / "culinarycut" / "v1").exists()  # generated in the build folder, not the sources

    python = fresh_venv(tmp_path / "venv")
    run([python, "-m", "pip", "install", "--no-index", wheel], cwd=tmp_path)
    site_packages = next((tmp_path / "venv" / "lib").glob("python3*/site-packages"))
    assert_package_serves(python, site_packages / "culinarycut", address, cwd=tmp_path)


def test_an_editable_install_generates_the_stubs_next_to_the_sources(clean_checkout, tmp_path, address):
    package = clean_checkout / "client" / "python"
    python = fresh_venv(tmp_path / "venv")
    run([python, "-m", "pip", "install", "--no-build-isolation", "--no-index", "-e", package], cwd=tmp_path)
    assert STUBS <= {path.name for path in (package / "culinarycut" / "v1").glob("*.py")}
    assert_package_serves(python, package / "culinarycut", address, cwd=tmp_path)
