"""Generates the culinarycut.v1 Python modules (messages and gRPC stubs) from proto/culinarycut/v1/*.proto.

Run by the package build (setup.py) and by scripts/gen_python_stubs.sh (CMake). It uses the grpc_tools of
the interpreter that runs it and then imports what it wrote with that interpreter's protobuf and grpcio:
generated code only works with the runtime its generator was made for (Debian 12's grpc_tools 1.14
writes old-style descriptors that Debian's protobuf 3.21 with its C++ backend reads), so the build
runs this with the Python the package is installed into.

    python generate_stubs.py --protos <repo>/proto --out <folder that gets culinarycut/v1/>
"""
from __future__ import annotations

import argparse
import importlib
import sys
import types
from pathlib import Path

PACKAGE = ("culinarycut", "v1")


def generate(protos_root: Path, out_root: Path) -> list[Path]:
    """Writes out_root/culinarycut/v1/{name}_pb2.py and {name}_pb2_grpc.py for every .proto; returns them."""
    try:
        import grpc_tools
        from grpc_tools import protoc
    except ImportError:
        raise SystemExit(
            f"generate_stubs: grpc_tools is not importable by {sys.executable}; install the one that "
            "matches your grpcio (Debian: apt-get install python3-grpc-tools; PyPI: pip install "
            "grpcio-tools==<your grpcio version>)") from None
    protos = sorted(protos_root.joinpath(*PACKAGE).glob("*.proto"))
    if not protos:
        raise SystemExit(f"generate_stubs: no .proto files in {protos_root.joinpath(*PACKAGE)}; "
                         "build from a CulinaryCut checkout (the protos live in its proto/ folder)")
    package_dir = out_root.joinpath(*PACKAGE)
    package_dir.mkdir(parents=True, exist_ok=True)
    # The well-known types (google/protobuf/wrappers.proto) ship inside grpc_tools.
    well_known = Path(grpc_tools.__file__).parent / "_proto"
    args = ["grpc_tools.protoc", f"-I{protos_root}", f"-I{well_known}", f"--python_out={out_root}",
            f"--grpc_python_out={out_root}", *map(str, protos)]
    if protoc.main(args) != 0:
        raise SystemExit(f"generate_stubs: grpc_tools.protoc failed on {[p.name for p in protos]}")
    init = package_dir / "__init__.py"
    init.write_text('"""Generated from proto/culinarycut/v1 by generate_stubs.py; do not edit."""\n')
    outputs = [init]
    for proto in protos:
        outputs += [package_dir / f"{proto.stem}_pb2.py", package_dir / f"{proto.stem}_pb2_grpc.py"]
    return outputs


def check_imports(out_root: Path, outputs: list[Path]) -> None:
    """Imports every generated module with this interpreter, without running culinarycut/__init__.py."""
    parent = types.ModuleType(PACKAGE[0])
    parent.__path__ = [str(out_root / PACKAGE[0])]  # the generated modules import each other through it
    sys.modules[PACKAGE[0]] = parent
    for path in outputs:
        if path.name != "__init__.py":
            try:
                importlib.import_module(".".join([*PACKAGE, path.stem]))
            except Exception as err:
                raise SystemExit(f"generate_stubs: {path} does not import with this Python's protobuf / "
                                 f"grpcio ({type(err).__name__}: {err}); the grpc_tools that generated it "
                                 "does not match them") from None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--protos", type=Path, required=True, help="folder holding culinarycut/v1/*.proto")
    parser.add_argument("--out", type=Path, required=True, help="folder that gets culinarycut/v1/")
    args = parser.parse_args(argv)
    outputs = generate(args.protos.resolve(), args.out.resolve())
    check_imports(args.out.resolve(), outputs)
    print(f"generate_stubs: {len(outputs) - 1} modules in {args.out.joinpath(*PACKAGE)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
