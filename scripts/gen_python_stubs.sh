#!/usr/bin/env bash
# Generates the Python protobuf/gRPC stubs with grpc_tools (Debian's python3-grpc-tools) into
# client/python/culinarycut/v1/ (build outputs, not committed). Idempotent.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

PROTOS=(proto/culinarycut/v1/scene.proto proto/culinarycut/v1/score.proto proto/culinarycut/v1/simulator.proto proto/culinarycut/v1/task.proto)
OUT=client/python
mkdir -p "$OUT/culinarycut/v1"

# grpc_tools bundles its own protoc (3.5 on Debian 12, no proto3 `optional`) and the well-known
# types (google/protobuf/wrappers.proto) under its _proto folder.
WELL_KNOWN="$(/usr/bin/python3 -c 'import grpc_tools, os; print(os.path.join(os.path.dirname(grpc_tools.__file__), "_proto"))')"
/usr/bin/python3 -m grpc_tools.protoc -I proto -I "$WELL_KNOWN" \
  --python_out="$OUT" --grpc_python_out="$OUT" "${PROTOS[@]}"

# Fail here rather than at first import if the generated modules are unusable.
PYTHONPATH="$ROOT/$OUT" /usr/bin/python3 -c \
  'from culinarycut.v1 import scene_pb2, score_pb2, simulator_pb2, simulator_pb2_grpc, task_pb2, task_pb2_grpc'
echo "python stubs generated in $OUT/culinarycut/v1"
