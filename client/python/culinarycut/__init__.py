"""Python client for the CulinaryCut simulation server (gRPC, package culinarycut.v1)."""
try:
    from culinarycut.v1 import scene_pb2, simulator_pb2, simulator_pb2_grpc, task_pb2, task_pb2_grpc  # noqa: F401
except ImportError as _err:  # the stubs are build outputs, not checked in
    raise ImportError(
        "culinarycut: generated gRPC stubs (culinarycut.v1.*_pb2) are missing or broken; reinstall the "
        "package (pip install --no-build-isolation -e client/python, as scripts/install_deps.sh does) or "
        f"run scripts/gen_python_stubs.sh from the repository root (original error: {_err})"
    ) from _err

from culinarycut import errors
from culinarycut.client import Client
from culinarycut.env import CulinaryCutEnv
from culinarycut.registration import register_environments
from culinarycut.spaces import Box, Dict

__version__ = "0.1.0"
register_environments()  # CulinaryCut/Robot-v0, CulinaryCut/CutCucumber-v0 (when gymnasium is installed)
__all__ = ["Client", "CulinaryCutEnv", "Box", "Dict", "errors", "scene_pb2", "simulator_pb2", "task_pb2"]
