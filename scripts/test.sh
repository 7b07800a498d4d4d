#!/usr/bin/env bash
# Installs, builds and runs every test: the C++ suites (Catch2) and the Python client suite
# (pytest against the real server binary), all through ctest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install_deps.sh" --tests
"$root/scripts/build.sh"
cd "$root/build"
ctest --output-on-failure -j "${CULINARYCUT_JOBS:-$(nproc)}"
