#!/usr/bin/env bash
# Generate the Python protobuf/gRPC stubs into client/python/culinarycut/v1/ (build outputs, not committed).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

PROTOS=(proto/culinarycut/v1/scene.proto proto/culinarycut/v1/simulator.proto)
OUT=client/python
mkdir -p "$OUT/culinarycut/v1"

# Debian's python3-grpc-tools bundles protoc 3.5, which rejects proto3 `optional`; the system protoc
# (3.21, same version as python3-protobuf) with grpc_python_plugin does not, so prefer it.
PLUGIN="$(command -v grpc_python_plugin || true)"
if command -v protoc >/dev/null 2>&1 && [[ -n "$PLUGIN" ]]; then
  protoc -I proto --python_out="$OUT" --grpc_python_out="$OUT" \
    --plugin=protoc-gen-grpc_python="$PLUGIN" "${PROTOS[@]}"
else
  /usr/bin/python3 -m grpc_tools.protoc -I proto --python_out="$OUT" --grpc_python_out="$OUT" "${PROTOS[@]}"
fi

# Fail here rather than at first import if the generated modules are unusable.
PYTHONPATH="$ROOT/$OUT" /usr/bin/python3 -c \
  'from culinarycut.v1 import scene_pb2, simulator_pb2, simulator_pb2_grpc'
echo "python stubs generated in $OUT/culinarycut/v1"
