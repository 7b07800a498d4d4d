"""Builds the culinarycut package (metadata in pyproject.toml) with its gRPC stubs generated at build time.

The stubs (culinarycut/v1/*_pb2*.py) come from the repository's proto/culinarycut/v1 through
generate_stubs.py, in a build sub-command of its own: a wheel gets them in its build folder, an editable
install next to the sources (where the editable package is imported from).
"""
from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

from setuptools import Command, setup
from setuptools.command.build import build

HERE = Path(__file__).resolve().parent
PROTOS_ROOT = HERE.parent.parent / "proto"  # the repository's proto/ folder


class BuildGrpcStubs(Command):
    """Generates culinarycut/v1 from the protos (a sub-command of build, so editable installs run it too)."""

    description = "generate the culinarycut.v1 gRPC stubs with grpc_tools"
    user_options: list = []
    editable_mode = False  # setuptools sets it for `pip install -e`

    def initialize_options(self) -> None:
        self.build_lib = None
        self.outputs: list[str] = []

    def finalize_options(self) -> None:
        self.set_undefined_options("build_py", ("build_lib", "build_lib"))

    def run(self) -> None:
        out = HERE if self.editable_mode else Path(self.build_lib)
        environment = dict(os.environ)
        if importlib.util.find_spec("grpc_tools") is None:
            # pip's isolated build hides the target environment behind PYTHONPATH; the stubs must be made
            # by that environment's grpc_tools, the one that matches its protobuf and grpcio.
            environment.pop("PYTHONPATH", None)
        subprocess.run([sys.executable, str(HERE / "generate_stubs.py"), "--protos", str(PROTOS_ROOT),
                        "--out", str(out)], env=environment, check=True)
        self.outputs = [str(path) for path in sorted(out.joinpath("culinarycut", "v1").glob("*.py"))]

    def get_outputs(self) -> list[str]:
        return [] if self.editable_mode else self.outputs

    def get_output_mapping(self) -> dict[str, str]:
        return {}


class BuildWithGrpcStubs(build):
    sub_commands = build.sub_commands + [("build_grpc_stubs", None)]


setup(cmdclass={"build": BuildWithGrpcStubs, "build_grpc_stubs": BuildGrpcStubs})
