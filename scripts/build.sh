#!/usr/bin/env bash
# Configures and builds CulinaryCut in Release into build/ (server, clients, tests, benchmarks,
# and the Python stubs in client/python/culinarycut/v1).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="${CULINARYCUT_JOBS:-$(nproc)}"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release
cmake --build "$root/build" -j "$jobs"
