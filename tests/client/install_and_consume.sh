#!/usr/bin/env bash
# Installs the C++ client from a build tree into a fresh prefix, builds a separate CMake project
# against it with find_package(culinarycut), and runs that program against a real server.
# Usage: install_and_consume.sh BUILD_DIR SOURCE_DIR SERVER_BINARY
set -euo pipefail
build_dir=$1 source_dir=$2 server=$3
source "$(dirname "$0")/../support/start_server.sh"
work=$(mktemp -d)
SERVER_PID=""
cleanup() { [ -n "$SERVER_PID" ] && kill "$SERVER_PID" 2>/dev/null; wait 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT
cmake --install "$build_dir" --component client --prefix "$work/prefix" > "$work/install.log"
test -f "$work/prefix/lib/cmake/culinarycut/culinarycutConfig.cmake"
test -f "$work/prefix/include/culinarycut/client.h"
test -f "$work/prefix/include/culinarycut/v1/simulator.grpc.pb.h"
cmake -S "$source_dir/tests/client/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release > "$work/configure.log"
cmake --build "$work/consumer" -j "${CULINARYCUT_JOBS:-2}" > "$work/build.log"
start_server "$server" "$work/server.log"
"$work/consumer/consumer" "$SERVER_ADDRESS"
