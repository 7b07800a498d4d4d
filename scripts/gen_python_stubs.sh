#!/usr/bin/env bash
# Generates the Python protobuf/gRPC stubs into client/python/culinarycut/v1/ (build outputs, not
# committed) with client/python/generate_stubs.py, as the package's own build does. Runs with the
# project virtualenv's Python when there is one (its protobuf is what imports the stubs), else
# /usr/bin/python3; both use Debian's grpc_tools. Idempotent.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
python="$root/.venv/bin/python"
[ -x "$python" ] || python=/usr/bin/python3
"$python" "$root/client/python/generate_stubs.py" --protos "$root/proto" --out "$root/client/python"
